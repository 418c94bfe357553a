"""A run whose applied torques do not balance through the gear train, or whose dt is too coarse,
says so (issue 25 item 5)."""

from __future__ import annotations

import warnings

import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.dt_advice import coarse_step_notes
from pinwind.dynamics.torque_balance import imbalances
from pinwind.errors import PinwindWarning, StepTooCoarse, TorquesUnbalanced
from pinwind.loads.generator import ConstantTorque, LinearSlip
from tests.conftest import MODELS, load_model

#: The Saleh stage with the ring fixed: ω_sun / ω_carrier = 1 + z_ring / z_sun = 1 + 120/24.
SUN_RATIO = 1.0 + 120.0 / 24.0


@pytest.fixture(scope="module")
def planetary():
    return pinwind.load(MODELS / "saleh2017_planetary.urdf")


def test_quick_start_without_the_sun_torque_warns_with_the_torque_that_balances_it(planetary):
    with pytest.warns(TorquesUnbalanced) as caught:
        pinwind.simulate(planetary, duration=0.01, dt=1e-3, torques={"carrier": 1e6})
    (message,) = [str(w.message) for w in caught if w.category is TorquesUnbalanced]
    assert 'referred to joint "carrier" they leave 1e+06 N·m' in message
    balancing = -1e6 / SUN_RATIO  # power balance T_sun ω_sun + T_carrier ω_carrier = 0
    assert f'A torque of {balancing:.10g} N·m on "sun"' in message
    assert f"ω_sun / ω_carrier = {SUN_RATIO:g}" in message


def test_net_torque_is_the_applied_torques_referred_to_the_carrier(planetary):
    (found,) = imbalances(planetary, {"carrier": 1e6, "sun": -1.6e5})
    assert (found.joint, found.balancing_joint) == ("carrier", "sun")
    assert_allclose(found.net_torque, 1e6 - SUN_RATIO * 1.6e5, rtol=1e-12)
    assert_allclose(found.ratio, SUN_RATIO, rtol=1e-12)
    assert_allclose(found.balancing_torque, -1e6 / SUN_RATIO, rtol=1e-12)


def test_balanced_quick_start_warns_nothing(planetary):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PinwindWarning)
        pinwind.simulate(
            planetary, duration=0.01, dt=1e-3, torques={"carrier": 1e6, "sun": -1e6 / SUN_RATIO}
        )


@pytest.mark.parametrize(
    "held",
    [
        {"speeds": {"carrier": 1.0}},
        {"generators": {"sun": LinearSlip(slope=1e5, sync_speed=10.0)}},
        {"generators": {"sun": ConstantTorque(torque=1e6 / SUN_RATIO)}},
    ],
    ids=["speed driver", "generator law", "constant generator torque that balances"],
)
def test_a_train_held_or_balanced_by_a_driver_or_generator_warns_nothing(planetary, held):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PinwindWarning)
        pinwind.simulate(
            planetary, duration=0.01, dt=1e-3, torques={"sun": 0.0} if "speeds" in held else
            {"carrier": 1e6}, **held,
        )  # fmt: skip


def test_two_steps_of_one_second_in_a_two_second_run_warn():
    (note,) = coarse_step_notes(2.0, 1.0)
    assert note.startswith("dt = 1 s leaves 2 steps in the 2 s run")
    assert "dt ≤ 0.2 s" in note  # 2 s / 10 steps


def test_a_run_of_two_steps_warns(planetary):
    with pytest.warns(StepTooCoarse, match="leaves 2 steps"):
        pinwind.simulate(
            planetary, duration=2.0, dt=1.0, torques={"carrier": 1e6, "sun": -1e6 / SUN_RATIO}
        )


def test_dt_beyond_half_the_torsional_spring_period_warns():
    """Cai's half-shafts: the spring mode's frequency is sqrt(k/J) of the shaft on its spring
    with the gear train held; it must be named with the dt that resolves it."""
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    with pytest.warns(StepTooCoarse, match="highest torsional-spring mode"):
        pinwind.simulate(gb, duration=0.1, dt=0.01, speeds={"input_shaft": 20.0})
    assert coarse_step_notes(0.1, 1e-4, 110.0) == []


def test_a_torque_signal_counts_by_its_mean_and_the_warning_says_so(planetary):
    # A ramp and a step were checked at their means over the run, and the warning called the
    # step's mean (−1e5 N·m at the last of 10 001 times: −9.999 N·m) the torque "now" on the sun.
    from pinwind.loads.signals import Ramp

    ramp = Ramp(start_value=0.0, end_value=1e6, start_time=0.0, end_time=5.0)
    with pytest.warns(TorquesUnbalanced) as caught:
        pinwind.simulate(planetary, duration=0.01, dt=1e-3, torques={"carrier": ramp})
    (message,) = [str(w.message) for w in caught if w.category is TorquesUnbalanced]
    assert "(torque signals taken at their mean over the run)" in message
    mean = 1e6 / 5.0 * 0.01 / 2  # the ramp's mean over [0, 0.01 s]: half its value at the end
    assert f'A torque of {-mean / SUN_RATIO:.10g} N·m on "sun"' in message
    with pytest.warns(TorquesUnbalanced) as caught:  # constant torques: no such note
        pinwind.simulate(planetary, duration=0.01, dt=1e-3, torques={"carrier": 1e6})
    assert all("mean over the run" not in str(w.message) for w in caught)
