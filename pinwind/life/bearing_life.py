"""Rolling-bearing life: ISO 281 basic rating life L10 from a bearing's reaction history.

ISO 281:2007 §7: L10 = (C / P)^p millions of revolutions, p = 3 for ball bearings and 10/3 for
roller bearings, C the basic dynamic load rating and P the dynamic equivalent radial load
(``model/bearing.py``: P = F_r + Y1 F_a up to F_a / F_r = e, X2 F_r + Y2 F_a above). A load that
varies over the run is replaced by the constant load of equal life, the revolution-weighted
p-th power mean

    P_eq = (Σ P_i^p n_i / Σ n_i)^(1/p)

(Palmgren–Miner on revolutions), n_i the revolutions at P_i. Its sums Σ P_i^p n_i and Σ n_i
(`BearingLoadSum`) add over histories: a fatigue set adds those of its cases, each scaled to
its wind bin's hours (``life/set_bearing_life.py``). From a run: F_r is the part of the
bearing force (``bearing_force_local``, joint frame) normal to the joint axis, F_a the part along
it, and the revolutions are ∫|ω| dt of the joint speed (trapezoid rule over the samples), which
pinwind gives relative to the parent body: a planet bearing turns at the planet's speed relative
to the carrier. L10h = L10 · 10⁶ / (revolutions per hour of the run).

The type and dynamic load rating of each bearing come from the model file's ``<bearing>``
elements (docs/model_format.md); a bearing without C is "not rated". A shaft's bearing made of
rows (``<row>``: the rolling bearings of a main shaft or a planet, each with its own type, C and
load factors; Nejad et al. 2016 Tables VI and IX) is rated row by row (`row_rating`, the one
rating of a row): each row's radial and axial force (``analysis/bearing_rows.py``, by its
springs at its position) with the shaft's speed relative to its housing, named ``BEARING.ROW``
(``stage1_planet1.PL-A``, `model.bearing_rows.row_name`). A run's sums with their modified and
reference parts, bearings and rows: ``life/life_sums.run_load_sums``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.dynamics.bearing_load import across_axis, along_axis
from pinwind.errors import InvalidBearingRating
from pinwind.life.modified_life import modified_rating_life
from pinwind.life.skidding import seconds_below_minimum
from pinwind.model.bearing import BearingRating, bearing_rating
from pinwind.model.bearing_rows import row_name

#: A whole bearing whose tilting moment exceeds this arm [m] times its radial force (at their
#: largest over the run) is refused a single-bearing life (`tilt_refusal`).
TILT_ARM = 0.05


def dynamic_equivalent_load(
    rating: BearingRating, radial: np.ndarray, axial: np.ndarray
) -> np.ndarray:
    """Dynamic equivalent radial load P [N] of radial and axial loads F_r, F_a [N] (≥ 0).

    ISO 281 §6: P = F_r + Y1 F_a when F_a ≤ e F_r, else X2 F_r + Y2 F_a.
    """
    radial, axial = np.asarray(radial, dtype=float), np.asarray(axial, dtype=float)
    with np.errstate(invalid="ignore"):  # e = ∞ (no axial factors) times F_r = 0
        below = (axial <= rating.e * radial) | (axial == 0.0)
    return np.where(below, radial + rating.y1 * axial, rating.x2 * radial + rating.y2 * axial)


def basic_rating_life(rating: BearingRating, load: float) -> float:
    """Basic rating life L10 = (C / P)^p at a constant equivalent load P [N], in [10⁶ rev].

    Infinite at P = 0.

    Raises:
        InvalidBearingRating: the bearing has no dynamic load rating C.
    """
    if rating.dynamic_load_rating is None:
        raise InvalidBearingRating(
            rating.joint, "has no dynamic load rating C; give rating_c_kN to rate it"
        )
    if load <= 0.0:
        return math.inf
    return (rating.dynamic_load_rating / load) ** rating.exponent


def radial_and_axial(force_in_joint: np.ndarray, axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F_r, F_a) [N]: the parts of forces (n, 3) normal to and along a joint axis (≥ 0).

    Args:
        force_in_joint: force on the bearing, joint frame [N], (n, 3).
        axis: the joint axis in the joint frame (any length).
    """
    k = (np.asarray(axis, dtype=float) / np.linalg.norm(axis)).reshape(1, 3)
    forces = np.asarray(force_in_joint, dtype=float)[:, None, :]
    return across_axis(forces, k)[:, 0], np.abs(along_axis(forces, k)[:, 0])


