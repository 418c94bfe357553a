"""Each bearing row's load zone and largest rolling-element load over a run (ISO/TS 16281).

A row's internal geometry comes from the model (`geometry_of`: its ``<row>``'s rollers and
roller size, else estimated from its ``size_mm``; ``model/bearing_life_data.py``), its load W =
(F_u, F_w, F_a, M_u, M_w) on the bearing is the opposite of the row's force and tilt moment on
the shaft (the series ``row_force``, ``row_moment``: its bearing's axes u, w, k), and the
rolling elements' loads that balance it are ``dynamics/load_distribution.py``'s. `row_contacts`
gives each sample's load-zone angle 2ψ_l and largest element load Q_max, the derived series
``row_load_zone`` and ``row_max_element_load`` (``dynamics/series.py``, through
``bearing_load``); the lives over a run use the same geometry and cells
(``life/life_sums.py``).

Like loads are solved once (`load_cells`): without clearance Q_max is homogeneous of degree 1
in W and the zone of degree 0 (the contact laws are power laws through 0), so the loads'
directions are grouped in cells 1/``LOAD_CELLS`` wide and |W| scales the result.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from pinwind.dynamics.load_distribution import (
    Distribution,
    InternalGeometry,
    distribute,
    estimate_geometry,
)
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.model.bearing_rows import row_name


def geometry_of(kind: str, data: BearingLifeData, size: tuple | None) -> InternalGeometry | None:
    """The row's internal geometry: the model's, else estimated from its size; None without."""
    size = data.size or size
    if size is None:
        return None
    est = estimate_geometry(
        kind, size, clearance=data.clearance, contact_angle=data.contact_angle,
        rotating=data.rotating,
    )  # fmt: skip
    if data.rollers is None and data.roller is None:
        return est
    dwe, length = (
        data.roller if data.roller is not None else (est.roller_diameter, est.roller_length)
    )
    return InternalGeometry(
        kind, data.rollers or est.rollers, est.rows, est.contact_angle, dwe, length,
        est.pitch_diameter, data.clearance, rotating=data.rotating,
        estimated=data.rollers is None or data.roller is None,
    )  # fmt: skip


#: Loads are solved once per cell 1/LOAD_CELLS of the run's largest load wide (`load_cells`).
LOAD_CELLS = 200


def load_cells(
    load: np.ndarray, *, homogeneous: bool = False, arm: float = 1.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Group the samples' loads in cells: (cells (k, 5), inverse (n,), size (n,)).

    ``cells`` is the mean load of each occupied cell, ``inverse`` each sample's cell and
    ``size`` each sample's load as a multiple of its cell's.

    The loads W = (F, M) are measured as (F, M/arm) [N] and grouped in cells 1/``LOAD_CELLS``
    of the largest |W| over the run wide; a cell's distribution is solved once at the mean of
    its samples' loads. P_ref is smooth in the load, so the life's error is of second order in
    the cell width; a steady load is one cell. Without clearance the element loads are
    homogeneous of degree 1 in W (q(sW) = s q(W): the contact law is a power law through 0),
    so ``homogeneous`` groups the loads' directions only (each W scaled to unit size, cells
    1/``LOAD_CELLS`` wide) and ``size`` carries the magnitude: a load that varies in size only
    is one cell.
    """
    unit = np.array([1.0, 1.0, 1.0, arm, arm])
    key, measured, size = cell_keys(load, homogeneous=homogeneous, arm=arm)
    _, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse)
    cells = np.stack(
        [np.bincount(inverse, weights=measured[:, i]) / count for i in range(5)], axis=1
    )
    return cells * unit, inverse, size


