"""Every rolling bearing's lives from a run, row by row: ISO 281 basic and modified, ISO/TS 16281.

A shaft's rows (``<row>`` in its ``<bearing>``; ``model/bearing_rows.py``) carry its load at
their positions, the tilting moment of the shaft included (``analysis/bearing_rows.row_loads``).
Each row is rated on its own load history (its force on the shaft, reversed: the load on the
bearing), turning at its joint's speed relative to the parent:

- **basic** L10 = (C/P_eq)^p from the dynamic equivalent loads P = X F_r + Y F_a of its own
  load factors (``life/bearing_life.py``);
- **modified** L_nm = a₁ a_ISO L10 with a_ISO per sample from the viscosity ratio κ at that
  sample's speed and e_C C_u / P (``life/modified_life.py``, ``life/lubrication.py``), summed over
  the revolutions as ISO 281:2007 §9.3.4 does; not computed when C_u is neither given nor
  estimable (no C₀);
- **reference** L_10r = (C/P_ref,eq)^p from the internal load distribution of each sample
  (``life/load_distribution.py``), with the load-zone angle and the largest element load.

A whole ``<bearing>`` without rows is rated by ``life/bearing_life.py``; one that carries a
tilting moment larger than ``bearing_life.TILT_ARM`` × its radial force is refused there with
the reason (``bearing_life.tilt_refusal``): its moment would load the shaft's bearings in a way
one bearing at the joint cannot say.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.life.bearing_life import (
    dynamic_equivalent_load,
    load_power_sum,
    mean_load,
    sample_weights,
)
from pinwind.life.load_distribution import (
    Distribution,
    InternalGeometry,
    distribute,
    estimate_geometry,
    reference_load,
)
from pinwind.life.lubrication import Lubricant, contamination_factor
from pinwind.life.modified_life import (
    KAPPA_MAX,
    KAPPA_MIN,
    estimated_fatigue_limit,
    modified_life_sum,
    rated_viscosity,
    reliability_factor,
)
from pinwind.life.skidding import seconds_below_minimum
from pinwind.model.bearing import bearing_rating
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.model.bearing_rows import rolling_load


@dataclass(frozen=True)
class RowLife:
    """One rolling bearing's lives over a run (NaN where not computed; ``notes`` say why).

    Attributes:
        name, bearing, kind: the row, its joint, its type.
        position: axial position from the joint [m].
        rating: C [N] (None: not rated); exponent: p.
        revolutions: [rev]; duration: [s].
        equivalent_load: ISO 281 P_eq [N]; l10 [10⁶ rev]; l10h [h].
        reliability: R [%]; a1: a₁ [-].
        kappa_mean: revolution-weighted mean κ [-]; a_iso: the life's a_ISO, L_nm / (a₁ L10).
        contamination: e_C [-]; fatigue_limit: C_u [N] (NaN: none).
        lnm: modified life [10⁶ rev]; lnmh: [h].
        reference_load: P_ref,eq [N]; l10r [10⁶ rev]; l10rh [h].
        max_element_load: Q_max over the run [N]; load_zone_min: smallest load zone [rad].
        element_load: Q_max per sample [N], (n,); load_zone: 2ψ_l per sample [rad], (n,).
        not_carried: largest axial force [N] and tilting moment [N·m] the row's type does not
            carry (reported, not rated).
        notes: defaults and estimates used, and why a life is missing.
        below_minimum: the share of the time it turned below its minimum load [-] (skidding
            risk, ``life/skidding.py``); NaN when not rated.
    """

    name: str
    bearing: str
    kind: str
    position: float
    rating: float | None
    exponent: float
    revolutions: float
    duration: float
    equivalent_load: float
    l10: float
    l10h: float
    reliability: float
    a1: float
    kappa_mean: float
    a_iso: float
    contamination: float
    fatigue_limit: float
    lnm: float
    lnmh: float
    reference_load: float
    l10r: float
    l10rh: float
    max_element_load: float
    load_zone_min: float
    element_load: np.ndarray = field(repr=False)
    load_zone: np.ndarray = field(repr=False)
    not_carried: tuple[float, float] = (0.0, 0.0)
    notes: tuple[str, ...] = ()
    below_minimum: float = math.nan

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON (SI; lives in 10⁶ rev and h; None for NaN)."""

        def num(x: float | None) -> float | None:
            return None if x is None or (isinstance(x, float) and math.isnan(x)) else x

        return {
            "row": self.name,
            "bearing": self.bearing,
            "type": self.kind,
            "position_m": self.position,
            "dynamic_load_rating_N": self.rating,
            "revolutions": self.revolutions,
            "equivalent_load_N": num(self.equivalent_load),
            "l10_million_rev": num(self.l10),
            "l10_h": num(self.l10h),
            "reliability_percent": self.reliability,
            "a1": self.a1,
            "kappa_mean": num(self.kappa_mean),
            "a_iso": num(self.a_iso),
            "contamination_eC": num(self.contamination),
            "fatigue_limit_N": num(self.fatigue_limit),
            "lnm_million_rev": num(self.lnm),
            "lnm_h": num(self.lnmh),
            "reference_load_N": num(self.reference_load),
            "l10r_million_rev": num(self.l10r),
            "l10r_h": num(self.l10rh),
            "share_below_minimum_load": num(self.below_minimum),
            "max_element_load_N": num(self.max_element_load),
            "load_zone_min_deg": num(math.degrees(self.load_zone_min)),
            "axial_not_carried_N": self.not_carried[0],
            "tilting_not_carried_Nm": self.not_carried[1],
            "notes": list(self.notes),
        }


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
    measured = load / unit
    norm = np.linalg.norm(measured, axis=1)
    size = np.ones(len(load))
    if homogeneous:
        size = norm
        measured = measured / np.where(norm > 0.0, norm, 1.0)[:, None]
        scale = 1.0
    else:
        scale = max(float(np.max(norm, initial=0.0)), 1e-300)
    key = np.round(measured / scale * LOAD_CELLS).astype(np.int64)
    _, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse)
    cells = np.stack(
        [np.bincount(inverse, weights=measured[:, i]) / count for i in range(5)], axis=1
    )
    return cells * unit, inverse, size


