"""ISO 281:2007 modified life: ν₁, κ, a_ISO and a₁ by hand from the standard's formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.life.lubrication import VG_GRADES, Lubricant, contamination_factor
from pinwind.life.modified_life import (
    life_modification_factor,
    rated_viscosity,
    reliability_factor,
)


@pytest.mark.parametrize(
    ("speed_rpm", "dm_mm", "nu_mm2s", "regime"),
    [
        # one operating point per κ regime (roller bearing, e_C C_u / P = 0.2)
        (15.0, 1500.0, 40.0, (1.5859, 1.3993, 0.054381)),  # 0.1 ≤ κ < 0.4
        (200.0, 500.0, 20.0, (1.5859, 1.2348, 0.19087)),  # 0.4 ≤ κ < 1
        (1500.0, 300.0, 15.0, (1.5859, 1.2348, 0.071739)),  # 1 ≤ κ ≤ 4
    ],
)
def test_kappa_and_a_iso_follow_iso_281_by_hand(speed_rpm, dm_mm, nu_mm2s, regime):
    # ISO 281:2007 §9.3.3: ν₁ in mm²/s from n [r/min] and d_m [mm], two branches at 1000 r/min.
    if speed_rpm < 1000:
        nu1 = 45000.0 * speed_rpm**-0.83 * dm_mm**-0.5
    else:
        nu1 = 4500.0 * speed_rpm**-0.5 * dm_mm**-0.5
    got_nu1 = rated_viscosity(speed_rpm, dm_mm * 1e-3)
    assert_allclose(got_nu1, nu1 * 1e-6, rtol=1e-12)
    kappa = nu_mm2s / nu1
    lo, hi = {0.054381: (0.1, 0.4), 0.19087: (0.4, 1.0), 0.071739: (1.0, 4.0)}[regime[2]]
    assert lo <= kappa < hi, kappa  # the point is in the regime it checks
    c1, c2, c3 = regime
    x = 0.2
    expected = 0.1 * (1.0 - (c1 - c2 / kappa**c3) * x**0.4) ** -9.185
    assert_allclose(life_modification_factor(kappa, x, ball=False), expected, rtol=1e-12)


def test_a_iso_is_capped_at_50_and_kappa_above_4_counts_as_4():
    # e_C C_u / P = 1.5 at κ = 4: the bracket 1 − (1.5859 − 1.2348·4^−0.071739)·1.5^0.4 is
    # 1 − 0.4452·1.176 = 0.476 → 0.1 · 0.476^−9.185 ≈ 91 > 50.
    bracket = 1.0 - (1.5859 - 1.2348 * 4**-0.071739) * 1.5**0.4
    assert 0.1 * bracket**-9.185 > 50.0
    assert life_modification_factor(4.0, 1.5, ball=False) == 50.0
    assert life_modification_factor(9.0, 0.05, ball=False) == life_modification_factor(
        4.0, 0.05, ball=False
    )
    # a bracket ≤ 0 (very clean, light load) is the cap too
    assert life_modification_factor(4.0, 20.0, ball=True) == 50.0


@pytest.mark.parametrize("ball", [False, True])
@pytest.mark.parametrize("boundary", [0.4, 1.0])
def test_a_iso_is_continuous_across_the_kappa_regimes(ball, boundary):
    below = life_modification_factor(boundary * (1 - 1e-9), 0.1, ball=ball)
    above = life_modification_factor(boundary, 0.1, ball=ball)
    # The standard's 5-digit constants meet within 0.05 %; c₃ = 0.019087 would jump by 15 %.
    assert_allclose(below, above, rtol=5e-4)


def test_reliability_factor_matches_iso_281_table_12():
    # ISO 281:2007 Table 12: 90 % → 1, 95 % → 0.64, 99 % → 0.25, 99.95 % → 0.077
    for r, a1 in ((90.0, 1.0), (95.0, 0.64), (99.0, 0.25), (99.95, 0.077)):
        assert_allclose(reliability_factor(r), a1, atol=0.006)


def test_walther_line_passes_through_both_given_viscosities():
    oil = Lubricant(320, 273.15 + 40.0, viscosity_100=24e-6)
    assert_allclose(oil.viscosity(273.15 + 40.0), 320e-6, rtol=1e-12)
    assert_allclose(oil.viscosity(273.15 + 100.0), 24e-6, rtol=1e-12)
    assert not oil.slope_assumed
    hot = Lubricant(320, 273.15 + 70.0)
    assert hot.slope_assumed and 24e-6 < hot.viscosity() < 320e-6


def test_iso_3448_grades_and_table_13_midpoints():
    assert VG_GRADES[2] == 2.2 and VG_GRADES[3200] == 3200.0 and len(VG_GRADES) == 20
    # normal cleanliness: 0.6 … 0.5 below 100 mm, 0.8 … 0.6 from 100 mm
    assert_allclose(contamination_factor("normal_cleanliness", 0.05), 0.55)
    assert_allclose(contamination_factor("normal_cleanliness", 0.5), 0.7)


def test_rated_viscosity_branches_meet_within_the_standards_step():
    # The two branches at 1000 r/min differ by 45000·1000^−0.83 / (4500·1000^−0.5) − 1 ≈ 2.3 %.
    slow = rated_viscosity(999.999, 0.2)
    fast = rated_viscosity(1000.0, 0.2)
    assert_allclose(slow / fast, 45000 * 1000**-0.83 / (4500 * 1000**-0.5), rtol=1e-5)
    assert math.isnan(float(rated_viscosity(0.0, 0.2)))
    assert np.all(np.diff(rated_viscosity(np.array([10.0, 100.0, 900.0]), 0.2)) < 0)
