"""ISO 281 bearing life: L10 by hand, the equivalent load of a varying history, bad ratings."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.errors import InvalidBearingRating, UnknownName
from pinwind.life.bearing_life import basic_rating_life, bearing_lives, life_of_history
from pinwind.model.bearing import bearing_rating
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

RPM = 2.0 * math.pi / 60.0


def _constant(force_n: tuple[float, float, float], speed_rpm: float, duration: float = 2.0):
    """A history of a constant force (joint frame, axis z) at a constant speed."""
    time = np.linspace(0.0, duration, 2001)
    force = np.tile(force_n, (len(time), 1))
    return time, force, np.full(len(time), speed_rpm * RPM)


def test_constant_radial_load_gives_l10_of_c_over_p_to_the_ten_thirds():
    rating = bearing_rating("shaft", "cylindrical_roller", dynamic_load_rating=100e3)
    time, force, speed = _constant((12e3, -16e3, 0.0), 600.0)  # |F_r| = 20 kN
    life = life_of_history("shaft", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 2.0]))  # fmt: skip
    l10 = 5.0 ** (10.0 / 3.0)  # (100 kN / 20 kN)^(10/3) million revolutions
    np.testing.assert_allclose(life.equivalent_load, 20e3, rtol=1e-12)
    np.testing.assert_allclose(life.l10, l10, rtol=1e-12)
    np.testing.assert_allclose(life.l10h, l10 * 1e6 / (600.0 * 60.0), rtol=1e-9)
    np.testing.assert_allclose(life.revolutions, 600.0 / 60.0 * 2.0, rtol=1e-9)


def test_ball_bearing_above_e_counts_the_axial_load_with_x_and_y():
    rating = bearing_rating("shaft", "deep_groove_ball", dynamic_load_rating=50e3)
    time, force, speed = _constant((0.0, 10e3, 5e3), 1500.0)  # F_a/F_r = 0.5 > e = 0.28
    life = life_of_history("shaft", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 1.0]))  # fmt: skip
    load = 0.56 * 10e3 + 1.55 * 5e3  # ISO 281 Table 3: X = 0.56, Y = 1.55
    np.testing.assert_allclose(life.equivalent_load, load, rtol=1e-12)
    np.testing.assert_allclose(life.l10, (50e3 / load) ** 3, rtol=1e-12)


def test_spherical_roller_below_e_adds_y1_times_the_axial_load():
    """ISO 281 Table 7, double row, α = 10°: e = 1.5 tan α = 0.2645, Y1 = 0.45 cot α = 2.552.
    A planet bearing's load F_r = 40 kN, F_a = 8 kN (F_a/F_r = 0.2 ≤ e): P = F_r + Y1 F_a."""
    alpha = math.radians(10.0)
    y1 = 0.45 / math.tan(alpha)
    assert 8e3 / 40e3 <= 1.5 * math.tan(alpha)
    rating = bearing_rating("planet1", "spherical_roller", dynamic_load_rating=1200e3)
    time, force, speed = _constant((24e3, 32e3, 8e3), 120.0)  # |F_r| = 40 kN
    life = life_of_history("planet1", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 1.0]))  # fmt: skip
    load = 40e3 + y1 * 8e3  # 60.42 kN, half as much again as F_r
    np.testing.assert_allclose(life.equivalent_load, load, rtol=1e-12)
    np.testing.assert_allclose(life.l10, (1200e3 / load) ** (10.0 / 3.0), rtol=1e-12)


def test_a_catalogue_spherical_roller_below_e_takes_its_own_y1_from_the_model_file():
    """A catalogue's factors for a 10° bearing rounded as catalogues print them (e = 0.24,
    Y1 = 2.8, X2 = 0.67, Y2 = 4.2, C = 1270 kN), read from the model file; F_a/F_r = 0.2:
    P = 40 kN + 2.8 × 8 kN = 62.4 kN."""
    text = two_gear_urdf().replace(
        "</gearbox>",
        '<bearing joint="a" type="spherical_roller" rating_c_kN="1270" e="0.24" y1="2.8" '
        'x2="0.67" y2="4.2"/></gearbox>',
    )
    rating = loads(text, path="pair.urdf").source.bearings["a"]
    time, force, speed = _constant((0.0, -40e3, 8e3), 300.0)
    life = life_of_history("a", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 1.0]))  # fmt: skip
    np.testing.assert_allclose(life.equivalent_load, 62.4e3, rtol=1e-12)
    np.testing.assert_allclose(life.l10, (1270.0 / 62.4) ** (10.0 / 3.0), rtol=1e-12)


