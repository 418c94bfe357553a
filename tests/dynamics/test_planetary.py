"""Saleh 2017 planetary stage (its Tables 2-3) against hand dynamics.

Ring fixed, carrier input, sun output: one degree of freedom θ_c. With r the pitch radii
(24/48/120 teeth, module 15 mm, no profile shift, so working = reference radii) and a = r_s + r_p:

    ω_sun = (1 + z_r/z_s) ω_c = 6 ω_c,    planet spin (absolute) ω_p = −(a/r_p) ω_c
    J_eq = I_c + Σ_pins (I_pin,zz + m_pin a²) + 3 (m_p a² + I_p (a/r_p)²) + 36 I_s
    α_c = (T_c + 6 T_s) / J_eq

Tangential tooth forces on one planet, S from the sun and R from the ring (both along the
carrier's direction of motion), from the sun's and a planet's spin balance:

    I_s α_s = T_s − 3 r_s S            →  S = (T_s − I_s α_s) / (3 r_s)
    I_p α_p = r_p (R − S)              →  R = S + I_p α_p / r_p

and F_n = |F_t| / cos α. The ring mount torque balances what the planets push onto the ring.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import TorquesUnbalanced
from tests.conftest import MODELS

# Table 3 of Saleh 2017, z axis = shaft axis.
I_CARRIER, I_SUN, I_PLANET, I_PIN = 88.264, 4.8370, 77.78, 1.87
M_PLANET, M_PIN, M_CARRIER, M_SUN, M_RING = 1113.1, 254.3, 405.091, 263.5, 1238.0
MODULE, ALPHA = 0.015, math.radians(24.5)
R_SUN, R_PLANET, R_RING = 24 * MODULE / 2, 48 * MODULE / 2, 120 * MODULE / 2
A = R_SUN + R_PLANET
J_EQ = (
    I_CARRIER
    + 3 * (I_PIN + M_PIN * A**2)
    + 3 * (M_PLANET * A**2 + I_PLANET * (A / R_PLANET) ** 2)
    + 36 * I_SUN
)


@pytest.fixture(scope="module")
def saleh():
    return pinwind.load(MODELS / "saleh2017_planetary.urdf")


def hand_forces(t_carrier: float, t_sun: float) -> tuple[float, float, float]:
    """(α_c, S, R): carrier acceleration and tangential forces on a planet, by hand."""
    alpha_c = (t_carrier + 6 * t_sun) / J_EQ
    s = (t_sun - I_SUN * 6 * alpha_c) / (3 * R_SUN)
    r = s + I_PLANET * (-(A / R_PLANET) * alpha_c) / R_PLANET
    return alpha_c, s, r


def assert_hand_dynamics(res, alpha_c, s, r) -> None:
    """The run's carrier and sun accelerations and six normal forces are the hand dynamics'
    (``hand_forces``: α_c, the planets' sun and ring tangential forces s and r), to 1e-9."""
    assert_allclose(res.joint("carrier").acceleration, alpha_c, rtol=1e-9)
    assert_allclose(res.joint("sun").acceleration, 6 * alpha_c, rtol=1e-9)
    for i in (1, 2, 3):
        assert_allclose(res.mesh(f"sun_planet{i}").normal, abs(s) / math.cos(ALPHA), rtol=1e-9)
        assert_allclose(res.mesh(f"planet{i}_ring").normal, abs(r) / math.cos(ALPHA), rtol=1e-9)


def test_rated_torque_splits_equally_and_gives_sun_mesh_force_of_hand_balance(saleh):
    t_carrier = 1e6  # rated rotor torque, Saleh 2017 §4.1
    t_sun = -t_carrier / 6
    res = pinwind.simulate(
        saleh, duration=0.2, dt=1e-3, torques={"carrier": t_carrier, "sun": t_sun}
    )
    expected = abs(t_sun) / (3 * R_SUN * math.cos(ALPHA))
    for i in (1, 2, 3):
        for mesh in (f"sun_planet{i}", f"planet{i}_ring"):
            assert_allclose(res.mesh(mesh).normal, expected, rtol=1e-9)
            assert_allclose(res.mesh(mesh).tangential, expected * math.cos(ALPHA), rtol=1e-9)
            assert_allclose(res.mesh(mesh).radial, expected * math.sin(ALPHA), rtol=1e-9)
    # In balance nothing accelerates, and the ring mount reacts T_c + T_s.
    assert_allclose(res.joint("carrier").acceleration, 0.0, atol=1e-9)
    assert_allclose(res.joint("ring").torque, -(t_carrier + t_sun), rtol=1e-9)
    assert_allclose(res.bearing("ring").moment[:, 2], -(t_carrier + t_sun), rtol=1e-9)


def test_speed_ratio_carrier_to_sun_is_exactly_six_at_rated_speed(saleh):
    carrier_rpm = 14.2  # Saleh 2017 §4.1: 14.2 rpm rotor, 85.2 rpm sun
    omega = carrier_rpm * 2 * math.pi / 60
    res = pinwind.simulate(
        saleh, duration=0.5, dt=1e-3, speeds={"carrier": omega}, torques={"sun": -1e6 / 6}
    )
    assert_allclose(res.joint("sun").speed / res.joint("carrier").speed, 6.0, rtol=1e-12)
    assert_allclose(res.joint("sun").speed[-1] * 60 / (2 * math.pi), 85.2, rtol=1e-10)
    assert_allclose(res.joint("planet1").speed, -(R_RING / R_PLANET) * omega, rtol=1e-10)
    # The driver holds the speed against the sun torque: it supplies 6 × 1e6/6 N·m.
    assert_allclose(res.joint("carrier").torque, 1e6, rtol=1e-9)


@pytest.mark.parametrize("t_carrier, t_sun", [(1.2e6, -1e6 / 6), (3e5, 0.0), (0.0, 5e4)])
def test_unbalanced_torque_accelerates_with_equivalent_inertia(saleh, t_carrier, t_sun):
    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(
            saleh, duration=0.3, dt=1e-3, torques={"carrier": t_carrier, "sun": t_sun}
        )
    alpha_c, s, r = hand_forces(t_carrier, t_sun)
    assert_hand_dynamics(res, alpha_c, s, r)
    # The ring takes the planets' ring-mesh forces: 3 r_r R about the shaft.
    assert_allclose(res.joint("ring").torque, 3 * R_RING * r, rtol=1e-9)
    # Speeds follow α t exactly under constant torque (semi-implicit Euler).
    assert_allclose(res.joint("carrier").speed, alpha_c * res.time, rtol=1e-9, atol=1e-12)


def test_loaded_flank_follows_the_direction_of_power_flow(saleh):
    # Carrier drives: the planets push the sun forward, so the sun (gear A of sun_planet) is
    # driven, not driving: flank −1. Reversed torques (generator motoring) flip every flank.
    with pytest.warns(TorquesUnbalanced):
        forward = pinwind.simulate(saleh, duration=0.01, dt=1e-3, torques={"carrier": 1e6})
    with pytest.warns(TorquesUnbalanced):
        reverse = pinwind.simulate(saleh, duration=0.01, dt=1e-3, torques={"carrier": -1e6})
    for mesh in forward.mesh_names:
        assert np.all(forward.mesh(mesh).flank == -reverse.mesh(mesh).flank)
        assert_allclose(forward.mesh(mesh).normal, reverse.mesh(mesh).normal, rtol=1e-9)
    assert np.all(forward.mesh("sun_planet1").flank == -1)
    # Tooth force on the sun (−force on B) turns the sun forward (+z).
    force_on_sun = -forward.mesh("sun_planet1").force_on_b[-1]
    lever = forward.mesh("sun_planet1").pitch_point[-1]
    assert np.cross(lever, force_on_sun)[2] > 0


def test_redundant_planet_rows_give_minimum_norm_multipliers(saleh):
    # An asymmetric load case still has rank-deficient rows; the multipliers must have no
    # component in the null space of Jᵀ (the statically indeterminate part).
    from pinwind.dynamics.mesh import MeshSet

    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(saleh, duration=0.01, dt=1e-3, torques={"carrier": 7e5, "sun": 3e4})
    ms = MeshSet(saleh)
    data = saleh.model.createData()
    import pinocchio as pin

    q, v = res.angle[-1], res.speed[-1]
    pin.computeJointJacobiansTimeVariation(saleh.model, data, q, v)
    ms.set_velocity(v)
    jac, _ = ms.combine(ms.evaluate(saleh.model, data), res.mesh_flank[-1])
    lam = res.mesh_normal[-1]
    u, sv, _ = np.linalg.svd(jac)
    rank = int(np.sum(sv > 1e-9 * sv[0]))
    assert rank == 4  # 6 mesh rows of a 3-planet stage with a fixed ring
    null = u[:, rank:]
    assert_allclose(null.T @ lam, 0.0, atol=1e-6 * np.abs(lam).max())


def test_sinusoidal_speed_driver_torque_is_equivalent_inertia_times_acceleration(saleh):
    # Kelso 2011 eq. 2-1: Ω = A sin(2π f t) + X. The driver row asks for the
    # speed change over each step, so its torque is J_eq ΔΩ/dt minus the reflected sun torque.
    rpm = 2 * math.pi / 60
    mean, amp, freq, dt, t_sun = 14.2 * rpm, 1.1 * rpm, 0.5, 1e-3, -1e5

    def omega(t):
        return mean + amp * math.sin(2 * math.pi * freq * t)

    res = pinwind.simulate(
        saleh, duration=1.0, dt=dt, speeds={"carrier": omega}, torques={"sun": t_sun}
    )
    t = res.time
    expected_speed = np.array([omega(x) for x in t])
    assert_allclose(res.joint("carrier").speed, expected_speed, rtol=1e-10)
    delta = (np.array([omega(x + dt) for x in t]) - expected_speed) / dt
    assert_allclose(res.joint("carrier").torque, J_EQ * delta - 6 * t_sun, rtol=1e-9)


def test_planet_sun_and_ring_forces_are_equal_at_the_operating_pressure_angle():
    """dtu500's bearings sit a few µm off the nominal centre distances (within the loader's
    1e-4); the teeth then work at acos((r_b,B ± r_b,A) / a′). A planet on one base circle has
    equal tangential forces at its two meshes, so equal normal forces along that angle."""
    gb = pinwind.load(MODELS / "dtu500_planetary.urdf")
    ratio = 1 + 91 / 20
    res = pinwind.simulate(
        gb,
        duration=0.01,
        dt=1e-3,
        torques={"carrier": 1e5, "sun": -1e5 / ratio},
        gravity=np.zeros(3),
    )
    for i in (1, 2, 3):
        sun = res.mesh(f"sun_planet{i}").normal[-1]
        ring = res.mesh(f"planet{i}_ring").normal[-1]
        np.testing.assert_allclose(sun, ring, rtol=1e-9)


def test_redundant_planet_rows_give_the_same_forces_by_row_basis_and_by_proxsuite():
    """Both solvers return the minimum-norm multipliers of the rank-4 planet rows."""
    from pinwind.dynamics.solver import SolverSettings

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    run = dict(
        duration=0.2,
        dt=1e-3,
        torques={"carrier": lambda t: 1.2e6 + 2e5 * np.sin(20 * t), "sun": -1e6 / 6},
    )
    with pytest.warns(TorquesUnbalanced):  # 1.2 MN·m on the carrier, 1 MN·m held: it accelerates
        direct = pinwind.simulate(gb, **run)
    with pytest.warns(TorquesUnbalanced):
        iterative = pinwind.simulate(gb, solver=SolverSettings(method="proxsuite"), **run)
    scale = np.abs(direct.mesh_normal).max()
    assert_allclose(iterative.mesh_normal, direct.mesh_normal, rtol=0, atol=1e-9 * scale)
    assert_allclose(iterative.speed, direct.speed, rtol=1e-9, atol=1e-12)
    # Equal sharing (the symmetric stage's minimum-norm answer) at every sample.
    sun = direct.mesh_normal[:, :3]
    assert_allclose(sun, np.broadcast_to(sun.mean(axis=1, keepdims=True), sun.shape), rtol=1e-9)


def test_a_generator_weight_changing_every_step_gives_the_same_forces_as_proxsuite():
    """The direct solve's Woodbury update (a joint's implicit weight changes, M₀ stays
    factorised) against proxsuite, which is handed the whole Hessian every step."""
    from pinwind.dynamics.solver import SolverSettings
    from pinwind.loads.generator import InductionMachine
    from pinwind.loads.rotor import Rotor
    from pinwind.loads.wind import KaimalWind

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    run = dict(duration=0.3, dt=1e-3, rotors={"carrier": Rotor.saleh2017()},
               wind=KaimalWind(mean=10.0, turbulence_intensity=0.15, seed=2, duration=5.0),
               generators={"sun": InductionMachine.cart600(poles=84, dynamic=True)},
               initial_speeds={"carrier": 14.2 * 2 * math.pi / 60})  # fmt: skip
    direct = pinwind.simulate(gb, **run)
    iterative = pinwind.simulate(gb, solver=SolverSettings(method="proxsuite"), **run)
    torque = direct.generator("sun").torque
    assert np.ptp(torque) > 0.1 * np.abs(torque).max()  # the weight does change
    scale = np.abs(direct.mesh_normal).max()
    assert_allclose(iterative.mesh_normal, direct.mesh_normal, rtol=0, atol=1e-8 * scale)
    assert_allclose(iterative.generator_torque, direct.generator_torque, rtol=1e-8)
    assert_allclose(iterative.speed, direct.speed, rtol=1e-9, atol=1e-12)


def test_a_torque_changing_every_step_gives_the_hand_dynamics_at_every_sample(saleh):
    # M and the mesh rows stay constant here, so after a few steps the solve is a kept linear
    # map of the forces (constrained_qp.hpp build_map) instead of the substitutions: every
    # sample's acceleration and tooth forces must still be the hand dynamics of the torque
    # applied at that sample, which changes every step (300 steps, 2.1 periods of 7 Hz).
    t_sun = -1e5

    def t_carrier(t: float) -> float:
        return 1.2e6 * (1.0 + 0.3 * math.sin(2 * math.pi * 7.0 * t))

    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(
            saleh, duration=0.3, dt=1e-3, torques={"carrier": t_carrier, "sun": t_sun}
        )
    applied = res.joint("carrier").torque
    assert_allclose(applied, [t_carrier(t) for t in res.time], rtol=1e-12)
    alpha_c, s, r = hand_forces(applied, t_sun)
    assert_hand_dynamics(res, alpha_c, s, r)
