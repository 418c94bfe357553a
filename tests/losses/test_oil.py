"""The oil's viscosity and density: Walther's line and DIN 51757's linear density, by hand."""

from __future__ import annotations

import math

from numpy.testing import assert_allclose

from pinwind.losses.oil import Lubricant


def test_walther_line_through_the_grade_and_its_100c_viscosity():
    # VG 220 with ν100 = 19 mm²/s: the line passes through both points, by construction
    oil = Lubricant(220, 313.15, 19e-6)
    assert_allclose(oil.viscosity(), 220e-6, rtol=1e-9)
    assert_allclose(oil.viscosity(373.15), 19e-6, rtol=1e-9)


def test_default_slope_gives_a_vg320_mineral_oil_its_usual_100c_viscosity():
    # B = 3.5 (VI ≈ 95): ν100 of a VG 320 gear oil from makers' sheets is 22-25 mm²/s.
    nu100 = Lubricant(320, 373.15).viscosity() * 1e6
    assert 20.0 < nu100 < 27.0


def test_density_and_dynamic_viscosity_at_70c_by_hand():
    # ρ(70 °C) = 880 (1 − 0.00065 × 55) = 848.54 kg/m³; η = ν ρ
    oil = Lubricant(320, 343.15)
    assert_allclose(oil.density(), 880.0 * (1 - 0.00065 * 55.0), rtol=1e-12)
    w40 = math.log10(math.log10(320.7))
    nu = 10 ** (10 ** (w40 - 3.5 * math.log10(343.15 / 313.15))) - 0.7  # mm²/s
    assert_allclose(oil.dynamic_viscosity(), nu * 1e-6 * 848.54, rtol=1e-9)
