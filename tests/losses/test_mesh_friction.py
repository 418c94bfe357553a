"""ISO/TR 14179-2's mean coefficient of friction μ_mz and Ohlendorf's H_V, by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.errors import InvalidLossInput
from pinwind.gears.gear_pair import GearPair
from pinwind.losses.mesh_friction import (
    mean_friction_coefficient,
    mesh_power_loss,
    pair_friction_coefficient,
    pitch_point_conditions,
    tooth_loss_factor,
)
from pinwind.losses.oil import Lubricant


def test_mean_friction_coefficient_at_two_operating_points_by_hand():
    # μ_mz = 0.048 (F_bt/b / (v_Σc ρ_redC))^0.2 η^-0.05 Ra^0.25 X_L, with F_bt [N], b [mm],
    # v [m/s], ρ [mm], η [mPa·s], Ra [µm] (ISO/TR 14179-2).
    # 1: F_bt = 20 kN, b = 100 mm, v_Σc = 10 m/s, ρ_redC = 20 mm, η = 50 mPa·s, Ra = 0.5 µm:
    #    (200 / 200)^0.2 = 1; 50^-0.05 = 0.82253; 0.5^0.25 = 0.84090 → 0.048 × 0.69167 = 0.033200
    mu_1 = 0.048 * 1.0 * 50.0**-0.05 * 0.5**0.25
    got = mean_friction_coefficient(
        transverse_force=20e3, face_width=0.1, sum_velocity=10.0, reduced_radius=0.02,
        dynamic_viscosity=0.05, roughness=0.5e-6,
    )  # fmt: skip
    assert_allclose(got, mu_1, rtol=1e-12)
    assert 0.03 < mu_1 < 0.04  # the usual range of dip-lubricated gears
    # 2: twice the load, half the speed (group × 4: μ × 4^0.2), polyalphaolefin X_L = 0.8
    got = mean_friction_coefficient(
        transverse_force=40e3, face_width=0.1, sum_velocity=5.0, reduced_radius=0.02,
        dynamic_viscosity=0.05, roughness=0.5e-6, lubricant_factor=0.8,
    )  # fmt: skip
    assert_allclose(got, mu_1 * 4.0**0.2 * 0.8, rtol=1e-12)


def test_mean_friction_coefficient_refuses_a_standstill():
    with pytest.raises(InvalidLossInput, match="sum_velocity"):
        mean_friction_coefficient(
            transverse_force=1e3, face_width=0.1, sum_velocity=0.0, reduced_radius=0.02,
            dynamic_viscosity=0.05, roughness=0.5e-6,
        )  # fmt: skip


def _textbook_pair() -> GearPair:
    # z 20/40, m 5 mm, α 20°, no profile shift, addendum 1 m: the textbook spur pair.
    return GearPair(20, 40, 0.005, math.radians(20.0), 0.05)


def _textbook_approach_ratios() -> tuple[float, float]:
    """ε_1, ε_2 of the textbook pair by hand: r_b = r cos α, r_a = r + m,
    ε_i = (√(r_ai² − r_bi²) − r_bi tan α) / p_b, p_b = π m cos α (lengths in mm)."""
    alpha = math.radians(20.0)
    p_b = math.pi * 5.0 * math.cos(alpha)
    r_b = [r * math.cos(alpha) for r in (50.0, 100.0)]
    e1, e2 = (
        (math.sqrt((r + 5.0) ** 2 - rb**2) - rb * math.tan(alpha)) / p_b
        for r, rb in zip((50.0, 100.0), r_b, strict=True)
    )
    return e1, e2


def test_tooth_loss_factor_of_a_textbook_spur_pair_by_hand():
    e1, e2 = _textbook_approach_ratios()  # ε_α = 1.6352
    assert_allclose(e1 + e2, 1.6352, atol=1e-4)
    u = 2.0
    h_v = math.pi * (u + 1) / (20 * u) * (1 - (e1 + e2) + e1**2 + e2**2)  # 0.1661
    assert_allclose(tooth_loss_factor(_textbook_pair()), h_v, rtol=1e-9)
    assert_allclose(h_v, 0.1661, atol=1e-4)


def _sliding_integral(e1: float, e2: float, n: int = 400_000) -> float:
    """2 ∫ s(y) |y| dy over the path y ∈ [−e1, e2] [base pitches], by the midpoint rule.

    s = ½ where two pairs share the load (the first and last ε_α − 1 of the path), else 1.
    """
    length = e1 + e2
    x = (np.arange(n) + 0.5) * length / n  # from the path's start
    share = np.where((x < length - 1.0) | (x > 1.0), 0.5, 1.0)
    return float(2.0 * np.sum(share * np.abs(x - e1)) * length / n)


def test_tooth_loss_factor_is_the_sliding_integral_where_the_pitch_point_is_in_a_double_zone():
    # planet 30 in ring 90, m 5 mm, 20°: u = −3, (u + 1)/u = 2/3 (less sliding than external).
    # ε_α = 1.91 > 1 + min(ε_1, ε_2): the pitch point lies in a double-contact zone, where
    # Ohlendorf's closed form 1 − ε_α + ε_1² + ε_2² is not the integral it stands for.
    alpha = math.radians(20.0)
    p_b = math.pi * 5.0 * math.cos(alpha)
    r1, r2 = 75.0, 225.0
    rb1, rb2 = r1 * math.cos(alpha), r2 * math.cos(alpha)
    e1 = (math.sqrt((r1 + 5.0) ** 2 - rb1**2) - rb1 * math.tan(alpha)) / p_b
    e2 = (rb2 * math.tan(alpha) - math.sqrt((r2 - 5.0) ** 2 - rb2**2)) / p_b  # ring tip inside
    assert min(e1, e2) < e1 + e2 - 1.0
    u = -3.0
    h_v = math.pi * (u + 1) / (30 * u) * _sliding_integral(e1, e2)
    pair = GearPair(30, 90, 0.005, alpha, 0.05, internal_2=True)
    assert_allclose(tooth_loss_factor(pair), h_v, rtol=1e-5)
    ohlendorf = math.pi * (u + 1) / (30 * u) * (1 - (e1 + e2) + e1**2 + e2**2)
    assert tooth_loss_factor(pair) < 0.995 * ohlendorf  # 1 % below: the zone just covers P


def test_tooth_loss_factor_is_ohlendorfs_closed_form_in_the_single_contact_zone():
    # the textbook pair (ε_1 = 0.80, ε_2 = 0.83 ≥ ε_α − 1 = 0.64): the integral by quadrature
    # equals Ohlendorf's bracket, and so does tooth_loss_factor
    e1, e2 = _textbook_approach_ratios()
    bracket = 1 - (e1 + e2) + e1**2 + e2**2
    assert_allclose(_sliding_integral(e1, e2), bracket, rtol=1e-5)
    assert_allclose(tooth_loss_factor(_textbook_pair()), math.pi * 3 / 40 * bracket, rtol=1e-12)


def test_pitch_point_sum_velocity_and_radius_by_hand():
    # v_t = ω r_w1 = 100 × 0.05 = 5 m/s; v_Σc = 2 v_t sin 20° = 3.4202 m/s;
    # ρ1 = 50 sin 20°, ρ2 = 100 sin 20° [mm]: ρ_red = ρ1 ρ2 / (ρ1 + ρ2) = 11.4007 mm
    v, rho = pitch_point_conditions(_textbook_pair(), 100.0)
    s = math.sin(math.radians(20.0))
    assert_allclose(v, 2 * 5.0 * s, rtol=1e-12)
    assert_allclose(rho, 0.05 * s * 0.1 * s / (0.15 * s), rtol=1e-12)


def test_mesh_power_loss_is_input_power_times_mu_times_h_v():
    assert_allclose(mesh_power_loss(2.0e6, 0.04, 0.17), 2.0e6 * 0.04 * 0.17, rtol=1e-15)


def test_pair_friction_coefficient_at_a_pitch_line_speed_by_hand():
    # textbook pair, F_bt = 10 kN, v_t = 5 m/s, VG 320 at 70 °C, Ra 0.5 µm: v_Σc = 2 × 5 sin 20°,
    # ρ_redC = 50 × 100 / 150 sin 20° [mm], η = ν ρ (Walther, DIN 51757) [mPa·s], b = 50 mm
    s = math.sin(math.radians(20.0))
    w40 = math.log10(math.log10(320.7))
    nu = 10 ** (10 ** (w40 - 3.5 * math.log10(343.15 / 313.15))) - 0.7
    eta = nu * 880.0 * (1 - 0.00065 * 55.0) * 1e-3
    mu = 0.048 * (10e3 / 50.0 / (10.0 * s * (100.0 / 3.0 * s))) ** 0.2 * eta**-0.05 * 0.5**0.25
    got = pair_friction_coefficient(
        _textbook_pair(), transverse_force=10e3, pitch_line_speed=5.0,
        oil=Lubricant(320, 343.15), roughness=0.5e-6,
    )  # fmt: skip
    assert_allclose(got, mu, rtol=1e-9)
