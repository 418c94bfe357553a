"""Generator laws in the compiled loop against closed forms derived here."""

from __future__ import annotations

import math
import re

import pytest
from numpy.testing import assert_allclose
from scipy.optimize import minimize_scalar

import pinwind
from pinwind.dynamics.elements import induction_torque
from pinwind.errors import InputError, UnknownJoint
from pinwind.loads.generator import ConstantTorque, InductionMachine, LinearSlip, VariableSpeed
from pinwind.model.gearbox import loads

RPM = 2 * math.pi / 60
# IFToMM 2018 Table 1's generator, written out here (not taken from the preset).
RS, RR, LLS, LLR, LM = 0.00053, 0.00048, 0.0365e-3, 0.052e-3, 1.97e-3
V_LINE, FREQ, POLES = 575.0, 60.0, 4
WE = 2 * math.pi * FREQ
W_SYNC = WE / (POLES / 2)  # 1800 rpm


def thevenin():
    """Thevenin equivalent of the stator and magnetising branches, seen from the rotor."""
    zs = complex(RS, WE * LLS)
    zm = complex(0.0, WE * LM)
    v_th = (V_LINE / math.sqrt(3)) * zm / (zs + zm)
    z_th = zs * zm / (zs + zm)
    return abs(v_th), z_th.real, z_th.imag, WE * LLR


def pair(pair_urdf):
    """20/40 external pair: b turns at −½ the speed of a."""
    return loads(pair_urdf(), path="pair.urdf")


def test_induction_machine_gives_no_torque_at_1800_rpm_for_4_poles_at_60_hz():
    machine = InductionMachine.cart600()
    assert_allclose(machine.sync_speed, 1800 * RPM, rtol=1e-15)
    assert induction_torque(machine, 1800 * RPM) == 0.0
    # Just above synchronous speed it generates, just below it motors.
    assert induction_torque(machine, 1801 * RPM) > 0 > induction_torque(machine, 1799 * RPM)


def test_induction_pull_out_torque_and_slip_equal_the_thevenin_closed_form():
    machine = InductionMachine.cart600()
    v_th, r_th, x_th, x_lr = thevenin()
    root = math.sqrt(r_th**2 + (x_th + x_lr) ** 2)
    slip_max = RR / root
    motoring_max = 3 * v_th**2 / (2 * W_SYNC * (r_th + root))
    generating_max = 3 * v_th**2 / (2 * W_SYNC * (-r_th + root))

    def speed(slip):
        return W_SYNC * (1 - slip)

    # Motoring: T_gen = −τ is most negative at s = s_max; generating: most positive at −s_max.
    best = minimize_scalar(lambda s: induction_torque(machine, speed(s)), bounds=(1e-4, 0.5),
                           method="bounded", options={"xatol": 1e-12})  # fmt: skip
    assert_allclose(best.x, slip_max, rtol=1e-5)
    assert_allclose(-best.fun, motoring_max, rtol=1e-9)
    best = minimize_scalar(lambda s: -induction_torque(machine, speed(s)), bounds=(-0.5, -1e-4),
                           method="bounded", options={"xatol": 1e-12})  # fmt: skip
    assert_allclose(best.x, -slip_max, rtol=1e-5)
    assert_allclose(-best.fun, generating_max, rtol=1e-9)


def test_induction_torque_at_any_slip_follows_the_equivalent_circuit():
    machine = InductionMachine.cart600()
    v_th, r_th, x_th, x_lr = thevenin()
    for slip in (-0.3, -0.01, -1e-4, 2e-3, 0.05, 1.0):
        rotor = RR / slip
        expected = 3 * v_th**2 * rotor / (W_SYNC * ((r_th + rotor) ** 2 + (x_th + x_lr) ** 2))
        assert_allclose(-induction_torque(machine, W_SYNC * (1 - slip)), expected, rtol=1e-10)


@pytest.mark.parametrize(
    ("law", "generator_torque"),
    [
        (ConstantTorque(12.0), lambda w: 12.0),
        (LinearSlip(slope=0.8, sync_speed=95.0), lambda w: 0.8 * (w - 95.0)),
        (VariableSpeed(gain=2e-3), lambda w: 2e-3 * w * w),
        (VariableSpeed(gain=2e-3, rated_power=5.0), lambda w: 5.0 / w),
        (InductionMachine.cart600(), lambda w: induction_torque(InductionMachine.cart600(), w)),
    ],
    ids=["constant", "linear-slip", "k-omega-squared", "constant-power", "induction"],
)
def test_driver_reaction_of_a_driven_pair_balances_the_generator_torque(
    pair_urdf, law, generator_torque
):
    gb = pair(pair_urdf)
    speed_a = -200.0  # rad/s; b turns at +100 rad/s (20/40 external pair)
    res = pinwind.simulate(gb, duration=0.05, dt=1e-3, speeds={"a": speed_a},
                           generators={"b": law})  # fmt: skip
    w_b = res.joint("b").speed[-1]
    assert_allclose(w_b, 100.0, rtol=1e-12)
    t_gen = generator_torque(w_b)
    # The generator brakes b: torque −T_gen on b (T_gen > 0 generates).
    assert_allclose(res.joint("b").torque[-1], -t_gen, rtol=1e-9, atol=1e-12)
    # At constant speed the driver supplies the power the generator takes: τ_a ω_a = T_gen ω_b.
    assert_allclose(res.joint("a").torque[-1] * speed_a, t_gen * w_b, rtol=1e-9, atol=1e-12)