def _hours(life_mrev: float, revolutions: float, seconds: float) -> float:
    per_hour = revolutions / seconds * 3600.0 if seconds > 0 else 0.0
    if math.isnan(life_mrev):
        return math.nan
    return life_mrev * 1e6 / per_hour if per_hour > 0.0 else math.inf


def rate_row(
    *,
    name: str,
    bearing: str,
    kind: str,
    position: float,
    rating: float | None,
    load_factors: tuple[float, float, float, float] | None,
    size: tuple[float, float, float] | None,
    data: BearingLifeData | None,
    time: np.ndarray,
    speed: np.ndarray,
    load: np.ndarray,
    reliability: float = 90.0,
    rolling: np.ndarray | None = None,
) -> RowLife:
    """One row's lives from its load on the bearing and its speed (module docstring).

    ``load`` is W (n, 5) = (F_u, F_w, F_a, M_u, M_w) [N, N·m] on the bearing in its joint frame,
    ``speed`` the joint's [rad/s], both at ``time`` [s]. ``rolling`` (n,) [N], when given, is
    the radial load its loaded rolling elements carry, a preload included
    (``model/bearing_rows.rolling_load``), which the skidding check takes for the radial load;
    None: the net radial load.

    Raises:
        ValueError: reliability outside 90 … 99.95 %.
    """
    data = data or BearingLifeData()
    a1 = reliability_factor(reliability)
    notes: list[str] = []
    oil_defaults = [d for d in data.defaults if d != "rotating_ring"]
    if oil_defaults:
        notes.append("default " + ", ".join(oil_defaults) + " (VG 320, 70 °C, normal cleanliness)")
    e, y1, x2, y2 = load_factors if load_factors else (None, None, None, None)
    iso = bearing_rating(
        f"{bearing}/{name}", kind, dynamic_load_rating=rating, e=e, y1=y1, x2=x2, y2=y2
    )
    p = iso.exponent
    weights = sample_weights(time)
    turns = weights * np.abs(speed) / (2.0 * math.pi)
    revolutions, seconds = float(turns.sum()), float(weights.sum())
    radial = np.hypot(load[:, 0], load[:, 1])
    axial = np.abs(load[:, 2])
    equivalent = dynamic_equivalent_load(iso, radial, axial)
    weight_of = turns if revolutions > 0 else weights
    p_eq = mean_load(load_power_sum(equivalent, weight_of, p), float(weight_of.sum()), p)
    nan = math.nan
    l10 = (rating / p_eq) ** p if rating and p_eq > 0 else (math.inf if rating else nan)
    # Modified life.
    geometry = geometry_of(kind, data, size)
    size_used = data.size or size
    dm = 0.5 * (size_used[0] + size_used[1]) if size_used else (
        geometry.pitch_diameter if geometry else None
    )  # fmt: skip
    kappa_mean = a_iso = e_c = c_u = lnm = nan
    if dm is None:
        notes.append("no modified life: no size_mm (the mean diameter d_m sets ν₁)")
    else:
        e_c = data.contamination if data.contamination is not None else contamination_factor(
            data.contamination_class, dm
        )  # fmt: skip
        if data.fatigue_limit is not None:
            c_u = data.fatigue_limit
        elif data.static_rating is not None:
            c_u = estimated_fatigue_limit(data.static_rating, dm, ball=kind.endswith("_ball"))
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
            low = np.any(moving & (kappa < KAPPA_MIN))
            high = np.any(moving & (kappa > KAPPA_MAX))
            if low:
                notes.append("κ < 0.1 at some samples: ISO 281 does not cover it; κ = 0.1 used")
            if high:
                notes.append("κ > 4 at some samples: κ = 4 used (ISO 281)")
        if rating and not math.isnan(c_u) and revolutions > 0:
            used, total = modified_life_sum(
                equivalent, turns, np.where(moving, kappa, 1.0), exponent=p,
                contamination=e_c, fatigue_limit=c_u, ball=kind.endswith("_ball"),
            )  # fmt: skip
            lnm = a1 * total / used * rating**p if used > 0 else math.inf  # [10⁶ rev]
            a_iso = lnm / (a1 * l10) if l10 > 0 and math.isfinite(l10) else nan
    # Reference life.
    p_ref = l10r = q_max = zone_min = nan
    element_load = load_zone = np.full(len(time), nan)
    not_carried = (0.0, 0.0)
    if geometry is None:
        notes.append("no reference life: no size_mm or internal geometry")
    else:
        if geometry.estimated:
            notes.append("internal geometry estimated from size_mm")
        w = np.array(load, dtype=float)
        if geometry.contact_angle > 0.0 and geometry.rows == 1:
            # A single angular row faces the way its mean axial load pushes it.
            w[:, 2] *= -1.0 if float(np.mean(w[:, 2])) < 0.0 else 1.0
        # Only what the type carries is distributed (and grouped).
        carried = np.array(
            [1.0, 1.0, 0.0 if geometry.axially_free else 1.0]
            + [1.0 if geometry.carries_tilt else 0.0] * 2
        )
        cells, inverse, magnitude = load_cells(
            w * carried, homogeneous=geometry.clearance == 0.0, arm=0.5 * geometry.pitch_diameter
        )
        dist: Distribution = distribute(geometry, cells)
        not_carried = (
            float(np.max(np.abs(w[:, 2]), initial=0.0)) if geometry.axially_free else 0.0,
            float(np.max(np.hypot(w[:, 3], w[:, 4]), initial=0.0))
            if not geometry.carries_tilt
            else 0.0,
        )
        element_load = dist.max_element_load[inverse] * magnitude
        load_zone = dist.load_zone[inverse]
        failed = int(np.sum(~dist.converged[inverse]))
        if failed:
            below = 0
            if geometry.contact_angle > 0.0 and geometry.rows == 1:
                thrust = np.hypot(w[:, 0], w[:, 1]) * math.tan(geometry.contact_angle)
                below = int(np.sum(w[:, 2] < thrust))
            notes.append(
                f"no reference life: no equilibrium at {failed} of {len(time)} samples"
                + (
                    f" ({below} with the axial load below the single angular row's induced "
                    "thrust F_r tan α: rate it with its paired row)"
                    if below
                    else " (a moment beyond what the rollers' length holds)"
                )
            )
        else:
            p_sample = reference_load(geometry, dist.slice_loads)[inverse] * magnitude
            p_ref = mean_load(load_power_sum(p_sample, weight_of, p), float(weight_of.sum()), p)
            l10r = (rating / p_ref) ** p if rating and p_ref > 0 else nan
            q_max = float(np.max(element_load))
            zone_min = float(np.min(load_zone))
    if not rating:
        notes.append("not rated: no rating_c_kN")
    rolling_equivalent = equivalent
    if rolling is not None:
        rolling_equivalent = dynamic_equivalent_load(iso, np.maximum(rolling, radial), axial)
        notes.append("skidding checked on the preloaded rolling elements' load")
    return RowLife(
        name, bearing, kind, position, rating, p, revolutions, seconds, p_eq,
        l10 if rating else nan, _hours(l10, revolutions, seconds) if rating else nan,
        reliability, a1, kappa_mean, a_iso, e_c, c_u, lnm, _hours(lnm, revolutions, seconds),
        p_ref, l10r, _hours(l10r, revolutions, seconds), q_max, zone_min, element_load,
        load_zone, not_carried, tuple(notes),
        seconds_below_minimum(iso, weights, speed, rolling_equivalent) / seconds
        if seconds
        else nan,
    )  # fmt: skip


