"""The compiled step loop: hands a gearbox to ``pinwind.dynamics._native`` and runs it in chunks.

The step (assembly, proxsuite QP, flank switching, projection, bearing reactions, integration and
recording) is C++ in ``pinwind/dynamics/cpp/``, calling Pinocchio and proxsuite directly: done in
Python, the glue around those calls cost twenty times the calls themselves. This module describes
the gearbox to it as plain arrays (the Pinocchio joint tree, the mesh, spring and driver
constants) and maps the status it returns to pinwind's errors.

The C++ side builds its own ``pinocchio.Model`` from the joint tree; ``Stepper.mass_matrix`` lets
the tests check that its M equals Pinocchio's own.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pinwind.dynamics import _native
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.result import Result
from pinwind.dynamics.solver import SolverSettings
from pinwind.errors import ConflictingConstraints, Diverged, MalformedModel, SolverFailed
from pinwind.model.gearbox import Gearbox

#: Constraint residual |J v − target| above which velocities are projected, relative to
#: 1 + max |v| [m/s or rad/s].
PROJECTION_TOL = 1e-14

_REVOLUTE = {"JointModelRX": 0, "JointModelRY": 1, "JointModelRZ": 2}


def joint_tree(gearbox: Gearbox) -> dict:
    """The Pinocchio model as arrays: parents, joint types and placements, body inertias.

    Gravity is not part of it: each run gives its own.
    """
    model = gearbox.model
    joints = range(1, model.njoints)
    types, axes = [], []
    for j in joints:
        joint = model.joints[j]
        kind = joint.shortname()
        if kind in _REVOLUTE:
            types.append(_REVOLUTE[kind])
            axes.append(np.zeros(3))
        elif kind == "JointModelRevoluteUnaligned":
            types.append(3)
            axes.append(np.asarray(joint.extract().axis, dtype=float))
        else:
            raise MalformedModel(
                gearbox.path,
                f'<joint name="{model.names[j]}">',
                f"Pinocchio made it a {kind}; only revolute bearings are supported",
            )
    inertias = [model.inertias[j] for j in joints]
    return {
        "joints": model.njoints - 1,
        "joint_names": [model.names[j] for j in joints],
        "joint_parent": np.array([model.parents[j] for j in joints], dtype=np.int64),
        "joint_type": np.array(types, dtype=np.int64),
        "joint_axis": np.array(axes, dtype=float).reshape(-1, 3),
        "joint_placement": np.array([model.jointPlacements[j].homogeneous for j in joints]),
        "body_mass": np.array([i.mass for i in inertias], dtype=float),
        "body_com": np.array([i.lever for i in inertias], dtype=float).reshape(-1, 3),
        "body_inertia": np.array([i.inertia for i in inertias], dtype=float).reshape(-1, 3, 3),
        "armature": np.asarray(model.armature, dtype=float).copy(),
    }


def body_frames(model: pin.Model) -> list[int]:
    """Ids of the link frames whose world poses are recorded."""
    return [f for f in range(model.nframes) if model.frames[f].type == pin.FrameType.BODY]


class CompiledStepper:
    """One run of the compiled step loop, writing into a Result's arrays.

    Args:
        gearbox: the model.
        result: preallocated Result (its arrays are filled in place, sample by sample).
        q0, v0: initial angles [rad] and speeds [rad/s]; v0 is projected onto the constraints.
        dt: time step [s].
        gravity: gravity in world [m/s²].
        driver_index: velocity index of each speed driver and locked bearing, in row order.
        driver_names: their joint names, for messages.
        settings: proxsuite settings.
    """

    def __init__(
        self,
        gearbox: Gearbox,
        result: Result,
        q0: np.ndarray,
        v0: np.ndarray,
        *,
        dt: float,
        gravity: np.ndarray,
        driver_index: list[int],
        driver_names: list[str],
        settings: SolverSettings,
    ):
        model = gearbox.model
        meshes = MeshSet(gearbox)
        springs = gearbox.springs
        frames = body_frames(model)
        spec = joint_tree(gearbox)
        spec["gravity"] = np.asarray(gravity, dtype=float)
        spec.update(meshes.spec)
        spec.update(
            {
                "cos_a": meshes.cos_a,
                "sin_a": meshes.sin_a,
                "eps": meshes.eps,
                "tan_beta": meshes.tan_beta,
                "joint_a": meshes.joint_a.astype(np.int64),
                "joint_b": meshes.joint_b.astype(np.int64),
                "springs": len(springs),
                "spring_index_1": np.array([s.v_index_1 for s in springs], dtype=np.int64),
                "spring_index_2": np.array([s.v_index_2 for s in springs], dtype=np.int64),
                "spring_stiffness": np.array([s.stiffness for s in springs], dtype=float),
                "spring_damping": np.array([s.damping for s in springs], dtype=float),
                "spring_preload": np.array([s.preload_angle for s in springs], dtype=float),
                "bearing_damping": np.array(model.damping, dtype=float).copy(),
                "drivers": len(driver_index),
                "driver_index": np.array(driver_index, dtype=np.int64),
                "frames": len(frames),
                "frame_parent": np.array(
                    [model.frames[f].parentJoint for f in frames], dtype=np.int64
                ),
                "frame_placement": np.array(
                    [model.frames[f].placement.homogeneous for f in frames]
                ).reshape(-1, 4, 4),
                "dt": float(dt),
                "projection_tol": PROJECTION_TOL,
                "eps_abs": float(settings.eps_abs),
                "eps_rel": float(settings.eps_rel),
                "max_iter": int(settings.max_iter),
            }
        )
        out = {name: getattr(result, name) for name in Result.ARRAYS}
        out.update(result.energy)
        self._stepper = _native.Stepper(
            spec, np.asarray(q0, dtype=float), np.asarray(v0, dtype=float), out, len(result)
        )
        self.drivers = list(driver_names)

    def run(self, start: int, stop: int, torque: np.ndarray, target: np.ndarray) -> int:
        """Step samples start:stop; returns ``stop``, or raises with the samples before it final.

        Args:
            torque: (stop − start, nv) applied joint torques at each sample's time [N·m].
            target: (stop − start + 1, drivers) driver speeds at those times and the next [rad/s].

        Raises:
            Diverged, SolverFailed, ConflictingConstraints: with ``.samples`` the number of final
            samples.
        """
        status = self._stepper.run(
            start, stop, np.ascontiguousarray(torque), np.ascontiguousarray(target)
        )
        code = status["code"]
        if code == 0:
            return status["sample"]
        step, time = status["step"], status["time"]
        if code == 1:
            err = Diverged(step, time, status["what"])
        elif code == 2:
            err = SolverFailed(
                step,
                time,
                status["what"],
                f"primal residual {status['primal']:.3g}, dual residual {status['dual']:.3g} "
                f"N·m after {status['iterations']} iterations. Check for conflicting speed "
                "drivers (two drivers on joints that the gears couple) or a driver on a locked "
                "bearing.",
            )
        else:
            err = ConflictingConstraints(step, time, status["residual"], self.drivers)
        err.samples = status["sample"]
        raise err

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """Joint-space inertia at q from the compiled copy of the model [kg·m²]."""
        return self._stepper.mass_matrix(np.asarray(q, dtype=float))
