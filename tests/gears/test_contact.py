"""Path of contact against closed forms computed here and against the DTU seed's Table 6."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InvalidGearTrain, PinwindError
from pinwind.gears.contact import (
    ContactRatioBelowOne,
    InvoluteInterference,
    PathOfContact,
    TipInsideBaseCircle,
    pairs_in_contact,
    path_of_contact,
)
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.involute import PairGeometry
from tests.conftest import dtu_pairs

ALPHA_20 = math.radians(20.0)
#: Face width [m] of pairs whose overlap ratio no test here reads (spur pairs, or unasserted).
WIDTH = 0.05


def inv(angle: float) -> float:
    return math.tan(angle) - angle


def inv_inverse(value: float) -> float:
    """Newton on tan a − a = value (independent of the brentq in the code)."""
    angle = (3.0 * value) ** (1.0 / 3.0)
    for _ in range(50):
        angle -= (inv(angle) - value) / math.tan(angle) ** 2
    return angle


def roll(tip_radius: float, base_radius: float) -> float:
    """Distance from a base-circle tangency point to the tip circle along the line of action."""
    return math.sqrt(tip_radius**2 - base_radius**2)


def test_textbook_spur_pair_has_contact_ratio_1_64():
    # z 20/40, m 5 mm, α 20°, no shift: r_a = m (z/2 + 1), r_b = (m z/2) cos α, a = 150 mm.
    # g_α = sqrt(55² − 46.985²) + sqrt(105² − 93.969²) − 150 sin 20°
    #     = 28.590 + 46.849 − 51.303 = 24.136 mm, p_b = 5π cos 20° = 14.761 mm, ε_α = 1.635.
    m, alpha = 5e-3, ALPHA_20
    rb1, rb2 = 10 * m * math.cos(alpha), 20 * m * math.cos(alpha)
    ra1, ra2 = 11 * m, 21 * m
    line = 30 * m * math.sin(alpha)
    g = roll(ra1, rb1) + roll(ra2, rb2) - line
    p_b = math.pi * m * math.cos(alpha)

    path = GearPair(20, 40, module=m, pressure_angle=alpha, face_width=WIDTH).path_of_contact()

    np.testing.assert_allclose(path.contact_ratio, 1.64, atol=0.006)  # the rounded book value
    np.testing.assert_allclose(path.contact_ratio, g / p_b, rtol=1e-12)
    np.testing.assert_allclose(path.length, g, rtol=1e-12)
    np.testing.assert_allclose(path.base_pitch, p_b, rtol=1e-12)
    np.testing.assert_allclose(path.start_roll_1, line - roll(ra2, rb2), rtol=1e-12)
    # C is at r_b1 tan α = r_1 sin α from T1 when there is no shift.
    np.testing.assert_allclose(path.pitch_roll_1, 10 * m * math.sin(alpha), rtol=1e-12)


def test_path_of_contact_from_plain_numbers_is_the_textbook_pair():
    # The same z 20/40, m 5 mm, α 20° pair given as its numbers only, no GearPair.
    m, alpha = 5e-3, ALPHA_20
    rb1, rb2 = 10 * m * math.cos(alpha), 20 * m * math.cos(alpha)
    ra1, ra2 = 11 * m, 21 * m
    g = roll(ra1, rb1) + roll(ra2, rb2) - 30 * m * math.sin(alpha)
    p_b = math.pi * m * math.cos(alpha)
    geometry = PairGeometry(
        centre_distance=30 * m, working_pressure_angle=alpha, working_radius_1=10 * m,
        working_radius_2=20 * m, base_radius_1=rb1, base_radius_2=rb2,
    )  # fmt: skip

    path = path_of_contact(geometry, tip_radius_1=ra1, tip_radius_2=ra2, base_pitch=p_b)

    np.testing.assert_allclose(path.length, g, rtol=1e-12)
    np.testing.assert_allclose(path.contact_ratio, g / p_b, rtol=1e-12)
    np.testing.assert_allclose(path.pitch_roll_1, 10 * m * math.sin(alpha), rtol=1e-12)
    assert path.overlap_ratio == 0.0
    np.testing.assert_allclose([path.single_start, path.single_end], [g - p_b, p_b], rtol=1e-12)
    np.testing.assert_allclose([path.tip_radius_1, path.tip_radius_2], [ra1, ra2], rtol=1e-12)
    assert path.overlap_ratio == 0.0


def test_helical_pair_uses_transverse_geometry_and_gives_overlap_ratio():
    # z 19/57, m_n 4 mm, α_n 20°, β 15°, b 40 mm, no shift. Transverse plane:
    # α_t = atan(tan 20°/cos 15°) = 20.647°, m_t = m_n/cos β, r = z m_t/2, r_a = r + m_n,
    # a = r1 + r2 and α_wt = α_t. Overlap ε_β = b sin β/(π m_n) = 40 · 0.25882/12.566 = 0.8238.
    m_n, beta, b = 4e-3, math.radians(15.0), 40e-3
    alpha_t = math.atan(math.tan(ALPHA_20) / math.cos(beta))
    m_t = m_n / math.cos(beta)
    r1, r2 = 19 * m_t / 2, 57 * m_t / 2
    rb1, rb2 = r1 * math.cos(alpha_t), r2 * math.cos(alpha_t)
    g = roll(r1 + m_n, rb1) + roll(r2 + m_n, rb2) - (r1 + r2) * math.sin(alpha_t)
    p_bt = math.pi * m_t * math.cos(alpha_t)

    path = GearPair(
        19, 57, module=m_n, pressure_angle=ALPHA_20, helix_angle=beta, face_width=b
    ).path_of_contact()

    np.testing.assert_allclose(path.overlap_ratio, 0.8238, atol=1e-4)
    np.testing.assert_allclose(path.overlap_ratio, b * math.sin(beta) / (math.pi * m_n), rtol=1e-12)
    np.testing.assert_allclose(path.working_pressure_angle, alpha_t, atol=1e-9)
    np.testing.assert_allclose(path.base_pitch, p_bt, rtol=1e-12)
    np.testing.assert_allclose(path.contact_ratio, g / p_bt, rtol=1e-9)


def dtu_reference(module: float = 10e-3, alpha: float = ALPHA_20):
    """A, B, D and E of both DTU meshes, computed by hand from ISO 21771.

    Tip radii without tip shortening, r_a = m (z/2 + 1 + x) for the sun and planet and
    r_a = m (z/2 − 1 − x) for the ring with its ISO profile shift x = −0.840 (r_a = 453.4 mm).
    """
    cos_a = math.cos(alpha)
    p_b = math.pi * module * cos_a
    rb_s, rb_p, rb_r = (module * z / 2 * cos_a for z in (20, 35, 91))
    ra_s = module * (10 + 1 + 0.582)
    ra_p = module * (17.5 + 1 + 0.419)
    ra_r = module * (45.5 - 1 + 0.840)

    # Sun/planet: inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2), a_w = m (z1+z2)/2 cos α/cos α_w.
    alpha_w = inv_inverse(inv(alpha) + 2 * math.tan(alpha) * (0.582 + 0.419) / 55)
    line = module * 55 / 2 * cos_a / math.cos(alpha_w) * math.sin(alpha_w)  # |T1 T2|
    a_sp = line - roll(ra_p, rb_p)
    e_sp = roll(ra_s, rb_s)
    # Planet/ring, ring with z = −91: (x1 + x2)/(z1 + z2) = (0.419 − 0.840)/(35 − 91).
    alpha_w = inv_inverse(inv(alpha) + 2 * math.tan(alpha) * (0.419 - 0.840) / (35 - 91))
    line = module * 56 / 2 * cos_a / math.cos(alpha_w) * math.sin(alpha_w)
    a_pr = roll(ra_r, rb_r) - line  # T2 lies behind T1: the ring's tip point minus |T1 T2|
    e_pr = roll(ra_p, rb_p)
    return p_b, (a_sp, e_sp), (a_pr, e_pr)


def dtu_paths() -> tuple[PathOfContact, PathOfContact]:
    sun_planet, planet_ring = dtu_pairs()
    return sun_planet.path_of_contact(), planet_ring.path_of_contact()


def test_dtu_stage_reproduces_table6_switch_points():
    """Jørgensen 2014 Table 6 lists three roll lengths per mesh, A, B and D.

    s is the base-circle roll length measured from the inner gear's tangency point T1 (the sun,
    resp. the planet). The three values are:
    - A, where contact starts, 2 pairs (s_min);
    - B = A + g_α − p_b, where single-pair contact starts ("switch");
    - D = A + p_b, where it ends (s_max).
    The paper's "s_max" is D, one base pitch after A, and **not** the end of contact E = A + g_α.
    E would be 0.0677 m (sun/planet) and 0.0935 m (planet/ring). The paper's s-window is one base
    pitch long, A to D.

    Our geometry: module 10 mm, α 20°, no tip shortening, ring x = −0.840 with the ISO 21771 sign
    (ring tip radius 453.4 mm). Hand values:
    - sun/planet: A 24.272, B 38.184, D 53.794, E 67.706 mm (ε_α 1.471);
    - planet/ring: A 43.969, B 64.022, D 73.490, E 93.543 mm (ε_α 1.679).
    These agree with the table within half a unit of its last printed digit, which is the
    tolerance used (5e-5 m for 4-decimal entries, 5e-4 m for 0.044 and 0.064). So the seed used
    no tip shortening and the standard addendum.
    """
    p_b, (a_sp, e_sp), (a_pr, e_pr) = dtu_reference()
    sun_planet, planet_ring = dtu_paths()

    ours_sp = [a_sp, e_sp - p_b, a_sp + p_b]  # A, B = E − p_b, D
    ours_pr = [a_pr, e_pr - p_b, a_pr + p_b]
    np.testing.assert_allclose(ours_sp, [0.0243, 0.0382, 0.0538], rtol=0, atol=5e-5)
    np.testing.assert_allclose(ours_pr[:2], [0.044, 0.064], rtol=0, atol=5e-4)
    np.testing.assert_allclose(ours_pr[2], 0.0735, rtol=0, atol=5e-5)

    for path, expected, end in ((sun_planet, ours_sp, e_sp), (planet_ring, ours_pr, e_pr)):
        a = path.start_roll_1
        got = [a, a + path.single_start, a + path.single_end]
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
        np.testing.assert_allclose(a + path.length, end, rtol=0, atol=1e-9)
    # The end of contact is far from Table 6's third value: that value is D, not E.
    assert sun_planet.start_roll_1 + sun_planet.length - 0.0538 > 0.01
    np.testing.assert_allclose(
        [sun_planet.contact_ratio, planet_ring.contact_ratio], [1.471, 1.679], atol=5e-4
    )


def test_dtu_ring_tip_radius_follows_iso_sign_of_profile_shift():
    # ISO 21771: d_a = d + 2 (z/|z|) m_n (h_aP* + x), so the ring tip radius is
    # 455 mm − 10 mm (1 − 0.840) = 453.4 mm.
    _, planet_ring = dtu_paths()
    np.testing.assert_allclose(planet_ring.tip_radius_2, 0.4534, rtol=1e-12)


def test_opposite_internal_shift_sign_puts_dtu_ring_tip_past_the_planet_base_circle():
    # With the other sign, r_a = r − m (h_a* − x) = 455 − 18.4 = 436.6 mm. The ring's tip would
    # reach past T1, on the planet's base circle (A at −18.5 mm), and Table 6 could not be
    # reproduced.
    with pytest.raises(InvoluteInterference) as err:
        dtu_pairs()[1].path_of_contact(tip_radius_2=0.4366)
    assert err.value.start < 0.0
    assert "interference" in str(err.value)


def test_internal_gear_as_gear_1_gives_the_same_path_seen_from_the_ring():
    # The same mesh with the ring named first. The path has the same length, and A is the same
    # physical point. It is now measured from the ring's tangency point, which lies
    # a_w sin α_wt behind the planet's.
    _, planet_ring = dtu_paths()
    ring_planet = GearPair(
        91,
        35,
        module=10e-3,
        pressure_angle=ALPHA_20,
        profile_shift_1=-0.840,
        profile_shift_2=0.419,
        internal_1=True,
        face_width=WIDTH,
    ).path_of_contact()
    alpha_w = inv_inverse(inv(ALPHA_20) + 2 * math.tan(ALPHA_20) * (0.419 - 0.840) / (35 - 91))
    line = 10e-3 * 56 / 2 * math.cos(ALPHA_20) * math.tan(alpha_w)  # a_w sin α_w
    np.testing.assert_allclose(ring_planet.length, planet_ring.length, rtol=1e-12)
    np.testing.assert_allclose(
        ring_planet.start_roll_1, planet_ring.start_roll_1 + line, rtol=0, atol=1e-8
    )
    np.testing.assert_allclose(ring_planet.pitch_roll_1, planet_ring.pitch_roll_1 + line, atol=1e-8)


def test_pairs_in_contact_are_two_in_double_zones_and_one_in_single_zone():
    path = GearPair(
        20, 40, module=5e-3, pressure_angle=ALPHA_20, face_width=WIDTH
    ).path_of_contact()
    b, d, g, p = path.single_start, path.single_end, path.length, path.base_pitch
    s = np.array([0.5 * b, 0.5 * (b + d), 0.5 * (d + g)])
    np.testing.assert_array_equal(pairs_in_contact(path, s), [2, 1, 2])
    # Taken modulo the base pitch: any pair may serve as the reference.
    np.testing.assert_array_equal(pairs_in_contact(path, s + 3 * p), [2, 1, 2])
    assert pairs_in_contact(path, 0.5 * (b + d)).shape == ()


@pytest.mark.parametrize("addendum", [1.0, 1.35])
def test_mean_number_of_pairs_in_contact_equals_contact_ratio(addendum):
    # Averaged over one base pitch, the number of loaded pairs is ε_α. With h_a* = 1.35 on
    # 60/60 teeth ε_α > 2, so the count runs 2-3.
    path = GearPair(
        60,
        60,
        module=2e-3,
        pressure_angle=ALPHA_20,
        addendum_coefficient=addendum,
        face_width=WIDTH,
    ).path_of_contact()
    phase = (np.arange(200_000) + 0.5) / 200_000 * path.base_pitch
    counts = pairs_in_contact(path, phase)
    np.testing.assert_allclose(counts.mean(), path.contact_ratio, rtol=0, atol=1e-4)
    if addendum > 1.0:
        assert path.contact_ratio > 2.0
        assert set(np.unique(counts)) == {2, 3}


def test_short_tips_give_contact_ratio_below_one():
    # Tips cut to 0.4 m_n above the reference circle, 20/40, m 5 mm, 20°:
    # g_α = sqrt(52² − 46.985²) + sqrt(102² − 93.969²) − 51.303 = 22.28 + 39.67 − 51.30
    #     = 10.65 mm, ε_α = 10.65/14.761 = 0.72.
    m = 5e-3
    with pytest.raises(ContactRatioBelowOne) as err:
        GearPair(20, 40, module=m, pressure_angle=ALPHA_20, face_width=WIDTH).path_of_contact(
            tip_radius_1=10.4 * m, tip_radius_2=20.4 * m
        )
    np.testing.assert_allclose(err.value.contact_ratio, 0.72, atol=0.005)
    assert "ε_α" in str(err.value) and "< 1" in str(err.value)


def test_tip_inside_base_circle_is_reported_with_both_radii():
    m = 5e-3
    with pytest.raises(TipInsideBaseCircle) as err:
        GearPair(20, 40, module=m, pressure_angle=ALPHA_20, face_width=WIDTH).path_of_contact(
            tip_radius_2=0.09
        )
    assert err.value.gear == 2
    assert "90.0000 mm" in str(err.value) and "93.9693 mm" in str(err.value)


def test_small_unshifted_pinion_with_large_gear_interferes():
    # 12 teeth against 80, no shift: gear 2's tip meets the line of action before T1
    # (sqrt(r_a2² − r_b2²) = sqrt(82² − 75.175²) = 32.75 mm > a sin α = 92 sin 20° = 31.47 mm
    # for m = 2 mm).
    with pytest.raises(InvoluteInterference):
        GearPair(12, 80, module=2e-3, pressure_angle=ALPHA_20, face_width=WIDTH).path_of_contact()


def test_two_internal_gears_and_bad_numbers_are_rejected():
    with pytest.raises(InvalidGearTrain):
        GearPair(
            35,
            91,
            module=1e-3,
            pressure_angle=ALPHA_20,
            internal_1=True,
            internal_2=True,
            face_width=WIDTH,
        ).path_of_contact()
    with pytest.raises(InvalidGearTrain):
        GearPair(-20, 40, module=1e-3, pressure_angle=ALPHA_20, face_width=WIDTH).path_of_contact()
    with pytest.raises(PinwindError):
        GearPair(20, 40, module=0.0, pressure_angle=ALPHA_20, face_width=WIDTH).path_of_contact()