def test_driver_and_generator_on_one_joint_net_torque_is_zero_and_driver_gives_t_gen(pair_urdf):
    gb = pair(pair_urdf)
    t_gen, speed, duration = 1.5e3, -200.0, 0.05  # N·m braking a, rad/s, s
    res = pinwind.simulate(gb, duration=duration, dt=1e-3, speeds={"a": speed},
                           generators={"a": ConstantTorque(t_gen)})  # fmt: skip
    # b carries no load at constant speed: no mesh force, so τ_driver − T_gen = I·α = 0.
    net = res.joint("a").torque
    assert_allclose(net[1:], 0.0, atol=1e-9)
    # The driver's torque, by the documented sum torque + T_gen, is T_gen...
    driver = net + res.generator("a").torque
    assert_allclose(driver[1:], t_gen, rtol=1e-12)
    # ... and the drivers' term of the energy ledger, computed apart, is its work T_gen·ω·t.
    assert_allclose(res.energy["work_drivers"][-1], t_gen * speed * duration, rtol=1e-6)


def test_stiff_slip_law_runs_stably_on_a_light_shaft(pair_urdf):
    # k h / J_eq ≈ 1e4 · 1e-3 / 0.0075 ≫ 2: an explicit law would diverge at this step.
    gb = pair(pair_urdf)
    res = pinwind.simulate(gb, duration=0.5, dt=1e-3, torques={"a": 5.0},
                           generators={"b": LinearSlip(slope=1e4, sync_speed=-50.0)},
                           initial_speeds={"a": 0.0})  # fmt: skip
    # Steady state: T_a ω_a = T_gen ω_b with ω_a = −2 ω_b: 5 · (−2) = k (ω_b + 50) → ω_b.
    w_b = -50.0 - 10.0 / 1e4
    assert_allclose(res.joint("b").speed[-1], w_b, rtol=1e-9)


def test_generator_on_an_unknown_joint_names_the_joints(pair_urdf):
    with pytest.raises(UnknownJoint, match='unknown joint "c" in generators; joints are: a, b'):
        pinwind.simulate(
            pair(pair_urdf), duration=0.01, dt=1e-3, generators={"c": ConstantTorque(1.0)}
        )


def test_odd_pole_count_is_refused(pair_urdf):
    with pytest.raises(InputError, match="poles = 3 must be even"):
        pinwind.simulate(pair(pair_urdf), duration=0.01, dt=1e-3,
                         generators={"b": InductionMachine.cart600(poles=3)})  # fmt: skip


def test_generator_work_joins_the_energy_ledger(pair_urdf):
    gb = pair(pair_urdf)
    res = pinwind.simulate(gb, duration=0.3, dt=1e-4, torques={"a": 5.0},
                           generators={"b": VariableSpeed(gain=1e-3)})  # fmt: skip
    e = res.energy
    balance = e["work_applied"] + e["work_drivers"] + e["work_gravity"] - e["dissipated"]
    assert_allclose(e["kinetic"] - e["kinetic"][0], balance, rtol=1e-9, atol=1e-9)
    assert e["kinetic"][-1] > 0


def _ramp_error(gb, dt: float) -> float:
    """Largest error of ω_b [rad/s] against the closed form under a torque ramp on a.

    The rigid pair reduced to b (ω_a = −2 ω_b): J ω̇ = F₀ + F₁ t − k ω with J the inertia seen
    by b (from Pinocchio's CRBA), F₀ = k ω_s, F₁ = −2 c (the ramp c t on a, reflected), whose
    solution is ω = (F₀ − F₁ τ)/k + F₁ t/k + (ω₀ − (F₀ − F₁ τ)/k) e^{−t/τ}, τ = J/k.
    """
    import numpy as np
    import pinocchio as pin

    from pinwind.loads.signals import Ramp

    k, w_s, c = 2.0, -40.0, 30.0
    ratio = np.zeros(gb.model.nv)
    ratio[gb.v_index("a")], ratio[gb.v_index("b")] = -2.0, 1.0
    inertia = ratio @ pin.crba(gb.model, gb.model.createData(), gb.neutral()) @ ratio
    res = pinwind.simulate(gb, duration=0.1, dt=dt, torques={"a": Ramp(0.0, c, 0.0, 1.0)},
                           generators={"b": LinearSlip(slope=k, sync_speed=w_s)},
                           gravity=np.zeros(3), initial_speeds={"b": 0.0})  # fmt: skip
    t = res.time
    tau, f0, f1 = inertia / k, k * w_s, -2.0 * c
    base = (f0 - f1 * tau) / k
    exact = base + f1 * t / k + (0.0 - base) * np.exp(-t / tau)
    return float(np.abs(res.joint("b").speed - exact).max())


