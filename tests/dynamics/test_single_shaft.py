"""A model without gears: one shaft on one bearing (Pinocchio hands 1-DoF matrices as vectors)."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

import pinwind
from pinwind.model.gearbox import loads

SHAFT = """<robot name="shaft"><link name="housing"/>
  <link name="s"><inertial><mass value="2"/>
    <inertia ixx="1" iyy="1" izz="0.5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="s" type="continuous"><parent link="housing"/><child link="s"/>
    <axis xyz="0 0 1"/><dynamics damping="0.1"/></joint>
  <gearbox/>
</robot>"""


def test_shaft_accelerates_with_torque_over_inertia_and_its_bearing_carries_its_weight():
    gb = loads(SHAFT, path="shaft.urdf")
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, torques={"s": 1.0})
    assert_allclose(res.bearing("s").force[:, 1], 2.0 * 9.81, rtol=1e-12)
    # The acceleration over each step is the torque at its middle over I_zz (the trapezoidal
    # rule, ρ∞ = 1): α = (T − c (ω_k + ω_k+1)/2) / I_zz, and it carries ω_k to ω_k+1.
    omega = res.joint("s").speed
    alpha = res.joint("s").acceleration[:-1]
    assert_allclose(alpha, (1.0 - 0.1 * (omega[:-1] + omega[1:]) / 2.0) / 0.5, rtol=1e-12)
    assert_allclose(np.diff(omega), alpha * 1e-3, rtol=1e-12)


def test_driven_shaft_needs_the_damping_torque():
    gb = loads(SHAFT, path="shaft.urdf")
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, speeds={"s": 3.0})
    assert_allclose(res.joint("s").speed, 3.0, rtol=1e-12)
    assert_allclose(res.joint("s").torque, 0.1 * 3.0, rtol=1e-9)


#: The shaft's body tilted on its axis: products of inertia I_xz, I_yz [kg·m²] about its centre
#: of mass on the axis, so its world inertia turns with it.
TILTED = SHAFT.replace('ixz="0" iyz="0"', 'ixz="0.1" iyz="0.05"')


def test_a_tilted_shaft_needs_the_tilting_moment_of_eulers_equations():
    """Turning about the fixed axis z through its centre of mass, a body with I_xz, I_yz needs
    the moment (Euler's equations, body axes) M_x = I_xz α − I_yz ω², M_y = I_yz α + I_xz ω²
    from its bearing: the recorded reaction in the joint frame must follow the body's angle
    (a step that took its world inertia once would keep the first sample's)."""
    gb = loads(TILTED, path="tilted.urdf")
    res = pinwind.simulate(gb, duration=0.02, dt=1e-3, torques={"s": 1.0})
    omega = res.joint("s").speed
    alpha = res.joint("s").acceleration
    assert omega[-1] > 0.01  # the ω² terms count
    moment = res.bearing("s").moment_local
    scale = 0.1 * abs(alpha).max()
    assert_allclose(moment[:, 0], 0.1 * alpha - 0.05 * omega**2, rtol=0, atol=1e-12 * scale)
    assert_allclose(moment[:, 1], 0.05 * alpha + 0.1 * omega**2, rtol=0, atol=1e-12 * scale)
