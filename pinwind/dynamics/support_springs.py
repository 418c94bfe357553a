"""The support structure in a run: its springs and the housing's and bedplate's displacements.

The support's slides (``model/support.py``: the tower modes' slides under the bedplate, the
mounts' slides and roll hinge under the housing) are each held by a linear spring F = −k q, the
linear term of the compiled bearing springs (``cpp/bearing_spring.hpp``, an axial slide's law);
their dampers are the slides' own viscous damping. ``element_specs.support_springs`` gives the
compiled specs. The slides are joints and bearings of the run, so their series say where the support
has moved and what it carries, with no series of their own: a slide's ``angle`` is its
displacement along its axis [m] (the roll hinge's its roll [rad]), its ``bearing_force`` the
tower's or the mounts' force on what they carry. A rigid support (the default) has no slides.

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


def roll_share(gearbox: Any) -> np.ndarray | None:
    """Share f (nv,): a joint torque τ applied acts on the roll hinge as f @ τ (module docstring).

    f_j = a_j · a_roll for the joints on the housing, directly or through a compliant bearing's
    slides (a_j their axes, world, at rest), 0 for the others; None without a roll hinge.
    """
    if "support_mount_roll" not in gearbox.support_slides:
        return None
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, gearbox.neutral())
    roll = model.getJointId("support_mount_roll")
    roll_axis = data.oMi[roll].rotation @ gearbox.joint_axis("support_mount_roll")
    housing = model.getJointId(list(gearbox.support_slides)[-1])
    # A shaft in a compliant bearing hangs on the housing through its bearing's slides.
    slides = {model.getJointId(n) for n in gearbox.slide_joints if n not in gearbox.support_slides}
    out = np.zeros(model.nv)
    for name in gearbox.joint_names:
        jid = model.getJointId(name)
        parent = model.parents[jid]
        while parent in slides:
            parent = model.parents[parent]
        if parent == housing and name not in gearbox.slide_joints:
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
