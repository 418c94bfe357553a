"""ISO 6336-2/-3 rating: factors against closed forms and chart values, stresses by hand."""

import math
from dataclasses import fields

import pytest

from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.involute import involute
from pinwind.gears.rating_iso import (
    IsoFactors,
    ResolvedIsoFactors,
    form_factors,
    iso_rating,
    single_pair_ratios,
)


def _pair(z1=17, z2=52, internal=False, **kw):
    return GearPair(
        z1, z2, module=0.004, pressure_angle=math.radians(20.0), face_width=0.05,
        internal_2=internal, **kw,
    )  # fmt: skip


def test_zone_factor_of_unshifted_20_degree_spur_pair_is_2_495():
    r = iso_rating(_pair(), MeshLoad(20e3, 1.0))
    # Z_H = √(2/(cos α sin α)) at α_w = α = 20°: 2.495, the chart value of ISO 6336-2.
    assert r.factors.Z_H == pytest.approx(2.4946, abs=1e-4)


def test_elasticity_factor_of_two_steels_is_189_8_root_mpa():
    r = iso_rating(_pair(), MeshLoad(20e3, 1.0))
    assert r.factors.Z_E / 1e3 == pytest.approx(189.81, abs=0.01)  # √Pa → √MPa


def test_method_c_form_factors_of_20_teeth_match_iso_chart():
    pair = GearPair(20, 100, module=0.001, pressure_angle=math.radians(20.0), face_width=0.01)
    assert pair.tip_diameter(1) == pytest.approx(0.022, rel=1e-12)
    y_fa, y_sa = form_factors(pair, 1, at_tip=True)
    # ISO 6336-3 (DIN 3990-3) charts for the ISO 53 A rack, x = 0, z = 20: Y_Fa 2.80, Y_Sa 1.55.
    assert y_fa == pytest.approx(2.80, abs=0.01)
    assert y_sa == pytest.approx(1.55, abs=0.01)


def test_single_pair_ratio_from_roll_distances_equals_iso_formula():
    pair = _pair()
    m1, m2 = single_pair_ratios(pair)
    eps = pair.path.contact_ratio
    alpha_w = math.radians(20.0)
    z1, z2 = 17, 52
    ta1 = math.sqrt((19 / (17 * math.cos(alpha_w))) ** 2 - 1)  # d_a1/d_b1 = (z1+2)/(z1 cos α)
    ta2 = math.sqrt((54 / (52 * math.cos(alpha_w))) ** 2 - 1)
    iso_m1 = math.tan(alpha_w) / math.sqrt(
        (ta1 - 2 * math.pi / z1) * (ta2 - (eps - 1) * 2 * math.pi / z2)
    )
    iso_m2 = math.tan(alpha_w) / math.sqrt(
        (ta2 - 2 * math.pi / z2) * (ta1 - (eps - 1) * 2 * math.pi / z1)
    )
    assert m1 == pytest.approx(iso_m1, rel=1e-12)
    assert m2 == pytest.approx(iso_m2, rel=1e-12)


def test_stresses_with_every_factor_given_equal_the_iso_equations_by_hand():
    pair = _pair(material_1="18CrNiMo7-6", material_2="42CrMo4")
    given = IsoFactors(
        K_A=1.25, K_gamma=1.1, K_v=1.05, K_Hbeta=1.3, K_Fbeta=1.25, K_Halpha=1.1, K_Falpha=1.1,
        Z_H=2.49, Z_E=189.8e3, Z_eps=0.88, Z_beta=1.0, Z_B=1.1, Z_D=1.0,
        Z_NT=(0.95, 1.0), Z_L=(0.98, 0.98), Z_v=(0.99, 0.99), Z_R=(0.96, 0.96),
        Z_W=(1.0, 1.05), Z_X=(1.0, 1.0), Y_F=(1.65, 1.35), Y_S=(1.80, 2.00), Y_beta=1.0,
        Y_B=(1.0, 1.0), Y_DT=1.0, Y_ST=2.0, Y_NT=(0.9, 1.0), Y_delta=(0.99, 1.0),
        Y_R=(1.0, 0.98), Y_X=(1.0, 1.0), S_H_min=1.2, S_F_min=1.5,
    )  # fmt: skip
    f_t = 25e3
    r = iso_rating(pair, MeshLoad(f_t, 3.0), given)
    d1, b, u, m = 0.068, 0.05, 52 / 17, 0.004
    sigma_h0 = 2.49 * 189.8e3 * 0.88 * 1.0 * math.sqrt(f_t / (d1 * b) * (u + 1) / u)
    k_h = math.sqrt(1.25 * 1.1 * 1.05 * 1.3 * 1.1)
    assert r.sigma_H0 == pytest.approx(sigma_h0, rel=1e-12)
    assert r.sigma_H == pytest.approx((1.1 * sigma_h0 * k_h, sigma_h0 * k_h), rel=1e-12)
    s_h1 = 1500e6 * 0.95 * 0.98 * 0.99 * 0.96 / (1.1 * sigma_h0 * k_h)
    s_h2 = 770e6 * 0.98 * 0.99 * 0.96 * 1.05 / (sigma_h0 * k_h)
    assert r.S_H == pytest.approx((s_h1, s_h2), rel=1e-12)
    k_f = 1.25 * 1.1 * 1.05 * 1.25 * 1.1
    sigma_f = (f_t / (b * m) * 1.65 * 1.80 * k_f, f_t / (b * m) * 1.35 * 2.00 * k_f)
    assert r.sigma_F == pytest.approx(sigma_f, rel=1e-12)
    s_f = (500e6 * 2 * 0.9 * 0.99 / sigma_f[0], 310e6 * 2 * 0.98 / sigma_f[1])
    assert r.S_F == pytest.approx(s_f, rel=1e-12)
    assert r.sigma_H_permissible[0] == pytest.approx(s_h1 * r.sigma_H[0] / 1.2, rel=1e-12)


