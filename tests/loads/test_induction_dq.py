"""Krause's dq induction machine against the equivalent circuit and its own eigenvalues."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

import pinwind
from pinwind.loads.generator import InductionMachine
from pinwind.model.gearbox import loads

RPM = 2 * math.pi / 60
RS, RR, LLS, LLR, LM = 0.00053, 0.00048, 0.0365e-3, 0.052e-3, 1.97e-3  # 001 Table 1
V_LINE, WE, P = 575.0, 2 * math.pi * 60.0, 2  # pole pairs


def circuit_torque(speed: float) -> float:
    """Generator torque of the per-phase equivalent circuit at shaft speed [rad/s] (T_gen)."""
    w_sync = WE / P
    slip = (w_sync - speed) / w_sync
    zs = complex(RS, WE * LLS)
    zm = complex(0, WE * LM)
    zr = complex(RR / slip, WE * LLR)
    i_s = (V_LINE / math.sqrt(3)) / (zs + zm * zr / (zm + zr))
    i_r = i_s * zm / (zm + zr)
    return -3 * abs(i_r) ** 2 * (RR / slip) / w_sync


def flux_matrix(speed: float) -> np.ndarray:
    """dλ/dt = A λ + u of the dq model in the synchronous frame (λ_qs, λ_ds, λ_qr, λ_dr)."""
    ls, lr = LLS + LM, LLR + LM
    inductance = np.array([[ls, 0, LM, 0], [0, ls, 0, LM], [LM, 0, lr, 0], [0, LM, 0, lr]])
    slip_speed = WE - P * speed
    rotation = np.array([[0, WE, 0, 0], [-WE, 0, 0, 0], [0, 0, 0, slip_speed],
                         [0, 0, -slip_speed, 0]])  # fmt: skip
    return -np.diag([RS, RS, RR, RR]) @ np.linalg.inv(inductance) - rotation


@pytest.fixture
def pair(pair_urdf):
    return loads(pair_urdf(), path="pair.urdf")  # 20/40: b turns at −½ a


def _held(pair, speed_b, machine, duration, dt=1e-3):
    res = pinwind.simulate(pair, duration=duration, dt=dt, speeds={"a": -2 * speed_b},
                           generators={"b": machine})  # fmt: skip
    return res.time, -res.joint("b").torque


@pytest.mark.parametrize("slip", [-0.005, -0.02, 0.01])
def test_dq_steady_state_equals_the_equivalent_circuit_torque_at_the_same_slip(pair, slip):
    speed = (WE / P) * (1 - slip)
    machine = InductionMachine.cart600(dynamic=True, steady_start=True)
    _, torque = _held(pair, speed, machine, duration=0.2)
    assert_allclose(torque, circuit_torque(speed), rtol=1e-6)


def test_locked_speed_start_shows_the_60_hz_transient_decaying_to_the_circuit_torque(pair):
    speed = 1809 * RPM  # slip −0.5 %: generating
    steady = circuit_torque(speed)
    t, torque = _held(pair, speed, InductionMachine.cart600(dynamic=True), duration=4.0)
    deviation = torque - steady
    # Switched on at zero flux: the stator's DC flux offset is seen at the grid frequency in the
    # synchronous frame; the first cycles swing by more than the steady torque itself.
    first = t < 0.5
    spectrum = np.abs(np.fft.rfft(deviation[first]))
    freq = np.fft.rfftfreq(first.sum(), t[1] - t[0])
    assert_allclose(freq[1 + np.argmax(spectrum[1:])], 60.0, atol=2.0)
    assert np.abs(deviation[t < 0.1]).max() > abs(steady)
    # ... to the equivalent circuit's torque.
    assert np.abs(deviation[t > 3.5]).max() < 1e-6 * abs(steady)


def reference_torque(speed: float, times: np.ndarray) -> np.ndarray:
    """Generator torque of Krause's equations from zero flux, solved here with DOP853."""
    a = flux_matrix(speed)
    u = np.array([math.sqrt(2) * V_LINE / math.sqrt(3), 0, 0, 0])
    sol = solve_ivp(lambda t, x: a @ x + u, (0, times[-1]), np.zeros(4), method="DOP853",
                    t_eval=times, rtol=1e-11, atol=1e-12)  # fmt: skip
    ls, lr = LLS + LM, LLR + LM
    inductance = np.array([[ls, 0, LM, 0], [0, ls, 0, LM], [LM, 0, lr, 0], [0, LM, 0, lr]])
    flux = sol.y
    current = np.linalg.solve(inductance, flux)
    return -1.5 * P * (flux[1] * current[0] - flux[0] * current[1])


@pytest.mark.parametrize("dt", [1e-3, 1e-4])
def test_locked_speed_start_follows_krause_equations_solved_independently(pair, dt):
    # At the mechanics' 1 ms the 60 Hz transient has 17 samples per period: the fluxes are
    # integrated exactly over each step (ω held), so neither amplitude nor phase may drift.
    speed = 1809 * RPM
    t, torque = _held(pair, speed, InductionMachine.cart600(dynamic=True), duration=0.5, dt=dt)
    # Sample k records the torque over step k → k + 1: with ρ∞ = 1 the step's force is the mean
    # of those at its ends (cpp/time_step.hpp), the fluxes' torques at t_k and t_k + dt.
    reference = 0.5 * (reference_torque(speed, t) + reference_torque(speed, t + dt))
    swing = np.abs(reference - circuit_torque(speed)).max()
    first_cycles = t < 0.1
    assert np.abs(torque - reference)[first_cycles].max() < 1e-6 * swing
    assert np.abs(torque - reference).max() < 1e-6 * swing


def test_dq_machine_on_a_light_shaft_settles_stably_at_the_mechanical_step(pair):
    # 001's machine on a shaft of 0.006 kg·m² (and 0.0015 behind the pair): its slip stiffness,
    # ≈ 2e4 N·m·s/rad, is 3000 times what an explicit torque could take at h = 1 ms.
    # The slip mode ω̇ = λ ω, λ = −(dT_gen/dω) / J_eq, is far from resolved (λh ≈ −2000); the
    # trapezoidal step (ρ∞ = 1) keeps it stable but damps it per step only by
    # r = (1 + λh/2) / (1 − λh/2) ≈ −0.998 (the former first-order step took it out at once), so
    # the run lasts the steps that take r^n below 1e-14.
    w_sync, dt = WE / P, 1e-3
    j_eq = 0.006 + 4 * 0.0015  # I_b + I_a (ω_a / ω_b)²
    slope = (circuit_torque(w_sync * (1 + 1e-5)) - circuit_torque(w_sync * (1 - 1e-5))) / (
        2e-5 * w_sync
    )
    lam_h = -slope * dt / j_eq
    r = (1 + lam_h / 2) / (1 - lam_h / 2)
    steps = math.ceil(math.log(1e-14) / math.log(abs(r)))
    res = pinwind.simulate(pair, duration=steps * dt, dt=dt, torques={"a": -50.0},
                           generators={"b": InductionMachine.cart600(dynamic=True)},
                           initial_speeds={"a": -2 * w_sync})  # fmt: skip
    # Power balance: T_gen ω_b = T_a ω_a with ω_a = −2 ω_b: T_gen = 100 N·m, generating.
    assert_allclose(-res.joint("b").torque[-1], 100.0, rtol=1e-6)
    assert_allclose(circuit_torque(res.joint("b").speed[-1]), 100.0, rtol=1e-6)
