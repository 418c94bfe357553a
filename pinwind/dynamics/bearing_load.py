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


def axes_in_joint(block: Any, gearbox: Any) -> np.ndarray:
    """Unit axis k of every bearing of ``block`` in its joint frame, (bearings, 3) [-]."""
    return np.array([gearbox.joint_axis(name) for name in block.bearing_names]).reshape(-1, 3)


def _flat(vectors: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vectors (samples, bearings, 3) and their bearings' axes, both as (samples·bearings, 3).

    Numpy's loops then run over every sample and bearing at once: broadcasting the axes over
    the samples would run them 16 bearings at a time, and einsum's general path, 2-5x slower
    on a block (derived on every run).
    """
    return vectors.reshape(-1, 3), np.tile(axes, (vectors.shape[0], 1))


def _along(flat: np.ndarray, k: np.ndarray) -> np.ndarray:
    """v·k of (n, 3) vectors and axes, component by component (exact for an axis ±e_i)."""
    out = flat[:, 0] * k[:, 0]
    term = np.empty_like(out)
    for i in (1, 2):
        np.multiply(flat[:, i], k[:, i], out=term)
        out += term
    return out


def along_axis(vectors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """v·k of vectors (samples, bearings, 3) and unit axes (bearings, 3)."""
    return _along(*_flat(vectors, axes)).reshape(vectors.shape[:-1])


def _common_plane(axes: np.ndarray) -> tuple[int, int] | None:
    """The components (a, b), a < b, other than j when every axis is exactly ±e_j; else None."""
    zero = axes == 0.0
    for j in range(3):
        if np.all(np.abs(axes[:, j]) == 1.0) and zero[:, [i for i in range(3) if i != j]].all():
            a, b = (i for i in range(3) if i != j)
            return a, b
    return None


def across_axis(vectors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """|v − (v·k) k| of vectors (samples, bearings, 3) and unit axes (bearings, 3).

    When every axis is ±e_j (the shipped models' bearings turn about their joint frame's z)
    and every component is finite, sqrt(v_a² + v_b²) over the two other components: the same
    bits as the general sum, since there v·k = ±v_j exactly, the components a, b are left
    unchanged (v_a − (±0)) and j's is exactly 0, added last. Four passes over the block
    instead of seventeen.
    """
    plane = _common_plane(np.asarray(axes)) if len(axes) else None
    if plane is not None and np.isfinite(np.sum(vectors)):  # a non-finite sum: one is not
        a, b = plane
        square = np.multiply(vectors[..., a], vectors[..., a])
        term = np.multiply(vectors[..., b], vectors[..., b])
        square += term
        return np.sqrt(square, out=square)
    flat, k = _flat(vectors, axes)
    along = _along(flat, k)
    square = np.zeros_like(along)
    normal = np.empty_like(along)
    for i in range(3):
        np.multiply(along, k[:, i], out=normal)
        np.subtract(flat[:, i], normal, out=normal)
        normal *= normal
        square += normal
    return np.sqrt(square, out=square).reshape(vectors.shape[:-1])


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
