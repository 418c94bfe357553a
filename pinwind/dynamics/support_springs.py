"""The support structure in a run: its springs and the housing's and bedplate's displacements.

The support's slides (``model/support.py``: the tower modes' slides under the bedplate, the
mounts' slides and roll hinge under the housing) are each held by a linear spring F = −k q, the
linear term of the compiled bearing springs (``cpp/bearing_spring.hpp``, an axial slide's law);
their dampers are the slides' own viscous damping. ``support_spring_specs`` gives the compiled
specs; three series (``derive`` functions of ``dynamics/series.py``, (block, gearbox) → array)
say where the support has moved:

- ``support_bedplate_displacement``: the bedplate's displacement on its tower modes [m], world,
  (samples, 3);
- ``support_housing_displacement``: the housing's displacement on its mounts, relative to the
  bedplate [m], world, (samples, 3);
- ``support_housing_roll``: the housing's roll about the shaft axis on its torque arms, relative
  to the bedplate [rad], (samples,).

All three are 0 for a rigid support (the default).

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


def _translation(block: Any, gearbox: Any, prefix: str) -> np.ndarray:
    """Σ q_s axis_s over the slides whose name starts with ``prefix``, world [m]."""
    out = np.zeros((len(block.time), 3))
    for name, slide in gearbox.support_slides.items():
        if name.startswith(prefix) and slide.kind == "prismatic":
            axis = gearbox.world_from_housing @ slide.axis
            out += np.outer(block.angle[:, block.joint_names.index(name)], axis)
    return out


def bedplate_displacement(block: Any, gearbox: Any) -> np.ndarray:
    """The bedplate's displacement on its tower modes [m], (samples, 3), world."""
    return _translation(block, gearbox, "support_tower_")


def housing_displacement(block: Any, gearbox: Any) -> np.ndarray:
    """The housing's displacement on its mounts, relative to the bedplate [m], (samples, 3)."""
    return _translation(block, gearbox, "support_mount_")


def housing_roll(block: Any, gearbox: Any) -> np.ndarray:
    """The housing's roll about the shaft axis on its mounts [rad], (samples,)."""
    if "support_mount_roll" not in gearbox.support_slides:
        return np.zeros(len(block.time))
    return np.array(block.angle[:, block.joint_names.index("support_mount_roll")], dtype=float)


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
