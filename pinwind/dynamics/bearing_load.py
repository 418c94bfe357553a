"""The loads a bearing engineer reads, from a bearing's reaction in its joint frame.

The reaction on the child body at the bearing centre (``bearing_force_local``,
``bearing_moment_local``: joint frame) split about the bearing axis k (unit, joint frame):

- radial force F_r = |F − (F·k) k| ≥ 0 [N] and axial force F_a = F·k [N] (signed along k);
- tilting moment M_t = |M − (M·k) k| ≥ 0 [N·m], which the bearing carries;
- transmitted torque M·k [N·m], the moment along the axis: the torque of the shaft (its
  drive, lock or load), not a load on the bearing, which is why |M| alone misleads.

These are the ``derive`` functions of the series ``bearing_radial``, ``bearing_axial``,
``bearing_tilting`` and ``bearing_torque`` (``dynamics/series.py``): (block, gearbox) → array
(samples, bearings). The block is a ``Result``, the gearbox a ``Gearbox`` (not imported: the
series schema imports nothing of pinwind that could import it back).
"""

from __future__ import annotations

from typing import Any

import numpy as np


def axes_in_joint(block: Any, gearbox: Any) -> np.ndarray:
    """Unit axis k of every bearing of ``block`` in its joint frame, (bearings, 3) [-]."""
    return np.array([gearbox.joint_axis(name) for name in block.bearing_names]).reshape(-1, 3)


def along_axis(vectors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """v·k of vectors (samples, bearings, 3) and unit axes (bearings, 3)."""
    return np.einsum("sbi,bi->sb", vectors, axes)


def across_axis(vectors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """|v − (v·k) k| of vectors (samples, bearings, 3) and unit axes (bearings, 3)."""
    normal = vectors - along_axis(vectors, axes)[..., None] * axes
    # The sum of squares by einsum: np.linalg.norm over a last axis of 3 takes twice as long.
    return np.sqrt(np.einsum("sbi,sbi->sb", normal, normal))


def radial_force(block: Any, gearbox: Any) -> np.ndarray:
    """Radial force F_r ≥ 0 [N]: the reaction force normal to the bearing axis."""
    return across_axis(block.bearing_force_local, axes_in_joint(block, gearbox))


def axial_force(block: Any, gearbox: Any) -> np.ndarray:
    """Axial force F·k [N]: the reaction force along the bearing axis, signed along k."""
    return along_axis(block.bearing_force_local, axes_in_joint(block, gearbox))


def tilting_moment(block: Any, gearbox: Any) -> np.ndarray:
    """Tilting moment ≥ 0 [N·m]: the reaction moment normal to the bearing axis."""
    return across_axis(block.bearing_moment_local, axes_in_joint(block, gearbox))


def transmitted_torque(block: Any, gearbox: Any) -> np.ndarray:
    """Transmitted torque M·k [N·m]: the reaction moment along the bearing axis, signed along k."""
    return along_axis(block.bearing_moment_local, axes_in_joint(block, gearbox))
