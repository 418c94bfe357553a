"""Blade-pitch control of the rotor (loads/pitch_control.py, cpp/rotor.hpp) on a one-DOF rotor.

The model: the NREL 5 MW's rotor and generator on one rigid shaft, the rotor's speed the shaft's
(the generator's law and inertia restated on the rotor shaft, ratio N = 97). Every expectation
comes from the shipped ROSCO table through scipy (``RegularGridInterpolator``, ``brentq``,
``lsim``), DISCON's constants and closed forms written out here, not from pinwind's own
interpolation.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.interpolate import RegularGridInterpolator
from scipy.optimize import brentq
from scipy.signal import lsim

import pinwind
from pinwind.errors import InputError
from pinwind.loads.generator import VariableSpeed
from pinwind.loads.pitch_control import PitchControl
from pinwind.loads.rotor import Rotor
from pinwind.loads.rotor_performance import NREL5MW_PERFORMANCE, read_performance
from pinwind.loads.signals import Step
from pinwind.model.gearbox import loads

#: Gearbox ratio, air density [kg/m³], rotor radius [m] (Jonkman et al. 2009 Table 1-1).
N, RHO, RADIUS = 97.0, 1.225, 63.0
#: The speed set point on the rotor shaft [rad/s]: 12.1 rpm, 1173.7 rpm of the generator over 97
#: (DISCON's PC_RefSpd, 122.9096 rad/s, is 1173.7 rpm to 7 digits).
SET = 1173.7 / N * 2 * math.pi / 60
#: Rated generator torque on the rotor shaft [N·m]: ROSCO's VS_RtTq 43 093.55 N·m × 97.
RATED_TORQUE = 43093.55 * N
#: Drivetrain inertia on the rotor shaft [kg·m²]: rotor 38 759 236 + generator 534.116 × 97²
#: (Jonkman et al. 2009 Table 5-1).
INERTIA = 38_759_236.0 + 534.116 * N**2
#: DISCON's K_P [s] and K_I [-] on the generator speed, θ_K [rad], rate limit [rad/s], corner
#: frequency [rad/s] (OpenFAST reg_tests/5MW_Baseline/ServoData/Source/DISCON.f90).
KP_GEN, KI_GEN, THETA_K, RATE, CORNER = 0.01882681, 0.008068634, 0.1099965, 0.1396263, 1.570796
#: The generator on the rotor shaft: Jonkman's K ω² (2.332287 N·m·s² on the generator, × N³),
#: rated torque from DISCON's VS_RtGnSp 121.6805 rad/s up, region 2½ at 10 % slip.
GENERATOR = VariableSpeed(
    gain=2.332287 * N**3, rated_torque=RATED_TORQUE, rated_speed=121.6805 / N, slip=0.1
)

URDF = """<robot name="rotor">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="1.0"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <axis xyz="0 0 1"/></joint>
  <gearbox/>