def load_power_sum(loads: np.ndarray, weights: np.ndarray, exponent: float) -> float:
    """Σ P_i^p w_i: the p-th power sum of loads P_i [N] weighted by w_i (revolutions or seconds).

    Sums of parts of a history (or of cases standing for hours) add; `mean_load` turns one
    back into a load. Unscaled: a MN load to the power 10/3 is 1e20, far from overflow.
    """
    loads, weights = np.asarray(loads, dtype=float), np.asarray(weights, dtype=float)
    return float(np.sum(loads**exponent * weights))


def mean_load(power_sum: float, weight: float, exponent: float) -> float:
    """The constant load of equal life, (Σ P_i^p w_i / Σ w_i)^(1/p) [N]; 0 for no weight."""
    if weight <= 0.0:
        return 0.0
    return (power_sum / weight) ** (1.0 / exponent)


def sample_weights(time: np.ndarray) -> np.ndarray:
    """Trapezoid-rule weights w_k [s]: Σ w_k f_k = ∫ f dt over the samples; Σ w_k = duration."""
    time = np.asarray(time, dtype=float)
    if len(time) < 2:
        return np.zeros(len(time))
    steps = np.diff(time)
    weights = np.zeros(len(time))
    weights[:-1] += steps / 2.0
    weights[1:] += steps / 2.0
    return weights