#: The log channels the lives read: joint angles and speeds (the revolutions), the bearings'
#: local force and moment (a whole bearing's life and tilt refusal) and the rows' loads.
LIFE_CHANNELS = (
    "/joints", "/bearings/force_local", "/bearings/moment_local", "/rows/force", "/rows/moment",
)  # fmt: skip


def row_lives(result: Any, gearbox: Any, *, reliability: float = 90.0) -> list[RowLife]:
    """The lives of every row of the run's shafts, bearing by bearing in the model's order.

    A planet's rows turn their outer ring against the load unless the model says otherwise
    (``rotating_ring``). Row loads come from
    ``pinwind.analysis.bearing_rows.row_loads(result, gearbox)`` (its
    RowLoad's name, bearing, position, radial (n, 2), axial (n,), tilting (n, 2), forces on the
    shaft in the bearing's joint frame); the load on the bearing is their opposite.
    """
    from pinwind.analysis.bearing_rows import row_loads
    from pinwind.model.gear_roles import gearbox_planetary_gears

    rows = {(b, r.name): r for b, rs in gearbox.source.bearing_rows.items() for r in rs}
    planet_links = {
        gearbox.gears[g].spec.link for s in gearbox_planetary_gears(gearbox) for g in s.planets
    }
    out = []
    for load in row_loads(result, gearbox):
        row = rows[(load.bearing, load.name)]
        data = row.life
        in_planet = gearbox.source.joints[load.bearing]["child"] in planet_links
        if data is not None and in_planet and "rotating_ring" in data.defaults:
            # A planet's bearing turns its outer ring (the planet's bore) against the load.
            data = dataclasses.replace(data, rotating="outer")
        w = -np.column_stack([load.radial, load.axial, load.tilting])
        speed = result.speed[:, result.joint_names.index(load.bearing)]
        rolling = None
        in_step = load.bearing in gearbox.compliant_bearings and any(
            r.name == row.name for r in gearbox.compliant_bearings[load.bearing].rows
        )
        if in_step and row.clearance < 0.0:
            # A preloaded row's sides (cpp/bearing_rows.hpp): its rolling elements carry the
            # preload whatever the net load.
            rolling = np.hypot(
                rolling_load(load.radial[:, 0], row.stiffness[1], row.clearance),
                rolling_load(load.radial[:, 1], row.stiffness[2], row.clearance),
            )
        out.append(
            rate_row(
                name=load.name, bearing=load.bearing, kind=row.kind, position=load.position,
                rating=row.rating, load_factors=row.load_factors, size=row.size, data=data,
                time=result.time, speed=speed, load=w, reliability=reliability,
                rolling=rolling,
            )
        )  # fmt: skip
    return out
