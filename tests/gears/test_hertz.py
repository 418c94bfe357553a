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
