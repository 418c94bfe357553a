"""ISO 6336-1 method B mesh stiffness against hand computations and the DTU seed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InputError, InvalidGearTrain
from pinwind.gears.contact import PathOfContact, pairs_in_contact
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import (
    contact_line_pair_stiffness,
    mesh_stiffness,
    pair_stiffness_along_path,
    single_pair_stiffness,
)
from tests.conftest import dtu_pairs

ALPHA_20 = math.radians(20.0)
#: Face width [m] of a pair whose stiffness no test here reads.
WIDTH = 0.05
# ISO 6336-1 method B, C1…C9 [mm·µm/N], typed again here from the standard's table.
C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def iso_flexibility(z_n1: float, z_n2: float, x1: float, x2: float) -> float:
    """q′ [mm·µm/N]; z_n2 = math.inf for an internal gear."""
    return (
        C[0]
        + C[1] / z_n1
        + C[2] / z_n2
        + C[3] * x1
        + C[4] * x1 / z_n1
        + C[5] * x2
        + C[6] * x2 / z_n2
        + C[7] * x1**2
        + C[8] * x2**2
    )


def test_single_stiffness_of_unshifted_17_43_spur_pair():
    # q′ = 0.04723 + 0.15551/17 + 0.25791/43 = 0.04723 + 0.0091476 + 0.0059979 = 0.0623755,
    # c′_th = 16.032 N/(mm·µm); c′ = 16.032 · C_M 0.8 · C_B 0.975 = 12.505 N/(mm·µm)
    # (C_B = 1 + 0.5 (1.2 − 1.25) = 0.975 at 20°). b = 20 mm: 250.10 N/µm = 2.5010e8 N/m.
    k = single_pair_stiffness(
        GearPair(17, 43, module=2e-3, pressure_angle=ALPHA_20, face_width=20e-3)
    )
    np.testing.assert_allclose(k, 0.8 * 0.975 / 0.0623755 * 20 * 1e6, rtol=2e-6)
    np.testing.assert_allclose(k, 2.5010e8, rtol=1e-4)


def test_single_stiffness_does_not_depend_on_module():
    # Method B is a stiffness per unit face width that only sees z, x, β and the rack.
    k_small = single_pair_stiffness(
        GearPair(20, 50, module=1e-3, pressure_angle=ALPHA_20, face_width=0.1)
    )
    k_large = single_pair_stiffness(
        GearPair(20, 50, module=25e-3, pressure_angle=ALPHA_20, face_width=0.1)
    )
    np.testing.assert_allclose(k_small, k_large, rtol=1e-14)


def test_dtu_sun_planet_single_stiffness_by_hand():
    # Jørgensen 2014: sun 20 (x 0.582), planet 35 (x 0.419), b = 210 mm, spur.
    # q′ terms: 0.04723 + 0.0077755 + 0.0073689 − 0.0036957 − 0.0033913 − 0.0008087
    #           − 0.0028957 + 0.0017919 + 0.0003195 = 0.0536944
    # c′ = 0.78/0.0536944 = 14.527 N/(mm·µm); c′ b = 14.527 · 210 N/µm = 3.0506e9 N/m.
    q = iso_flexibility(20, 35, 0.582, 0.419)
    np.testing.assert_allclose(q, 0.0536944, atol=2e-7)
    k = single_pair_stiffness(
        GearPair(
            20,
            35,
            module=10e-3,
            pressure_angle=ALPHA_20,
            profile_shift_1=0.582,
            profile_shift_2=0.419,
            face_width=0.21,
        )
    )
    np.testing.assert_allclose(k, 0.78 / q * 210 * 1e6, rtol=1e-12)
    np.testing.assert_allclose(k, 3.0506e9, rtol=1e-4)


def test_dtu_planet_ring_single_stiffness_treats_ring_as_rack():
    # Ring internal: z_n2 = ∞, so the C3 and C7 terms vanish. x2 = −0.840 keeps its ISO sign in
    # C6 x2 and C9 x2².
    # q′ = 0.04723 + 0.15551/35 − 0.00635·0.419 − 0.11654·0.419/35 − 0.00193·(−0.840)
    #      + 0.00529·0.419² + 0.00182·0.840²
    #    = 0.04723 + 0.0044431 − 0.0026607 − 0.0013952 + 0.0016212 + 0.0009287 + 0.0012842
    #    = 0.0514513
    # c′ b = 0.78/0.0514513 · 210e6 = 3.1836e9 N/m.
    q = iso_flexibility(35, math.inf, 0.419, -0.840)
    np.testing.assert_allclose(q, 0.0514513, atol=2e-7)
    k = single_pair_stiffness(dtu_pairs()[1])
    np.testing.assert_allclose(k, 0.78 / q * 210e6, rtol=1e-12)
    np.testing.assert_allclose(k, 3.1836e9, rtol=1e-4)


def test_dtu_single_pair_stiffness_is_near_003_fem_value():
    # Jørgensen 2014 §2.4: FEM single-tooth mesh stiffness "around 3.5·10⁹ N/m".
    # ISO method B gives 3.05e9 (sun/planet) and 3.18e9 (planet/ring), 9-13 % lower. The
    # tolerance is 20 %: C_M = 0.8 is ISO's mean ratio of measured to theoretical stiffness, and
    # the seed's FEM models its own gear bodies and contact.
    sun_planet = single_pair_stiffness(dtu_pairs()[0])
    planet_ring = single_pair_stiffness(dtu_pairs()[1])
    np.testing.assert_allclose([sun_planet, planet_ring], [3.5e9, 3.5e9], rtol=0.2)


def test_internal_gear_equals_external_gear_with_infinitely_many_teeth():
    kwargs = dict(module=4e-3, pressure_angle=ALPHA_20, profile_shift_1=0.3, face_width=50e-3)
    ring = single_pair_stiffness(GearPair(24, 80, profile_shift_2=-0.2, internal_2=True, **kwargs))
    rack_like = single_pair_stiffness(GearPair(24, 10**12, profile_shift_2=-0.2, **kwargs))
    external = single_pair_stiffness(GearPair(24, 80, profile_shift_2=-0.2, **kwargs))
    np.testing.assert_allclose(ring, rack_like, rtol=1e-9)
    assert abs(ring - external) > 1e-3 * external


def test_helical_single_stiffness_uses_virtual_teeth_and_cos_beta():
    # z 21/64, β 15°, α_n 20°, x 0.2/−0.1. α_t = atan(tan α_n/cos β), β_b = atan(tan β cos α_t),
    # z_n = z/(cos² β_b cos β); c′ = 0.78 cos β/q′.
    beta = math.radians(15.0)
    alpha_t = math.atan(math.tan(ALPHA_20) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    factor = math.cos(beta_b) ** 2 * math.cos(beta)
    q = iso_flexibility(21 / factor, 64 / factor, 0.2, -0.1)
    k = single_pair_stiffness(
        GearPair(
            21,
            64,
            module=3e-3,
            pressure_angle=ALPHA_20,
            profile_shift_1=0.2,
            profile_shift_2=-0.1,
            helix_angle=beta,
            face_width=30e-3,
        )
    )
    np.testing.assert_allclose(k, 0.78 * math.cos(beta) / q * 30e6, rtol=1e-12)


@pytest.mark.parametrize(
    ("dedendum", "alpha_deg", "c_b"),
    [(1.2, 20.0, 1.0), (1.25, 20.0, 0.975), (1.4, 20.0, 0.9), (1.25, 25.0, 0.975 * 1.1)],
)
def test_basic_rack_factor_scales_single_stiffness(dedendum, alpha_deg, c_b):
    # C_B = [1 + 0.5 (1.2 − h_fP/m_n)] [1 − 0.02 (20° − α_n)]: 1.4 → 0.9, α_n 25° → × 1.1.
    alpha = math.radians(alpha_deg)
    k = single_pair_stiffness(
        GearPair(
            30,
            60,
            module=3e-3,
            pressure_angle=alpha,
            face_width=10e-3,
            dedendum_coefficient=dedendum,
        )
    )
    np.testing.assert_allclose(k, 0.8 * c_b / iso_flexibility(30, 60, 0, 0) * 10e6, rtol=1e-12)


def test_mesh_stiffness_is_iso_c_gamma_alpha():
    # z 20/40, m 5, α 20°, no shift: ε_α = 24.136/14.761 = 1.6351 from the closed form in
    # test_contact.py; c_γα b = c′ b (0.75 ε_α + 0.25).
    m = 5e-3
    rb1, rb2 = 10 * m * math.cos(ALPHA_20), 20 * m * math.cos(ALPHA_20)
    g = (
        math.sqrt((11 * m) ** 2 - rb1**2)
        + math.sqrt((21 * m) ** 2 - rb2**2)
        - 30 * m * math.sin(ALPHA_20)
    )
    eps = g / (math.pi * m * math.cos(ALPHA_20))
    kwargs = dict(module=m, pressure_angle=ALPHA_20, face_width=40e-3)
    single = single_pair_stiffness(GearPair(20, 40, **kwargs))
    np.testing.assert_allclose(
        mesh_stiffness(GearPair(20, 40, **kwargs)), single * (0.75 * eps + 0.25), rtol=1e-12
    )


def planet_ring_path_and_stiffness() -> tuple[PathOfContact, float]:
    pair = dtu_pairs()[1]
    return pair.path_of_contact(), single_pair_stiffness(pair)


@pytest.mark.parametrize("mesh", ["textbook", "dtu_planet_ring"])
def test_mean_mesh_stiffness_equals_iso_c_gamma(mesh):
    # The mean over one base pitch of the summed stiffness is ∫₀^g k(s) ds / p_bt: every point
    # of the path is visited by exactly one pair per pitch.
    if mesh == "textbook":
        path = GearPair(
            20, 40, module=5e-3, pressure_angle=ALPHA_20, face_width=WIDTH
        ).path_of_contact()
        single = 1.0e9
    else:
        path, single = planet_ring_path_and_stiffness()
    s, k = pair_stiffness_along_path(path, single)
    integral = float(np.sum(np.diff(s) * 0.5 * (k[1:] + k[:-1])))
    expected = single * (0.75 * path.contact_ratio + 0.25)
    np.testing.assert_allclose(integral / path.base_pitch, expected, rtol=1e-12)


def test_summed_stiffness_is_c_prime_in_single_zone_and_1_75_c_prime_in_double_zone():
    path, single = planet_ring_path_and_stiffness()
    s, k = pair_stiffness_along_path(path, single)
    p, g = path.base_pitch, path.length

    def summed(phase: float) -> float:
        # The pairs sit at phase, phase + p_bt, ...; stiffness is 0 off the path.
        positions = phase + p * np.arange(3)
        on_path = positions <= g
        return float(np.sum(np.interp(positions[on_path], s, k)))

    b, d = path.single_start, path.single_end
    for phase, pairs, factor in ((0.5 * b, 2, 1.75), (0.5 * (b + d), 1, 1.0)):
        assert pairs_in_contact(path, phase) == pairs
        np.testing.assert_allclose(summed(phase), factor * single, rtol=1e-12)
    # Mean over a fine, jump-avoiding phase grid agrees with c_γα b to O(1/N).
    phases = (np.arange(20_000) + 0.5) / 20_000 * p
    mean = np.mean([summed(x) for x in phases])
    np.testing.assert_allclose(mean, single * (0.75 * path.contact_ratio + 0.25), rtol=1e-4)


def test_pair_stiffness_rejects_contact_ratio_above_two():
    path = PathOfContact(
        base_pitch=1.0,
        length=2.3,
        contact_ratio=2.3,
        overlap_ratio=0.0,
        start_roll_1=0.1,
        pitch_roll_1=1.0,
        single_start=1.3,
        single_end=1.0,
        tip_radius_1=1.0,
        tip_radius_2=2.0,
        working_pressure_angle=ALPHA_20,
    )
    with pytest.raises(InputError, match="2.3000"):
        pair_stiffness_along_path(path, 1e9)


def test_nonpositive_face_width_is_rejected():
    with pytest.raises(InvalidGearTrain, match="face width"):
        single_pair_stiffness(
            GearPair(20, 40, module=5e-3, pressure_angle=ALPHA_20, face_width=0.0)
        )


def helical_path(epsilon_alpha: float, epsilon_beta: float) -> PathOfContact:
    """A path of contact with unit base pitch and the given transverse and overlap ratios."""
    return PathOfContact(
        base_pitch=1.0,
        length=epsilon_alpha,
        contact_ratio=epsilon_alpha,
        overlap_ratio=epsilon_beta,
        start_roll_1=0.1,
        pitch_roll_1=0.8,
        single_start=epsilon_alpha - 1.0,
        single_end=1.0,
        tip_radius_1=1.0,
        tip_radius_2=2.0,
        working_pressure_angle=ALPHA_20,
    )


@pytest.mark.parametrize(
    ("epsilon_alpha", "epsilon_beta"), [(1.5, 1.09), (1.62, 0.45), (1.3, 2.0), (2.2, 0.8)]
)
def test_helical_summed_stiffness_follows_the_contact_line_length(epsilon_alpha, epsilon_beta):
    # Plane of action g_α = ε_α p_bt long, face width b; a pair's contact line is inclined at β_b
    # across the face, so the pair at y (front section) touches at y − z tan β_b for z ∈ [0, b].
    # L(y): the measure of the face where that lies on [0, g_α], summed over the pairs (here by
    # midpoint quadrature across the face, not the trapezoid), over its mean b ε_α.
    path = helical_path(epsilon_alpha, epsilon_beta)
    mean = 3.0e9
    y_table, k_table = contact_line_pair_stiffness(path, mean)
    overlap = epsilon_beta  # b tan β_b = ε_β p_bt, p_bt = 1; measure z in units of b tan β_b
    z = (np.arange(4000) + 0.5) / 4000 * overlap
    phases = np.linspace(0.0, 1.0, 101)
    pairs = np.arange(int(epsilon_alpha + epsilon_beta) + 2)
    lengths = np.array(
        [
            sum(np.mean((x + j - z >= 0.0) & (x + j - z <= epsilon_alpha)) for j in pairs)
            for x in phases
        ]
    )
    stiffness = np.array(
        [sum(np.interp(x + j, y_table, k_table, right=0.0) for j in pairs) for x in phases]
    )
    np.testing.assert_allclose(stiffness / mean, lengths / epsilon_alpha, atol=1e-3)


@pytest.mark.parametrize(
    ("epsilon_alpha", "epsilon_beta"), [(1.5, 1.09), (1.62, 0.45), (1.8, 1.6), (1.3, 2.0)]
)
def test_helical_stiffness_extremes_match_the_minimum_contact_length(epsilon_alpha, epsilon_beta):
    # With n_α, n_β the fractional parts of ε_α, ε_β, the total contact-line length over its mean
    # ranges over 1 + [max(0, n_α + n_β − 1) − n_α n_β] / (ε_α ε_β) (the minimum is AGMA 908's
    # L_min = (ε_α b − n_α n_β p_x or (1 − n_α)(1 − n_β) p_x) / cos β_b) to
    # 1 + [min(n_α, n_β) − n_α n_β] / (ε_α ε_β); ε_β = 1.09, ε_α = 1.5 gives 0.9725–1.0275.
    path = helical_path(epsilon_alpha, epsilon_beta)
    mean = 2.0e9
    y_table, k_table = contact_line_pair_stiffness(path, mean)
    phases = np.linspace(0.0, 1.0, 20_001)
    stiffness = sum(np.interp(phases + j, y_table, k_table, right=0.0) for j in range(5))
    n_a, n_b = epsilon_alpha % 1.0, epsilon_beta % 1.0
    spread = epsilon_alpha * epsilon_beta
    low = 1.0 + (max(0.0, n_a + n_b - 1.0) - n_a * n_b) / spread
    high = 1.0 + (min(n_a, n_b) - n_a * n_b) / spread
    np.testing.assert_allclose(
        [stiffness.min(), stiffness.max()], [low * mean, high * mean], rtol=1e-9
    )
    np.testing.assert_allclose(np.mean(stiffness[:-1]), mean, rtol=1e-6)


def test_contact_line_stiffness_refuses_a_spur_pair():
    with pytest.raises(InputError, match="ε_β > 0"):
        contact_line_pair_stiffness(helical_path(1.6, 0.0), 1e9)


def test_single_stiffness_numbers_the_pinion_first_whichever_external_gear_comes_first():
    # NREL 5 MW stage 3 as its model names it: wheel 95 (x 0.669) before pinion 24 (x 0.48),
    # β 10°, b 360 mm. ISO's gear 1 is the pinion: q′ = q′(z_n 24, z_n 95, x 0.48, x 0.669) by
    # the coefficients typed above, c′ b = 0.78 cos β / q′ · 360e6 N/m. Numbering the wheel 1
    # (C2/z_n1 + C3/z_n2 with z_n1 the wheel's) gives a q′ 2.8 % larger.
    beta = math.radians(10.0)
    alpha_t = math.atan(math.tan(ALPHA_20) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    factor = math.cos(beta_b) ** 2 * math.cos(beta)
    q = iso_flexibility(24 / factor, 95 / factor, 0.48, 0.669)
    wrong = iso_flexibility(95 / factor, 24 / factor, 0.669, 0.48)
    assert wrong / q - 1 > 0.02
    wheel_first = GearPair(
        95,
        24,
        module=14e-3,
        pressure_angle=ALPHA_20,
        profile_shift_1=0.669,
        profile_shift_2=0.48,
        helix_angle=beta,
        face_width=0.36,
    )
    expected = 0.78 * math.cos(beta) / q * 360e6
    np.testing.assert_allclose(single_pair_stiffness(wheel_first), expected, rtol=1e-12)
    np.testing.assert_allclose(single_pair_stiffness(wheel_first.reversed()), expected, rtol=1e-12)


def test_compliant_nrel_stage1_sun_mesh_takes_the_17_tooth_planet_as_iso_gear_1():
    # The model names the sun (19 teeth, x 0.617) first, but the planet (17, x 0.802) is ISO's
    # pinion. Spur, b 491 mm: c′ b = 0.78/q′(17, 19, 0.802, 0.617) · 491e6 N/m and c_γα b =
    # c′ b (0.75 ε_α + 0.25); the sun first gives a q′ 2.4 % smaller.
    import dataclasses

    import pinwind
    from pinwind.dynamics.compliant import mean_mesh_stiffness, single_pair
    from pinwind.model.compliance import MeshCompliance
    from tests.conftest import MODELS

    loaded = pinwind.load(MODELS / "nrel5mw_gearbox.urdf").mesh("stage1_sun_planet1")
    mesh = dataclasses.replace(loaded, compliance=MeshCompliance())
    q = iso_flexibility(17, 19, 0.802, 0.617)
    assert 1 - iso_flexibility(19, 17, 0.617, 0.802) / q > 0.02
    expected = 0.78 / q * 491e6
    np.testing.assert_allclose(single_pair(mesh), expected, rtol=1e-12)
    np.testing.assert_allclose(
        mean_mesh_stiffness(mesh),
        expected * (0.75 * mesh.path.contact_ratio + 0.25),
        rtol=1e-12,
    )


#: KISSsoft's ISO 6336:2006 method B reports of the NREL 5 MW planetary stages (Rebouças 2020,
#: docs/references.md): (z_sun, z_planet, z_ring, x_sun, x_planet, x_ring, b [mm]) and the
#: printed single stiffness c′ [N/(mm·µm)] of the sun–planet and planet–ring meshes, with
#: C_M = 0.8, C_R = 0.862 (b_s/b = 0.25), C_B = 0.975 and β = 0.
KISSSOFT_NREL_STAGES = (
    ((19, 17, 56, 0.6170, 0.8021, -0.5013, 491.0), (12.362, 13.289)),
    ((18, 36, 93, 0.3890, 0.5039, 0.1171, 550.0), (12.240, 14.053)),
)


@pytest.mark.parametrize(("stage", "printed"), KISSSOFT_NREL_STAGES)
def test_internal_gear_is_a_rack_in_q_prime_as_kisssoft_prints_it(stage, printed):
    # ISO 6336-1 method B's q′ for an internal pair: KISSsoft's c′ of both NREL 5 MW ring meshes
    # is that of z_n2 = ∞ (the C3 and C7 terms vanish), and not of the ring's tooth count with
    # either sign: for stage 1, 0.8 · 0.862 · 0.975/q′ with q′ = 0.050612 (z_n2 = ∞) is 13.284
    # against the printed 13.289; with z_n2 = −56 (q′ = 0.043842) it would be 15.336, with
    # z_n2 = +56 (q′ = 0.057382) 11.717. The sun meshes take the pinion (fewer teeth) as gear 1:
    # stage 1's 17-tooth planet, 12.357 against 12.362 (the sun as gear 1 would give 12.660).
    z_s, z_p, z_r, x_s, x_p, x_r, width = stage
    factor = 0.8 * 0.862 * 0.975
    pinion, wheel = sorted(((z_s, x_s), (z_p, x_p)))
    hand = (
        factor / iso_flexibility(pinion[0], wheel[0], pinion[1], wheel[1]),
        factor / iso_flexibility(z_p, math.inf, x_p, x_r),
    )
    kwargs = dict(module=0.02, pressure_angle=ALPHA_20, face_width=width * 1e-3)
    pairs = (
        GearPair(z_s, z_p, profile_shift_1=x_s, profile_shift_2=x_p, **kwargs),
        GearPair(z_p, z_r, profile_shift_1=x_p, profile_shift_2=x_r, internal_2=True, **kwargs),
    )
    for pair, by_hand, kisssoft in zip(pairs, hand, printed, strict=True):
        c_prime = single_pair_stiffness(pair, rim_factor=0.862) / (width * 1e6)  # N/(mm·µm)
        np.testing.assert_allclose(c_prime, by_hand, rtol=1e-12)
        # KISSsoft prints C_R and c′ to three decimals: within 1e-3 of it.
        np.testing.assert_allclose(c_prime, kisssoft, rtol=1e-3)
    # The other readings of the ring's z_n2 are 5-15 % off the printed value.
    for z_n2 in (-z_r, z_r):
        other = factor / iso_flexibility(z_p, z_n2, x_p, x_r)
        assert abs(other / printed[1] - 1) > 0.04
