"""Bad run inputs fail before any stepping, with a message naming the input and the value."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.errors import Diverged, InputError, NonFiniteInput, TorquesUnbalanced, UnknownJoint
from pinwind.model.gearbox import loads
from tests.conftest import MODELS


@pytest.fixture(scope="module")
def pair():
    from tests.conftest import two_gear_urdf

    return loads(two_gear_urdf(), path="pair.urdf")


def test_unknown_joint_in_torques_lists_the_joints(pair):
    with pytest.raises(UnknownJoint, match=r'unknown joint "c" in torques; joints are: a, b'):
        pinwind.simulate(pair, duration=0.01, dt=1e-3, torques={"c": 1.0})


def test_unknown_joint_in_speeds_is_named(pair):
    with pytest.raises(UnknownJoint, match=r'"shaft" in speeds'):
        pinwind.simulate(pair, duration=0.01, dt=1e-3, speeds={"shaft": 1.0})


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_torque_is_rejected(pair, value):
    with pytest.raises(NonFiniteInput, match=r'torques\["a"\] is'):
        pinwind.simulate(pair, duration=0.01, dt=1e-3, torques={"a": value})


def test_non_finite_speed_function_stops_the_run_before_the_step_that_needs_it(pair):
    # Step k asks for the driver speed at t_(k+1): NaN from t = 6 ms stops the run before step 5.
    with pytest.raises(
        NonFiniteInput, match=r'speeds\["b"\] is nan rad/s at t = 0.006 s.*before step 5\)'
    ):
        pinwind.simulate(
            pair, duration=0.02, dt=1e-3, speeds={"b": lambda t: math.nan if t > 0.0055 else 0.0}
        )


def test_non_finite_speed_at_the_start_is_rejected_before_stepping(pair):
    with pytest.raises(NonFiniteInput, match=r'speeds\["b"\] is nan rad/s at t = 0 s'):
        pinwind.simulate(pair, duration=0.02, dt=1e-3, speeds={"b": lambda t: math.nan})


@pytest.mark.parametrize("dt", [0.0, -1e-3, math.nan])
def test_time_step_must_be_positive_and_finite(pair, dt):
    with pytest.raises(InputError, match="dt"):
        pinwind.simulate(pair, duration=0.01, dt=dt)


@pytest.mark.parametrize("duration", [0.0, -1.0, math.inf])
def test_duration_must_be_positive_and_finite(pair, duration):
    with pytest.raises(InputError, match="duration"):
        pinwind.simulate(pair, duration=duration, dt=1e-3)


def test_torque_that_turns_non_finite_mid_run_names_the_step_and_time(pair):
    # The inputs are probed at t = 0, duration/2 and duration before the run; this one only
    # fails in between, so the run itself has to catch it.
    def torque(t):
        return math.inf if 0.0065 < t < 0.0075 else 1.0

    with pytest.raises(NonFiniteInput, match=r"at step 7 \(t = 0.007 s\)"):
        with pytest.warns(TorquesUnbalanced):  # 1 N·m on a, nothing on b: it accelerates
            pinwind.simulate(pair, duration=0.01, dt=1e-3, torques={"a": torque})


def test_runaway_load_stops_with_the_step_and_time(pair):
    # A diverging run stops naming the step and time. Every stiff part is implicit, so no dt
    # makes a stable model diverge; a physically unstable load does: a K ω² law with K < 0
    # motors the shaft with +|K| ω², so J_eq ω̇ = |K| ω² and ω = ω₀ / (1 − |K| ω₀ t / J_eq), which
    # passes every bound before t* = J_eq / (|K| ω₀). two_gear_urdf: J_eq = I_a + I_b / 4 =
    # 0.003 kg·m² on gear a; ω₀ = 10 rad/s and |K| = 3e-4 N·m·s² give t* = 1 s, and the speed
    # reaches the plausible bound 1e5 rad/s at t* (1 − ω₀ / 1e5) = 0.9999 s.
    from pinwind.loads.generator import VariableSpeed

    j_eq, gain, omega0 = 0.0015 + 0.006 / 4, 3e-4, 10.0
    blow_up = j_eq / (gain * omega0)
    with pytest.raises(
        Diverged, match=r"diverged at step \d+ \(t = [0-9.e+-]+ s\).*Reduce dt"
    ) as info:
        pinwind.simulate(
            pair,
            duration=2.0,
            dt=1e-3,
            generators={"a": VariableSpeed(gain=-gain)},
            initial_speeds={"a": omega0},
        )
    np.testing.assert_allclose(info.value.time, blow_up * (1 - omega0 / 1e5), rtol=1e-2)


def test_a_fixed_ring_cannot_be_driven():
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with pytest.raises(InputError, match=r'joint "ring" is a fixed mount'):
        pinwind.simulate(gb, duration=0.01, dt=1e-3, speeds={"ring": 1.0})


def test_two_drivers_on_one_gear_train_is_reported_as_conflicting():
    from pinwind.errors import ConflictingConstraints
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    # The sun must turn at 6 × the carrier: 1 and 1 rad/s cannot both hold.
    with pytest.raises(ConflictingConstraints, match="conflicting speed drivers"):
        pinwind.simulate(gb, duration=0.01, dt=1e-3, speeds={"carrier": 1.0, "sun": 1.0})


def test_a_torque_and_a_speed_on_one_joint_are_refused_naming_both(pair):
    # The driver would absorb the torque: it would load no gear, silently.
    from pinwind.errors import ConflictingInputs

    with pytest.raises(ConflictingInputs, match=r'"a" is given both torques\["a"\] and speeds'):
        pinwind.simulate(pair, duration=0.01, dt=1e-3, torques={"a": 1e3}, speeds={"a": 1.0})


def test_a_torque_on_a_fixed_mount_is_refused():
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with pytest.raises(InputError, match=r'joint "ring" is a fixed mount.*vanish into the lock'):
        pinwind.simulate(gb, duration=0.01, dt=1e-3, torques={"ring": 1e5})


@pytest.mark.parametrize(
    "duration, dt, below, above",
    [(1.0, 0.3, "0.9 s", "1.2 s"), (1.0, 0.15, "0.9 s", "1.05 s"), (0.0105, 1e-3, "0.01", "0.011")],
)
def test_duration_that_dt_does_not_divide_is_refused_with_the_nearest_ones(
    pair, duration, dt, below, above
):
    with pytest.raises(InputError, match="not a whole number of steps") as info:
        pinwind.simulate(pair, duration=duration, dt=dt)
    message = str(info.value)
    assert f"duration = {duration:g} s" in message and f"dt = {dt:g} s" in message
    assert f"nearest durations are {below}" in message and f"and {above}" in message


def test_result_arrays_that_do_not_fit_in_memory_give_one_clear_error(pair, monkeypatch):
    import sys

    from pinwind.errors import OutOfMemory

    simulate_module = sys.modules["pinwind.dynamics.simulate"]

    def no_memory(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(simulate_module, "_allocate", no_memory)
    with pytest.raises(OutOfMemory, match=r"memory ran out .* 10001 samples \(duration = 10 s"):
        pinwind.simulate(pair, duration=10.0, dt=1e-3)


def test_speed_beyond_the_plausible_bound_stops_the_run_at_the_first_absurd_sample(pair, tmp_path):
    # two_gear_urdf: I_a = 0.0015, I_b = 0.006 kg·m², ω_b = −(20/40) ω_a, so
    # J_eq = I_a + I_b / 4 = 0.003 kg·m² and ω_a = (T / J_eq) t_k under a constant torque T.
    torque, dt = 2600.0, 1e-3
    alpha = torque / (0.0015 + 0.006 / 4)
    first = math.floor(1e5 / (alpha * dt)) + 1  # first sample with ω_a > 1e5 rad/s: 116
    log = tmp_path / "absurd.mcap"
    with pytest.raises(Diverged, match=r'diverged at step \d+ .*joint "a" turns at') as info:
        with pytest.warns(TorquesUnbalanced):  # the runaway is the point
            pinwind.simulate(pair, duration=1.0, dt=dt, torques={"a": torque}, log=log)
    assert info.value.step == first == 116
    assert "Likely causes" in str(info.value)
    kept = pinwind.read_log(log)
    assert len(kept) == first
    assert np.abs(kept.speed).max() <= 1e5


def test_a_run_recording_every_tenth_sample_stops_at_the_first_recorded_absurd_one(pair):
    # As above, ω_a passes 1e5 rad/s at sample 116; keeping every 10th sample with nothing else
    # reading the blocks, only samples 0, 10, 20, ... are recorded: the first absurd one is 120.
    torque, dt = 2600.0, 1e-3
    with pytest.raises(Diverged, match=r'diverged at step 120 .*joint "a" turns at') as info:
        with pytest.warns(TorquesUnbalanced):  # the runaway is the point
            pinwind.simulate(pair, duration=1.0, dt=dt, torques={"a": torque}, keep=10,
                             statistics=False)  # fmt: skip
    assert info.value.step == 120


def test_initial_speed_of_the_carrier_starts_the_whole_train_at_rated_speed():
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    omega = 14.2 * 2 * math.pi / 60  # Saleh 2017 §4.1: rotor 14.2 rpm
    res = pinwind.simulate(
        gb,
        duration=0.01,
        dt=1e-3,
        initial_speeds={"carrier": omega},
        torques={"carrier": 1e6, "sun": -1e6 / 6},
    )
    # Ring fixed: ω_sun = (1 + z_r/z_s) ω_c = 6 ω_c; planet relative to the carrier −(z_r/z_p) ω_c.
    np.testing.assert_allclose(res.joint("carrier").speed, omega, rtol=1e-12)
    np.testing.assert_allclose(res.joint("sun").speed, 6 * omega, rtol=1e-12)
    for i in (1, 2, 3):
        np.testing.assert_allclose(res.joint(f"planet{i}").speed, -120 / 48 * omega, rtol=1e-12)
    np.testing.assert_allclose(res.joint("ring").speed, 0.0, atol=1e-12)


def test_initial_speeds_that_contradict_the_gear_ratio_are_refused():
    from pinwind.errors import ConflictingConstraints
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with pytest.raises(ConflictingConstraints, match="carrier, sun"):
        pinwind.simulate(gb, duration=0.01, dt=1e-3, initial_speeds={"carrier": 1.0, "sun": 1.0})


def test_constant_torques_held_as_one_row_step_as_the_same_torques_given_as_functions():
    # Constant torques reach the compiled loop as one row held over each block; the same values
    # given as functions of time are tabled sample by sample. Two loads on one joint add up.
    planetary = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    held = {"carrier": 1.2e5, "sun": -1.5e4}
    tabled = {"carrier": lambda t: 1.2e5, "sun": lambda t: -1.5e4}
    runs = []
    for torques in (held, tabled):
        with pytest.warns(TorquesUnbalanced):
            runs.append(pinwind.simulate(planetary, duration=0.05, dt=1e-3, torques=torques))
    a, b = runs
    for name in ("mesh_normal", "speed", "torque", "bearing_force"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    # the carrier's applied torque is the one given, at every sample
    carrier = planetary.v_index("carrier")
    np.testing.assert_allclose(a.torque[:, carrier], 1.2e5, rtol=1e-12)


def test_a_dt_that_makes_more_steps_than_a_run_can_take_is_refused(pair):
    # 0.02 s / 1e-30 s = 2e28 steps: the binding's 64-bit sample count could not take them (a
    # TypeError from the compiled stepper); at least 0.02 / 1e12 = 2e-14 s.
    with pytest.raises(InputError) as info:
        pinwind.simulate(pair, duration=0.02, dt=1e-30)
    message = str(info.value)
    assert message.startswith("dt = 1e-30 s makes 2e+28 steps of the 0.02 s run")
    assert "at least 2e-14 s" in message


def test_a_start_speed_beyond_a_gear_s_is_refused_naming_the_fastest_joint(pair):
    # b at 6e4 rad/s turns a (20 teeth against b's 40) at 6e4 · 40/20 = 1.2e5 rad/s, beyond the
    # 1e5 rad/s a run stops at: started there, the compiled step did not return (1e30 rpm).
    from pinwind.errors import SpeedOutOfRange

    with pytest.raises(SpeedOutOfRange) as info:
        pinwind.simulate(pair, duration=0.01, dt=1e-3, initial_speeds={"b": 6e4})
    message = str(info.value)
    assert message.startswith('at the start joint "a" turns at -1.2e+05 rad/s')
    assert f"({-1.2e5 * 30 / math.pi:.4g} rpm)" in message
    assert 'from initial_speeds["b"] = 6e+04 rad/s' in message


def test_a_speed_driver_beyond_a_gear_s_speed_stops_before_the_step_that_asks_for_it(pair):
    # Step k asks for the driver speed at t_(k+1): 2e5 rad/s (> 1e5) from t = 6 ms stops the
    # run before step 5, as a NaN does. At 1e30 rpm the compiled step never returned.
    from pinwind.errors import SpeedOutOfRange

    with pytest.raises(SpeedOutOfRange) as info:
        pinwind.simulate(
            pair, duration=0.02, dt=1e-3, speeds={"b": lambda t: 2e5 if t > 0.0055 else 0.0}
        )
    message = str(info.value)
    assert message.startswith(f'speeds["b"] is 2e+05 rad/s ({2e5 * 30 / math.pi:.4g} rpm) at ')
    assert "t = 0.006 s" in message and "(the run stopped before step 5)" in message


def test_a_wind_without_a_rotor_is_refused_not_dropped(pair):
    # Only a rotor takes the wind; without one it was dropped, even a NaN.
    with pytest.raises(InputError, match=r"wind nan m/s is given but the run has no rotor"):
        pinwind.simulate(pair, duration=0.01, dt=1e-3, wind=math.nan)


def test_an_initial_speed_on_a_compliant_bearings_slide_is_refused_naming_the_slide():
    # The slides start at rest; a speed given one was reported as "speed drivers on
    # shaft_radial_x conflict with the gear meshes" on a model with neither.
    text = """<?xml version="1.0"?>
<robot name="shaft"><link name="ground"/>
  <link name="shaft"><inertial><mass value="100"/>
    <inertia ixx="2" iyy="2" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <axis xyz="0 0 1"/></joint>
  <gearbox><bearing joint="shaft" radial_stiffness="1e8"/></gearbox></robot>"""
    gb = loads(text, path="shaft.urdf")
    with pytest.raises(InputError, match=r'initial_speeds\["shaft_radial_x"\] = 0.005: .* slide'):
        pinwind.simulate(gb, duration=0.01, dt=1e-3, initial_speeds={"shaft_radial_x": 0.005})
    # at rest, as it starts anyway, it runs; the shaft's own speed is an input
    res = pinwind.simulate(
        gb, duration=0.01, dt=1e-3, initial_speeds={"shaft_radial_x": 0.0, "shaft": 2.0}
    )
    np.testing.assert_allclose(res.joint("shaft").speed, 2.0, rtol=1e-12)
