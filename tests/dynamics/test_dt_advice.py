"""The step's numerical damping of a mesh mode: the formula against a measured decay, and the dt
advice that the warning and the summary give. (These tests encoded the former first-order step's
dashpot θ k dt; they now check the generalized-α step's: none at ρ∞ = 1, the spectral radius's
for ρ∞ < 1.)

The pair is ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, 20°, J_A = 0.0015 and
J_B = 0.006 kg·m²) with a constant mesh stiffness, so its one mesh mode has
ω² = k (r_b,A²/J_A + r_b,B²/J_B), k = c′b (0.75 ε_α + 0.25).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import pinwind
from pinwind.dynamics.dt_advice import (
    DEFAULT_SCHEME,
    dt_advice,
    dt_for_damping_ratio,
    numerical_damping_ratio,
)
from pinwind.dynamics.integrator import Integrator
from pinwind.errors import InputError, PinwindWarning, StepTooCoarse
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

MODULE, ALPHA = 0.002, math.radians(20.0)
J_A, J_B = 0.0015, 0.006
R_BA = 20 * MODULE * math.cos(ALPHA) / 2
R_BB = 40 * MODULE * math.cos(ALPHA) / 2
K_SINGLE = 1e8  # single-pair stiffness c′b [N/m]


def _contact_ratio() -> float:
    """ε_α by hand: (√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a sin α) / p_b."""
    r_a1, r_a2 = 20 * MODULE / 2 + MODULE, 40 * MODULE / 2 + MODULE
    a = 60 * MODULE / 2
    length = math.sqrt(r_a1**2 - R_BA**2) + math.sqrt(r_a2**2 - R_BB**2) - a * math.sin(ALPHA)
    return length / (math.pi * MODULE * math.cos(ALPHA))


K_MESH = K_SINGLE * (0.75 * _contact_ratio() + 0.25)  # ISO 6336-1 c_γα, constant [N/m]
OMEGA = math.sqrt(K_MESH * (R_BA**2 / J_A + R_BB**2 / J_B))
PRELOAD = 1000.0  # tooth force at rest [N]


def _free_vibration(
    dt: float, periods: float, damping_ratio: float = 0.0, integrator: Integrator = DEFAULT_SCHEME
):
    """A pair under balanced torques, starting undeflected: it swings about PRELOAD."""
    period = 2 * math.pi / OMEGA
    return pinwind.simulate(
        loads(two_gear_urdf(), "pair.urdf"),
        duration=round(periods * period / dt) * dt,
        dt=dt,
        torques={"a": PRELOAD * R_BA, "b": PRELOAD * R_BB},
        gravity=np.zeros(3),
        initial_deflection="none",
        meshes={
            "m": MeshCompliance(
                stiffness=K_SINGLE, variation="constant", damping_ratio=damping_ratio
            )
        },
        integrator=integrator,
    )


def _measured_damping_ratio(force: np.ndarray, dt: float) -> float:
    """ζ from the decay of the swing's peaks: ln(peak) falls by ζ ω per second."""
    swing = force - PRELOAD
    inner = swing[1:-1]
    peaks = np.flatnonzero((inner > swing[:-2]) & (inner >= swing[2:]) & (inner > 0.0)) + 1
    slope = np.polyfit(peaks * dt, np.log(swing[peaks]), 1)[0]
    return -slope / OMEGA


def _hand_damping_ratio(rho: float, omega_h: float) -> float:
    """ζ of generalized-α on ẍ = −ω² x by hand: the principal root λ of its amplification
    matrix (Chung & Hulbert 1993 eqs. 2-3, state (x, h v, h² a)), λ = exp(ω̄h(−ζ ± i√(1 − ζ²)))."""
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    gamma, beta = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    w2 = omega_h**2
    b = np.array([[1, 0, -beta], [0, 1, -gamma], [w2 * (1 - af), 0, 1 - am]])
    a = np.array([[1, 1, 0.5 - beta], [0, 1, 1 - gamma], [-w2 * af, 0, -am]])
    roots = np.linalg.eigvals(np.linalg.solve(b, a))
    root = roots[np.argmax(np.abs(roots))]
    return -math.log(abs(root)) / abs(np.log(root))


