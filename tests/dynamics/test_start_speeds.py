"""A run starts at the speeds of the machine turning: across meshes and springs (issue 36).

The pair of ``tests/conftest.two_gear_urdf`` (20/40 teeth, a compliant mesh of constant
stiffness, undamped) with a generator shaft ``g`` on b's axis, joined to b by a torsional
coupling. The rotor's speed given on a alone turns b at −ω_a z_a/z_b (the teeth's ratio) and g
with b (the coupling carries a steady torque at one speed). Under balanced torques F r_b,A on a
and F r_b,B on g the machine then runs steady from the first step: the mesh carries F and the
coupling twists by F r_b,B / k, with no start-up transient.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import SpringsWoundAtStart, StepTooCoarse
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

MODULE, ALPHA = 0.002, math.radians(20.0)
R_BA = 20 * MODULE * math.cos(ALPHA) / 2
R_BB = 40 * MODULE * math.cos(ALPHA) / 2
K_COUPLING = 800.0  # N·m/rad
FORCE = 1000.0  # N, the mesh force of the balanced torques
GENERATOR = """
  <link name="g">
    <inertial><mass value="3.0"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="g" type="continuous">
    <parent link="housing"/><child link="g"/>
    <origin xyz="0.06 0 0.3"/><axis xyz="0 0 1"/>
  </joint>
"""


def _machine():
    text = two_gear_urdf().replace("<gearbox>", GENERATOR + "<gearbox>")
    text = text.replace(
        "</gearbox>",
        f'<torsional_spring name="coupling" joint1="b" joint2="g" stiffness="{K_COUPLING!r}"/>'
        "</gearbox>",
    )
    return loads(text, "coupled.urdf")


def _run(**kwargs):
    mesh = MeshCompliance(stiffness=1e8, variation="constant", damping=0.0)
    # 0.1 ms is 7.5 steps a period of the mesh mode: enough for the start, and the run says
    # the mode is not resolved
    with pytest.warns(StepTooCoarse, match="highest mesh mode"):
        return pinwind.simulate(
            _machine(), duration=0.05, dt=1e-4, gravity=np.zeros(3), meshes={"m": mesh},
            torques={"a": FORCE * R_BA, "g": FORCE * R_BB}, **kwargs,
        )  # fmt: skip


def test_a_rotor_speed_carries_across_the_coupling_and_the_machine_starts_steady():
    omega = 10.0
    res = _run(initial_speeds={"a": omega})
    # The speeds from the teeth ratio, the generator with its shaft.
    expected = -omega * R_BA / R_BB
    assert_allclose(res.joint("b").speed[0], expected, rtol=1e-12)
    assert_allclose(res.joint("g").speed[0], expected, rtol=1e-12)
    # Steady from t = 0: the mesh force is the static F at every sample (no start-up swing of
    # the coupling, which would ring at √(k/J) ≈ 35 Hz with the whole torque), the speeds stay.
    assert_allclose(res.mesh("m").normal, FORCE, rtol=1e-6)
    assert_allclose(res.joint("g").speed, expected, rtol=1e-6)
    twist = res.joint("b").angle - res.joint("g").angle
    assert_allclose(twist, -FORCE * R_BB / K_COUPLING, rtol=1e-6)


def test_speeds_given_across_a_coupling_out_of_ratio_warn_and_name_the_spring():
    with pytest.warns(SpringsWoundAtStart, match=r'"coupling" \("b" -5 rad/s, "g" 0 rad/s'):
        res = _run(initial_speeds={"a": 10.0, "g": 0.0})
    assert res.joint("g").speed[0] == 0.0
    assert_allclose(res.joint("b").speed[0], -5.0, rtol=1e-12)
