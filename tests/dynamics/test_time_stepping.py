"""The time step (``dynamics/integrator.py``): second order, with numerical dissipation set by ρ∞.

The model is a free compliant pair (``tests/conftest.two_gear_urdf``: 20/40 teeth, module 2 mm,
20°, J_A = 0.0015 and J_B = 0.006 kg·m²) with one mesh of constant stiffness and no backlash, so
that both flanks make one linear spring across zero: a two-inertia oscillator. Along the line of
action, x = r_b,A θ_A + r_b,B θ_B (zero on rigid rolling, r_b,A ω_A = −r_b,B ω_B) obeys

    m x'' = −k x − c x',   m = 1 / (r_b,A²/J_A + r_b,B²/J_B),   ω² = k/m,   ζ = c / (2 √(k m))

Balanced torques F r_b,A on A and F r_b,B on B load the teeth with F and leave the rigid rotation
at rest; starting undeflected, x swings about its static value x_s = F/k (up to the sign of the
deflection's convention) with amplitude |x_s|. The amplitude A = √((x − x_s)² + (x'/ω)²) is
constant for c = 0 and decays as e^{−ζ ω t}; its phase advances at ω.
"""

from __future__ import annotations

import math
from contextlib import nullcontext

import numpy as np
import pytest

import pinwind
from pinwind.dynamics import Integrator
from pinwind.errors import InputError, StepTooCoarse
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

MODULE, ALPHA = 0.002, math.radians(20.0)
Z_A, Z_B = 20, 40
J_A, J_B = 0.0015, 0.006
R_BA = Z_A * MODULE * math.cos(ALPHA) / 2
R_BB = Z_B * MODULE * math.cos(ALPHA) / 2
BASE_PITCH = math.pi * MODULE * math.cos(ALPHA)
K_SINGLE = 1e8
#: The static tooth force of the balanced torques [N].
PRELOAD = 1000.0


def _contact_ratio() -> float:
    """ε_α by hand: (√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a sin α) / p_b."""
    r_a1, r_a2 = Z_A * MODULE / 2 + MODULE, Z_B * MODULE / 2 + MODULE
    a = (Z_A + Z_B) * MODULE / 2
    length = math.sqrt(r_a1**2 - R_BA**2) + math.sqrt(r_a2**2 - R_BB**2) - a * math.sin(ALPHA)
    return length / BASE_PITCH


#: The mesh stiffness, ISO 6336-1's mean c_γα = c′ (0.75 ε_α + 0.25) for a constant variation.
K_MESH = K_SINGLE * (0.75 * _contact_ratio() + 0.25)
MASS = 1.0 / (R_BA**2 / J_A + R_BB**2 / J_B)
OMEGA = math.sqrt(K_MESH / MASS)
PERIOD = 2 * math.pi / OMEGA


def _free_pair(
    steps_per_period: float, periods: float, *, damping: float = 0.0, coarse: bool = False, **kw
):
    """x − x_s, x' and the step of the pair released undeflected under balanced torques.

    ``coarse``: the step damps the mesh mode numerically (ρ∞ < 1 at these steps a period), and
    the run says so (``StepTooCoarse``, asserted).
    """
    dt = PERIOD / steps_per_period
    said = pytest.warns(StepTooCoarse, match="highest mesh mode") if coarse else nullcontext()
    with said:
        res = pinwind.simulate(
            loads(two_gear_urdf(), "pair.urdf"),
            duration=periods * PERIOD,
            dt=dt,
            torques={"a": PRELOAD * R_BA, "b": PRELOAD * R_BB},
            gravity=np.zeros(3),
            initial_deflection="none",
            meshes={"m": MeshCompliance(stiffness=K_SINGLE, variation="constant", damping=damping)},
            **kw,
        )
    a, b = res.joint("a"), res.joint("b")
    x = R_BA * a.angle + R_BB * b.angle
    xdot = R_BA * a.speed + R_BB * b.speed
    # The sign of x against the mesh's deflection δ (positive when the teeth are loaded).
    sign = np.sign(np.dot(x, res.mesh("m").transmission_error))
    return x - sign * PRELOAD / K_MESH, xdot, dt, res


