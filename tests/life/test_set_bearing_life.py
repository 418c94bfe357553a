"""Bearing life over a site's life from a fatigue set's cases, against ISO 281 by hand."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from pinwind.life.bearing_life import load_sum_of_history
from pinwind.life.case_cycles import CaseCycles
from pinwind.life.set_bearing_life import set_bearing_lives
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import fatigue_toml

RPM = 2.0 * math.pi / 60.0


def write_bearing_case(fset, case, *, joint, radial_n, speed_rpm, seconds):
    """A case reduction whose bearing ``joint`` ran at a constant radial load and speed."""
    time = np.linspace(0.0, seconds, 4001)
    force = np.tile((0.0, radial_n, 0.0), (len(time), 1))  # joint frame, axis z: all radial
    load_sum = load_sum_of_history(
        joint,
        fset.bearings.get(joint),
        time=time,
        force_in_joint=force,
        speed=np.full(len(time), speed_rpm * RPM),
        axis=np.array([0.0, 0.0, 1.0]),
    )
    fset.out.mkdir(parents=True, exist_ok=True)
    reduced = CaseCycles(case, fset.case_key(case), seconds, 0.0, bearings=(load_sum,))
    reduced.save(fset.cycles_path(case))


def test_two_bins_at_two_constant_loads_combine_by_their_revolutions_over_the_site(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))  # bins: 10 m/s 1000 h, 16 m/s 250 h
    rating = fset.bearings["planet1"]  # cylindrical roller: P = F_r, p = 10/3
    low, high = fset.cases()
    write_bearing_case(fset, low, joint="planet1", radial_n=200e3, speed_rpm=60.0, seconds=2.0)
    write_bearing_case(fset, high, joint="planet1", radial_n=400e3, speed_rpm=90.0, seconds=4.0)
    (life,) = set_bearing_lives(fset)[0]
    # revolutions over the life: hours · 60 · rpm per bin
    r_low, r_high = 1000.0 * 60.0 * 60.0, 250.0 * 60.0 * 90.0
    p = 10.0 / 3.0
    p_eq = ((200e3**p * r_low + 400e3**p * r_high) / (r_low + r_high)) ** (1.0 / p)
    l10 = (rating.dynamic_load_rating / p_eq) ** p  # 10⁶ rev
    l10h = l10 * 1e6 / ((r_low + r_high) / 1250.0)  # at the mean revolutions per hour
    assert life.rated
    assert_allclose(life.revolutions, r_low + r_high, rtol=1e-9)
    assert_allclose(life.equivalent_load, p_eq, rtol=1e-9)
    assert_allclose(life.l10, l10, rtol=1e-9)
    assert_allclose(life.l10h, l10h, rtol=1e-9)
    assert_allclose(life.duration, 1250.0 * 3600.0, rtol=1e-12)


def test_seeds_of_a_bin_share_its_hours(tmp_path):
    # Two seeds at the same constant load and speed: the same life as one of them alone.
    text = fatigue_toml(tmp_path).read_text().replace("seeds = [3]", "seeds = [3, 4]")
    (tmp_path / "set.toml").write_text(text)
    fset = load_fatigue_set(tmp_path / "set.toml")
    for case in fset.cases():
        write_bearing_case(fset, case, joint="planet1", radial_n=300e3, speed_rpm=70.0,
                           seconds=1.0 + case.seed)  # fmt: skip
    (life,) = set_bearing_lives(fset)[0]
    assert_allclose(life.revolutions, 1250.0 * 60.0 * 70.0, rtol=1e-9)
    assert_allclose(life.equivalent_load, 300e3, rtol=1e-9)
    rating = fset.bearings["planet1"]
    l10 = (rating.dynamic_load_rating / 300e3) ** (10.0 / 3.0)
    assert_allclose(life.l10h, l10 * 1e6 / (70.0 * 60.0), rtol=1e-9)


def test_bearing_the_model_does_not_rate_is_listed_as_not_rated(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    assert "ring" not in fset.bearings
    for case in fset.cases():
        write_bearing_case(fset, case, joint="ring", radial_n=1e3, speed_rpm=0.0, seconds=1.0)
    (life,) = set_bearing_lives(fset)[0]
    assert not life.rated
    assert life.as_dict()["l10_h"] is None and life.as_dict()["equivalent_load_N"] is None