@dataclass(frozen=True)
class BearingLife:
    """A bearing's ISO 281 life from a run (or why it has none).

    Attributes:
        joint: the bearing.
        rating: its rating, or None when the model declares none.
        equivalent_load: P_eq [N], revolution-weighted (time-weighted if it did not turn);
            NaN without a rating.
        revolutions: revolutions in the run [rev].
        duration: the time the loads stand for [s]: a run's duration, or a site's operating
            hours over its design life (``life/set_bearing_life.py``).
        l10: basic rating life [10⁶ rev] (NaN when not rated).
        l10h: basic rating life [h] at the mean speed over ``duration`` (inf if it did not turn).
        refused: why it has no life though rated (a tilting moment one bearing cannot rate,
            `tilt_refusal`), else "".
        lnm: ISO 281 modified rating life at 90 % reliability [10⁶ rev] (NaN: its sums have
            no modified part: no C_u, no size, or reduced before it was kept).
        lnmh: the same [h] at the mean speed over ``duration``.
        reference_load: ISO/TS 16281 P_ref,eq [N] (NaN: no internal geometry).
        l10r: ISO/TS 16281 reference rating life [10⁶ rev]; l10rh: the same [h].
    """

    joint: str
    rating: BearingRating | None
    equivalent_load: float
    revolutions: float
    duration: float
    l10: float
    l10h: float
    refused: str = ""
    lnm: float = math.nan
    lnmh: float = math.nan
    reference_load: float = math.nan
    l10r: float = math.nan
    l10rh: float = math.nan

    @property
    def rated(self) -> bool:
        """The bearing has a type and a dynamic load rating C."""
        return self.rating is not None and self.rating.rated

    @property
    def life_consumed(self) -> float:
        """The fraction of L10 its revolutions use: revolutions / (L10 · 10⁶) [-].

        Palmgren–Miner on revolutions at P_eq, equal to duration / L10h; 1 is the basic rating
        life reached (10 % of such bearings failed). NaN when not rated.
        """
        if not self.rated:
            return math.nan
        return self.revolutions / (self.l10 * 1e6) if self.l10 > 0.0 else math.inf

    @property
    def mean_speed_rpm(self) -> float:
        """Mean speed [rpm]: its revolutions over its duration."""
        return 60.0 * self.revolutions / self.duration if self.duration > 0 else math.nan

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON (SI, lives in 10⁶ rev and h; ``rated`` false: no life)."""
        return {
            "bearing": self.joint,
            "rated": self.rated,
            "type": self.rating.kind if self.rating else None,
            "dynamic_load_rating_N": self.rating.dynamic_load_rating if self.rating else None,
            "equivalent_load_N": None if math.isnan(self.equivalent_load) else self.equivalent_load,
            "revolutions": self.revolutions,
            "mean_speed_rpm": self.mean_speed_rpm,
            "l10_million_rev": self.l10 if self.rated and not self.refused else None,
            "l10_h": self.l10h if self.rated and not self.refused else None,
            "lnm_million_rev": _number(self.lnm),
            "lnm_h": _number(self.lnmh),
            "reference_load_N": _number(self.reference_load),
            "l10r_million_rev": _number(self.l10r),
            "l10r_h": _number(self.l10rh),
            "refused": self.refused or None,
        }


def _number(x: float) -> float | None:
    """A life for JSON: None for NaN (not computed); inf stays (JSON writers say Infinity)."""
    return None if math.isnan(x) else x


@dataclass(frozen=True)
class BearingLoadSum:
    """What ISO 281 needs of a bearing's load history, in sums that add over histories.

    A fatigue set scales each case's sums to the hours its wind bin stands for (`times`) and adds
    them over the bins (`plus`): P_eq over the site's life is then
    (Σ P_i^p n_i / Σ n_i)^(1/p) over all of them, the revolution-weighted rule of ISO 281.

    Attributes:
        joint: the bearing.
        exponent: life exponent p of the power sums (NaN when the model gives no type).
        power_sum: Σ P_i^p n_i, n_i the revolutions at P_i [N^p·rev] (NaN without a type).
        revolutions: Σ n_i [rev].
        time_power_sum: Σ P_i^p Δt_i [N^p·s], which weights a bearing that does not turn.
        seconds: Σ Δt_i, the history's duration [s].
        seconds_below_minimum: the seconds it turned under less than the minimum load it needs
            to roll (``life/skidding.py``) [s]; NaN without a rating C (or from a reduction
            written before it was kept).
        modified_sum: Σ n_i P_i^p / a_ISO,i [N^p·rev], ISO 281:2007 §9.3.4's sum of the
            modified life (``modified_life.modified_life_sum``); NaN when it has none (no C_u
            nor C₀, no size: ``life/life_sums.py``).
        reference_sum: Σ P_ref,i^p n_i [N^p·rev] of the ISO/TS 16281 reference loads
            (``dynamics/load_distribution.reference_load``); NaN without an internal geometry.
        reference_time_sum: Σ P_ref,i^p Δt_i [N^p·s], which weights a bearing that does not
            turn.
    """

    joint: str
    exponent: float
    power_sum: float
    revolutions: float
    time_power_sum: float
    seconds: float
    seconds_below_minimum: float = math.nan
    modified_sum: float = math.nan
    reference_sum: float = math.nan
    reference_time_sum: float = math.nan

    def times(self, factor: float) -> BearingLoadSum:
        """The sums of ``factor`` repetitions of the history (``factor`` ≥ 0)."""
        return dataclasses.replace(
            self,
            power_sum=self.power_sum * factor,
            revolutions=self.revolutions * factor,
            time_power_sum=self.time_power_sum * factor,
            seconds=self.seconds * factor,
            seconds_below_minimum=self.seconds_below_minimum * factor,
            modified_sum=self.modified_sum * factor,
            reference_sum=self.reference_sum * factor,
            reference_time_sum=self.reference_time_sum * factor,
        )

    def plus(self, other: BearingLoadSum) -> BearingLoadSum:
        """The sums of this history followed by ``other`` (of the same bearing and p)."""
        return dataclasses.replace(
            self,
            power_sum=self.power_sum + other.power_sum,
            revolutions=self.revolutions + other.revolutions,
            time_power_sum=self.time_power_sum + other.time_power_sum,
            seconds=self.seconds + other.seconds,
            seconds_below_minimum=self.seconds_below_minimum + other.seconds_below_minimum,
            modified_sum=self.modified_sum + other.modified_sum,
            reference_sum=self.reference_sum + other.reference_sum,
            reference_time_sum=self.reference_time_sum + other.reference_time_sum,
        )

    @property
    def below_minimum_share(self) -> float:
        """The share of the history's time it turned below its minimum load [-] (skidding risk)."""
        return self.seconds_below_minimum / self.seconds if self.seconds > 0.0 else math.nan

    @property
    def equivalent_load(self) -> float:
        """P_eq [N], revolution-weighted (time-weighted if it did not turn); NaN without a type."""
        if math.isnan(self.exponent):
            return math.nan
        if self.revolutions > 0.0:
            return mean_load(self.power_sum, self.revolutions, self.exponent)
        return mean_load(self.time_power_sum, self.seconds, self.exponent)

    @property
    def reference_load(self) -> float:
        """ISO/TS 16281 P_ref,eq [N], weighted as `equivalent_load`; NaN without a geometry."""
        if math.isnan(self.exponent) or math.isnan(self.reference_sum):
            return math.nan
        if self.revolutions > 0.0:
            return mean_load(self.reference_sum, self.revolutions, self.exponent)
        return mean_load(self.reference_time_sum, self.seconds, self.exponent)


