"""A rolling bearing's life sums from its load history: ISO 281 basic and modified, ISO/TS 16281.

`history_sums` turns the load W = (F_u, F_w, F_a, M_u, M_w) [N, N·m] on one bearing or row (its
joint frame, axis k = F_a's) and its speed over a history into the sums
``bearing_life.BearingLoadSum`` keeps, which add over histories (a fatigue set adds its cases,
each scaled to its wind bin's hours: ``life/set_bearing_life.py``). With n_i the revolutions
and Δt_i the seconds of sample i (trapezoid rule):

- **basic** Σ P_i^p n_i of ISO 281's dynamic equivalent load P = X F_r + Y F_a
  (``bearing_life.dynamic_equivalent_load``), L10 = (C/P_eq)^p;
- **modified** Σ n_i P_i^p / a_ISO,i, a_ISO at the sample's viscosity ratio κ = ν/ν₁(n, d_m) and
  e_C C_u / P (ISO 281:2007 §9.3.4: Palmgren-Miner over the load levels,
  ``modified_life.modified_life_sum``), L_nm = a₁ C^p Σ n_i / Σ (n_i P_i^p / a_ISO,i)
  (``modified_life.modified_rating_life``); none without the mean diameter d_m (``size_mm``)
  or a fatigue load limit C_u (given, or estimated from C₀ by ISO 281 Annex B);
- **reference** Σ P_ref,i^p n_i of each sample's internal load distribution (ISO/TS
  16281:2008, ``dynamics/load_distribution.py``), L10r = (C/P_ref,eq)^p; none without an internal
  geometry (``size_mm``, or rollers and roller_mm). The distribution is solved once per cell of
  like loads (``dynamics/row_contact.cell_distribution``), which also gives each sample's
  largest element load Q_max and load-zone angle 2ψ_l (`sample_distribution`).

Every sum is revolution-weighted as ISO 281's P_eq is, so sums over a site's bins give its
lives by the same rule as L10 (``set_bearing_life``); lives in hours follow at the mean speed
(``bearing_life.life_hours``). The lubricant, cleanliness, C_u and inside are the model's
``<bearing>`` or ``<row>`` attributes (``model/bearing_life_data.py``; defaults VG 320 at
70 °C, normal cleanliness, which `history_sums` notes).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.dynamics.bearing_load import along_axis
from pinwind.dynamics.load_distribution import (
    InternalGeometry,
    reference_load,
)
from pinwind.dynamics.row_contact import cell_distribution, geometry_of, life_data_of
from pinwind.life.bearing_life import (
    BearingLoadSum,
    dynamic_equivalent_load,
    load_power_sum,
    load_sum_of_history,
    radial_and_axial,
    row_rating,
    sample_weights,
)
from pinwind.life.lubrication import Lubricant, contamination_factor
from pinwind.life.modified_life import (
    KAPPA_MAX,
    KAPPA_MIN,
    estimated_fatigue_limit,
    modified_life_sum,
    rated_viscosity,
)
from pinwind.model.bearing import BearingRating
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.model.bearing_rows import rolling_load, row_name


@dataclass(frozen=True)
class SampleDistribution:
    """A bearing's internal load distribution at each sample of a history (ISO/TS 16281).

    Attributes:
        max_element_load: Q_max per sample [N], (n,); NaN where no equilibrium was found.
        load_zone: load-zone angle 2ψ_l per sample [rad], (n,); NaN likewise.
        reference_load: P_ref per sample [N], (n,); NaN likewise.
        failed: samples without equilibrium.
        below_thrust: of those, samples whose axial load is below a single angular row's
            induced thrust F_r tan α (it needs its paired row).
        not_carried: largest axial force [N] and tilting moment [N·m] the type does not carry.
    """

    max_element_load: np.ndarray
    load_zone: np.ndarray
    reference_load: np.ndarray
    failed: int
    below_thrust: int
    not_carried: tuple[float, float]


def sample_distribution(geometry: InternalGeometry, load: np.ndarray) -> SampleDistribution:
    """The distribution of the load W (n, 5) = (F_u, F_w, F_a, M_u, M_w) [N, N·m] on the bearing.

    A single angular row faces the way its mean axial load pushes it; only what the type
    carries is distributed (``InternalGeometry.carries_tilt``, ``axially_free``), once per
    cell of like loads (``dynamics/row_contact.cell_distribution``).
    """
    w, dist, inverse, magnitude = cell_distribution(geometry, load)
    not_carried = (
        float(np.max(np.abs(w[:, 2]), initial=0.0)) if geometry.axially_free else 0.0,
        float(np.max(np.hypot(w[:, 3], w[:, 4]), initial=0.0))
        if not geometry.carries_tilt
        else 0.0,
    )
    failed_at = ~dist.converged[inverse]
    below = 0
    if failed_at.any() and geometry.contact_angle > 0.0 and geometry.rows == 1:
        thrust = np.hypot(w[:, 0], w[:, 1]) * math.tan(geometry.contact_angle)
        below = int(np.sum(failed_at & (w[:, 2] < thrust)))
    p_ref = reference_load(geometry, dist.slice_loads)
    return SampleDistribution(
        dist.max_element_load[inverse] * magnitude, dist.load_zone[inverse],
        p_ref[inverse] * magnitude, int(np.sum(failed_at)), below, not_carried,
    )  # fmt: skip


@dataclass(frozen=True)
class HistorySums:
    """A bearing's life sums over a history and what its modified and reference lives used.

    Attributes:
        sums: the sums that add over histories (basic, modified and reference).
        kappa_mean: revolution-weighted mean viscosity ratio κ [-] (NaN: no modified life).
        contamination: e_C [-]; fatigue_limit: C_u [N] (NaN: none).
        distribution: each sample's internal load distribution, or None without a geometry.
        notes: defaults and estimates used, and why a life is missing.
    """

    sums: BearingLoadSum
    kappa_mean: float
    contamination: float
    fatigue_limit: float
    distribution: SampleDistribution | None = field(repr=False)
    notes: tuple[str, ...]


def history_sums(
    name: str,
    rating: BearingRating,
    *,
    data: BearingLifeData | None,
    size: tuple[float, float, float] | None,
    time: np.ndarray,
    speed: np.ndarray,
    load: np.ndarray,
    rolling: np.ndarray | None = None,
) -> HistorySums:
    """A bearing's (or row's) life sums from its load W and speed (module docstring).

    Args:
        name: the bearing or row (``BEARING.ROW``), the sums' name.
        rating: its ISO 281 data (type and load factors; C is not needed for the sums).
        data: its lubricant, cleanliness, C_u and inside (None: pinwind's defaults).
        size: (D, d, B) [m] when the element has one besides ``data`` (a ``<row>``), or None.
        time: sample times [s], (n,).
        speed: its joint's speed relative to the parent [rad/s], (n,).
        load: W (n, 5) = (F_u, F_w, F_a, M_u, M_w) on the bearing, joint frame [N, N·m].
        rolling: the radial load its loaded rolling elements carry [N], (n,), for the skidding
            check (`preloaded_rolling_load`); None: its radial load.
    """
    data = data or BearingLifeData()
    kind, p = rating.kind, rating.exponent
    ball = kind.endswith("_ball")
    notes: list[str] = []
    oil_defaults = [d for d in data.defaults if d != "rotating_ring"]
    if oil_defaults:
        notes.append("default " + ", ".join(oil_defaults) + " (VG 320, 70 °C, normal cleanliness)")
    load = np.asarray(load, dtype=float).reshape(-1, 5)
    force = np.column_stack([np.hypot(load[:, 0], load[:, 1]), np.zeros(len(load)), load[:, 2]])
    basic = load_sum_of_history(
        name, rating, time=time, force_in_joint=force, speed=speed,
        axis=np.array([0.0, 0.0, 1.0]), rolling=rolling,
    )  # fmt: skip
    if rolling is not None:
        notes.append("skidding checked on the preloaded rolling elements' load")
    equivalent = dynamic_equivalent_load(rating, force[:, 0], np.abs(force[:, 2]))
    weights = sample_weights(time)
    turns = weights * np.abs(speed) / (2.0 * math.pi)
    revolutions = float(turns.sum())
    geometry = geometry_of(kind, data, size)
    size_used = data.size or size
    dm = 0.5 * (size_used[0] + size_used[1]) if size_used else None
    nan = math.nan
    kappa_mean = e_c = c_u = modified = nan
    if dm is None:
        notes.append("no modified life: no size_mm (the mean diameter d_m sets ν₁)")
    else:
        e_c = data.contamination if data.contamination is not None else contamination_factor(
            data.contamination_class, dm
        )  # fmt: skip
        if data.fatigue_limit is not None:
            c_u = data.fatigue_limit
        elif data.static_rating is not None:
            c_u = estimated_fatigue_limit(data.static_rating, dm, ball=ball)
            notes.append("C_u estimated from C₀ (ISO 281 Annex B)")
        else:
            notes.append("no modified life: give fatigue_limit_kN (C_u) or rating_c0_kN (C₀)")
        if data.viscosity is not None:
            nu = data.viscosity
        else:
            oil = Lubricant(data.grade, data.temperature, data.viscosity_100)
            nu = oil.viscosity()
            if oil.slope_assumed:
                notes.append("ν(T) with the assumed Walther slope 3.5 (no viscosity_100C_cSt)")
        with np.errstate(invalid="ignore"):
            kappa = nu / rated_viscosity(np.abs(speed) * 60.0 / (2.0 * math.pi), dm)
        moving = turns > 0
        if revolutions > 0:
            kappa_mean = float(np.sum(np.where(moving, kappa, 0.0) * turns) / revolutions)
            if np.any(moving & (kappa < KAPPA_MIN)):
                notes.append("κ < 0.1 at some samples: ISO 281 does not cover it; κ = 0.1 used")
            if np.any(moving & (kappa > KAPPA_MAX)):
                notes.append("κ > 4 at some samples: κ = 4 used (ISO 281)")
        if not math.isnan(c_u):
            modified, _ = modified_life_sum(
                equivalent, turns, np.where(moving, kappa, 1.0), exponent=p,
                contamination=e_c, fatigue_limit=c_u, ball=ball,
            )  # fmt: skip
    reference = reference_time = nan
    dist = None
    if geometry is None:
        notes.append("no reference life: no size_mm or internal geometry")
    else:
        if geometry.estimated:
            notes.append("internal geometry estimated from size_mm")
        dist = sample_distribution(geometry, load)
        if dist.failed:
            notes.append(
                f"no reference life: no equilibrium at {dist.failed} of {len(load)} samples"
                + (
                    f" ({dist.below_thrust} with the axial load below the single angular row's "
                    "induced thrust F_r tan α: rate it with its paired row)"
                    if dist.below_thrust
                    else " (a moment beyond what the rollers' length holds)"
                )
            )
        else:
            reference = load_power_sum(dist.reference_load, turns, p)
            reference_time = load_power_sum(dist.reference_load, weights, p)
    sums = dataclasses.replace(
        basic, modified_sum=modified, reference_sum=reference, reference_time_sum=reference_time
    )
    return HistorySums(sums, kappa_mean, e_c, c_u, dist, tuple(notes))


def run_load_sums(
    result: Any, gearbox: Any, *, life: Mapping[str, BearingLifeData] | None = None
) -> list[BearingLoadSum]:
    """The life sums of every bearing of a run, then of every row, each named as rated.

    Bearings in the order of ``result.bearing_names``: W = (F_r, 0, F_a, 0, 0) of the
    bearing force (``bearing_force_local``, joint frame; its tilting moment is left to its
    rows, ``bearing_life.tilt_refusal``), sums named by the joint. Rows in the order of
    ``analysis.bearing_rows.row_loads``: W the opposite of the row's force and tilt moment on
    the shaft, named ``BEARING.ROW`` (`row_rating`). Revolutions are the joint's speed relative
    to its parent (a planet's rows turn at the planet's speed relative to the carrier). The
    lubricant and inside of each are the model's (`life_data_of`).

    Args:
        result: the run (``Result``: time, joint speeds, bearing forces and the row series).
        gearbox: the model it ran (its ``<bearing>`` and ``<row>`` elements).
        life: each bearing's and row's life data by its rated name, instead of the model's
            (`bearing_life_data`; a fatigue set's, with its ``[fatigue.bearings]``).
    """
    from pinwind.analysis.bearing_rows import row_loads

    ratings = gearbox.source.bearings
    life = bearing_life_data(gearbox) if life is None else life
    out = []
    for i, name in enumerate(result.bearing_names):
        speed = result.speed[:, result.joint_names.index(name)]
        axis = np.asarray(gearbox.joint_axis(name), dtype=float)
        force = np.asarray(result.bearing_force_local[:, i], dtype=float)
        rating = ratings.get(name)
        if rating is None:
            out.append(
                load_sum_of_history(
                    name, None, time=result.time, force_in_joint=force, speed=speed, axis=axis
                )
            )
            continue
        radial, _ = radial_and_axial(force, axis)
        k = (axis / np.linalg.norm(axis)).reshape(1, 3)
        w = np.zeros((len(force), 5))
        w[:, 0], w[:, 2] = radial, along_axis(force[:, None, :], k)[:, 0]
        data = life.get(name)
        history = history_sums(
            name, rating, data=data, size=None, time=result.time, speed=speed, load=w
        )
        out.append(history.sums)
    rows = {(b, r.name): r for b, rs in gearbox.source.bearing_rows.items() for r in rs}
    for load in row_loads(result, gearbox):
        row = rows[(load.bearing, load.name)]
        w = -np.column_stack([load.radial, load.axial, load.tilting])
        history = history_sums(
            row_name(load.bearing, load.name), row_rating(load.bearing, row),
            data=life.get(row_name(load.bearing, load.name)), size=row.size,
            time=result.time, speed=result.speed[:, result.joint_names.index(load.bearing)],
            load=w, rolling=preloaded_rolling_load(gearbox, load.bearing, row, load.radial),
        )  # fmt: skip
        out.append(history.sums)
    return out


def preloaded_rolling_load(
    gearbox: Any, bearing: str, row: Any, radial: np.ndarray
) -> np.ndarray | None:
    """The radial load a preloaded row's loaded rolling elements carry [N], (n,), or None.

    For a row in the step (its bearing's springs) with a preload (``radial_clearance_mm`` < 0):
    each radial direction's loaded side carries ``model/bearing_rows.rolling_load`` of the
    row's net load along it (``radial`` (n, 2) along u, w [N]), K_j |c| + |F_j|/2 while both
    sides press, combined as the radial load is; None for any other row (its net load is what
    its rollers carry).
    """
    bearing_in_step = gearbox.compliant_bearings.get(bearing)
    in_step = bearing_in_step is not None and any(r.name == row.name for r in bearing_in_step.rows)
    if not in_step or row.clearance >= 0.0:
        return None
    return np.hypot(
        rolling_load(radial[:, 0], row.stiffness[1], row.clearance),
        rolling_load(radial[:, 1], row.stiffness[2], row.clearance),
    )


def bearing_life_data(gearbox: Any) -> dict[str, BearingLifeData]:
    """The life data `run_load_sums` uses for each bearing and row, by its rated name.

    The model's ``<bearing>`` data (and rotating ring, `life_data_of`), and each row's with the
    row's own size when its data gives none: what its modified and reference sums depend on
    besides the loads (a fatigue set's case key, ``life/fatigue_set.py``).
    """
    given = gearbox.source.bearing_life
    out = {
        name: life_data_of(gearbox, name, given.get(name))
        for name in dict.fromkeys([*gearbox.source.bearings, *given])
    }
    for bearing, rows in gearbox.source.bearing_rows.items():
        for row in rows:
            data = life_data_of(gearbox, bearing, row.life)
            if data.size is None and row.size is not None:
                data = dataclasses.replace(data, size=row.size)
            out[row_name(bearing, row.name)] = data
    return out