def test_two_level_history_is_the_revolution_weighted_p_mean():
    # 2 s at 30 kN and 100 rpm, then 1 s at 60 kN and 300 rpm: n1 = 200/60, n2 = 300/60 rev.
    dt = 1e-4
    time = np.arange(0.0, 3.0 + dt / 2, dt)
    first = time < 2.0
    force = np.zeros((len(time), 3))
    force[:, 0] = np.where(first, 30e3, 60e3)
    speed = np.where(first, 100.0, 300.0) * RPM
    rating = bearing_rating("shaft", "spherical_roller", dynamic_load_rating=400e3)
    life = life_of_history("shaft", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 1.0]))  # fmt: skip
    p = 10.0 / 3.0
    n1, n2 = 100.0 / 60.0 * 2.0, 300.0 / 60.0 * 1.0
    p_eq = ((30e3**p * n1 + 60e3**p * n2) / (n1 + n2)) ** (1.0 / p)
    # one sample in 30 000 sits on the step: the quadrature is that close to the hand value
    np.testing.assert_allclose(life.equivalent_load, p_eq, rtol=1e-4)
    np.testing.assert_allclose(life.revolutions, n1 + n2, rtol=1e-4)
    l10 = (400e3 / p_eq) ** p
    np.testing.assert_allclose(life.l10, l10, rtol=4e-4)
    np.testing.assert_allclose(life.l10h, l10 * 1e6 / ((n1 + n2) / 3.0 * 3600.0), rtol=4e-4)


def test_bearing_of_a_run_carries_the_weight_and_one_without_c_is_not_rated():
    # Shaft a (1 kg) turns at a constant 100 rpm with nothing to drive: its bearing carries
    # its weight, 9.81 N normal to the shaft; b has a type but no C, the ring none at all.
    text = two_gear_urdf().replace(
        "</gearbox>",
        '<bearing joint="a" type="cylindrical_roller" rating_c_kN="1"/>'
        '<bearing joint="b" type="deep_groove_ball"/></gearbox>',
    )
    gearbox = loads(text, path="pair.urdf")
    res = pinwind.simulate(gearbox, duration=0.3, dt=1e-3, speeds={"a": 100.0 * RPM})
    lives = {life.joint: life for life in bearing_lives(res, gearbox)}
    assert list(lives) == res.bearing_names
    a, b = lives["a"], lives["b"]
    assert a.rated and not b.rated
    np.testing.assert_allclose(a.equivalent_load, 9.81, rtol=1e-6)
    l10 = (1000.0 / 9.81) ** (10.0 / 3.0)
    np.testing.assert_allclose(a.l10, l10, rtol=1e-5)
    np.testing.assert_allclose(a.l10h, l10 * 1e6 / (100.0 * 60.0), rtol=1e-5)
    assert b.as_dict()["l10_h"] is None and b.as_dict()["type"] == "deep_groove_ball"


def test_plain_model_lists_every_bearing_as_not_rated():
    gearbox = loads(two_gear_urdf(), path="pair.urdf")
    res = pinwind.simulate(gearbox, duration=0.01, dt=1e-3, speeds={"a": 10.0 * RPM})
    lives = bearing_lives(res, gearbox)
    assert [life.joint for life in lives] == ["a", "b"]
    assert not any(life.rated for life in lives)
    assert all(math.isnan(life.equivalent_load) for life in lives)


def test_still_bearing_has_an_infinite_life_in_hours():
    rating = bearing_rating("shaft", "tapered_roller", dynamic_load_rating=80e3)
    time, force, speed = _constant((20e3, 0.0, 0.0), 0.0)
    life = life_of_history("shaft", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 1.0]))  # fmt: skip
    np.testing.assert_allclose(life.equivalent_load, 20e3, rtol=1e-12)
    assert life.l10h == math.inf


