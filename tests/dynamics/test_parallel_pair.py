"""A parallel spur pair held by its output: statics by hand.

Gear 1 (20 teeth) on shaft ``a`` at the origin, gear 2 (40 teeth) on shaft ``b`` at +x, module
2 mm, α = 20°, reference centre distance 60 mm (tests/conftest.py). A torque T on shaft a against
a speed driver that holds shaft b still gives the textbook tooth forces

    F_t = T / r_1,   F_r = F_t tan α,   F_n = F_t / cos α,   holding torque = T r_2 / r_1

(gear 1 turns gear 2 backwards, so the driver holds gear 2 with a positive torque).

and each bearing carries the tooth force on its gear plus the gear's weight.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import TorquesUnbalanced
from pinwind.model.gearbox import loads

R1, R2, ALPHA, G = 0.020, 0.040, math.radians(20.0), 9.81
M1, M2 = 1.0, 2.0


def test_tooth_force_of_a_held_pair_is_torque_over_pitch_radius(pair_urdf):
    gb = loads(pair_urdf(), path="pair.urdf")
    torque = 12.0
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, torques={"a": torque}, speeds={"b": 0.0})
    f_t = torque / R1
    mesh = res.mesh("m")
    assert_allclose(mesh.tangential, f_t, rtol=1e-9)
    assert_allclose(mesh.radial, f_t * math.tan(ALPHA), rtol=1e-9)
    assert_allclose(mesh.normal, f_t / math.cos(ALPHA), rtol=1e-9)
    assert_allclose(res.joint("b").torque, torque * R2 / R1, rtol=1e-9)
    assert_allclose(res.joint("a").speed, 0.0, atol=1e-12)


def test_bearings_carry_the_tooth_force_and_the_weights(pair_urdf):
    gb = loads(pair_urdf(), path="pair.urdf")
    torque = 12.0
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, torques={"a": torque}, speeds={"b": 0.0})
    # Gear 1 turns +z under T and pushes gear 2's tooth along +y at the pitch point (x = r_1);
    # the separating radial force pushes gear 2 along +x.
    f_t = torque / R1
    force_on_2 = np.array([f_t * math.tan(ALPHA), f_t, 0.0])
    weight_1, weight_2 = np.array([0.0, -M1 * G, 0.0]), np.array([0.0, -M2 * G, 0.0])
    assert_allclose(
        res.mesh("m").force_on_b, np.tile(force_on_2, (len(res), 1)), rtol=1e-9, atol=1e-9
    )
    # Statics of each gear: bearing force + tooth force + weight = 0.
    assert_allclose(res.bearing("a").force[-1], force_on_2 - weight_1, rtol=1e-9, atol=1e-9)
    assert_allclose(res.bearing("b").force[-1], -force_on_2 - weight_2, rtol=1e-9, atol=1e-9)
    # The bearing of a passes the input torque; b's passes the driver's holding torque.
    assert_allclose(res.bearing("a").moment[-1], [0.0, 0.0, torque], atol=1e-9)
    assert_allclose(res.bearing("b").moment[-1], [0.0, 0.0, torque * R2 / R1], atol=1e-9)
    # In the joint frame (axes aligned with world here) the numbers are the same.
    assert_allclose(res.bearing("b").force_local, res.bearing("b").force, atol=1e-12)


def test_free_pair_accelerates_with_reflected_inertia(pair_urdf):
    # J_eq about shaft a = I_1 + I_2 (r_1/r_2)²; F_t on gear 2 = I_2 α_2 / r_2.
    gb = loads(pair_urdf(), path="pair.urdf")
    i1, i2, torque = 0.0015, 0.006, 3.0
    with pytest.warns(TorquesUnbalanced):  # nothing holds the pair: it accelerates, as meant
        res = pinwind.simulate(gb, duration=0.1, dt=1e-3, torques={"a": torque})
    alpha_1 = torque / (i1 + i2 * (R1 / R2) ** 2)
    alpha_2 = -alpha_1 * R1 / R2
    assert_allclose(res.joint("a").acceleration, alpha_1, rtol=1e-9)
    assert_allclose(res.joint("b").acceleration, alpha_2, rtol=1e-9)
    assert_allclose(res.mesh("m").tangential, i2 * abs(alpha_2) / R2, rtol=1e-9)
    assert np.all(res.mesh("m").flank == 1)  # gear 1 (A) turning positively drives gear 2
