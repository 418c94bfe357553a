"""Default steel bodies of the builders against hand calculations."""

from __future__ import annotations

import math

import numpy as np

from pinwind.model.builders.gear_bodies import combine, part_at, steel_gear, steel_ring_gear

RHO = 7850.0  # kg/m³, steel


def test_steel_gear_is_a_disc_of_pitch_diameter_and_face_width():
    # 40 teeth, m = 3 mm: pitch diameter 120 mm (Kelso 2011), 15 mm wide.
    mass, ixx, izz = steel_gear(40, module=3e-3, face_width=0.015)
    r, b = 0.060, 0.015
    m = RHO * math.pi * r**2 * b
    np.testing.assert_allclose(mass, m, rtol=1e-14)
    np.testing.assert_allclose(izz, m * r**2 / 2.0, rtol=1e-14)
    np.testing.assert_allclose(ixx, m * (3.0 * r**2 + b**2) / 12.0, rtol=1e-14)


def test_helical_steel_gear_uses_the_transverse_pitch_diameter():
    beta = math.radians(15.0)
    mass, _, izz = steel_gear(23, module=5.5e-3, face_width=0.056, helix_angle=beta)
    r = 23 * 5.5e-3 / (2.0 * math.cos(beta))
    np.testing.assert_allclose(mass, RHO * math.pi * r**2 * 0.056, rtol=1e-14)
    np.testing.assert_allclose(izz, mass * r**2 / 2.0, rtol=1e-14)


def test_steel_ring_gear_is_a_rim_three_and_a_half_modules_deep():
    # 120 teeth, m = 15 mm: pitch radius 0.9 m, rim out to 0.9525 m, 380 mm wide.
    mass, _, izz = steel_ring_gear(120, module=0.015, face_width=0.38)
    r_i, r_o = 0.9, 0.9 + 3.5 * 0.015
    np.testing.assert_allclose(mass, RHO * math.pi * (r_o**2 - r_i**2) * 0.38, rtol=1e-14)
    np.testing.assert_allclose(izz, mass * (r_o**2 + r_i**2) / 2.0, rtol=1e-14)


def test_two_equal_discs_apart_add_the_parallel_axis_term():
    props = (2.0, 0.3, 0.5)
    body = combine([part_at(props, -0.1), part_at(props, 0.1)])
    np.testing.assert_allclose(body.mass, 4.0, rtol=1e-15)
    np.testing.assert_allclose(body.com, np.zeros(3), atol=1e-15)
    # Ixx = Iyy = 2 (0.3 + 2·0.1²), Izz = 2·0.5: the offset is along the axis.
    np.testing.assert_allclose(np.diag(body.inertia), [0.64, 0.64, 1.0], rtol=1e-14)
