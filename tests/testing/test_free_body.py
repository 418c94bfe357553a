"""free_body_balance: the ground's bearings hold the whole gearbox's weight and torques."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import pinwind
from pinwind.errors import CheckFailed, PinwindWarning
from pinwind.model.gearbox import loads
from pinwind.testing import free_body_balance
from pinwind.testing.free_body import free_body
from tests.conftest import MODELS
from tests.dynamics.test_flank_contact import pair_urdf
from tests.dynamics.test_support import GEARBOX_MASS, supported_pair, tower

G = 9.81
#: Saleh 2017 Table 3: carrier, sun, 3 planets, ring, 3 pins [kg].
SALEH_MASS = 405.091 + 263.5 + 3 * 1113.1 + 1238 + 3 * 254.3
RPM = 2 * math.pi / 60


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def _saleh():
    return _run(
        pinwind.load(MODELS / "saleh2017_planetary.urdf"),
        duration=0.01, dt=1e-3, torques={"carrier": 1e6}, speeds={"sun": 85.2 * RPM},
    )  # fmt: skip


def test_a_planetary_stage_at_rated_torque_hangs_its_weight_on_its_ground_bearings():
    """Carrier, sun and the locked ring stand on the housing: together they carry the 6009 kg
    stage, and their moments about the axis (1 MN·m in, the sun's driver and the ring's lock)
    cancel."""
    res = _saleh()
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    free_body_balance(res, gb, rtol=1e-9)
    body = free_body(res, gb, -1)
    assert sorted(body.bearings) == ["carrier", "ring", "sun"]
    np.testing.assert_allclose(body.reactions[:3], [0.0, SALEH_MASS * G, 0.0], atol=1e-6)


def test_a_pinion_in_a_compliant_bearing_is_held_through_its_slides():
    gb = loads(pair_urdf(gravity=f"0 {-G!r} 0"))
    res = _run(gb, duration=0.005, dt=1e-5, torques={"a": 100.0, "b": -200.0})
    free_body_balance(res, gb, rtol=1e-9)
    assert "a" in free_body(res, gb, -1).bearings  # read at the bearing joint, not a slide


def test_a_gearbox_on_its_tower_and_mounts_is_held_by_the_tower_slides():
    support = (
        '<support housing="housing"><mount stiffness_x="5e8" stiffness_y="5e8" '
        'stiffness_z="5e8"/>' + tower("vertical", 5.0, 1e3) + "</support>"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        gb = loads(supported_pair(support))
    res = _run(gb, duration=0.002, dt=1e-4, torques={"a": 1.0, "b": -2.0})
    free_body_balance(res, gb, sample=0, rtol=1e-9)
    body = free_body(res, gb, 0)
    assert body.bearings == ["support_tower_vertical"]
    # The static start: the tower slide carries its 1 t modal mass and the gearbox on it.
    np.testing.assert_allclose(body.reactions[1], (1e3 + GEARBOX_MASS) * G, rtol=1e-9)


def test_a_bearing_reaction_short_of_a_weight_is_caught_with_the_imbalance():
    res = _saleh()
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res.bearing_force[-1, res.bearing_names.index("ring"), 1] -= 1238 * G  # the ring's weight
    with pytest.raises(CheckFailed) as caught:
        free_body_balance(res, gb, rtol=1e-6)
    assert caught.value.measured > 0.05
    assert "ΣF" in str(caught.value)