</robot>"""


@pytest.fixture(scope="module")
def table() -> RegularGridInterpolator:
    """C_p(λ, β) of the shipped ROSCO table, linear in each cell (scipy's, not pinwind's)."""
    grid = read_performance(NREL5MW_PERFORMANCE)
    return RegularGridInterpolator((np.array(grid.tsr), np.array(grid.pitch)), grid.cp)


def aero_torque(cp: RegularGridInterpolator, speed: float, wind: float, pitch: float) -> float:
    """½ ρ π R² v³ C_p(ω R / v, β) / ω [N·m]."""
    power = 0.5 * RHO * math.pi * RADIUS**2 * wind**3 * cp([[speed * RADIUS / wind, pitch]])[0]
    return float(power / speed)


def steady_pitch(cp: RegularGridInterpolator, wind: float) -> float:
    """The β of ½ ρ π R² v³ C_p(λ_rated, β) = rated torque × rated speed [rad]."""
    return brentq(lambda b: aero_torque(cp, SET, wind, b) - RATED_TORQUE, 0.0,
                  math.radians(24.5), xtol=1e-15)  # fmt: skip


def run(wind, *, duration, control=None, pitch=0.0, speed=SET, dt=0.01):
    """The one-DOF rotor at every step of ``duration`` [s], controlled by ``control``."""
    rotor = Rotor.nrel5mw(inertia=INERTIA, pitch=pitch, pitch_control=control)
    return pinwind.simulate(loads(URDF, path="rotor.urdf"), duration=duration, dt=dt,
                            rotors={"shaft": rotor}, generators={"shaft": GENERATOR},
                            wind=wind, initial_speeds={"shaft": speed}, keep="all")  # fmt: skip


def test_the_preset_is_discons_generator_gains_restated_on_the_rotor_speed():
    # A pitch of K e on a generator speed error e_g = N e_r is N K e_r on the rotor's.
    c = PitchControl.nrel5mw()
    assert_allclose([c.kp, c.ki], [N * KP_GEN, N * KI_GEN], rtol=1e-15)
    assert_allclose(c.speed_set, 122.9096 / N, rtol=1e-6)  # 12.1 rpm
    assert_allclose(math.degrees(c.gain_angle), 6.302336, rtol=1e-6)
    assert_allclose([math.degrees(c.rate), c.corner / (2 * math.pi)], [8.0, 0.25], rtol=1e-6)
    assert (c.pitch_min, c.pitch_max) == (0.0, math.pi / 2)


@pytest.mark.parametrize("wind", [14.0, 18.0])
def test_pitch_settles_where_the_table_gives_rated_power_at_rated_speed(table, wind):
    # From β = 0 in a steady wind above rated the rotor overspeeds, the controller pitches it
    # back; after 90 s the speed is the set point and the pitch the root of
    # ½ ρ π R² v³ C_p(λ_rated, β) = T_rated Ω_rated on the table. The compiled rotor is bilinear
    # in the same table: what is left is the transient's, below 1e-8 rad after 90 s.
    res = run(wind, duration=90.0, control=PitchControl.nrel5mw())
    pitch, speed = res.rotor("shaft").pitch, res.joint("shaft").speed
    assert pitch.max() > steady_pitch(table, wind)  # it went past on the way
    assert_allclose(pitch[-1], steady_pitch(table, wind), rtol=0, atol=1e-8)
    assert_allclose(speed[-1], SET, rtol=1e-9)


def test_below_rated_the_pitch_stays_at_zero_and_the_run_is_the_uncontrolled_one():
    # 8 m/s: the K ω² law holds λ near 7.6, 0.97 rad/s, below the set point of 1.267 rad/s: the
    # filtered speed error stays negative, the integral at its floor 0, the command below 0.
    controlled = run(8.0, duration=30.0, control=PitchControl.nrel5mw(), speed=1.0)
    fixed = run(8.0, duration=30.0, speed=1.0)
    assert np.all(controlled.rotor("shaft").pitch == 0.0)
    assert controlled.joint("shaft").speed.max() < 0.9 * SET
    for name, values in fixed.arrays().items():
        assert np.array_equal(controlled.arrays()[name], values, equal_nan=True), name


@pytest.mark.parametrize("rate_deg_s", [8.0, 2.0])
def test_the_pitch_rate_never_exceeds_its_limit_after_a_wind_step(table, rate_deg_s):
    # From the steady state of 12 m/s to 25 m/s at t = 2 s, dt 0.01 s. The preset's 8°/s
    # (0.1396263 rad/s) is never exceeded; the preset's loop asks for up to 7.7°/s here, so a
    # limit of 2°/s shows it binding: the pitch then moves at exactly the limit for seconds.
    dt, limit = 0.01, math.radians(rate_deg_s)
    control, start = PitchControl.nrel5mw(rate=limit), steady_pitch(table, 12.0)
    res = run(Step(time=2.0, before=12.0, after=25.0), duration=8.0, dt=dt, control=control,
              pitch=start)  # fmt: skip
    rate = np.diff(res.rotor("shaft").pitch) / dt
    assert np.abs(rate).max() <= limit * (1 + 1e-9)
    assert_allclose(limit, RATE if rate_deg_s == 8.0 else math.radians(2.0), rtol=1e-6)
    if rate_deg_s == 2.0:
        assert np.sum(rate > limit * (1 - 1e-9)) > 200  # 2 s at the limit


def test_after_a_long_spell_below_rated_the_pitch_leaves_zero_as_soon_as_the_speed_is_over():
    # 60 s at 8 m/s (speed error about −0.3 rad/s: an integral left free would reach −18 rad and
    # hold the command at 0 for tens of seconds after the speed passes the set point), then
    # 20 m/s. With the integral held at 0 the pitch leaves 0 in the very step the filtered
    # speed passes the set point, by K_P (+ K_I h) times that step's error: the filter
    # ω_f ← (1 − α) ω + α ω_f, α = e^{−ω_c h}, run here over the recorded speeds.
    dt = 0.01
    res = run(Step(time=60.0, before=8.0, after=20.0), duration=70.0, dt=dt,
              control=PitchControl.nrel5mw(), speed=1.0)  # fmt: skip
    speed, pitch = res.joint("shaft").speed, res.rotor("shaft").pitch
    alpha = math.exp(-CORNER * dt)
    filtered = np.empty_like(speed)
    filtered[0] = speed[0]
    for k in range(1, speed.size):
        filtered[k] = (1 - alpha) * speed[k] + alpha * filtered[k - 1]
    first = int(np.argmax(pitch > 0.0))
    assert res.time[first] > 60.0
    assert filtered[first - 1] <= SET < filtered[first]
    proportional = (N * KP_GEN + N * KI_GEN * dt) * (filtered[first] - SET)
    assert_allclose(pitch[first], min(proportional, RATE * dt), rtol=1e-6)


def test_the_closed_loop_answers_a_small_wind_step_as_its_linearisation_with_jonkmans_design(
    table,
):
    # At 18 m/s (β₀ 14.7°), a 0.05 m/s wind step. The test's linear model, with the rotor's
    # partial derivatives from the table (central differences inside one bilinear cell):
    #   I Δω̇ = T_ω Δω + T_β Δβ + T_v Δv,  Δω̇_f = ω_c (Δω − Δω_f),  ΔI' = Δω_f,
    #   Δβ = G (K_P Δω_f + K_I ΔI),  G = GK/(1 + β₀ GK/θ_K)
    # (the gain factor GK(β) = 1/(1 + β/θ_K) is evaluated at the pitch itself, as DISCON does:
    # linearised, it divides the scheduled gain by 1 + β₀ GK/θ_K). The simulated speed follows
    # it within 1 % of its peak (the pitch is held over each 0.01 s step and the table's cell
    # is bilinear: both are second order in the step's size).
    c = PitchControl.nrel5mw()
    wind, step = 18.0, 0.05
    beta = steady_pitch(table, wind)

    def partial(i: int) -> float:  # ∂T/∂(ω, v, β)[i] by a central difference of 1e-6
        up, down = [SET, wind, beta], [SET, wind, beta]
        up[i] += 1e-6
        down[i] -= 1e-6
        return (aero_torque(table, *up) - aero_torque(table, *down)) / 2e-6

    t_w, t_v, t_b = partial(0), partial(1), partial(2)
    gk = 1 / (1 + beta / THETA_K)
    g = gk / (1 + beta * gk / THETA_K)
    a = np.array([[t_w / INERTIA, t_b * g * c.kp / INERTIA, t_b * g * c.ki / INERTIA],
                  [CORNER, -CORNER, 0.0], [0.0, 1.0, 0.0]])  # fmt: skip
    b = np.array([[t_v / INERTIA], [0.0], [0.0]])
    res = run(Step(time=1.0, before=wind, after=wind + step), duration=40.0, control=c,
              pitch=beta)  # fmt: skip
    _, linear, _ = lsim((a, b, np.array([[1.0, 0.0, 0.0]]), np.zeros((1, 1))),
                        np.where(res.time >= 1.0, step, 0.0), res.time)  # fmt: skip
    simulated = res.joint("shaft").speed - SET
    assert_allclose(simulated, linear, rtol=0, atol=0.01 * np.abs(linear).max())
    # Jonkman et al. 2009 §7.3 designed K_P, K_I for ω_n = 0.6 rad/s and ζ = 0.7 at β = 0 from
    # I Δφ̈ + (−∂P/∂β) GK K_P N/Ω Δφ̇ + (−∂P/∂β) GK K_I N/Ω Δφ = 0 (the filter, the aerodynamic
    # damping T_ω and the schedule's own feedback left out), ∂P/∂β = −25.52 MW/rad from his
    # linearisation, and GK to follow ∂P/∂β over β. With ∂P/∂β = Ω T_β of this table (CCBlade,
    # −65.9 MW/rad here) the same closed form gives ω_n 0.53 rad/s and ζ 0.62: the table's
    # ∂P/∂β rises less over β than GK assumes (GK ∂P/∂β −19.8 MW/rad here against −25.5), so
    # ω_n lies within 15 % of the design's and ζ in its 0.6-0.7.
    dp_db = SET * t_b  # ∂P/∂β [W/rad]
    stiffness, damping = -dp_db * gk * c.ki / SET, -dp_db * gk * c.kp / SET
    omega_n = math.sqrt(stiffness / INERTIA)
    zeta = damping / (2 * math.sqrt(stiffness * INERTIA))
    assert abs(omega_n / 0.6 - 1) < 0.15
    assert 0.6 <= zeta <= 0.7
    # The loop as run (the linear model's oscillating pair: filter, T_ω and the schedule's
    # feedback in) is slower and about as damped: 0.47 rad/s, ζ 0.66.
    pair = max(np.linalg.eigvals(a), key=lambda z: z.imag)
    assert 0.4 < abs(pair) < 0.6 and 0.55 < -pair.real / abs(pair) < 0.75


def test_the_energy_ledger_closes_while_the_pitch_moves(table):
    # The pitch changes the rotor's torque, not how its work is booked: through a wind step
    # that moves the pitch by degrees, ½ J ω² − ½ J ω₀² is the applied work (rotor and
    # generator, trapezoidal in the speed over each step), and the rotor's part is
    # Σ τ_rotor (ω_k + ω_{k+1})/2 dt from the recorded torque.
    dt = 0.01
    res = run(Step(time=1.0, before=14.0, after=18.0), duration=15.0, dt=dt,
              control=PitchControl.nrel5mw(), pitch=steady_pitch(table, 14.0))  # fmt: skip
    e, speed = res.energy, res.joint("shaft").speed
    assert np.ptp(res.rotor("shaft").pitch) > math.radians(3.0)
    kinetic = 0.5 * (INERTIA + 1.0) * speed**2
    assert_allclose(e["kinetic"], kinetic, rtol=1e-12)
    assert_allclose(e["kinetic"] - kinetic[0], e["work_applied"], rtol=0,
                    atol=1e-9 * kinetic[0])  # fmt: skip
    rotor = np.cumsum(res.rotor("shaft").torque[:-1] * 0.5 * (speed[1:] + speed[:-1]) * dt)
    generator = np.cumsum(-res.generator("shaft").torque[:-1] * 0.5 * (speed[1:] + speed[:-1]) * dt)
    assert_allclose(e["work_applied"][1:], rotor + generator, rtol=0, atol=1e-9 * kinetic[0])


def test_bad_controller_values_are_refused_with_the_value_and_the_fix():
    with pytest.raises(InputError, match=r"ki is -1.*positive"):
        dataclasses.replace(PitchControl.nrel5mw(), ki=-1.0)
    with pytest.raises(InputError, match="pitch_min below pitch_max"):
        PitchControl.nrel5mw(pitch_min=0.5, pitch_max=0.1)
    with pytest.raises(InputError, match="outside its controller's limits"):
        Rotor.nrel5mw(pitch=-0.1, pitch_control=PitchControl.nrel5mw())
