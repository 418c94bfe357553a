"""The support structure in a run: its springs and the housing's and bedplate's displacements.

The support's slides (``model/support.py``: the tower modes' slides under the bedplate, the
mounts' slides and roll hinge under the housing) are each held by a linear spring F = −k q, the
linear term of the compiled bearing springs (``cpp/bearing_spring.hpp``, an axial slide's law);
their dampers are the slides' own viscous damping. ``support_spring_specs`` gives the compiled
specs. The slides are bearings of the run (``bearing_names``): their reactions are the tower's
and the mounts' forces on what they carry (``bearing_force``), and the series
``bearing_support_displacement`` (a ``derive`` function of ``dynamics/series.py``: (block,
gearbox) → (samples, bearings, 3)) is each prismatic slide's translation q a in world [m]: the
bedplate's displacement is the sum over the ``support_tower_*`` slides, the housing's on the
bedplate the sum over the ``support_mount_*`` ones; the roll is the ``angle`` of
``support_mount_roll`` [rad]. All are 0 for a rigid support (the default).

A torque applied to a shaft that turns in the housing (``simulate(torques=...)``, the rotor's)
acts on it from the ground, not from the housing, when the housing can roll: the torque arms
then carry the difference of the input and output torques, as on a turbine whose rotor is
driven by the air. In joint coordinates that torque T is also a generalised force T (a · a_roll)
on the roll hinge (``roll_share``), a the shaft's axis; torques on other joints (a planet's)
still react on their parent body, and the generators, rotors and speed drivers of the compiled
step on the housing (a generator flanged to it).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

from pinwind.dynamics import _native


def support_spring_specs(gearbox: Any) -> list[_native.BearingSpringSpec]:
    """The compiled linear springs of the support's slides (one spec per slide)."""
    out = []
    for name, slide in gearbox.support_slides.items():
        spec = _native.BearingSpringSpec()
        spec.index_axial, spec.axial_stiffness = gearbox.v_index(name), float(slide.stiffness)
        out.append(spec)
    return out


def displacement(block: Any, gearbox: Any) -> np.ndarray:
    """Each support slide's translation q a [m], (samples, bearings, 3), world (module docstring).

    0 for the roll hinge (its coordinate is its ``angle`` [rad]) and every other bearing.
    """
    out = np.zeros((len(block.time), len(block.bearing_names), 3))
    for name, slide in gearbox.support_slides.items():
        if slide.kind == "prismatic" and name in block.bearing_names:
            axis = gearbox.world_from_housing @ slide.axis
            column = block.angle[:, block.joint_names.index(name)]
            out[:, block.bearing_names.index(name)] = np.outer(column, axis)
    return out


def roll_share(gearbox: Any) -> np.ndarray | None:
    """Share f (nv,): a joint torque τ applied acts on the roll hinge as f @ τ (module docstring).

    f_j = a_j · a_roll for the joints on the housing (a_j their axes, world, at rest), 0 for the
    others; None without a roll hinge.
    """
    if "support_mount_roll" not in gearbox.support_slides:
        return None
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, gearbox.neutral())
    roll = model.getJointId("support_mount_roll")
    roll_axis = data.oMi[roll].rotation @ gearbox.joint_axis("support_mount_roll")
    housing = model.getJointId(list(gearbox.support_slides)[-1])
    out = np.zeros(model.nv)
    for name in gearbox.joint_names:
        jid = model.getJointId(name)
        if model.parents[jid] == housing and name not in gearbox.support_slides:
            axis = data.oMi[jid].rotation @ gearbox.joint_axis(name)
            out[gearbox.v_index(name)] = float(axis @ roll_axis)
    return out


def from_ground(gearbox: Any, share: np.ndarray | None, torque: np.ndarray) -> np.ndarray:
    """Applied joint torques (samples, nv) with their part on the roll hinge added [N·m].

    ``share`` is ``roll_share(gearbox)``.
    """
    if share is None:
        return torque
    out = np.array(torque, dtype=float)
    out[:, gearbox.v_index("support_mount_roll")] += out @ share
    return out
