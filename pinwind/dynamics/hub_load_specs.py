"""Hub loads on the model: each ``HubLoad`` (loads/hub_loads.py) as the compiled element's spec.

The compiled element (``cpp/hub_loads.hpp``) needs, per load: the body's joint and the joints
that move it (their velocity columns), the hub axes in that joint's frame, the point in it, and
its six input columns. The hub axes follow loads/hub_loads.py: x along the body's joint axis as
the model gives it (the shaft axis; a positive torque M_x drives the joint forwards), z the part
of ``up`` normal to x (``up`` given in the model's world frame at its neutral pose, or against
gravity), y = z × x. A ``fixed`` load keeps the orientation of the bearing's housing: the
frame of the joint above the bearing (above its slides and tilts, for a compliant one), turned
as the body's joint is at the model's neutral pose; it neither turns with the shaft nor tilts
with its bearing's deflection (the weight of a rotor stays vertical).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from pinwind.dynamics import _native
from pinwind.errors import InputError
from pinwind.loads.hub_loads import HubFrame, HubLoad
from pinwind.model.gearbox import Gearbox

#: Smallest normal part of ``up`` to the shaft axis, relative to its length: below it the hub's
#: z is undefined.
UP_NORMAL_MIN = 1e-6


def hub_load_specs(
    loads: Sequence[HubLoad], gearbox: Gearbox, gravity: np.ndarray, first_column: int
) -> list[_native.HubLoadSpec]:
    """The compiled spec of each hub load, its inputs from column ``first_column`` on, six each.

    Raises:
        InputError: a body the model does not have (naming the bodies), a body no joint moves,
            no ``up`` and no gravity, or an ``up`` along the shaft axis.
    """
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    bodies = {model.frames[f].name: f for f in gearbox.body_frames()}  # the Result's bodies
    specs = []
    for i, load in enumerate(loads):
        where = f'hub load on "{load.body}"'
        if load.body not in bodies:
            raise InputError(f"{where}: no such body; bodies are: {', '.join(b for b in bodies)}")
        frame = model.frames[bodies[load.body]]
        joint = int(frame.parentJoint)
        if joint == 0:
            raise InputError(f"{where}: the body is fixed to the ground; load a body that turns")
        x = gearbox.joint_axis(model.names[joint])
        up = _up(load, gravity, where)
        up_in_joint = data.oMi[joint].rotation.T @ up
        normal = up_in_joint - (up_in_joint @ x) * x
        if np.linalg.norm(normal) <= UP_NORMAL_MIN * np.linalg.norm(up_in_joint):
            raise InputError(
                f"{where}: up {tuple(up)} is parallel to the shaft axis "
                f"{tuple(np.round(data.oMi[joint].rotation @ x, 6))} (world); give up= a "
                "direction across the shaft, the hub's z (vertical for a horizontal shaft)"
            )
        z = normal / np.linalg.norm(normal)
        housing = _housing(gearbox, joint)
        spec = _native.HubLoadSpec()
        spec.joint = joint
        spec.parent = housing
        spec.columns = _supporting_columns(model, joint)
        spec.axes = np.column_stack([x, np.cross(z, x), z])
        spec.placement = data.oMi[housing].rotation.T @ data.oMi[joint].rotation
        spec.point = frame.placement.act(np.asarray(load.point, dtype=float))
        spec.rotating = load.frame is HubFrame.ROTATING
        spec.column = first_column + 6 * i
        specs.append(spec)
    return specs


def fixed_axes_at_rest(spec: _native.HubLoadSpec, gearbox: Gearbox) -> np.ndarray:
    """The fixed hub axes (columns x, y, z) in the world at the model's neutral pose."""
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    return data.oMi[spec.parent].rotation @ spec.placement @ spec.axes


def _up(load: HubLoad, gravity: np.ndarray, where: str) -> np.ndarray:
    """The load's up direction in the world: its own, or against gravity."""
    if load.up is not None:
        return np.asarray(load.up, dtype=float)
    g = np.asarray(gravity, dtype=float)
    if not np.any(g):
        raise InputError(
            f"{where}: the hub's z (up) is undefined: the model has no gravity; give up=(x, y, z), "
            "the vertical in the model's world frame"
        )
    return -g


def _housing(gearbox: Gearbox, joint: int) -> int:
    """The joint whose frame the bearing of ``joint`` sits in.

    Its parent, or for a compliant bearing the parent of its slides and tilts (which move with
    the shaft's deflection).
    """
    model = gearbox.model
    bearing = gearbox.compliant_bearings.get(model.names[joint])
    slides = set() if bearing is None else set(bearing.v_index.values())
    parent = int(model.parents[joint])
    while parent > 0 and model.joints[parent].idx_v in slides:
        parent = int(model.parents[parent])
    return parent


def _supporting_columns(model: pin.Model, joint: int) -> list[int]:
    """Velocity columns of ``joint`` and of every joint between it and the world."""
    columns: list[int] = []
    while joint > 0:
        start = model.joints[joint].idx_v
        columns += range(start, start + model.joints[joint].nv)
        joint = model.parents[joint]
    return sorted(columns)