def test_slip_law_on_a_torque_ramp_is_second_order_in_dt(pair_urdf):
    gb = pair(pair_urdf)
    coarse, fine = _ramp_error(gb, 2e-3), _ramp_error(gb, 1e-3)
    # Halving dt divides the error by four or more (at least second order; the weight's own
    # term is of third order here); a first-order step would divide it by two.
    assert coarse / fine > 3.5


# --- variable speed with region 3 at constant torque ---------------------------------------------

#: The NREL 5 MW on its generator shaft: Jonkman's K [N·m·s²], ROSCO's VS_RtTq [N·m], DISCON's
#: VS_RtGnSp [rad/s] and 10 % slip (VS_SlPc).
K_5MW, T_RATED, W_RATED, SLIP = 2.332287, 43093.55, 121.6805, 0.1


def test_constant_torque_region_3_follows_jonkmans_regions_2_two_and_a_half_and_3():
    # DISCON's region 2½: the line of 10 % slip through (ω_r, T_r), ω_s = ω_r/1.1, from where it
    # meets K ω² (the lower root of K ω² = s (ω − ω_s), DISCON's VS_TrGnSp) up to ω_r; T_r above.
    from pinwind.dynamics.drivetrain import generator_slope, generator_torque

    law = VariableSpeed(K_5MW, rated_torque=T_RATED, rated_speed=W_RATED, slip=SLIP)
    sync = W_RATED / (1 + SLIP)
    slope = T_RATED / (W_RATED - sync)
    trans = (slope - math.sqrt(slope * (slope - 4 * K_5MW * sync))) / (2 * K_5MW)
    assert_allclose(trans * 60 / (2 * math.pi), 1137.0, atol=1.0)  # Jonkman's 1136.7 rpm
    for w in (80.0, 0.99 * trans):
        assert_allclose(generator_torque(law, w), K_5MW * w**2, rtol=1e-14)
    for w in (1.001 * trans, 0.5 * (trans + W_RATED), 0.999 * W_RATED):
        assert_allclose(generator_torque(law, w), slope * (w - sync), rtol=1e-12)
    for w in (W_RATED, 122.9096, 140.0):
        assert generator_torque(law, w) == T_RATED
    assert_allclose(generator_torque(law, -100.0), -K_5MW * 100.0**2, rtol=1e-14)  # odd in ω
    # Unlike constant power (−P/ω², a negative damper) the slope is never negative.
    speeds = [80.0, 0.5 * (trans + W_RATED), 125.0, 140.0]
    assert min(generator_slope(law, w) for w in speeds) >= 0.0
    power = VariableSpeed(K_5MW, rated_power=T_RATED * 122.9096)
    assert_allclose(generator_slope(power, 140.0), -T_RATED * 122.9096 / 140.0**2, rtol=1e-12)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"rated_power": 5e6}, "give one"),
        ({"rated_speed": 0.0}, "give rated_speed > 0"),
        ({"slip": -0.1}, "slip > 0"),
        ({"rated_torque": 100.0}, "does not meet K ω²"),
    ],
)
def test_bad_constant_torque_region_3_is_refused_with_the_values_and_the_fix(changes, message):
    values = dict(gain=K_5MW, rated_torque=T_RATED, rated_speed=W_RATED, slip=SLIP)
    with pytest.raises(InputError, match=message):
        VariableSpeed(**{**values, **changes})


@pytest.mark.parametrize("slope", [-1e30, -1.0, math.nan])
def test_a_slip_law_whose_torque_falls_with_speed_is_refused(slope):
    # T_gen = k (ω − ω_sync) with k < 0 runs the shaft away (it diverged at step 1 in a run).
    said = f"linear-slip generator: slope {slope!r} N·m·s/rad is not ≥ 0"
    with pytest.raises(InputError, match=re.escape(said)):
        LinearSlip(slope=slope, sync_speed=10.0)


def test_a_scenario_slip_law_with_a_negative_slope_exits_2_naming_its_key(tmp_path):
    from tests.conftest import MODELS
    from tests.test_cli import run

    scenario = tmp_path / "s.toml"
    scenario.write_text(
        f'model = "{(MODELS / "saleh2017_planetary.urdf").as_posix()}"\nduration = 0.01\n'
        'dt = 1e-3\n[generator.sun]\nlaw = "linear-slip"\nslope = -1e30\nsync_rpm = 83.9\n'
    )
    out = run("run", str(scenario), "--no-log", "--no-progress")
    assert out.returncode == 2, out.stdout
    assert f"{scenario}:4: generator.sun: linear-slip generator: slope -1e+30" in out.stderr
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
