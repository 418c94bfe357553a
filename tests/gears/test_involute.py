"""Involute pair geometry against closed forms, a textbook example and the DTU seed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.gears.involute import half_tooth_angle, pair_geometry

ALPHA_20 = math.radians(20.0)


def inv(angle: float) -> float:
    return math.tan(angle) - angle


def inv_inverse(value: float) -> float:
    """Newton on tan a − a = value (independent of the brentq in the code)."""
    angle = (3.0 * value) ** (1.0 / 3.0)  # inv a ≈ a³/3 for small a
    for _ in range(50):
        angle -= (inv(angle) - value) / math.tan(angle) ** 2
    return angle


def working_pressure_angle(z1: int, z2: int, x1: float, x2: float, alpha: float) -> float:
    """ISO 21771 with signed tooth numbers (internal gear negative)."""
    return inv_inverse(inv(alpha) + 2.0 * math.tan(alpha) * (x1 + x2) / (z1 + z2))


@pytest.mark.parametrize(("z1", "z2", "module"), [(24, 48, 15e-3), (40, 80, 3e-3), (17, 91, 1e-3)])
def test_unshifted_external_pair_sits_at_reference_centre_distance(z1, z2, module):
    geo = pair_geometry(z1, z2, module=module, pressure_angle=ALPHA_20)
    np.testing.assert_allclose(geo.centre_distance, module * (z1 + z2) / 2.0, rtol=1e-12)
    np.testing.assert_allclose(geo.working_pressure_angle, ALPHA_20, rtol=0, atol=1e-9)
    np.testing.assert_allclose(geo.working_radius_1, module * z1 / 2.0, rtol=1e-12)
    np.testing.assert_allclose(geo.working_radius_2, module * z2 / 2.0, rtol=1e-12)


def test_unshifted_internal_pair_sits_at_half_the_tooth_difference():
    # Saleh planet–ring: m (z_ring − z_planet)/2 = 15 mm · (120 − 48)/2 = 540 mm.
    geo = pair_geometry(48, 120, module=15e-3, pressure_angle=math.radians(24.5), internal_2=True)
    np.testing.assert_allclose(geo.centre_distance, 0.540, rtol=1e-12)
    np.testing.assert_allclose(geo.working_pressure_angle, math.radians(24.5), atol=1e-9)


def test_zero_total_shift_leaves_pressure_angle_and_centre_distance_unchanged():
    geo = pair_geometry(
        18, 45, module=4e-3, pressure_angle=ALPHA_20, profile_shift_1=0.35, profile_shift_2=-0.35
    )
    np.testing.assert_allclose(geo.working_pressure_angle, ALPHA_20, rtol=0, atol=1e-9)
    np.testing.assert_allclose(geo.centre_distance, 4e-3 * 63 / 2.0, rtol=1e-12)


def test_khk_profile_shifted_external_pair():
    # KHK "Calculation of Gear Dimensions", Table 4-4 (profile shifted spur gears): z 12/24,
    # m 3 mm, α 20°, x 0.6/0.36 give α_w = 26.0886° and a = 56.4999 mm (y = 0.8333).
    # Check by hand: inv α_w = 0.014904 + 2 tan 20° · 0.96/36 = 0.034316 → 26.0886°,
    # a_w = 54 cos 20°/cos α_w = 56.4999 mm.
    geo = pair_geometry(
        12, 24, module=3e-3, pressure_angle=ALPHA_20, profile_shift_1=0.6, profile_shift_2=0.36
    )
    np.testing.assert_allclose(math.degrees(geo.working_pressure_angle), 26.0886, atol=1e-4)
    np.testing.assert_allclose(geo.centre_distance * 1e3, 56.4999, atol=1e-4)
    np.testing.assert_allclose(
        geo.working_pressure_angle, working_pressure_angle(12, 24, 0.6, 0.36, ALPHA_20), atol=1e-12
    )


def test_base_circles_fix_the_working_centre_distance():
    # r_b = r_w cos α_w on both gears, and the working circles touch: r_w1 + r_w2 = a_w.
    geo = pair_geometry(
        19, 53, module=5e-3, pressure_angle=ALPHA_20, profile_shift_1=0.4, profile_shift_2=0.1
    )
    cos_w = math.cos(geo.working_pressure_angle)
    np.testing.assert_allclose(geo.base_radius_1, 5e-3 * 19 / 2 * math.cos(ALPHA_20), rtol=1e-12)
    np.testing.assert_allclose(geo.working_radius_1 * cos_w, geo.base_radius_1, rtol=1e-12)
    np.testing.assert_allclose(geo.working_radius_2 * cos_w, geo.base_radius_2, rtol=1e-12)
    np.testing.assert_allclose(
        geo.working_radius_1 + geo.working_radius_2, geo.centre_distance, rtol=1e-12
    )


def test_internal_pair_follows_iso_sign_convention():
    # ISO 21771: the internal gear counts z = −24. A negative x on the ring gives a positive
    # contribution (x1 + x2)/(z1 + z2) = (0 − 0.516)/(16 − 24) > 0: the pressure angle grows and
    # the pinion moves away from the ring's centre, a_w > m (z2 − z1)/2 = 12 mm.
    geo = pair_geometry(
        16, 24, module=3e-3, pressure_angle=ALPHA_20, profile_shift_2=-0.516, internal_2=True
    )
    alpha_w = working_pressure_angle(16, -24, 0.0, -0.516, ALPHA_20)
    np.testing.assert_allclose(geo.working_pressure_angle, alpha_w, atol=1e-12)
    expected = 3e-3 * 8 / 2.0 * math.cos(ALPHA_20) / math.cos(alpha_w)
    np.testing.assert_allclose(geo.centre_distance, expected, rtol=1e-12)
    assert geo.centre_distance > 12e-3
    # Internal pair: the working circles touch from inside, r_w2 − r_w1 = a_w.
    np.testing.assert_allclose(
        geo.working_radius_2 - geo.working_radius_1, geo.centre_distance, rtol=1e-12
    )


def dtu_meshes(module: float = 10e-3, alpha: float = ALPHA_20):
    # Jørgensen 2014 §2.1: teeth 20/35/91, x_s 0.582, x_p 0.419, x_r −0.840.
    sun_planet = pair_geometry(
        20, 35, module=module, pressure_angle=alpha, profile_shift_1=0.582, profile_shift_2=0.419
    )
    planet_ring = pair_geometry(
        35,
        91,
        module=module,
        pressure_angle=alpha,
        profile_shift_1=0.419,
        profile_shift_2=-0.840,
        internal_2=True,
    )
    return sun_planet, planet_ring


def test_dtu_sun_and_ring_meshes_share_one_centre_distance():
    sun_planet, planet_ring = dtu_meshes()
    np.testing.assert_allclose(sun_planet.centre_distance / 10e-3, 28.4005, rtol=5e-6)
    np.testing.assert_allclose(planet_ring.centre_distance / 10e-3, 28.4005, rtol=5e-6)


def test_dtu_table6_contact_points_follow_from_module_10mm_and_20deg():
    # Jørgensen 2014 Table 6: along the line of action, measured from the inner
    # gear's base-circle tangent point, contact starts at s0, single-tooth contact starts at
    # s0 + (g − p_b) and the next tooth enters at s0 + p_b. Sun/planet: 0.0243, 0.0382,
    # 0.0538 m; planet/ring: 0.044, 0.064, 0.0735 m. Tip radii r_a = m (|z|/2 ± (1 + x)).
    m = 10e-3
    p_b = math.pi * m * math.cos(ALPHA_20)
    sun_planet, planet_ring = dtu_meshes()

    def tip_length(z: int, x: float, internal: bool = False) -> float:
        r_b = m * z / 2 * math.cos(ALPHA_20)
        r_a = m * (z / 2 - 1 - x) if internal else m * (z / 2 + 1 + x)
        return math.sqrt(r_a**2 - r_b**2)

    line = sun_planet.centre_distance * math.sin(sun_planet.working_pressure_angle)
    s0 = line - tip_length(35, 0.419)
    g = tip_length(20, 0.582) + tip_length(35, 0.419) - line
    np.testing.assert_allclose([s0, s0 + g - p_b, s0 + p_b], [0.0243, 0.0382, 0.0538], atol=5e-5)

    line = planet_ring.centre_distance * math.sin(planet_ring.working_pressure_angle)
    s0 = tip_length(91, -0.840, internal=True) - line
    g = tip_length(35, 0.419) - s0
    np.testing.assert_allclose([s0, s0 + g - p_b, s0 + p_b], [0.044, 0.064, 0.0735], atol=5e-5)


def test_dtu_meshes_disagree_at_25_degrees():
    # The other "typical" pressure angle of the seed (α = 25°) breaks the common centre
    # distance, which is one more reason the shipped model uses 20°.
    sun_planet, planet_ring = dtu_meshes(alpha=math.radians(25.0))
    assert abs(sun_planet.centre_distance - planet_ring.centre_distance) > 1e-4 * 0.284


def test_helical_pair_centre_distance_uses_transverse_module():
    beta = math.radians(15.0)
    geo = pair_geometry(21, 64, module=4e-3, pressure_angle=ALPHA_20, helix_angle=beta)
    np.testing.assert_allclose(geo.centre_distance, 4e-3 * 85 / (2 * math.cos(beta)), rtol=1e-12)
    alpha_t = math.atan(math.tan(ALPHA_20) / math.cos(beta))
    np.testing.assert_allclose(geo.working_pressure_angle, alpha_t, atol=1e-9)


@pytest.mark.parametrize("internal", [False, True])
@pytest.mark.parametrize("shift", [0.0, 0.419, -0.84])
def test_half_tooth_angle_on_the_reference_circle_is_a_quarter_pitch_plus_the_shift(
    internal, shift
):
    # ISO 21771: s = m (π/2 + 2 x tan α) on d = z m, so ψ = s/d = (π/2 + 2 x tan α)/z.
    z, m = 35, 0.01
    psi = half_tooth_angle(
        z, module=m, pressure_angle=ALPHA_20, radius=z * m / 2.0, profile_shift=shift,
        internal=internal,
    )  # fmt: skip
    np.testing.assert_allclose(
        psi, (math.pi / 2.0 + 2.0 * shift * math.tan(ALPHA_20)) / z, rtol=1e-13
    )


@pytest.mark.parametrize(
    ("z1", "z2", "x1", "x2", "internal"),
    [
        (20, 35, 0.582, 0.419, False),  # DTU 500 kW sun-planet (Jørgensen 2014)
        (35, 91, 0.419, -0.840, True),  # DTU 500 kW planet-ring
        (17, 40, 0.3, -0.1, False),
    ],
)
def test_meshing_teeth_fill_the_working_pitch_without_backlash(z1, z2, x1, x2, internal):
    # On the working pitch circles the two tooth thicknesses add up to the working pitch
    # 2π r_w/z: 2 r_w1 ψ1 + 2 r_w2 ψ2 = 2π r_w1/z1, i.e. z1 ψ1 + z2 ψ2 = π (r_w1/z1 = r_w2/z2).
    m = 0.008
    geo = pair_geometry(
        z1, z2, module=m, pressure_angle=ALPHA_20, profile_shift_1=x1, profile_shift_2=x2,
        internal_2=internal,
    )  # fmt: skip
    psi_1 = half_tooth_angle(
        z1, module=m, pressure_angle=ALPHA_20, radius=geo.working_radius_1, profile_shift=x1
    )
    psi_2 = half_tooth_angle(
        z2, module=m, pressure_angle=ALPHA_20, radius=geo.working_radius_2, profile_shift=x2,
        internal=internal,
    )  # fmt: skip
    np.testing.assert_allclose(z1 * psi_1 + z2 * psi_2, math.pi, rtol=1e-12)


def test_unshifted_tooth_is_half_a_pitch_thick_on_the_reference_circle():
    # x = 0: tooth and gap share the reference pitch π m_t equally, so the tooth subtends π/z
    # there, half of it π/(2z); the same for an internal gear (its gap is the external tooth).
    z, m, beta = 23, 4e-3, math.radians(15.0)
    r = z * m / (2 * math.cos(beta))
    for internal in (False, True):
        psi = half_tooth_angle(
            z, module=m, pressure_angle=ALPHA_20, radius=r, helix_angle=beta, internal=internal
        )
        np.testing.assert_allclose(psi, math.pi / (2 * z), rtol=1e-12)


def test_half_tooth_angle_moves_by_the_involute_from_the_reference_circle():
    # A profile shift x adds 2 x tan α_n / z; at radius r the flank has turned by
    # inv α(r) − inv α, cos α(r) = r_b / r: thinner outwards on an external gear, thicker on an
    # internal one.
    z, m, x = 30, 2e-3, 0.3
    r_b = z * m / 2 * math.cos(ALPHA_20)
    r = 1.04 * z * m / 2
    turn = inv(math.acos(r_b / r)) - inv(ALPHA_20)
    reference = math.pi / (2 * z) + 2 * x * math.tan(ALPHA_20) / z
    external = half_tooth_angle(z, module=m, pressure_angle=ALPHA_20, radius=r, profile_shift=x)
    internal = half_tooth_angle(
        z, module=m, pressure_angle=ALPHA_20, radius=r, profile_shift=x, internal=True
    )
    np.testing.assert_allclose(external, reference - turn, rtol=1e-12)
    np.testing.assert_allclose(internal, reference + turn, rtol=1e-12)