def load_sum_of_history(
    joint: str,
    rating: BearingRating | None,
    *,
    time: np.ndarray,
    force_in_joint: np.ndarray,
    speed: np.ndarray,
    axis: np.ndarray,
    rolling: np.ndarray | None = None,
    weights: np.ndarray | None = None,
) -> BearingLoadSum:
    """A bearing's ISO 281 sums from its force and speed histories.

    Args:
        joint: the bearing's name.
        rating: its ISO 281 data; None when the model declares no type (sums of loads NaN).
        time: sample times [s], (n,).
        force_in_joint: bearing force on the child body, joint frame [N], (n, 3).
        speed: joint speed relative to the parent [rad/s], (n,).
        axis: joint axis in the joint frame.
        rolling: the radial load its loaded rolling elements carry [N], (n,), a preload
            included (``model/bearing_rows.rolling_load``), for the skidding check only;
            None: its radial force.
        weights: each sample's share of the time [s] (default `sample_weights` of ``time``;
            a part of a longer history gives its samples' shares of the whole).
    """
    weights = sample_weights(time) if weights is None else np.asarray(weights, dtype=float)
    turns = weights * np.abs(speed) / (2.0 * math.pi)  # revolutions per sample [rev]
    exponent = power_sum = time_power_sum = below = math.nan
    if rating is not None:
        radial, axial = radial_and_axial(np.asarray(force_in_joint, dtype=float), axis)
        loads = dynamic_equivalent_load(rating, radial, axial)
        exponent = rating.exponent
        power_sum = load_power_sum(loads, turns, exponent)
        time_power_sum = load_power_sum(loads, weights, exponent)
        if rolling is not None:  # a preloaded row's rollers carry the preload (skidding)
            loads = dynamic_equivalent_load(rating, np.maximum(rolling, radial), axial)
        below = seconds_below_minimum(rating, weights, speed, loads)
    return BearingLoadSum(
        joint, exponent, power_sum, float(turns.sum()), time_power_sum, float(weights.sum()),
        below,
    )  # fmt: skip


def life_of_load_sum(rating: BearingRating | None, load_sum: BearingLoadSum) -> BearingLife:
    """A bearing's life from its sums: L10 at P_eq, L10h at their mean speed.

    Raises:
        InvalidBearingRating: the sums are of another life exponent than the rating's.
    """
    if rating is not None and not math.isclose(load_sum.exponent, rating.exponent):
        raise InvalidBearingRating(
            load_sum.joint,
            f"its load sums are of p = {load_sum.exponent:g}, its type's p is "
            f"{rating.exponent:g}; recompute them from the run",
        )
    p_eq = l10 = lnm = p_ref = l10r = math.nan
    if rating is not None:
        p_eq = load_sum.equivalent_load
        p_ref = load_sum.reference_load
    if rating is not None and rating.rated:
        l10 = basic_rating_life(rating, p_eq)
        if not math.isnan(p_ref):
            l10r = basic_rating_life(rating, p_ref)
        lnm = modified_rating_life(
            rating.dynamic_load_rating or math.nan, rating.exponent,
            load_sum.modified_sum, load_sum.revolutions,
        )  # fmt: skip
    revolutions, seconds = load_sum.revolutions, load_sum.seconds
    return BearingLife(
        load_sum.joint, rating, p_eq, revolutions, seconds, l10,
        life_hours(l10, revolutions, seconds), lnm=lnm,
        lnmh=life_hours(lnm, revolutions, seconds), reference_load=p_ref, l10r=l10r,
        l10rh=life_hours(l10r, revolutions, seconds),
    )  # fmt: skip


def life_hours(life: float, revolutions: float, seconds: float) -> float:
    """A life [10⁶ rev] in hours [h] at the mean speed of ``revolutions`` over ``seconds``.

    L_h = L · 10⁶ / (revolutions per hour); inf for a bearing that did not turn, NaN for NaN.
    """
    if math.isnan(life):
        return math.nan
    per_hour = revolutions / seconds * 3600.0 if seconds > 0 else 0.0
    return life * 1e6 / per_hour if per_hour > 0.0 else math.inf


def life_of_history(
    joint: str,
    rating: BearingRating | None,
    *,
    time: np.ndarray,
    force_in_joint: np.ndarray,
    speed: np.ndarray,
    axis: np.ndarray,
) -> BearingLife:
    """A bearing's life from its force and speed histories (`load_sum_of_history`'s args)."""
    load_sum = load_sum_of_history(
        joint, rating, time=time, force_in_joint=force_in_joint, speed=speed, axis=axis
    )
    return life_of_load_sum(rating, load_sum)


