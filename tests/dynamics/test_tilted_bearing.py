"""Bearing reactions on a tilted shaft: world and joint axes related by the joint's rotation.

One shaft on a bearing whose frame is tilted (origin rpy 0.3, 0.5, 0.2 rad, axis its own z), with
its centre of mass c = 0.2 m along the axis from the bearing centre, at rest under gravity g.
Statics by hand: the bearing holds the body's weight and its moment about the bearing centre,

    f = −m g,   M = c × f   (world axes),

and nothing about the shaft axis (c is on it, so c × g ⟂ axis): the shaft stays at rest. In the
joint frame the same reaction reads Rᵀ f and Rᵀ M, R the joint's rotation from its rpy.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import pinwind
from pinwind.model.gearbox import loads

RPY = (0.3, 0.5, 0.2)
MASS = 12.0
OFFSET = 0.2
GRAVITY = np.array([0.0, 0.0, -9.81])


def tilted_shaft_urdf(mass: float, offset: float, rpy, inertia=(0.5, 0.5, 0.1)) -> str:
    """A shaft of ``mass`` [kg], its centre ``offset`` [m] along its axis, on one continuous
    joint whose axis (joint z) is tilted by roll-pitch-yaw ``rpy`` [rad] from the world's z."""
    ixx, iyy, izz = inertia
    return f"""<?xml version="1.0"?>
<robot name="tilted">
  <link name="housing"/>
  <link name="shaft">
    <inertial><origin xyz="0 0 {offset!r}"/><mass value="{mass!r}"/>
      <inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="shaft" type="continuous">
    <parent link="housing"/><child link="shaft"/>
    <origin xyz="0.1 -0.2 0.3" rpy="{" ".join(repr(a) for a in rpy)}"/><axis xyz="0 0 1"/>
  </joint>
  <gearbox/>
</robot>
"""


URDF = tilted_shaft_urdf(MASS, OFFSET, RPY)


def test_tilted_bearing_moment_is_the_weight_s_moment_in_world_and_in_joint_axes():
    """Guards the world bearing moment ``rot * f.angular()`` (``cpp/stepper.hpp``, the bearing
    series): left in joint axes it differs from the hand statics on any tilted axis."""
    res = pinwind.simulate(loads(URDF, "tilted.urdf"), duration=0.01, dt=1e-3, gravity=GRAVITY)
    bearing = res.bearing("shaft")
    world_from_joint = pin.rpy.rpyToMatrix(*RPY)
    centre = world_from_joint @ np.array([0.0, 0.0, OFFSET])  # COM from the bearing, world axes
    force = -MASS * GRAVITY
    moment = np.cross(centre, force)
    assert np.linalg.norm(moment) > 5.0  # the tilt makes a moment of several N·m
    np.testing.assert_allclose(res.joint("shaft").speed, 0.0, atol=1e-12)
    for k in range(len(res)):
        np.testing.assert_allclose(bearing.force[k], force, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(bearing.moment[k], moment, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(
            bearing.force_local[k], world_from_joint.T @ force, rtol=1e-12, atol=1e-9
        )
        np.testing.assert_allclose(
            bearing.moment_local[k], world_from_joint.T @ moment, rtol=1e-12, atol=1e-9
        )