def _discrete_frequency(rho: float, omega_h: float) -> float:
    """ω̄h = |ln λ| of the same principal root (``_hand_damping_ratio``)."""
    return -math.log(_root_modulus(rho, omega_h)) / _hand_damping_ratio(rho, omega_h)


def _root_modulus(rho: float, omega_h: float) -> float:
    """|λ| of the principal root: the spectral radius ρ(ωh)."""
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    gamma, beta = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    w2 = omega_h**2
    b = np.array([[1, 0, -beta], [0, 1, -gamma], [w2 * (1 - af), 0, 1 - am]])
    a = np.array([[1, 1, 0.5 - beta], [0, 1, 1 - gamma], [-w2 * af, 0, -am]])
    return float(np.abs(np.linalg.eigvals(np.linalg.solve(b, a))).max())


def test_the_trapezoidal_step_keeps_an_undamped_pair_s_amplitude(recwarn):
    dt = 2 * math.pi / OMEGA / 20
    res = _free_vibration(dt, periods=6)
    swing = res.mesh("m").normal - PRELOAD
    # The trapezoidal rule on m ẍ = −k x turns (√k x, √m v) by θ = 2 atan(ωh/2) a step and
    # keeps its length: x_n = −A cos(nθ), A = PRELOAD / k (from rest, undeflected). Sample n
    # records the force over the step, k (x_n + x_{n+1})/2 = −PRELOAD cos(θ/2) cos((n + ½)θ).
    theta = 2 * math.atan(OMEGA * dt / 2)
    n = np.arange(len(swing))
    expected = -PRELOAD * math.cos(theta / 2) * np.cos((n + 0.5) * theta)
    np.testing.assert_allclose(swing, expected, rtol=0, atol=1e-9 * PRELOAD * len(swing))
    assert numerical_damping_ratio(OMEGA, dt, DEFAULT_SCHEME) == 0.0
    assert not [w for w in recwarn if "mesh mode" in str(w.message)]