def bearing_load_sums(result: Any, gearbox: Any) -> list[BearingLoadSum]:
    """ISO 281 sums of every bearing of a run, in the order of ``result.bearing_names``.

    Args:
        result: the run (``Result``: time, joint speed, ``bearing_force_local``).
        gearbox: the model it ran (``Gearbox``; its file's ``<bearing>`` elements and joint axes).
    """
    ratings: Mapping[str, BearingRating] = gearbox.source.bearings
    return [
        load_sum_of_history(
            name,
            ratings.get(name),
            time=result.time,
            force_in_joint=result.bearing_force_local[:, i],
            speed=result.speed[:, result.joint_names.index(name)],
            axis=gearbox.joint_axis(name),
        )
        for i, name in enumerate(result.bearing_names)
    ]


def bearing_lives(result: Any, gearbox: Any) -> list[BearingLife]:
    """ISO 281 life of every bearing of a run, in the order of ``result.bearing_names``.

    Bearings the model file rates (``<bearing type=... rating_c_kN=...>``) get L10 and L10h;
    the others are listed with ``rated`` False (and P_eq when their type is given). A rated
    bearing whose tilting moment exceeds ``TILT_ARM`` × its radial force has no life
    and ``refused`` says why (its moment would be dropped); rate its rows instead.

    Args:
        result: the run (``Result``: time, joint speed, ``bearing_force_local``).
        gearbox: the model it ran (``Gearbox``; its file's ``<bearing>`` elements and joint axes).
    """
    ratings: Mapping[str, BearingRating] = gearbox.source.bearings
    lives = []
    for i, load_sum in enumerate(bearing_load_sums(result, gearbox)):
        life = life_of_load_sum(ratings.get(load_sum.joint), load_sum)
        moments = getattr(result, "bearing_moment_local", None)
        if life.rated and moments is not None and len(moments):
            axis = np.asarray(gearbox.joint_axis(load_sum.joint), dtype=float)
            k = (axis / np.linalg.norm(axis)).reshape(1, 3)
            tilting = across_axis(np.asarray(moments[:, i], dtype=float)[:, None, :], k)[:, 0]
            radial, _ = radial_and_axial(result.bearing_force_local[:, i], axis)
            reason = tilt_refusal(radial, tilting)
            if reason:
                life = dataclasses.replace(life, l10=math.nan, l10h=math.nan, refused=reason)
        lives.append(life)
    return lives


def tilt_refusal(radial: np.ndarray, tilting: np.ndarray) -> str | None:
    """Why a whole bearing carrying this tilting moment gets no single life, or None.

    Args:
        radial: |F_r| [N], (n,); tilting: |M| about the radial axes [N·m], (n,).
    """
    f_max = float(np.max(radial, initial=0.0))
    m_max = float(np.max(tilting, initial=0.0))
    if m_max <= TILT_ARM * f_max or m_max == 0.0:
        return None
    return (
        f"it carries a tilting moment of up to {m_max / 1e3:.4g} kN·m beside {f_max / 1e3:.4g} "
        f"kN radial (more than {TILT_ARM * 1e3:g} mm × F_r), which one bearing at the joint "
        "cannot rate; give the shaft's bearings as <row>s at their positions in its <bearing> "
        "(docs/bearing_life.md) and rate them with `pinwind life`"
    )


def row_rating(bearing: str, row: Any) -> BearingRating:
    """A row's ISO 281 data, named `row_name` (``lss.INP-A``): the one rating of a ``<row>``.

    Its type, C and load factors (its own, or its type's) from the model file's ``<row>``
    (``model.bearing_rows.BearingRow``). The fatigue set (`row_ratings`), its cases' row sums
    and ``pinwind life`` (``row_life.rate_row``) all rate a row by it.
    """
    name = row_name(bearing, row.name)
    e, y1, x2, y2 = row.load_factors or (None, None, None, None)
    return bearing_rating(name, row.kind, dynamic_load_rating=row.rating, e=e, y1=y1, x2=x2, y2=y2)


def row_ratings(gearbox: Any) -> dict[str, BearingRating]:
    """The ISO 281 data of every row of the model's bearings, by `row_name` (`row_rating`)."""
    return {
        row_name(bearing, row.name): row_rating(bearing, row)
        for bearing, rows in gearbox.source.bearing_rows.items()
        for row in rows
    }