def test_internal_mesh_uses_difference_of_tooth_numbers_in_the_ratio_term():
    given = IsoFactors(K_v=1.0, K_Hbeta=1.0)
    external = iso_rating(_pair(48, 120), MeshLoad(1e5, 1.0), given)
    internal = iso_rating(_pair(48, 120, True), MeshLoad(1e5, 1.0), given)
    # (u + 1)/u is (120 + 48)/120 outside and (120 − 48)/120 inside; Z_H is the same (no shift)
    # and Z_ε follows each pair's contact ratio.
    expected = math.sqrt(72 / 168) * internal.factors.Z_eps / external.factors.Z_eps
    assert internal.sigma_H0 / external.sigma_H0 == pytest.approx(expected, rel=1e-12)
    assert internal.factors.Z_D == 1.0


def test_involute_helper_is_tan_minus_angle():
    assert involute(math.radians(20.0)) == pytest.approx(0.014904383867336446, rel=1e-12)


def test_resolved_factors_have_the_fields_of_the_given_ones_in_order():
    assert [f.name for f in fields(ResolvedIsoFactors)] == [f.name for f in fields(IsoFactors)]


def test_rating_again_with_the_resolved_factors_gives_the_same_stresses():
    pair, load = _pair(25, 97, True), MeshLoad(5e4, 4.0)
    first = iso_rating(pair, load, IsoFactors(K_A=1.25, base_pitch_deviation=12e-6))
    assert iso_rating(pair, load, first.factors) == first


def test_root_face_load_exponent_takes_the_tooth_depth_with_its_tip_alteration():
    """K_Fβ = K_Hβ^N_F with h the tooth depth h_aP + k m_n + h_fP (DIN 3990), the deeper tooth's.

    The NREL 5 MW helical stage's teeth: m_n = 14 mm, b = 360 mm, tips shortened by 0.938 mm on
    the pinion and 0.5 mm on the wheel here: h = 2.25 · 14 − 0.5 = 31.0 mm (the wheel's, the
    deeper tooth), b/h = 11.613, N_F = (b/h)²/(1 + b/h + (b/h)²) = 0.91447. The basic rack's
    2.25 m_n alone (31.5 mm) gives 0.91311: K_Fβ 3.6e-4 lower at K_Hβ = 1.3.
    """
    pair = GearPair(
        24, 95, module=0.014, pressure_angle=math.radians(20.0), face_width=0.36,
        profile_shift_1=0.48, profile_shift_2=0.669, helix_angle=math.radians(10.0),
        tip_alteration_1=-0.938e-3, tip_alteration_2=-0.5e-3,
    )  # fmt: skip
    b_h = 360.0 / 31.0
    n_f = b_h**2 / (1 + b_h + b_h**2)
    assert n_f == pytest.approx(0.91447, abs=1e-5)
    r = iso_rating(pair, MeshLoad(2e5, 1.0), IsoFactors(K_Hbeta=1.3))
    assert r.factors.K_Fbeta == pytest.approx(1.3**n_f, rel=1e-12)
