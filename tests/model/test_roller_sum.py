"""Harris's roller sum (model/roller_sum.py) against a direct sum written here, term by term."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.model.bearing_compliance import BearingCompliance
from pinwind.model.roller_sum import CONTACT_EXPONENTS

LINE = 10.0 / 9.0  # a roller's line contact: Q = K_n δ^(10/9)


def bearing(rollers=12, contact_stiffness=2e9, exponent=LINE, clearance=0.0):
    return BearingCompliance(
        law="roller_sum",
        rollers=rollers,
        contact_stiffness=contact_stiffness,
        load_exponent=exponent,
        clearance=clearance,
    )


def harris_radial_load(delta_r, *, rollers, kn, n, clearance):
    """F_r = Σ_j K_n (δ_r cos ψ_j − c)^n cos ψ_j over the rollers in contact (Harris & Kotzalas)."""
    total = 0.0
    for j in range(rollers):
        psi = 2.0 * math.pi * j / rollers
        compression = delta_r * math.cos(psi) - clearance
        if compression > 0.0:
            total += kn * compression**n * math.cos(psi)
    return total


def test_contact_exponents_are_harris_line_and_point_contact():
    assert CONTACT_EXPONENTS == {"line": 10.0 / 9.0, "point": 3.0 / 2.0}


@pytest.mark.parametrize(("rollers", "clearance"), [(12, 0.0), (9, 5e-6), (1, 2e-6), (20, 0.0)])
def test_force_for_a_radial_displacement_is_the_sum_over_the_rollers_in_contact(rollers, clearance):
    b = bearing(rollers=rollers, clearance=clearance)
    for delta in (3e-6, 1e-5, 4e-5):
        force = b.radial_force(np.array([delta, 0.0]))
        expected = harris_radial_load(delta, rollers=rollers, kn=2e9, n=LINE, clearance=clearance)
        np.testing.assert_allclose(-force[0], expected, rtol=1e-12)
        # The rollers at ±ψ from the displacement carry alike: no force across it.
        np.testing.assert_allclose(force[1], 0.0, atol=1e-12 * max(expected, 1.0))


def test_a_displacement_in_any_direction_loads_the_rollers_around_it():
    # Turning the displacement by one roller pitch turns the force with it.
    b = bearing(rollers=10)
    pitch = 2 * math.pi / 10
    r = 2e-5 * np.array([math.cos(0.3), math.sin(0.3)])
    turn = np.array([[math.cos(pitch), -math.sin(pitch)], [math.sin(pitch), math.cos(pitch)]])
    np.testing.assert_allclose(
        b.radial_force(turn @ r), turn @ b.radial_force(r), rtol=1e-12, atol=1e-9
    )


@pytest.mark.parametrize("contact", ["line", "point"])
def test_doubling_the_load_raises_the_deflection_by_two_to_the_one_over_n(contact):
    n = CONTACT_EXPONENTS[contact]
    b = bearing(rollers=40, exponent=n)
    load = np.array([0.0, -5e3])
    single = b.static_deflection(load)
    double = b.static_deflection(2 * load)
    np.testing.assert_allclose(double, 2 ** (1 / n) * single, rtol=1e-10, atol=1e-20)
    np.testing.assert_allclose(b.radial_force(single), -load, rtol=1e-10, atol=1e-9)


def test_no_force_inside_the_clearance():
    clearance = 2e-5
    b = bearing(clearance=clearance)
    rng = np.random.default_rng(7)
    angles = rng.uniform(0, 2 * math.pi, 50)
    radii = clearance * rng.uniform(0.0, 1.0, 50)
    r = np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)
    np.testing.assert_allclose(b.radial_force(r), 0.0, atol=0.0)
    np.testing.assert_allclose(b.radial_tangent(r[0]), 0.0, atol=0.0)


@pytest.mark.parametrize("clearance", [0.0, 4e-6])
def test_the_tangent_stiffness_is_the_finite_difference_of_the_force(clearance):
    b = bearing(rollers=9, clearance=clearance, exponent=1.5)
    r = np.array([1.3e-5, -0.7e-5])
    h = 1e-10
    numeric = np.empty((2, 2))
    for i in range(2):
        step = np.zeros(2)
        step[i] = h
        numeric[:, i] = -(b.radial_force(r + step) - b.radial_force(r - step)) / (2 * h)
    np.testing.assert_allclose(b.radial_tangent(r), numeric, rtol=1e-6)
