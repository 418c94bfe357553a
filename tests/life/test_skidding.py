"""Skidding risk: the share of the time a bearing turns below the load it needs to roll."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.life.bearing_life import load_sum_of_history, sample_weights
from pinwind.life.row_life import rate_row
from pinwind.life.skidding import minimum_load, seconds_below_minimum
from pinwind.model.bearing import bearing_rating

C = 1.0e6  # dynamic load rating [N]
ROLLER = bearing_rating("b", "cylindrical_roller", dynamic_load_rating=C)
BALL = bearing_rating("b", "deep_groove_ball", dynamic_load_rating=C)


def test_the_minimum_load_is_two_percent_of_c_for_rollers_and_one_for_balls():
    # SKF 2018, "Requisite minimum load": P = 0.02 C (roller bearings), 0.01 C (ball bearings).
    assert minimum_load(ROLLER) == 0.02 * C
    assert minimum_load(BALL) == 0.01 * C
    assert math.isnan(
        minimum_load(bearing_rating("b", "cylindrical_roller", dynamic_load_rating=None))
    )


def sine_history(level: float, amplitude: float, n: int = 200_001):
    """One period of P(t) = level + amplitude sin(2π t) over 1 s, at n samples."""
    time = np.linspace(0.0, 1.0, n)
    return time, level + amplitude * np.sin(2 * np.pi * time)


@pytest.mark.parametrize("level", [15e3, 20e3, 27e3])
def test_a_sine_load_is_below_the_minimum_for_the_arcsine_share_of_its_period(level):
    # P < P_min where sin θ < s = (P_min − level)/A: for θ over a period, 1/2 + arcsin(s)/π.
    amplitude, floor = 10e3, 0.02 * C
    time, load = sine_history(level, amplitude)
    weights = sample_weights(time)
    share = seconds_below_minimum(ROLLER, weights, np.full_like(time, 3.0), load) / weights.sum()
    expected = 0.5 + math.asin((floor - level) / amplitude) / math.pi
    assert_allclose(share, expected, atol=1e-4)


def test_a_bearing_that_stands_still_does_not_skid():
    time, load = sine_history(5e3, 1e3)  # always below 20 kN
    weights = sample_weights(time)
    assert seconds_below_minimum(ROLLER, weights, np.zeros_like(time), load) == 0.0
    assert_allclose(seconds_below_minimum(ROLLER, weights, np.ones_like(time), load), 1.0)


def test_the_seconds_below_add_over_histories_and_scale_with_their_repetitions():
    # A radial force history through a bearing's sums (ISO 281 P = F_r for a cylindrical
    # roller bearing), then three repetitions of it and another history after it.
    time, load = sine_history(20e3, 10e3)
    force = np.column_stack([load, np.zeros_like(load), np.zeros_like(load)])
    axis = np.array([0.0, 0.0, 1.0])
    one = load_sum_of_history(
        "b", ROLLER, time=time, force_in_joint=force, speed=np.full_like(time, 2.0), axis=axis
    )
    assert_allclose(one.below_minimum_share, 0.5, atol=1e-4)
    assert_allclose(one.times(3.0).seconds_below_minimum, 3.0 * one.seconds_below_minimum)
    still = load_sum_of_history(
        "b", ROLLER, time=time, force_in_joint=force, speed=np.zeros_like(time), axis=axis
    )
    assert_allclose(one.plus(still).below_minimum_share, 0.25, atol=1e-4)  # half, over twice
    assert math.isnan(
        load_sum_of_history("b", None, time=time, force_in_joint=force,
                            speed=np.ones_like(time), axis=np.array([0.0, 0.0, 1.0]))
        .seconds_below_minimum
    )  # fmt: skip


def test_a_rows_life_gives_its_share_of_the_time_below_the_minimum_load():
    time, load = sine_history(27e3, 10e3)
    w = np.zeros((len(time), 5))
    w[:, 0] = load  # F_u on the bearing
    rating = bearing_rating("shaft.A", "cylindrical_roller", dynamic_load_rating=C)
    life = rate_row(name="A", bearing="shaft", position=0.0, rating=rating,
                    size=None, data=None, time=time,
                    speed=np.full_like(time, 3.0), load=w)  # fmt: skip
    assert_allclose(life.below_minimum, 0.5 + math.asin(-0.7) / math.pi, atol=1e-4)
    assert_allclose(life.as_dict()["share_below_minimum_load"], life.below_minimum)


def test_pinwind_fatigue_gives_each_rated_bearings_share_below_its_minimum_per_wind_bin(tmp_path):
    from tests.cli.test_fatigue import _quick_text_and_json

    text, report = _quick_text_and_json(tmp_path)
    shares = report["share_below_minimum_load"]
    rated = {b["bearing"] for b in report["bearings"][0] if b["rated"]}
    assert set(k for k, v in shares["per_bin"].items() if any(x is not None for x in v)) == rated
    for per_bin in shares["per_bin"].values():
        assert len(per_bin) == len(report["speeds_m_s"])
        assert all(x is None or 0.0 <= x <= 1.0 for x in per_bin)
    assert "Skidding risk" in text and "[m/s]" in text
    json.dumps(shares)  # plain values
