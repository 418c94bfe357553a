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
  (``dynamics/load_distribution.py``), with the load-zone angle and the largest element load.

A whole ``<bearing>`` without rows is rated by ``life/bearing_life.py``; one that carries a
tilting moment larger than ``bearing_life.TILT_ARM`` × its radial force is refused there with
the reason (``bearing_life.tilt_refusal``): its moment would load the shaft's bearings in a way
one bearing at the joint cannot say.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.life.bearing_life import life_hours, life_of_load_sum, row_rating
from pinwind.life.life_sums import history_sums, life_data_of, preloaded_rolling_load
from pinwind.life.modified_life import reliability_factor
from pinwind.model.bearing import BearingRating
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.model.bearing_rows import row_name


@dataclass(frozen=True)
class RowLife:
    """One rolling bearing's lives over a run (NaN where not computed; ``notes`` say why).

    Attributes:
        name, bearing, kind: the row, its joint, its type.
        position: axial position from the joint [m].
        rating: C [N] (None: not rated); exponent: p.
        revolutions: [rev]; duration: [s].
        equivalent_load: ISO 281 P_eq [N]; l10 [10⁶ rev]; l10h [h].
        reliability_percent: R [%]; a1: a₁ [-].
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
    reliability_percent: float
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
            "reliability_percent": self.reliability_percent,
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


def rate_row(
    *,
    name: str,
    bearing: str,
    position: float,
    rating: BearingRating,
    size: tuple[float, float, float] | None,
    data: BearingLifeData | None,
    time: np.ndarray,
    speed: np.ndarray,
    load: np.ndarray,
    reliability_percent: float = 90.0,
    rolling: np.ndarray | None = None,
) -> RowLife:
    """One row's lives from its load on the bearing and its speed (module docstring).

    ``rating`` is the row's ISO 281 data (`bearing_life.row_rating`); ``load`` is W (n, 5) =
    (F_u, F_w, F_a, M_u, M_w) [N, N·m] on the bearing in its joint frame, ``speed`` the
    joint's [rad/s], both at ``time`` [s]. The lives come from the sums of
    ``life_sums.history_sums`` as a fatigue set's do (``bearing_life.life_of_load_sum``), L_nm
    times a₁. ``rolling`` (n,) [N], when given, is the radial load its loaded rolling elements
    carry, a preload included (``life_sums.preloaded_rolling_load``), which the skidding check
    takes for the radial load.

    Raises:
        InputError: ``reliability_percent`` outside 90 … 99.95 %.
    """
    a1 = reliability_factor(reliability_percent)
    history = history_sums(
        row_name(bearing, name), rating, data=data, size=size, time=time, speed=speed, load=load,
        rolling=rolling,
    )  # fmt: skip
    notes = list(history.notes)
    sums = history.sums
    life = life_of_load_sum(rating, sums)
    nan = math.nan
    lnm = a1 * life.lnm
    a_iso = life.lnm / life.l10 if life.l10 > 0 and math.isfinite(life.l10) else nan
    dist = history.distribution
    q_max = zone_min = nan
    element_load = load_zone = np.full(len(time), nan)
    not_carried = (0.0, 0.0)
    if dist is not None:
        element_load, load_zone, not_carried = (
            dist.max_element_load,
            dist.load_zone,
            dist.not_carried,
        )
        if not dist.failed:
            q_max = float(np.max(element_load, initial=0.0))
            zone_min = float(np.min(load_zone, initial=2.0 * math.pi))
    if not rating.rated:
        notes.append("not rated: no rating_c_kN")
    revolutions, seconds = sums.revolutions, sums.seconds
    return RowLife(
        name, bearing, rating.kind or "", position, rating.dynamic_load_rating, rating.exponent,
        revolutions, seconds, life.equivalent_load, life.l10, life.l10h, reliability_percent, a1,
        history.kappa_mean, a_iso, history.contamination, history.fatigue_limit, lnm,
        life_hours(lnm, revolutions, seconds), life.reference_load, life.l10r, life.l10rh,
        q_max, zone_min, element_load, load_zone, not_carried, tuple(notes),
        sums.below_minimum_share,
    )  # fmt: skip


#: The log channels the lives read: joint angles and speeds (the revolutions), the bearings'
#: local force and moment (a whole bearing's life and tilt refusal) and the rows' loads.
LIFE_CHANNELS = (
    "/joints", "/bearings/force_local", "/bearings/moment_local", "/rows/force", "/rows/moment",
)  # fmt: skip


def row_lives(result: Any, gearbox: Any, *, reliability_percent: float = 90.0) -> list[RowLife]:
    """The lives of every row of the run's shafts, bearing by bearing in the model's order.

    ``reliability_percent`` is R [%] of L_nm, 90 … 99.95 (ISO 281's a₁).

    A planet's rows turn their outer ring against the load unless the model says otherwise
    (``rotating_ring``). Row loads come from
    ``pinwind.analysis.bearing_rows.row_loads(result, gearbox)`` (its
    RowLoad's name, bearing, position, radial (n, 2), axial (n,), tilting (n, 2), forces on the
    shaft in the bearing's joint frame); the load on the bearing is their opposite.
    """
    from pinwind.analysis.bearing_rows import row_loads

    rows = {(b, r.name): r for b, rs in gearbox.source.bearing_rows.items() for r in rs}
    out = []
    for load in row_loads(result, gearbox):
        row = rows[(load.bearing, load.name)]
        w = -np.column_stack([load.radial, load.axial, load.tilting])
        speed = result.speed[:, result.joint_names.index(load.bearing)]
        out.append(
            rate_row(
                name=load.name, bearing=load.bearing, position=load.position,
                rating=row_rating(load.bearing, row), size=row.size,
                data=life_data_of(gearbox, load.bearing, row.life), time=result.time,
                speed=speed, load=w, reliability_percent=reliability_percent,
                rolling=preloaded_rolling_load(gearbox, load.bearing, row, load.radial),
            )
        )  # fmt: skip
    return out
