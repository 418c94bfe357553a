"""Hertz contact along the path of contact (Jørgensen 2014 eqs. 20-22)."""

import math

import numpy as np
import pytest

from pinwind.gears.gear_pair import GearPair
from pinwind.gears.hertz import hertz_along_path, hertz_pressure
from pinwind.gears.materials import MATERIALS

STEEL = MATERIALS["18CrNiMo7-6"]


def test_eqs_20_to_22_equal_the_classical_line_contact_formula():
    force, rho_1, rho_2, length = 3.0e5, 0.05, 0.12, 0.3
    e_star = 1.0 / (2 * (1 - 0.3**2) / 206e9)
    radius = 1.0 / (1 / rho_1 + 1 / rho_2)
    classical = math.sqrt(force * e_star / (math.pi * length * radius))
    p = hertz_pressure(force, rho_1, rho_2, length, STEEL, STEEL)
    assert float(p) == pytest.approx(classical, rel=1e-12)


def test_concave_ring_flank_lowers_the_pressure():
    convex = hertz_pressure(1e5, 0.05, 0.2, 0.1, STEEL, STEEL)
    concave = hertz_pressure(1e5, 0.05, -0.2, 0.1, STEEL, STEEL)
    assert float(concave) < float(convex)


def test_pair_carries_half_the_force_in_the_double_zone_and_all_of_it_in_the_single_zone():
    alpha = math.radians(24.5)
    pair = GearPair(24, 48, module=0.015, pressure_angle=alpha, face_width=0.38,
                    material_1=STEEL, material_2=STEEL)  # fmt: skip
    path = pair.path_of_contact()
    a = 0.015 * 72 / 2
    np.testing.assert_allclose(pair.geometry.centre_distance, a, rtol=1e-12)
    h = hertz_along_path(pair, 3.4e5, points=401)
    single = (h.roll > path.single_start + 1e-6) & (h.roll < path.single_end - 1e-6)
    double = (h.roll < path.single_start - 1e-6) | (h.roll > path.single_end + 1e-6)
    np.testing.assert_array_equal(h.pairs[single], 1)
    np.testing.assert_array_equal(h.pairs[double], 2)
    np.testing.assert_allclose(h.force[single], 3.4e5, rtol=1e-12)
    np.testing.assert_allclose(h.force[double], 1.7e5, rtol=1e-12)
    # ρ1 + ρ2 is the length T1T2 of the line of action for an external pair.
    np.testing.assert_allclose(h.rho_1 + h.rho_2, a * math.sin(alpha), rtol=1e-12)
    # The largest pressure sits at the sun's inner point of single contact B.
    k = int(np.argmax(h.p_max))
    assert h.roll[k] == pytest.approx(path.single_start, abs=path.length / 400 * 1.01)
    np.testing.assert_allclose(h.von_mises, 0.65 * h.p_max, rtol=1e-12)


@pytest.mark.parametrize(("teeth_2", "internal"), [(48, False), (120, True)])
def test_largest_pressure_is_the_closed_form_at_the_inner_point_of_single_contact(
    teeth_2, internal
):
    """The peak is at B, a base pitch below gear 1's tip, whatever the sampling.

    Saleh 2017's sun–planet (24/48) and planet–ring (48/120) pairs, m = 15 mm, α = 24.5°,
    b = 380 mm, x = 0: from A to E the pair carries F/2, then F from B to D, then F/2. The
    pressure is largest at an end of a zone; at B (ρ1 = √(r_a1² − r_b1²) − p_b, the pinion's
    smallest radius of curvature under the whole force) it is √(F E*/(π b R)),
    1/R = 1/ρ1 ± 1/ρ2 with ρ2 = T1T2 ∓ ρ1, T1T2 = (r_b2 ∓ r_b1) tan α. Sampled on a
    uniform grid (A to E in 200 steps) the largest read up to 0.13 % low.
    """
    alpha, m, b, force = math.radians(24.5), 0.015, 0.38, 3.4e5
    teeth_1 = 48 if internal else 24
    pair = GearPair(teeth_1, teeth_2, module=m, pressure_angle=alpha, face_width=b,
                    internal_2=internal, material_1=STEEL, material_2=STEEL)  # fmt: skip
    r_1, r_2 = teeth_1 * m / 2, teeth_2 * m / 2
    rb_1, rb_2 = r_1 * math.cos(alpha), r_2 * math.cos(alpha)
    p_b = math.pi * m * math.cos(alpha)
    rho_1 = math.sqrt((r_1 + m) ** 2 - rb_1**2) - p_b
    if internal:
        rho_2 = (rb_2 - rb_1) * math.tan(alpha) + rho_1
        curvature = 1 / rho_1 - 1 / rho_2
    else:
        rho_2 = (rb_1 + rb_2) * math.tan(alpha) - rho_1
        curvature = 1 / rho_1 + 1 / rho_2
    e_star = 1.0 / (2 * (1 - 0.3**2) / 206e9)
    p_b_point = math.sqrt(force * e_star * curvature / (math.pi * b))
    h = hertz_along_path(pair, force)
    assert h.largest == pytest.approx(p_b_point, rel=1e-12)
    assert h.p_max[np.argmax(h.p_max)] == h.largest
    assert h.force[np.argmax(h.p_max)] == pytest.approx(force, rel=1e-15)