@pytest.mark.parametrize("steps_per_period", [10, 6])
def test_numerical_damping_ratio_is_the_measured_decay_of_an_undamped_pair(steps_per_period):
    rho = 0.0
    dt = 2 * math.pi / OMEGA / steps_per_period
    with pytest.warns(PinwindWarning, match="no physical damping"):
        res = _free_vibration(dt, periods=12, integrator=Integrator(rho_infinity=rho))
    hand = _hand_damping_ratio(rho, OMEGA * dt)
    np.testing.assert_allclose(
        numerical_damping_ratio(OMEGA, dt, Integrator(rho_infinity=rho)), hand, rtol=1e-9
    )
    # The largest |swing| of each period falls by exp(−ζ ω̄) a second, ω̄ the discrete mode's
    # frequency: |ln λ| / h, from the same root.
    swing = np.abs(res.mesh("m").normal - PRELOAD)
    per = steps_per_period
    envelope = swing[: len(swing) // per * per].reshape(-1, per).max(axis=1)
    slope = np.polyfit(np.arange(len(envelope)) * per * dt, np.log(envelope), 1)[0]
    omega_bar = _discrete_frequency(rho, OMEGA * dt) / dt
    assert hand > 0.01
    np.testing.assert_allclose(-slope / omega_bar, hand, rtol=0.1)


def test_the_accurate_dt_keeps_the_numerical_ratio_at_a_tenth_of_the_physical():
    scheme = Integrator(rho_infinity=0.5)
    dt = dt_for_damping_ratio(OMEGA, 0.005, scheme)
    np.testing.assert_allclose(_hand_damping_ratio(0.5, OMEGA * dt), 0.005, rtol=1e-6)
    advice = dt_advice(OMEGA / (2 * math.pi), 1e-5, 0.05, scheme)
    np.testing.assert_allclose(advice.accurate_dt, dt, rtol=1e-9)
    np.testing.assert_allclose(
        advice.numerical_ratio, _hand_damping_ratio(0.5, OMEGA * 1e-5), rtol=1e-6
    )
    assert math.isinf(dt_advice(OMEGA / (2 * math.pi), 1e-5, 0.05).accurate_dt)


def test_an_unknown_scheme_is_refused_naming_the_schemes():
    with pytest.raises(InputError, match="generalized-alpha"):
        Integrator(scheme="newmark")


def test_warning_names_the_mode_both_damping_ratios_and_the_accurate_dt():
    zeta, rho = 0.05, 0.0
    dt = 2 * math.pi / OMEGA / 10  # ζ_num = 0.0549 > ζ at ρ∞ = 0 (_hand_damping_ratio)
    hand = _hand_damping_ratio(rho, OMEGA * dt)
    assert hand > zeta
    scheme = Integrator(rho_infinity=rho)
    with pytest.warns(PinwindWarning) as record:
        res = _free_vibration(dt, periods=1, damping_ratio=zeta, integrator=scheme)
    (message,) = (str(w.message) for w in record if "mesh mode" in str(w.message))
    assert f"{OMEGA / (2 * math.pi):.4g} Hz" in message
    assert f"ζ_num = {hand:.3g}" in message
    assert f"physical ζ = {zeta:.3g}" in message
    assert f"dt ≤ {dt_for_damping_ratio(OMEGA, zeta / 10, scheme):.2g} s" in message
    np.testing.assert_allclose(res.metadata["highest_mesh_mode_damping_ratio"], zeta, rtol=1e-9)


def test_a_step_that_damps_less_than_the_physics_does_not_warn(recwarn):
    # ρ∞ = 0 at 20 steps per period: ζ_num = 0.0116 < 0.05 (_hand_damping_ratio).
    _free_vibration(
        2 * math.pi / OMEGA / 20,
        periods=1,
        damping_ratio=0.05,
        integrator=Integrator(rho_infinity=0.0),
    )
    assert not [w for w in recwarn if "mesh mode" in str(w.message)]


def test_coarse_step_warns_step_too_coarse_with_the_frequency_error_and_the_dt_that_bounds_it():
    dt = 2 * math.pi / OMEGA / 8  # 8 steps per period: fewer than the 10 that resolve it
    with pytest.warns(StepTooCoarse) as record:
        _free_vibration(dt, periods=1, damping_ratio=0.05)
    (message,) = (str(w.message) for w in record if "mesh mode" in str(w.message))
    # The trapezoidal rule (ρ∞ = 1) turns the mode by 2 atan(ωh/2) a step: ω̄ = (2/h) atan(ωh/2).
    error = 2 / (OMEGA * dt) * math.atan(OMEGA * dt / 2) - 1
    assert f"frequency in the step is {100 * error:.2g} % off" in message
    # The dt at which that error is 0.5 %, solved by hand from the same closed form.
    omega_h = brentq(lambda x: 2 / x * math.atan(x / 2) - 0.995, 1e-3, 1.0)
    assert f"dt ≤ {omega_h / OMEGA:.2g} s" in message
    assert f"({2 * math.pi / omega_h:.3g} steps per period) keeps it within 0.5 %" in message


def test_energy_conserving_step_is_not_said_to_damp_an_undamped_mode():
    # ρ∞ = 1 adds no damping at any dt (|λ| = 1): an undamped mode's damping is not numerical.
    advice = dt_advice(OMEGA / (2 * math.pi), 2 * math.pi / OMEGA / 8, 0.0)
    assert advice.numerical_ratio == 0.0
    assert math.isinf(advice.accurate_dt)
    assert "keeps the amplitude at any dt" in advice.text()
    assert "all its damping is numerical" not in advice.text()


def test_advice_of_the_trapezoidal_rule_says_it_adds_no_damping_not_that_it_damps():
    # ρ∞ = 1: the amplification of a step has modulus 1 at any ωh, so ζ_num = 0 and the text
    # must not read "damps it with ζ_num = 0".
    text = dt_advice(OMEGA / (2 * math.pi), 2 * math.pi / OMEGA / 5, 0.05).text()
    assert "adds no damping to it (ζ_num = 0; its physical ζ = 0.05;" in text
    assert "damps it" not in text
    damped = dt_advice(
        OMEGA / (2 * math.pi), 2 * math.pi / OMEGA / 5, 0.05, Integrator(rho_infinity=0.0)
    )
    assert "damps it with ζ_num = " in damped.text() and "adds no damping" not in damped.text()
