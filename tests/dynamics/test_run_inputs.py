"""Bad run inputs fail before any stepping, with a message naming the input and the value."""

from __future__ import annotations

import math

import pytest

import pinwind
from pinwind.errors import Diverged, InputError, NonFiniteInput, UnknownJoint
from pinwind.model.gearbox import loads


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


def test_non_finite_speed_function_is_rejected_before_stepping(pair):
    with pytest.raises(NonFiniteInput, match=r'speeds\["b"\] is nan rad/s at t = 0.01 s'):
        pinwind.simulate(
            pair, duration=0.02, dt=1e-3, speeds={"b": lambda t: math.nan if t > 0 else 0.0}
        )


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
        pinwind.simulate(pair, duration=0.01, dt=1e-3, torques={"a": torque})


def test_unstable_time_step_stops_with_the_step_and_time():
    # Cai's shaft springs (k = 442.3 N·m/rad on ~1e-3 kg·m²) ring at ~600 rad/s: explicit
    # integration with dt = 10 ms (ω dt ≫ 2) grows without bound until it overflows.
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "cai_spur_pair.urdf")
    with pytest.raises(Diverged, match=r"diverged at step \d+ \(t = [0-9.e+-]+ s\).*Reduce dt"):
        pinwind.simulate(
            gb,
            duration=100.0,
            dt=1e-2,
            speeds={"input_shaft": 20.0},
            torques={"output_shaft": -49.0},
        )


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
