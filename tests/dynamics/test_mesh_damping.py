"""The compliant mesh's dashpot: a damped pair's free vibration decays at its damping ratio.

The pair of ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, 20°, J_A = 0.0015 and
J_B = 0.006 kg·m²) with one mesh of constant stiffness is a two-inertia oscillator along the line
of action, x = r_b,A θ_A + r_b,B θ_B:

    m x'' = −k x − c x',   m = 1 / (r_b,A²/J_A + r_b,B²/J_B),   ζ = c / (2 √(k m)).

Balanced torques load the teeth for the first half period and then stop, so that whatever state
the run starts in (undeflected, or deflected by the torques at t = 0), the pair vibrates freely
about x = 0 afterwards. Its successive peaks fall by the logarithmic decrement
δ = 2π ζ / √(1 − ζ²) per period. The step is the trapezoidal rule (ρ∞ = 1), which adds no
numerical damping, at 100 steps per period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.dynamics import Integrator
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf
from tests.dynamics.test_time_stepping import K_MESH, K_SINGLE, MASS, OMEGA, R_BA, R_BB

#: Tooth force of the torque pulse [N].
PULSE = 1000.0
ZETA = 0.05
STEPS_PER_PERIOD = 100
PERIODS = 6
#: The damped period 2π / (ω √(1 − ζ²)) [s].
PERIOD = 2 * math.pi / (OMEGA * math.sqrt(1 - ZETA**2))


def _released_pair(compliance: MeshCompliance) -> tuple[np.ndarray, int]:
    """x [m] of the pair released after a half-period torque pulse, and the release sample."""
    dt = PERIOD / STEPS_PER_PERIOD
    release = STEPS_PER_PERIOD // 2

    def pulse(radius: float):
        return lambda t: PULSE * radius if t < (release - 0.5) * dt else 0.0

    res = pinwind.simulate(
        loads(two_gear_urdf(), "pair.urdf"),
        duration=PERIODS * PERIOD,
        dt=dt,
        torques={"a": pulse(R_BA), "b": pulse(R_BB)},
        gravity=np.zeros(3),
        meshes={"m": compliance},
        integrator=Integrator(rho_infinity=1.0),
    )
    a, b = res.joint("a"), res.joint("b")
    return R_BA * a.angle + R_BB * b.angle, release


def _log_decrement(x: np.ndarray, release: int) -> float:
    """Mean ln(peak_i / peak_{i+1}) over the free vibration's successive positive peaks."""
    free = x[release + 1 :]
    inner = free[1:-1]
    peaks = np.flatnonzero((inner > free[:-2]) & (inner >= free[2:]) & (inner > 0.0)) + 1
    heights = free[peaks]
    assert len(heights) >= PERIODS - 2, heights
    return float(np.mean(np.log(heights[:-1] / heights[1:])))


@pytest.mark.parametrize(
    "compliance",
    [
        MeshCompliance(
            stiffness=K_SINGLE, variation="constant", damping=2 * ZETA * math.sqrt(K_MESH * MASS)
        ),
        MeshCompliance(stiffness=K_SINGLE, variation="constant", damping_ratio=ZETA),
    ],
    ids=["damping c given", "damping ratio given"],
)
def test_free_vibration_of_a_damped_pair_falls_by_the_log_decrement_of_its_damping_ratio(
    compliance,
):
    """Guards the dashpot c δ̇ of the compliant mesh (``cpp/compliant_mesh.hpp``: F = k δ + c δ̇
    and its implicit weight w = h (h k/4 + c/2)) and the damping a ratio stands for,
    c = 2 ζ √(k m_eq) (``dynamics/compliant.py`` ``mesh_setup``): twice the damping doubles δ."""
    x, release = _released_pair(compliance)
    expected = 2 * math.pi * ZETA / math.sqrt(1 - ZETA**2)
    np.testing.assert_allclose(_log_decrement(x, release), expected, rtol=0.02)