def _amplitude(x: np.ndarray, xdot: np.ndarray) -> np.ndarray:
    return np.hypot(x, xdot / OMEGA)


def _frequency(x: np.ndarray, xdot: np.ndarray, dt: float) -> float:
    """Mean angular frequency [rad/s] from the unwrapped phase of (x, x'/ω)."""
    phase = np.unwrap(np.arctan2(-xdot / OMEGA, x))
    t = dt * np.arange(len(x))
    return float(np.polyfit(t, phase, 1)[0])


def _loss_per_period(x, xdot, dt) -> float:
    """Fraction of the amplitude lost per period, from a fit of log A over the run."""
    t = dt * np.arange(len(x))
    slope = np.polyfit(t, np.log(_amplitude(x, xdot)), 1)[0]
    return 1.0 - math.exp(slope * PERIOD)


def test_the_pair_starts_undeflected_and_swings_about_the_static_deflection():
    x, xdot, _, res = _free_pair(200, 2, integrator=Integrator(rho_infinity=1.0))
    deflection = res.mesh("m").transmission_error
    # x is the mesh deflection (up to its sign), from the gears' angles.
    np.testing.assert_allclose(
        np.abs(x - np.sign(x[0]) * PRELOAD / K_MESH), np.abs(deflection), atol=1e-15
    )
    np.testing.assert_allclose(deflection[0], 0.0, atol=1e-15)
    np.testing.assert_allclose(_amplitude(x, xdot), PRELOAD / K_MESH, rtol=1e-9)


def test_energy_conserving_step_keeps_the_amplitude_at_20_steps_per_period():
    x, xdot, dt, _ = _free_pair(20, 20, integrator=Integrator(rho_infinity=1.0))
    assert abs(_loss_per_period(x, xdot, dt)) <= 1e-3
    # The trapezoidal rule keeps ½ m x'² + ½ k x² exactly on a linear spring.
    amplitude = _amplitude(x, xdot)
    np.testing.assert_allclose(amplitude, amplitude[0], rtol=1e-9)


def test_default_step_loses_under_one_percent_per_period_at_20_steps_per_period():
    x, xdot, dt, _ = _free_pair(20, 20)
    loss = _loss_per_period(x, xdot, dt)
    assert 0.0 <= loss <= 1e-2, loss


def _spectral_radius(rho: float, omega_h: float) -> float:
    """Spectral radius of generalized-α's amplification matrix on x'' = −ω² x at ωh.

    Chung & Hulbert 1993 eqs. 2-3 with the state (x, h v, h² a): B y_{n+1} = A y_n.
    """
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    gamma, beta = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    w2 = omega_h**2
    b = np.array([[1, 0, -beta], [0, 1, -gamma], [w2 * (1 - af), 0, 1 - am]])
    a = np.array([[1, 1, 0.5 - beta], [0, 1, 1 - gamma], [-w2 * af, 0, -am]])
    return float(np.abs(np.linalg.eigvals(np.linalg.solve(b, a))).max())


@pytest.mark.parametrize("steps_per_period", [2.0, 0.5])
def test_dissipative_step_damps_a_mode_it_cannot_resolve_at_its_spectral_radius(steps_per_period):
    rho = 0.8
    x, xdot, dt, _ = _free_pair(
        steps_per_period,
        200 / steps_per_period,
        integrator=Integrator(rho_infinity=rho),
        coarse=True,  # the point: a mode the step cannot resolve
    )
    expected = _spectral_radius(rho, 2 * math.pi / steps_per_period)
    steps = np.arange(len(x))
    measured = math.exp(np.polyfit(steps[1:], np.log(_amplitude(x, xdot)[1:]), 1)[0])
    assert expected < 0.99
    np.testing.assert_allclose(1.0 - measured, 1.0 - expected, rtol=0.05)


