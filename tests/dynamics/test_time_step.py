"""The step's numerical damping of a mesh mode: the formula against a measured decay, and the dt
advice that the warning and the summary give.

The pair is ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, 20°, J_A = 0.0015 and
J_B = 0.006 kg·m²) with a constant mesh stiffness, so its one mesh mode has
ω² = k (r_b,A²/J_A + r_b,B²/J_B), k = c′b (0.75 ε_α + 0.25).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.time_step import (
    DEFAULT_SCHEME,
    TimeStepScheme,
    dt_advice,
    dt_for_damping_ratio,
    numerical_damping_ratio,
)
from pinwind.errors import InputError, PinwindWarning
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


def _free_vibration(dt: float, periods: float, damping_ratio: float = 0.0):
    """A pair under balanced torques, starting undeflected: it swings about PRELOAD."""
    period = 2 * math.pi / OMEGA
    return pinwind.simulate(
        loads(two_gear_urdf(), "pair.urdf"),
        duration=round(periods * period / dt) * dt,
        dt=dt,
        torques={"a": PRELOAD * R_BA, "b": PRELOAD * R_BB},
        gravity=np.zeros(3),
        meshes={
            "m": MeshCompliance(
                stiffness=K_SINGLE, variation="constant", damping_ratio=damping_ratio
            )
        },
    )


def _measured_damping_ratio(force: np.ndarray, dt: float) -> float:
    """ζ from the decay of the swing's peaks: ln(peak) falls by ζ ω per second."""
    swing = force - PRELOAD
    inner = swing[1:-1]
    peaks = np.flatnonzero((inner > swing[:-2]) & (inner >= swing[2:]) & (inner > 0.0)) + 1
    slope = np.polyfit(peaks * dt, np.log(swing[peaks]), 1)[0]
    return -slope / OMEGA


@pytest.mark.parametrize("steps_per_period", [100, 20])
def test_numerical_damping_ratio_is_the_measured_decay_of_an_undamped_pair(steps_per_period):
    dt = 2 * math.pi / OMEGA / steps_per_period
    with pytest.warns(PinwindWarning, match="no physical damping"):
        res = _free_vibration(dt, periods=6)
    measured = _measured_damping_ratio(res.mesh("m").normal, dt)
    # ω dt / 4 by hand: π / (2 × steps per period).
    np.testing.assert_allclose(measured, math.pi / (2 * steps_per_period), rtol=0.1)
    np.testing.assert_allclose(
        numerical_damping_ratio(OMEGA, dt, DEFAULT_SCHEME), measured, rtol=0.1
    )


def test_theta_sets_the_numerical_dashpot_c_equal_theta_k_dt():
    # ζ = c / (2 m ω) with c = θ k dt and k = m ω²: θ ω dt / 2.
    scheme = TimeStepScheme(implicit_theta=0.3)
    np.testing.assert_allclose(
        numerical_damping_ratio(1000.0, 1e-4, scheme), 0.3 * 1000.0 * 1e-4 / 2, rtol=1e-12
    )


def test_the_accurate_dt_keeps_the_numerical_ratio_at_a_tenth_of_the_physical():
    # ω dt / 4 = ζ / 10  ⇒  dt = 0.4 ζ / ω.
    np.testing.assert_allclose(
        dt_for_damping_ratio(OMEGA, 0.005, DEFAULT_SCHEME), 0.4 * 0.05 / OMEGA, rtol=1e-9
    )
    advice = dt_advice(OMEGA / (2 * math.pi), 1e-5, 0.05)
    np.testing.assert_allclose(advice.accurate_dt, 0.4 * 0.05 / OMEGA, rtol=1e-9)
    np.testing.assert_allclose(advice.numerical_ratio, OMEGA * 1e-5 / 4, rtol=1e-12)


def test_an_unknown_scheme_is_refused_naming_the_schemes():
    with pytest.raises(InputError, match="implicit-mesh"):
        TimeStepScheme(kind="newmark")


def test_warning_names_the_mode_both_damping_ratios_and_the_accurate_dt():
    zeta = 0.05
    dt = 2 * math.pi / OMEGA / 20  # ζ_num = π / 40 = 0.0785 > ζ
    with pytest.warns(PinwindWarning) as record:
        res = _free_vibration(dt, periods=1, damping_ratio=zeta)
    (message,) = (str(w.message) for w in record if "mesh mode" in str(w.message))
    assert f"{OMEGA / (2 * math.pi):.4g} Hz" in message
    assert f"ζ_num = {math.pi / 40:.3g}" in message
    assert f"physical ζ = {zeta:.3g}" in message
    assert f"dt ≤ {0.4 * zeta / OMEGA:.2g} s" in message
    np.testing.assert_allclose(res.metadata["highest_mesh_mode_damping_ratio"], zeta, rtol=1e-9)


def test_a_step_that_damps_less_than_the_physics_does_not_warn(recwarn):
    _free_vibration(2 * math.pi / OMEGA / 100, periods=1, damping_ratio=0.05)
    assert not [w for w in recwarn if "mesh mode" in str(w.message)]
