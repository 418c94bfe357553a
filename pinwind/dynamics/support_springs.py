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
"""

from __future__ import annotations

from typing import Any

import numpy as np

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