@pytest.mark.parametrize(
    "kind, rating, message",
    [
        ("needle_roller", 10e3, 'type "needle_roller" has no ISO 281 life exponent'),
        ("tapered_roller", 0.0, "C = 0 N"),
        ("tapered_roller", -5.0, "C = -5 N"),
        ("tapered_roller", math.nan, "C = nan N"),
        ("tapered_roller", math.inf, "C = inf N"),
    ],
)
def test_rating_without_an_exponent_or_with_a_bad_c_raises(kind, rating, message):
    with pytest.raises(InvalidBearingRating, match=message) as err:
        bearing_rating("planet1", kind, dynamic_load_rating=rating)
    assert err.value.bearing == "planet1"


def test_negative_load_factor_raises():
    with pytest.raises(InvalidBearingRating, match="y2 = -1"):
        bearing_rating("sun", "tapered_roller", dynamic_load_rating=1e5, y2=-1.0)


def test_life_of_a_bearing_without_c_raises():
    rating = bearing_rating("sun", "tapered_roller", dynamic_load_rating=None)
    with pytest.raises(InvalidBearingRating, match="give rating_c_kN"):
        basic_rating_life(rating, 1e3)


@pytest.mark.parametrize(
    "element, error, message",
    [
        ('<bearing joint="a" type="toroidal" rating_c_kN="10"/>', InvalidBearingRating,
         'type "toroidal" has no ISO 281 life exponent'),
        ('<bearing joint="a" type="cylindrical_roller" rating_c_kN="-2"/>',
         InvalidBearingRating, "C = -2000 N"),
        ('<bearing joint="a" type="cylindrical_roller" rating_c_kN="inf"/>',
         pinwind.PinwindError, 'rating_c_kN="inf" is not finite'),
        ('<bearing joint="z" type="cylindrical_roller"/>', UnknownName, 'unknown joint "z"'),
        ('<bearing joint="a" type="cylindrical_roller"/>' * 2, pinwind.PinwindError,
         "rated twice"),
    ],
)  # fmt: skip
def test_bad_bearing_in_a_model_file_is_refused_naming_it(element, error, message):
    text = two_gear_urdf().replace("</gearbox>", element + "</gearbox>")
    with pytest.raises(error, match=message) as err:
        loads(text, path="pair.urdf")
    assert "pair.urdf" in str(err.value)


def test_bearing_on_a_fixed_joint_is_refused():
    text = (
        two_gear_urdf()
        .replace('<joint name="b" type="continuous">', '<joint name="b" type="fixed">')
        .replace("</gearbox>", '<bearing joint="b" type="cylindrical_roller"/></gearbox>')
    )
    with pytest.raises(InvalidBearingRating, match="fixed joint"):
        loads(text, path="pair.urdf")


def test_catalogue_factors_in_the_model_file_replace_the_type_defaults():
    text = two_gear_urdf().replace(
        "</gearbox>",
        '<bearing joint="a" type="Tapered_Roller" rating_c_kN="10" e="0.3" y2="2.0"/></gearbox>',
    )
    rating = loads(text, path="pair.urdf").source.bearings["a"]
    assert rating.kind == "tapered_roller"
    np.testing.assert_allclose([rating.dynamic_load_rating, rating.e, rating.x2, rating.y2],
                               [10e3, 0.3, 0.4, 2.0], rtol=1e-12)  # fmt: skip
    np.testing.assert_allclose(rating.exponent, 10.0 / 3.0, rtol=1e-12)


def test_life_consumed_under_a_constant_load_is_the_time_over_l10h():
    # ISO 281 by hand: C 1000 kN, P 100 kN, roller p = 10/3, 10 rpm for 3 h.
    rating = bearing_rating("shaft", "cylindrical_roller", dynamic_load_rating=1000e3)
    time, force, speed = _constant((100e3, 0.0, 0.0), 10.0, duration=3 * 3600.0)
    life = life_of_history("shaft", rating, time=time, force_in_joint=force, speed=speed,
                           axis=np.array([0.0, 0.0, 1.0]))  # fmt: skip
    l10h = 10.0 ** (10.0 / 3.0) * 1e6 / (10.0 * 60.0)  # 3.59e6 h
    np.testing.assert_allclose(life.life_consumed, 3.0 / l10h, rtol=1e-9)
    np.testing.assert_allclose(life.life_consumed, 3.0 / life.l10h, rtol=1e-12)