def cell_keys(
    load: np.ndarray, *, homogeneous: bool = False, arm: float = 1.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each sample's cell of `load_cells`: (key (n, 5) integers, measured (n, 5), size (n,)).

    ``measured`` is the load as (F, M/arm) [N], scaled to unit size when ``homogeneous``;
    ``size`` the sample's load as a multiple of it (1 unless ``homogeneous``). Samples of one
    key share a cell. Without ``homogeneous`` the cells are 1/``LOAD_CELLS`` of the largest
    |W| of these samples wide; with it, of the unit size, whatever the other samples: the keys
    of parts of a history are then the keys of the whole (``life/life_sums.py`` sums a run's
    parts).
    """
    unit = np.array([1.0, 1.0, 1.0, arm, arm])
    measured = load / unit
    norm = np.linalg.norm(measured, axis=1)
    size = np.ones(len(load))
    if homogeneous:
        size = norm
        measured = measured / np.where(norm > 0.0, norm, 1.0)[:, None]
        scale = 1.0
    else:
        scale = max(float(np.max(norm, initial=0.0)), 1e-300)
    return np.round(measured / scale * LOAD_CELLS).astype(np.int64), measured, size


def life_data_of(gearbox: Any, joint: str, data: BearingLifeData | None) -> BearingLifeData:
    """A bearing's life data with its rotating ring: a planet's outer ring unless the model says.

    A planet's bearing turns its outer ring (the planet's bore) against the load; the others
    their inner ring (``BearingLifeData.rotating``), unless the model gives ``rotating_ring``.
    """
    from pinwind.model.gear_roles import gearbox_planetary_gears

    data = data or BearingLifeData()
    if "rotating_ring" not in data.defaults:
        return data
    planets = {
        gearbox.gears[g].spec.link for s in gearbox_planetary_gears(gearbox) for g in s.planets
    }
    if gearbox.source.joints[joint]["child"] in planets:
        return dataclasses.replace(data, rotating="outer")
    return data


#: The last block's row contacts (`row_contacts`): its two series are derived from one solve.
_ROW_CONTACTS: dict[str, Any] = {"key": None, "value": None}
#: Per internal geometry at zero clearance: load direction cell → (2ψ_l, Q_max at unit load)
#: (`_contacts_by_cell`), kept across the blocks of a run (and runs: it depends on nothing
#: else); emptied past ``_CELL_MEMO_SIZE`` cells. About 190 bytes a cell: a turbulent run of
#: the NREL 5 MW gearbox's 24 rows meets some 560 new cells a second (a 1 000 000 cap let its
#: memory grow by 0.1 MB a simulated second for half an hour), and a cell solved again after
#: the memo is emptied is the same solve (each load is iterated on its own: ``distribute``;
#: the same to an ulp of the matrix products).
_CELL_MEMO: dict[InternalGeometry, dict[int, tuple[float, float]]] = {}
_CELL_MEMO_SIZE = 50_000


def row_contacts(block: Any, gearbox: Any) -> tuple[np.ndarray, np.ndarray]:
    """Each row's load-zone angle 2ψ_l [rad] and largest element load Q_max [N] per sample.

    (zone, q_max), each (samples, rows) in the order of ``block.row_names``: the internal load
    distribution (ISO/TS 16281 with Palmgren's and Hertz's contact laws, ``load_distribution``)
    of the load W on the row, the opposite of its force and tilt moment on the shaft
    (``row_force``, ``row_moment``: its bearing's axes u, w, k); NaN for a row without an
    internal geometry (no ``size_mm`` nor rollers and roller_mm) and where the row finds no
    equilibrium. At zero clearance under a pure radial load the zone is 180° and
    Q_max ≈ 4.08 F_r / Z for rollers (Stribeck; Harris and Kotzalas 2007 §7.3).

    A run derives it block by block (a few samples each), so the solves are kept across its
    blocks: at zero clearance Q_max is homogeneous of degree 1 in W and the zone of degree 0
    (`load_cells`), so each row's distribution is solved once per cell of load directions
    (1/``LOAD_CELLS`` wide, at the cell's centre) over the run and scaled by |W|; with a
    clearance, once per cell of each block's loads (`cell_distribution`). The derived series
    ``row_load_zone`` and ``row_max_element_load`` (``dynamics/series.py``) read it; the two of
    one block share one call.
    """
    force = np.asarray(block.row_force, dtype=float)
    moment = np.asarray(block.row_moment, dtype=float)
    key = (id(block), id(gearbox), force.shape, hash(force.tobytes()), hash(moment.tobytes()))
    if _ROW_CONTACTS["key"] == key:
        return _ROW_CONTACTS["value"]  # type: ignore[no-any-return]
    samples, count = force.shape[0], force.shape[1] if force.ndim == 3 else 0
    zone = np.full((samples, count), np.nan)
    q_max = np.full((samples, count), np.nan)
    rows = {
        row_name(b, r.name): (b, r) for b, c in gearbox.compliant_bearings.items() for r in c.rows
    }
    for i, name in enumerate(block.row_names):
        bearing, row = rows[name]
        geometry = geometry_of(row.kind, life_data_of(gearbox, bearing, row.life), row.size)
        if geometry is None or samples == 0:
            continue
        w = -np.concatenate([force[:, i, :], moment[:, i, :2]], axis=1)
        if geometry.clearance == 0.0:
            if sum(map(len, _CELL_MEMO.values())) > _CELL_MEMO_SIZE:
                _CELL_MEMO.clear()
            memo = _CELL_MEMO.setdefault(geometry, {})
            zone[:, i], q_max[:, i] = _contacts_by_cell(geometry, w, memo)
        else:
            _, dist, inverse, magnitude = cell_distribution(geometry, w)
            zone[:, i] = dist.load_zone[inverse]
            q_max[:, i] = dist.max_element_load[inverse] * magnitude
    _ROW_CONTACTS.update(key=key, value=(zone, q_max))
    return zone, q_max


def _contacts_by_cell(
    geometry: InternalGeometry,
    load: np.ndarray,
    memo: dict[int, tuple[float, float]],
) -> tuple[np.ndarray, np.ndarray]:
    """(2ψ_l, Q_max) per sample of a zero-clearance bearing, solving only cells ``memo`` lacks.

    The load is oriented and masked as `cell_distribution`'s; each sample's cell is its
    direction (F, M/R) / |(F, M/R)| rounded to 1/``LOAD_CELLS``, solved at the cell's centre.
    """
    w, carried = oriented(geometry, load)
    arm = 0.5 * geometry.pitch_diameter
    unit = np.array([1.0, 1.0, 1.0, arm, arm])
    measured = w * carried / unit
    size = np.linalg.norm(measured, axis=1)
    keys = np.round(measured / np.where(size > 0.0, size, 1.0)[:, None] * LOAD_CELLS)
    # One integer per cell (components in ±LOAD_CELLS, radix 2 LOAD_CELLS + 1): a 1-D unique.
    radix = (2 * LOAD_CELLS + 1) ** np.arange(5, dtype=np.int64)
    codes = (keys.astype(np.int64) + LOAD_CELLS) @ radix
    cells, first, inverse = np.unique(codes, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    as_codes = cells.tolist()
    new = [k for k, code in enumerate(as_codes) if code not in memo]
    if new:
        directions = keys[first[new]]
        norm = np.linalg.norm(directions, axis=1)
        directions = directions / np.where(norm > 0.0, norm, 1.0)[:, None] * unit
        dist = distribute(geometry, directions)
        for j, k in enumerate(new):
            memo[as_codes[k]] = (float(dist.load_zone[j]), float(dist.max_element_load[j]))
    values = np.array([memo[code] for code in as_codes]).reshape(-1, 2)
    zone = np.where(size > 0.0, values[inverse, 0], 0.0)
    return zone, values[inverse, 1] * size


def oriented(geometry: InternalGeometry, load: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(W, carried): the load W (n, 5) oriented, and the mask of what the type carries.

    A single angular row faces the way its mean axial load pushes it; ``carried`` is 1 on the
    components the type carries (``InternalGeometry.carries_tilt``, ``axially_free``).
    """
    w = np.array(load, dtype=float).reshape(-1, 5)
    if geometry.contact_angle > 0.0 and geometry.rows == 1:
        w[:, 2] *= -1.0 if float(np.mean(w[:, 2])) < 0.0 else 1.0
    carried = np.array(
        [1.0, 1.0, 0.0 if geometry.axially_free else 1.0]
        + [1.0 if geometry.carries_tilt else 0.0] * 2
    )
    return w, carried


def cell_distribution(
    geometry: InternalGeometry, load: np.ndarray
) -> tuple[np.ndarray, Distribution, np.ndarray, np.ndarray]:
    """The distribution of loads W (n, 5) on a bearing, solved once per cell of like loads.

    (W oriented, the cells' distribution, each sample's cell (n,), each sample's size as a
    multiple of its cell's (n,)): a sample's element loads are its cell's times its size
    (`load_cells`; by direction alone without clearance). Only what the type carries is
    distributed (`oriented`).
    """
    w, carried = oriented(geometry, load)
    cells, inverse, magnitude = load_cells(
        w * carried, homogeneous=geometry.clearance == 0.0, arm=0.5 * geometry.pitch_diameter
    )
    return w, distribute(geometry, cells), inverse, magnitude
