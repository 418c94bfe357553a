"""speed_ratios: every joint turns at its tooth ratio times the input's speed."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import pinwind
from pinwind.errors import CheckFailed, InputError, PinwindWarning
from pinwind.model.gearbox import loads
from pinwind.testing import speed_ratios
from pinwind.testing.kinematic_ratios import tooth_ratios
from tests.conftest import MODELS
from tests.dynamics.test_flank_contact import pair_urdf


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def test_the_saleh_stage_turns_its_sun_at_one_plus_z_ring_over_z_sun_times_the_carrier():
    """Ring 120, sun 24, planet 48 fixed ring: sun 1 + 120/24 = 6; a planet relative to the
    carrier −z_ring/z_planet = −2.5 (it rolls inside the ring)."""
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    ratios = tooth_ratios(gb, "carrier")
    np.testing.assert_allclose(ratios["sun"], 6.0, rtol=1e-12)
    np.testing.assert_allclose([ratios[f"planet{i}"] for i in (1, 2, 3)], -2.5, rtol=1e-12)
    res = _run(gb, duration=0.05, dt=1e-3, torques={"carrier": lambda t: 1e5 * (1 + t)},
               speeds={"sun": lambda t: 8.0 + 100.0 * t})  # fmt: skip
    figure = speed_ratios(res, gb, input_joint="carrier", rtol=1e-9)
    assert figure.measured <= 1e-9


def test_a_compliant_pair_turns_within_its_deflections_vibration_of_z1_over_z2():
    """20/40: gear b at −1/2 the pinion's speed, with the mesh's vibration about it."""
    gb = loads(pair_urdf(bearing="", mesh='stiffness_variation="constant" damping_ratio="0.1"'))
    np.testing.assert_allclose(tooth_ratios(gb, "a")["b"], -0.5, rtol=1e-12)
    res = _run(gb, duration=0.02, dt=1e-5, torques={"a": 50.0, "b": -100.0},
               initial_speeds={"a": 100.0})  # fmt: skip
    speed_ratios(res, gb, input_joint="a", rtol=1e-3)


def test_a_joint_off_its_ratio_is_caught_by_name_and_sample():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = _run(gb, duration=0.01, dt=1e-3, speeds={"carrier": 1.5})
    res.speed[4, res.joint_names.index("planet2")] *= 1.001
    with pytest.raises(CheckFailed) as caught:
        speed_ratios(res, gb, input_joint="carrier", rtol=1e-6)
    np.testing.assert_allclose(caught.value.measured, 1e-3, rtol=1e-6)
    assert 'joint "planet2" at sample 4' in str(caught.value)


def test_an_input_at_rest_or_a_joint_of_no_train_is_refused():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = _run(gb, duration=0.01, dt=1e-3)
    with pytest.raises(InputError, match="does not turn"):
        speed_ratios(res, gb, input_joint="carrier")
    with pytest.raises(InputError, match='"ring" does not turn with "carrier"'):
        speed_ratios(res, gb, input_joint="carrier", joints=["ring"])
