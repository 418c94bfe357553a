"""Kinematic speed ratios of a gear train, from the null space of its constraint rows."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pinwind.dynamics.mesh import MeshSet
from pinwind.errors import InputError, UnknownJoint
from pinwind.model.gearbox import Gearbox


def speed_ratio(gearbox: Gearbox, output: str, reference: str) -> float:
    """ω_output / ω_reference for a gear train with one degree of freedom (signed).

    Joint speeds are relative to the parent body, as everywhere in pinwind. The ratio comes from
    the null space of the mesh rows and the locks at the reference pose: no tooth-count
    bookkeeping, so it also holds for compound planets and several stages.

    Raises:
        UnknownJoint: a name is not a bearing of the gearbox.
        InputError: the train has more (or fewer) than one degree of freedom.
    """
    for name in (output, reference):
        if name not in gearbox.joint_names:
            raise UnknownJoint(name, "speed_ratio", gearbox.joint_names)
    model = gearbox.model
    data = model.createData()
    q, v = gearbox.neutral(), np.zeros(model.nv)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    meshes = MeshSet(gearbox)
    meshes.set_velocity(v)
    jac, _ = meshes.combine(meshes.evaluate(model, data), np.ones(meshes.count))
    locks = np.zeros((len(gearbox.locked_joints), model.nv))
    for i, name in enumerate(gearbox.locked_joints):
        locks[i, gearbox.v_index(name)] = 1.0
    rows = np.vstack([jac, locks])
    _, sv, vt = np.linalg.svd(rows)
    rank = int(np.sum(sv > 1e-10 * sv[0])) if sv.size else 0
    free = model.nv - rank
    if free != 1:
        raise InputError(
            f"the gear train has {free} degrees of freedom; a speed ratio needs exactly one"
        )
    mode = vt[-1]
    ref = mode[gearbox.v_index(reference)]
    if abs(ref) < 1e-12 * np.abs(mode).max():
        raise InputError(f'joint "{reference}" does not turn with the gear train')
    return float(mode[gearbox.v_index(output)] / ref)
