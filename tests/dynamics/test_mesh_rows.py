"""The mesh row and its bias against finite differences, on a gear whose centre moves.

Gear B sits on a swing arm pivoted away from gear A's axis, so the centre distance, the pitch
point and the line of action all change with the arm angle: the row J(q) is not constant and its
bias γ = J̇ v is not zero. Both are checked against central differences of the kinematics alone.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from numpy.testing import assert_allclose

from pinwind.dynamics.mesh import MeshSet
from pinwind.errors import TorquesUnbalanced
from pinwind.model.gearbox import loads

SWING_ARM = """<?xml version="1.0"?>
<robot name="swing_arm">
  <link name="housing"/>
  <link name="a"><inertial><mass value="1"/>
    <inertia ixx="1e-3" iyy="1e-3" izz="1.5e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0 0.03 0"/><mass value="0.5"/>
    <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="2"/>
    <inertia ixx="4e-3" iyy="4e-3" izz="6e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="a" type="continuous"><parent link="housing"/><child link="a"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="arm" type="continuous"><parent link="housing"/><child link="arm"/>
    <origin xyz="0.06 -0.05 0"/><axis xyz="0 0 1"/></joint>
  <joint name="b" type="continuous"><parent link="arm"/><child link="b"/>
    <origin xyz="0 0.05 0"/><axis xyz="0 0 1"/></joint>
  <gearbox>
    <gear name="g1" link="a" teeth="20" module_mm="2" face_width_mm="20"/>
    <gear name="g2" link="b" teeth="40" module_mm="2" face_width_mm="20"/>
    <mesh name="m" gear1="g1" gear2="g2"/>
  </gearbox>
</robot>
"""


@pytest.fixture(scope="module")
def arm():
    return loads(SWING_ARM, path="swing_arm.urdf")


def _rows(gb, q, v, flank):
    data = gb.model.createData()
    pin.computeJointJacobiansTimeVariation(gb.model, data, q, v)
    ms = MeshSet(gb)
    ms.set_velocity(v)
    rows = ms.evaluate(gb.model, data)
    jac, bias = ms.combine(rows, flank)
    return jac, bias, rows, data, ms


@pytest.mark.parametrize("flank", [1.0, -1.0])
def test_row_is_relative_velocity_of_material_points_along_the_line_of_action(arm, flank):
    rng = np.random.default_rng(7)
    model = arm.model
    for _ in range(5):
        q = rng.uniform(-0.3, 0.3, model.nq)
        v = rng.uniform(-2.0, 2.0, model.nv)
        jac, _, rows, data, ms = _rows(arm, q, v, np.array([flank]))
        p = rows.pitch_point[0]
        n = ms.line_of_action(rows, np.array([flank]))[0]
        h = 1e-6

        def point(joint_id, qq, data=data, p=p):
            d = model.createData()
            pin.forwardKinematics(model, d, qq)
            local = data.oMi[joint_id].actInv(p)
            return d.oMi[joint_id].act(local)

        velocity = {}
        for name in ("a", "b"):
            j = model.getJointId(name)
            plus, minus = pin.integrate(model, q, v * h), pin.integrate(model, q, -v * h)
            velocity[name] = (point(j, plus) - point(j, minus)) / (2 * h)
        assert_allclose(jac @ v, n @ (velocity["b"] - velocity["a"]), rtol=1e-7, atol=1e-10)


@pytest.mark.parametrize("flank", [1.0, -1.0])
def test_bias_is_the_time_derivative_of_the_row_at_zero_acceleration(arm, flank):
    rng = np.random.default_rng(11)
    model = arm.model
    f = np.array([flank])
    for _ in range(5):
        q = rng.uniform(-0.3, 0.3, model.nq)
        v = rng.uniform(-3.0, 3.0, model.nv)
        a = rng.uniform(-5.0, 5.0, model.nv)
        jac, bias, *_ = _rows(arm, q, v, f)
        h = 1e-5

        def c(s, q=q, v=v, a=a):
            qs = pin.integrate(model, q, v * s + 0.5 * a * s * s)
            js, *_ = _rows(arm, qs, v + a * s, f)
            return (js @ (v + a * s))[0]

        derivative = (c(h) - c(-h)) / (2 * h)
        assert_allclose(jac[0] @ a + bias[0], derivative, rtol=1e-6, atol=1e-8)
        assert abs(bias[0]) > 1e-3  # the arm makes the bias a real term here


def test_fixed_axes_give_a_constant_row_and_zero_bias(pair_urdf):
    gb = loads(pair_urdf(), path="pair.urdf")
    rng = np.random.default_rng(3)
    first = None
    for _ in range(4):
        q = rng.uniform(-3, 3, gb.model.nq)
        v = rng.uniform(-50, 50, gb.model.nv)
        jac, bias, *_ = _rows(gb, q, v, np.array([1.0]))
        # r_b1 ω_1 + r_b2 ω_2 along the line of action (Saleh 2017 eq. 39).
        rb1, rb2 = 0.020 * np.cos(np.radians(20)), 0.040 * np.cos(np.radians(20))
        assert_allclose(jac[0], [-rb1, -rb2], rtol=1e-12)
        assert_allclose(bias, 0.0, atol=1e-12)
        first = jac if first is None else first


def test_satisfied_velocity_gives_zero_residual(pair_urdf):
    gb = loads(pair_urdf(), path="pair.urdf")
    q = np.array([0.4, -1.1])
    v = np.array([2.0, -1.0])  # ω_2 = −(z_1/z_2) ω_1
    jac, *_ = _rows(gb, q, v, np.array([1.0]))
    assert_allclose(jac @ v, 0.0, atol=1e-15)


def test_simulating_a_moving_mesh_keeps_the_constraint_and_the_energy_budget(arm):
    # The row changes every step here, so velocity projection and fresh QP solves are exercised.
    # With M(q) changing, the discrete energy balance is only first-order: check it to 1e-3.
    import pinwind

    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(
            arm, duration=0.5, dt=1e-4, torques={"a": 0.05, "arm": 0.02}, gravity=[0.0, 0.0, 0.0]
        )
    assert res.constraint_residual.max() < 1e-10
    e = res.energy
    supplied = e["work_applied"] + e["work_drivers"] + e["work_springs"] + e["work_gravity"]
    change = e["kinetic"] - e["kinetic"][0]
    assert_allclose(change, supplied - e["dissipated"], atol=1e-3 * np.abs(supplied).max())
    assert np.all(res.mesh("m").normal >= 0.0)
