"""The rotor's thrust, weight and wind-shear moment laws (loads/rotor.py, cpp/rotor.hpp)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import dblquad

from pinwind.dynamics import _native
from pinwind.dynamics.elements import (
    rotor_power_coefficient,
    rotor_thrust,
    rotor_thrust_coefficient,
)
from pinwind.errors import InputError
from pinwind.loads.rotor import CtTable, Rotor, hub_weight, shear_arm
from pinwind.loads.rotor_performance import NREL5MW_PERFORMANCE, read_performance


@pytest.mark.parametrize("induction", [0.0, 0.05, 0.1, 0.2, 0.3, 1.0 / 3.0, -0.2])
def test_momentum_thrust_coefficient_is_the_actuator_discs_for_its_power_coefficient(induction):
    # Burton et al. 2011 §3.2: C_p = 4a(1 − a)², C_t = 4a(1 − a) for the same induction a.
    a = induction
    assert_allclose(_native.momentum_ct(4 * a * (1 - a) ** 2), 4 * a * (1 - a), rtol=1e-13,
                    atol=1e-15)  # fmt: skip


def test_above_betz_the_momentum_thrust_is_held_at_the_betz_discs():
    # C_p,Betz = 16/27 at a = 1/3, where C_t = 8/9.
    assert_allclose(_native.momentum_ct(0.7), 8.0 / 9.0, rtol=1e-14)


def test_thrust_is_half_rho_pi_r2_v2_ct_at_the_rotors_tip_speed_ratio():
    # A C_t table linear in λ: C_t(λ) = 0.1 λ between λ = 2 and 12, so at ω = 1.2 rad/s, v = 9 m/s
    # and R = 50 m, λ = 6.667 and T = ½ ρ π R² v² 0.1 λ.
    rotor = Rotor(radius=50.0, ct=CtTable(tsr=(2.0, 12.0), ct=((0.2,), (1.2,))))
    omega, wind = 1.2, 9.0
    tsr = omega * 50.0 / wind
    expected = 0.5 * 1.225 * math.pi * 50.0**2 * wind**2 * 0.1 * tsr
    assert_allclose(rotor_thrust(rotor, omega, wind), expected, rtol=1e-14)
    assert rotor_thrust(rotor, omega, 0.0) == 0.0  # no wind, no thrust


def test_a_heier_rotors_thrust_is_momentum_theorys_for_its_power_coefficient():
    rotor = Rotor.saleh2017()
    tsr = 6.37
    cp = rotor_power_coefficient(rotor, tsr)
    # The induction of this C_p, independently: the root a ≤ 1/3 of 4a³ − 8a² + 4a − C_p = 0.
    roots = np.roots([4.0, -8.0, 4.0, -cp])
    a = min(r.real for r in roots if abs(r.imag) < 1e-12 and r.real <= 1.0 / 3.0 + 1e-12
            and r.real >= 0)  # fmt: skip
    assert_allclose(rotor_thrust_coefficient(rotor, tsr), 4 * a * (1 - a), rtol=1e-12)


def test_the_nrel5mw_tables_peak_where_jonkman_2009_puts_the_rotors_optimum():
    # Jonkman et al. 2009 §7.1: C_p,max 0.482 at λ 7.55 and 0° pitch. On ROSCO's grid (λ in steps
    # of 0.5) the largest C_p at 0° sits at λ 7.5, within the grid's bilinear error of 0.482.
    grid = read_performance(NREL5MW_PERFORMANCE)
    zero = grid.pitch.index(0.0)
    best = int(np.argmax(grid.cp[:, zero]))
    assert grid.tsr[best] == 7.5
    assert_allclose(grid.cp[best, zero], 0.482, atol=1e-3)
    assert grid.cp.shape == grid.ct.shape == (24, 52)
    # The rotor reads the same numbers: C_t at a grid point is the file's own.
    rotor = Rotor.nrel5mw()
    assert_allclose(rotor_thrust_coefficient(rotor, 7.5), grid.ct[best, zero], rtol=1e-15)


def test_the_shear_arm_is_the_thrust_centres_height_over_the_disc():
    # ℓ = (1/πR²) ∬ z (1 + z/H)^{2α} dA, here by a 2-D quadrature in polar coordinates, where
    # the code integrates over horizontal strips.
    radius, height, alpha = 63.0, 90.0, 0.2
    moment, _ = dblquad(
        lambda r, phi: r * math.sin(phi) * (1 + r * math.sin(phi) / height) ** (2 * alpha) * r,
        0.0, 2 * math.pi, 0.0, radius, epsabs=0.0, epsrel=1e-12,
    )  # fmt: skip
    assert_allclose(shear_arm(radius, height, alpha), moment / (math.pi * radius**2), rtol=1e-9)


def test_a_weak_shear_over_a_small_disc_has_the_linear_profiles_arm():
    # For α → 0 and R ≪ H, (1 + z/H)^{2α} ≈ 1 + 2α z/H, and ℓ → 2α/(πR² H) ∫ z² dA = α R²/(2H).
    radius, height, alpha = 1.0, 1e4, 1e-4
    assert_allclose(shear_arm(radius, height, alpha), alpha * radius**2 / (2 * height), rtol=1e-3)
    assert shear_arm(radius, math.inf, 0.2) == 0.0 == shear_arm(radius, height, 0.0)


def test_a_hub_below_its_radius_is_refused_with_both_numbers():
    with pytest.raises(InputError, match=r"hub height 50.0 m is not above its radius 63.0 m"):
        Rotor(radius=63.0, hub_height=50.0, shear_exponent=0.2)


def test_the_weight_of_a_tilted_rotor_pushes_it_down_the_shaft_and_down():
    # A level model's gravity in the hub axes is (0, 0, −g); with the rotor end raised by τ the
    # shaft's x points down by τ: weight along x m g sin τ, along z −m g cos τ.
    tau, mass, g = math.radians(5.0), 1.1e5, 9.81
    expected = [mass * g * math.sin(tau), 0.0, -mass * g * math.cos(tau)]
    assert_allclose(hub_weight(mass, tau, np.array([0.0, 0.0, -g])), expected, rtol=1e-15)
    # Any other gravity: the weight has the length m |g| whatever the tilt.
    gravity = np.array([1.0, -2.0, -9.0])
    assert_allclose(np.linalg.norm(hub_weight(mass, 0.3, gravity)), mass * np.linalg.norm(gravity),
                    rtol=1e-15)  # fmt: skip


def test_rotor_parameters_out_of_range_are_refused_naming_them():
    with pytest.raises(InputError, match="rotor mass is -1.0 kg"):
        Rotor(radius=10.0, mass=-1.0)
    with pytest.raises(InputError, match="shaft_tilt is 5.0 rad"):
        Rotor(radius=10.0, shaft_tilt=5.0)
