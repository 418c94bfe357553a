"""The joint coordinates as motions of their bodies: a rotation about an axis or a translation.

Each coordinate of the velocity vector moves its body either by turning it about an axis (a
revolute bearing) or by moving it along a direction (a prismatic coordinate, a body translating
in a compliant bearing). Code that must treat the two alike or apart (the planetary mode classes,
the scale of a mode's animation) reads them here, from Pinocchio's joint Jacobian at the
reference pose, so that it holds for every kind of joint Pinocchio builds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinwind.model.gearbox import Gearbox


@dataclass(frozen=True)
class Coordinate:
    """One coordinate of the velocity vector as a motion of its body.

    Attributes:
        kind: ``"rotation"`` or ``"translation"``.
        axis: unit axis of the rotation or direction of the translation, world, reference pose.
    """

    kind: str
    axis: np.ndarray


def coordinates(gearbox: Gearbox) -> list[Coordinate]:
    """Each velocity coordinate's kind and axis at the reference pose, in velocity order."""
    model = gearbox.model
    data = model.createData()
    pin.computeJointJacobians(model, data, gearbox.neutral())
    out: list[Coordinate | None] = [None] * model.nv
    for jid in range(1, model.njoints):
        joint = model.joints[jid]
        jac = np.reshape(
            pin.getJointJacobian(model, data, jid, pin.LOCAL_WORLD_ALIGNED), (6, model.nv)
        )
        for k in range(joint.nv):
            col = jac[:, joint.idx_v + k]
            turns = bool(np.linalg.norm(col[3:]) > 0.0)
            axis = col[3:] if turns else col[:3]
            kind = "rotation" if turns else "translation"
            out[joint.idx_v + k] = Coordinate(kind, axis / np.linalg.norm(axis))
    return [c for c in out if c is not None]
