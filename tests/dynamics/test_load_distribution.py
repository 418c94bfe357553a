"""ISO/TS 16281 load distribution: Stribeck/Harris closed forms, Harris's clearance integral,
tilt by hand, and the calibration case against ISO 281."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import brentq

from pinwind.dynamics.load_distribution import InternalGeometry, distribute, reference_load

Z = 20


def roller_bearing(clearance: float = 0.0, slices: int = 10) -> InternalGeometry:
    return InternalGeometry(
        "cylindrical_roller", Z, 1, 0.0, 0.03, 0.05, 0.3, clearance, slices=slices
    )


def test_zero_clearance_radial_load_zone_is_180_and_q_max_is_stribecks():
    f = 1.0e5
    dist = distribute(roller_bearing(), np.array([[f, 0, 0, 0, 0]]))
    assert dist.converged.all()
    assert_allclose(np.degrees(dist.load_zone), 180.0, atol=1e-9)
    # Discrete sum by hand: F = Q_max Σ_{cos ψ > 0} cos^(10/9) ψ · cos ψ.
    c = np.cos(2 * np.pi * np.arange(Z) / Z)
    q_max = f / np.sum(np.where(c > 0, c, 0.0) ** (19 / 9))
    assert_allclose(dist.max_element_load, q_max, rtol=1e-7)
    # Harris's closed form for line contact, zero clearance: Q_max ≈ 4.08 F_r / Z.
    assert_allclose(dist.max_element_load, 4.08 * f / Z, rtol=0.01)


def test_clearance_shrinks_the_load_zone_as_harris_integral_says():
    f, c = 1.0e5, 20e-6
    geometry = roller_bearing(clearance=c)
    dist = distribute(geometry, np.array([[f, 0, 0, 0, 0]]))
    # Solve F = Σ K (δ_r cos ψ_j − c)₊^(10/9) cos ψ_j for δ_r by bisection (independent).
    k = geometry.slice_stiffness * geometry.slice_count
    psi = 2 * np.pi * np.arange(Z) / Z

    def excess(delta: float) -> float:
        d = np.maximum(delta * np.cos(psi) - c, 0.0)
        return float(np.sum(k * d ** (10 / 9) * np.cos(psi))) - f

    delta_r = brentq(excess, c, 1e-2, xtol=1e-16)
    assert_allclose(dist.displacement[0, 0], delta_r, rtol=1e-6)
    zone = 2 * math.acos(c / delta_r)
    assert_allclose(dist.load_zone[0], zone, rtol=1e-6)
    assert zone < math.pi
    # Harris's integral (continuum): F = Z Q_max J_r(ε), ε = (1 − c/δ_r)/2; with Z = 20 the
    # discrete sum is within a few % of it.
    eps = 0.5 * (1 - c / delta_r)
    psi_l = math.acos(c / delta_r)
    grid = np.linspace(-psi_l, psi_l, 20001)
    j_r = np.trapezoid((1 - (1 - np.cos(grid)) / (2 * eps)) ** (10 / 9) * np.cos(grid), grid)
    j_r /= 2 * math.pi
    assert_allclose(dist.max_element_load[0], f / (Z * j_r), rtol=0.05)


def test_tilt_loads_the_slices_linearly_along_the_roller():
    geometry = roller_bearing(slices=10)
    # Impose u = (δ, 0, 0, 0, θ) by hand: slice k of roller j compresses by
    # (δ + θ z_k) cos ψ_j; sum its loads into the ring's load W, then solve back from W.
    delta, theta = 30e-6, 4e-4
    ns = geometry.slice_count
    zk = ((np.arange(ns) + 0.5) / ns - 0.5) * geometry.roller_length
    psi = 2 * np.pi * np.arange(Z) / Z
    comp = np.maximum((delta + theta * zk)[None, :] * np.cos(psi)[:, None], 0.0)
    q = geometry.slice_stiffness * comp ** (10 / 9)
    w = np.array(
        [
            np.sum(q * np.cos(psi)[:, None]),
            np.sum(q * np.sin(psi)[:, None]),
            0.0,
            np.sum(q * (-zk[None, :] * np.sin(psi)[:, None])),
            np.sum(q * (zk[None, :] * np.cos(psi)[:, None])),
        ]
    )
    dist = distribute(geometry, w[None, :])
    assert dist.converged.all()
    assert_allclose(dist.displacement[0, [0, 4]], [delta, theta], rtol=1e-6)
    top = dist.slice_loads[0, 0]  # the roller at ψ = 0
    assert_allclose(top, q[0], rtol=1e-6)
    # its deflections rise linearly along the roller: q^(9/10) is linear in z_k
    deflection = top ** (9 / 10)
    assert_allclose(np.diff(deflection, 2), 0.0, atol=1e-9 * deflection.max())
    assert np.all(np.diff(top) > 0)


@pytest.mark.parametrize("rotating", ["inner", "outer"])
def test_calibration_case_reference_life_equals_iso_281_basic_life(rotating):
    # No clearance, no tilt, pure radial load: ISO/TS 16281's calibration case. The reference
    # load of Z = 20 discrete rollers equals F_r within the discretisation (TS: within 2 %).
    for kind, rows, alpha in (
        ("cylindrical_roller", 1, 0.0),
        ("toroidal_roller", 1, 0.0),
        ("spherical_roller", 2, math.radians(10)),
        ("deep_groove_ball", 1, 0.0),
    ):
        length = 0.0 if kind.endswith("ball") else 0.05
        geometry = InternalGeometry(kind, Z, rows, alpha, 0.03, length, 0.3, rotating=rotating)
        f = 2.0e5
        dist = distribute(geometry, np.array([[f, 0, 0, 0, 0]]))
        p_ref = reference_load(geometry, dist.slice_loads)[0]
        c = 1.0e6
        p = 3.0 if kind.endswith("ball") else 10 / 3
        assert_allclose((c / p_ref) ** p, (c / f) ** p, rtol=0.02, err_msg=kind)


def test_clearance_shortens_the_reference_life():
    f = np.array([[1.0e5, 0, 0, 0, 0]])
    tight = reference_load(roller_bearing(), distribute(roller_bearing(), f).slice_loads)
    loose_geometry = roller_bearing(clearance=40e-6)
    loose = reference_load(loose_geometry, distribute(loose_geometry, f).slice_loads)
    assert loose[0] > tight[0]


def test_self_aligning_bearing_reports_the_moment_it_does_not_carry():
    geometry = InternalGeometry("spherical_roller", Z, 2, math.radians(10), 0.03, 0.04, 0.3)
    dist = distribute(geometry, np.array([[1e5, 0, 1e4, 500.0, -300.0]]))
    assert dist.converged.all()
    assert_allclose(dist.not_carried[0], [0, 0, 0, 500.0, -300.0])


def test_pure_axial_load_puts_every_roller_of_an_angular_row_in_contact():
    # A single tapered row under a pure axial load F_a: by symmetry every roller carries
    # Q = F_a/(Z sin α) (Harris and Kotzalas 2007 §7.3, ε = ∞) and the load zone is the whole
    # circle, 360°.
    alpha, f_a = math.radians(15.0), 5.0e4
    geometry = InternalGeometry("tapered_roller", Z, 1, alpha, 0.03, 0.05, 0.3)
    dist = distribute(geometry, np.array([[0.0, 0.0, f_a, 0.0, 0.0]]))
    assert dist.converged.all()
    assert_allclose(dist.max_element_load, f_a / (Z * math.sin(alpha)), rtol=1e-7)
    assert_allclose(np.degrees(dist.load_zone), 360.0, atol=1e-6)


def test_an_axial_approach_widens_the_pressed_rows_load_zone():
    # A spherical roller bearing (rows at ±α) displaced by u = (ρ, 0, a) with a tan α = ρ/2:
    # row +α compresses by ρ cos ψ cos α + a sin α > 0 for cos ψ > −1/2 (zone 2 · 120° = 240°),
    # row −α for cos ψ > +1/2 (120°). Sum the rollers' loads into W by hand, solve back from W:
    # the zone is the pressed row's 240°, not the 180° of the radial approach alone.
    alpha = math.radians(10.0)
    geometry = InternalGeometry("spherical_roller", Z, 2, alpha, 0.03, 0.04, 0.3)
    rho = 40e-6
    a = 0.5 * rho / math.tan(alpha)
    psi = 2 * np.pi * np.arange(Z) / Z
    k = geometry.slice_stiffness * geometry.slice_count
    w = np.zeros(5)
    for sign in (1.0, -1.0):
        comp = np.maximum(rho * np.cos(psi) * math.cos(alpha) + sign * a * math.sin(alpha), 0.0)
        q = k * comp ** (10 / 9)
        w[0] += np.sum(q * np.cos(psi)) * math.cos(alpha)
        w[1] += np.sum(q * np.sin(psi)) * math.cos(alpha)
        w[2] += np.sum(q) * sign * math.sin(alpha)
    dist = distribute(geometry, w[None, :])
    assert dist.converged.all()
    assert_allclose(dist.displacement[0, :3], [rho, 0.0, a], rtol=1e-6, atol=1e-12)
    assert_allclose(np.degrees(dist.load_zone), 240.0, rtol=1e-6)
