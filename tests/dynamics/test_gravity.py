"""At rest under gravity the bearings carry the weights, and nothing else."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from tests.conftest import MODELS

G = 9.81
# Saleh 2017 Table 3 masses [kg]; pins are welded to the carrier.
MASS = {"ring": 1238.0, "sun": 263.5, "carrier": 405.091, "pin": 254.3, "planet": 1113.1}


@pytest.fixture(scope="module")
def saleh():
    return pinwind.load(MODELS / "saleh2017_planetary.urdf")


def test_default_gravity_is_perpendicular_to_the_shafts(saleh):
    assert_allclose(saleh.gravity, [0.0, -G, 0.0])


def test_bearings_at_rest_carry_the_weights_exactly(saleh):
    res = pinwind.simulate(saleh, duration=0.05, dt=1e-3)
    up = np.array([0.0, 1.0, 0.0])
    carried = {
        "ring": MASS["ring"],
        "sun": MASS["sun"],
        "planet1": MASS["planet"],
        "planet2": MASS["planet"],
        "planet3": MASS["planet"],
        # The carrier bearing holds the carrier, its pins and the planets hanging on them.
        "carrier": MASS["carrier"] + 3 * MASS["pin"] + 3 * MASS["planet"],
    }
    for name, mass in carried.items():
        assert_allclose(
            res.bearing(name).force, np.tile(mass * G * up, (len(res), 1)), rtol=1e-12, atol=1e-9
        )
        assert_allclose(res.bearing(name).moment, 0.0, atol=1e-6)
    assert_allclose(res.mesh_normal, 0.0, atol=1e-9)
    assert_allclose(res.speed, 0.0, atol=1e-12)


def test_gravity_along_the_shaft_loads_the_bearings_axially(saleh):
    res = pinwind.simulate(saleh, duration=0.01, dt=1e-3, gravity=[0.0, 0.0, -G])
    assert_allclose(res.bearing("sun").force[-1], [0.0, 0.0, MASS["sun"] * G], atol=1e-9)
    assert_allclose(res.bearing("ring").force_local[-1], [0.0, 0.0, MASS["ring"] * G], atol=1e-9)


def test_a_model_without_gravity_gets_the_default_and_its_bearings_carry_the_weights():
    from pinwind.model.gearbox import loads

    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    assert ' gravity="0 -9.81 0"' in text
    gb = loads(text.replace(' gravity="0 -9.81 0"', ""), path="saleh_no_gravity.urdf")
    # Shafts along z: the default is 9.81 m/s² perpendicular to them, along −y.
    assert_allclose(gb.gravity, [0.0, -G, 0.0], rtol=0, atol=1e-15)
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3)
    assert_allclose(res.metadata["gravity"], [0.0, -G, 0.0], rtol=0, atol=1e-15)
    up = np.array([0.0, 1.0, 0.0])
    assert_allclose(res.bearing("sun").force[-1], MASS["sun"] * G * up, rtol=1e-12)
    assert_allclose(res.bearing("ring").force[-1], MASS["ring"] * G * up, rtol=1e-12)
