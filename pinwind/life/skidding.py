"""Skidding risk: the time a rolling bearing turns under less than the load it needs to roll.

A rolling bearing under too light a load lets its rolling elements slide instead of roll (the
cage and the friction of the lubricant brake them), and the smearing this gives ends the life of
wind-turbine planet and high-speed bearings early (Keller et al. 2018 name it among the failure
modes of the GRC). The catalogues give the load a bearing needs as a rule of thumb of its dynamic
load rating C (SKF, Rolling bearings catalogue 2018, "Requisite minimum load"; Schaeffler,
Technical Pocket Guide): a dynamic equivalent load of at least

    P_min = 0.02 C   (roller bearings)         P_min = 0.01 C   (ball bearings).

ISO 281 gives none. The risk of a history is the share of the time the bearing turns with
P < P_min (P of ISO 281, ``bearing_life.dynamic_equivalent_load``); a bearing that stands still
does not skid. The time below the minimum adds over histories as the ISO 281 sums do
(``BearingLoadSum.seconds_below_minimum``), so a fatigue set gives it per wind bin.
"""

from __future__ import annotations

import math

import numpy as np

from pinwind.model.bearing import BALL_EXPONENT, BearingRating

#: Minimum equivalent load over the dynamic load rating, roller and ball bearings (module
#: docstring: SKF 2018, Schaeffler).
MINIMUM_LOAD_ROLLER = 0.02
MINIMUM_LOAD_BALL = 0.01
#: A joint turns when |ω| is above this [rad/s] (a held ring's speed is round-off).
TURNING = 1e-6


def minimum_load(rating: BearingRating | None) -> float:
    """P_min [N] of a rated bearing (module docstring); NaN without C."""
    if rating is None or rating.dynamic_load_rating is None:
        return math.nan
    ball = math.isclose(rating.exponent, BALL_EXPONENT)
    return (MINIMUM_LOAD_BALL if ball else MINIMUM_LOAD_ROLLER) * rating.dynamic_load_rating


def seconds_below_minimum(
    rating: BearingRating | None, weights: np.ndarray, speed: np.ndarray, loads: np.ndarray
) -> float:
    """Seconds the bearing turns with P < P_min, from the samples' weights [s] (NaN without C).

    ``weights``: each sample's share of the time [s] (``bearing_life.sample_weights``),
    ``speed`` the joint's [rad/s], ``loads`` its equivalent load P [N].
    """
    floor = minimum_load(rating)
    if math.isnan(floor):
        return math.nan
    below = (np.abs(speed) > TURNING) & (np.asarray(loads) < floor)
    return float(np.sum(np.asarray(weights)[below]))