@pytest.mark.parametrize("rho", [1.0, 0.9])
def test_frequency_is_the_closed_form_and_its_error_is_second_order(rho):
    errors = []
    for steps in (40, 80):
        x, xdot, dt, _ = _free_pair(
            steps, 10, integrator=Integrator(rho_infinity=rho), coarse=rho < 1.0
        )
        errors.append(abs(_frequency(x, xdot, dt) / OMEGA - 1.0))
    # At 40 steps per period the trapezoidal rule's period error is (ωh)²/12 = 0.2 %.
    assert errors[0] <= 5e-3
    np.testing.assert_allclose(errors[0] / errors[1], 4.0, rtol=0.15)


def _trapezoidal_frequency_error(steps_per_period: float) -> float:
    """ω̄/ω − 1 of the trapezoidal rule on an undamped mode: it turns (√k x, √m x') by
    θ = 2 atan(ωh/2) a step, so ω̄ = (2/h) atan(ωh/2) (Hairer & Wanner, Solving ODEs II, §V.1)."""
    omega_h = 2 * math.pi / steps_per_period
    return 2 / omega_h * math.atan(omega_h / 2) - 1


def test_trapezoidal_frequency_error_is_dahlquists_limit_and_26_steps_keep_half_a_percent():
    # An A-stable linear multistep method is at most second order, and the trapezoidal rule has
    # the smallest error constant among them (Dahlquist 1963): no unconditionally stable
    # second-order step of this family does better than this error at a given dt.
    error = {}
    for steps in (20, 40, 26):
        x, xdot, dt, _ = _free_pair(steps, 10, integrator=Integrator(rho_infinity=1.0))
        error[steps] = _frequency(x, xdot, dt) / OMEGA - 1.0
    # At 20 steps per period the error is the closed form's, −0.81 %, not worse.
    np.testing.assert_allclose(error[20], _trapezoidal_frequency_error(20), rtol=1e-3)
    assert error[20] < -5e-3
    # Second order: halving dt shrinks it four times.
    np.testing.assert_allclose(error[20] / error[40], 4.0, rtol=0.05)
    # 26 steps per period are the fewest that keep the frequency within 0.5 %.
    assert abs(error[26]) <= 5e-3 < abs(_trapezoidal_frequency_error(25))


@pytest.mark.parametrize("rho", [1.0, 0.9])
def test_damped_pair_decays_at_the_physical_damping_ratio_at_20_steps_per_period(rho):
    zeta = 0.05
    c = 2 * zeta * math.sqrt(K_MESH * MASS)
    x, xdot, dt, _ = _free_pair(20, 10, damping=c, integrator=Integrator(rho_infinity=rho))
    t = dt * np.arange(len(x))
    decay = -np.polyfit(t, np.log(_amplitude(x, xdot)), 1)[0]
    np.testing.assert_allclose(decay / OMEGA, zeta, rtol=5e-2)


def test_metadata_names_the_scheme_and_its_spectral_radius():
    *_, res = _free_pair(20, 1, integrator=Integrator(rho_infinity=0.5), coarse=True)
    meta = res.metadata["integrator"]
    assert meta["scheme"] == "generalized-alpha"
    assert meta["rho_infinity"] == 0.5
    # Chung & Hulbert 1993: αm = (2ρ − 1)/(ρ + 1), αf = ρ/(ρ + 1), γ = ½ − αm + αf.
    np.testing.assert_allclose(meta["alpha_m"], 0.0, atol=1e-15)
    np.testing.assert_allclose(meta["alpha_f"], 1 / 3, rtol=1e-15)
    np.testing.assert_allclose(meta["gamma"], 0.5 + 1 / 3, rtol=1e-15)
    np.testing.assert_allclose(meta["beta"], 0.25 * (4 / 3) ** 2, rtol=1e-15)


@pytest.mark.parametrize("rho", [-0.1, 1.5, float("nan"), True])
def test_spectral_radius_outside_zero_to_one_is_refused(rho):
    with pytest.raises(InputError, match="rho_infinity"):
        Integrator(rho_infinity=rho)
