"""The loads a bearing engineer reads, from a bearing's reaction in its joint frame.

The reaction on the child body at the bearing centre (``bearing_force_local``,
``bearing_moment_local``: joint frame) split about the bearing axis k (unit, joint frame):

- radial force F_r = |F − (F·k) k| ≥ 0 [N] and axial force F_a = F·k [N] (signed along k);
- tilting moment M_t = |M − (M·k) k| ≥ 0 [N·m], which the bearing carries;
- transmitted torque M·k [N·m], the moment along the axis: the torque of the shaft (its
  drive, lock or load), not a load on the bearing, which is why |M| alone misleads.

These are the ``derive`` functions of the series ``bearing_radial``, ``bearing_axial``,
``bearing_tilting`` and ``bearing_torque`` (``dynamics/series.py``): (block, gearbox) → array
(samples, bearings); ``row_radial`` and ``row_axial`` split a bearing row's force (F_u, F_w, F_k),
already in its bearing's joint frame with the axis last, the same way. The block is a
``Result``, the gearbox a ``Gearbox`` (not imported: the series schema imports nothing of pinwind
that could import it back).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pinwind.dynamics import _native


def axes_in_joint(block: Any, gearbox: Any) -> np.ndarray:
    """Unit axis k of every bearing of ``block`` in its joint frame, (bearings, 3) [-]."""
    return np.array([gearbox.joint_axis(name) for name in block.bearing_names]).reshape(-1, 3)


def _split(vectors: np.ndarray, axes: np.ndarray, along: bool) -> np.ndarray:
    """v·k (``along``) or |v − (v·k) k| of vectors (samples, bearings, 3) about unit axes.

    ``axes`` (bearings, 3); returns (samples, bearings). Compiled (``_native.split_about_axes``,
    one pass over the block): numpy's dozen passes with their temporaries cost as much as a
    twentieth of the rigid step. Its operations are the element-wise formula's in numpy's order:
    zeros' signs, NaN for a non-finite component, every bit the same.
    """
    v = np.asarray(vectors, dtype=float)
    out = np.empty(v.shape[:2])
    k = np.ascontiguousarray(axes, dtype=float)
    _native.split_about_axes(v, k, out if along else None, None if along else out)
    return out


def along_axis(vectors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """v·k of vectors (samples, bearings, 3) and unit axes (bearings, 3)."""
    return _split(vectors, axes, along=True)


def across_axis(vectors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """|v − (v·k) k| ≥ 0 of vectors (samples, bearings, 3) and unit axes (bearings, 3)."""
    return _split(vectors, axes, along=False)


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


def row_radial_force(block: Any, gearbox: Any) -> np.ndarray:
    """A bearing row's radial force |(F_u, F_w)| ≥ 0 [N] on the shaft, (samples, rows)."""
    return np.hypot(block.row_force[..., 0], block.row_force[..., 1])


def row_axial_force(block: Any, gearbox: Any) -> np.ndarray:
    """A bearing row's axial force F_k [N] on the shaft, signed along the axis, (samples, rows)."""
    return block.row_force[..., 2].copy()


def row_load_zone(block: Any, gearbox: Any) -> np.ndarray:
    """A bearing row's load-zone angle 2ψ_l [rad], (samples, rows); NaN without a geometry.

    From its internal load distribution (``dynamics/row_contact.row_contacts``, imported when
    called: it reads the model's bearing data, which the schema need not load).
    """
    from pinwind.dynamics.row_contact import row_contacts

    return row_contacts(block, gearbox)[0]


def row_max_element_load(block: Any, gearbox: Any) -> np.ndarray:
    """A bearing row's largest rolling-element load Q_max [N], (samples, rows); NaN likewise."""
    from pinwind.dynamics.row_contact import row_contacts

    return row_contacts(block, gearbox)[1]
