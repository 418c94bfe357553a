"""Rolling-bearing life: ISO 281 basic rating life L10 from a bearing's reaction history.

ISO 281:2007 §7: L10 = (C / P)^p millions of revolutions, p = 3 for ball bearings and 10/3 for
roller bearings, C the basic dynamic load rating and P the dynamic equivalent radial load
(``model/bearing.py``: P = F_r + Y1 F_a up to F_a / F_r = e, X2 F_r + Y2 F_a above). A load that
varies over the run is replaced by the constant load of equal life, the revolution-weighted
p-th power mean

    P_eq = (Σ P_i^p n_i / Σ n_i)^(1/p)

(Palmgren–Miner on revolutions), n_i the revolutions at P_i. From a run: F_r is the part of the
bearing force (``bearing_force_local``, joint frame) normal to the joint axis, F_a the part along
it, and the revolutions are ∫|ω| dt of the joint speed (trapezoid rule over the samples), which
pinwind gives relative to the parent body: a planet bearing turns at the planet's speed relative
to the carrier. L10h = L10 · 10⁶ / (revolutions per hour of the run).

The type and dynamic load rating of each bearing come from the model file's ``<bearing>``
elements (docs/model_format.md); a bearing without C is "not rated".
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.dynamics.bearing_load import across_axis, along_axis
from pinwind.errors import InvalidBearingRating
from pinwind.model.bearing import BearingRating


def dynamic_equivalent_load(
    rating: BearingRating, radial: np.ndarray, axial: np.ndarray
) -> np.ndarray:
    """Dynamic equivalent radial load P [N] of radial and axial loads F_r, F_a [N] (≥ 0).

    ISO 281 §6: P = F_r + Y1 F_a when F_a ≤ e F_r, else X2 F_r + Y2 F_a.
    """
    radial, axial = np.asarray(radial, dtype=float), np.asarray(axial, dtype=float)
    below = axial <= rating.e * radial
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


def equivalent_load(loads: np.ndarray, weights: np.ndarray, exponent: float) -> float:
    """The constant load of equal life: (Σ P_i^p w_i / Σ w_i)^(1/p) [N].

    Args:
        loads: dynamic equivalent loads P_i [N].
        weights: revolutions (or any measure) at each load, ≥ 0, not all zero.
        exponent: life exponent p.
    """
    loads, weights = np.asarray(loads, dtype=float), np.asarray(weights, dtype=float)
    scale = float(loads.max()) if loads.size else 0.0
    if scale <= 0.0:
        return 0.0
    # Scaled by the largest load: P^(10/3) of MN loads would overflow nothing, but stays exact.
    mean = float(np.sum((loads / scale) ** exponent * weights) / np.sum(weights))
    return scale * mean ** (1.0 / exponent)


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
        duration: the run's duration [s].
        l10: basic rating life [10⁶ rev] (NaN when not rated).
        l10h: basic rating life [h] at the run's mean speed (inf if it did not turn).
    """

    joint: str
    rating: BearingRating | None
    equivalent_load: float
    revolutions: float
    duration: float
    l10: float
    l10h: float

    @property
    def rated(self) -> bool:
        """The bearing has a type and a dynamic load rating C."""
        return self.rating is not None and self.rating.rated

    @property
    def mean_speed_rpm(self) -> float:
        """Mean speed over the run [rpm] (its revolutions over its duration)."""
        return 60.0 * self.revolutions / self.duration if self.duration > 0 else math.nan

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON (SI, lives in 10⁶ rev and h; ``rated`` false: no life)."""
        return {
            "bearing": self.joint,
            "rated": self.rated,
            "type": self.rating.kind if self.rating else None,
            "dynamic_load_rating_N": self.rating.dynamic_load_rating if self.rating else None,
            "equivalent_load_N": self.equivalent_load,
            "revolutions": self.revolutions,
            "mean_speed_rpm": self.mean_speed_rpm,
            "l10_million_rev": self.l10 if self.rated else None,
            "l10_h": self.l10h if self.rated else None,
        }


def life_of_history(
    joint: str,
    rating: BearingRating | None,
    *,
    time: np.ndarray,
    force_in_joint: np.ndarray,
    speed: np.ndarray,
    axis: np.ndarray,
) -> BearingLife:
    """A bearing's life from its force and speed histories.

    Args:
        joint: the bearing's name.
        rating: its ISO 281 data; None when the model declares no type (P_eq is then NaN).
        time: sample times [s], (n,).
        force_in_joint: bearing force on the child body, joint frame [N], (n, 3).
        speed: joint speed relative to the parent [rad/s], (n,).
        axis: joint axis in the joint frame.
    """
    weights = sample_weights(time)
    turns = weights * np.abs(speed) / (2.0 * math.pi)  # revolutions per sample [rev]
    revolutions = float(turns.sum())
    duration = float(time[-1] - time[0]) if len(time) else 0.0
    p_eq = l10 = l10h = math.nan
    if rating is not None:
        radial, axial = radial_and_axial(np.asarray(force_in_joint, dtype=float), axis)
        loads = dynamic_equivalent_load(rating, radial, axial)
        # A bearing that does not turn has no revolutions to weight by: its loads count by time.
        p_eq = equivalent_load(loads, turns if revolutions > 0.0 else weights, rating.exponent)
    if rating is not None and rating.rated:
        l10 = basic_rating_life(rating, p_eq)
        per_hour = revolutions / duration * 3600.0 if duration > 0 else 0.0
        l10h = l10 * 1e6 / per_hour if per_hour > 0.0 else math.inf
    return BearingLife(joint, rating, p_eq, revolutions, duration, l10, l10h)


def bearing_lives(result: Any, gearbox: Any) -> list[BearingLife]:
    """ISO 281 life of every bearing of a run, in the order of ``result.bearing_names``.

    Bearings the model file rates (``<bearing type=... rating_c_kN=...>``) get L10 and L10h;
    the others are listed with ``rated`` False (and P_eq when their type is given).

    Args:
        result: the run (``Result``: time, joint speed, ``bearing_force_local``).
        gearbox: the model it ran (``Gearbox``; its file's ``<bearing>`` elements and joint axes).
    """
    ratings: Mapping[str, BearingRating] = gearbox.source.bearings
    lives = []
    for i, name in enumerate(result.bearing_names):
        lives.append(
            life_of_history(
                name,
                ratings.get(name),
                time=result.time,
                force_in_joint=result.bearing_force_local[:, i],
                speed=result.speed[:, result.joint_names.index(name)],
                axis=gearbox.joint_axis(name),
            )
        )
    return lives
