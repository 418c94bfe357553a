"""The compiled step loop: hands a gearbox to ``pinwind.dynamics._native`` and runs it in chunks.

The step (assembly, the constrained solve (direct Schur by default, proxsuite on request), flank
switching, projection, bearing reactions, integration and recording) is C++ in
``pinwind/dynamics/cpp/``, calling Pinocchio and proxsuite directly: done in Python, the glue
around those calls cost twenty times the calls themselves. This module describes
the gearbox to it in typed structs (``_native.pyi``: the Pinocchio joint tree, the meshes, each
kind of element and constraint's specs from its builder in ``dynamics/element_specs.py``, the
Result's arrays to write) and maps the status it returns to pinwind's errors.

The C++ side builds its own ``pinocchio.Model`` from the joint tree; ``Stepper.mass_matrix`` lets
the tests check that its M equals Pinocchio's own.
"""

from __future__ import annotations

import numpy as np

from pinwind.dynamics import _native
from pinwind.dynamics.compliant import MeshSetup
from pinwind.dynamics.element_specs import RunElements, fill_kinds
from pinwind.dynamics.elements import LoadElements
from pinwind.dynamics.integrator import Integrator
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.result import Result
from pinwind.dynamics.solver import SolverSettings
from pinwind.errors import (
    ConflictingConstraints,
    Diverged,
    InputError,
    MalformedModel,
    SolverFailed,
)
from pinwind.model.gearbox import Gearbox

#: Constraint residual |J v − target| above which velocities are projected, relative to
#: 1 + max |v| [m/s or rad/s].
PROJECTION_TOL = 1e-14

#: Pinocchio's joints along or about an axis of the joint frame: the bearings, and the
#: compliant bearings' slides and tilt hinges (``model/gearbox.py``).
_ALIGNED = {
    "JointModelRX": _native.JointType.revolute_x,
    "JointModelRY": _native.JointType.revolute_y,
    "JointModelRZ": _native.JointType.revolute_z,
    "JointModelPX": _native.JointType.prismatic_x,
    "JointModelPY": _native.JointType.prismatic_y,
    "JointModelPZ": _native.JointType.prismatic_z,
}
#: Pinocchio's joints about or along any axis.
_UNALIGNED = {
    "JointModelRevoluteUnaligned": _native.JointType.revolute_unaligned,
    "JointModelPrismaticUnaligned": _native.JointType.prismatic_unaligned,
}


def joint_tree(gearbox: Gearbox, gravity: np.ndarray) -> _native.JointTree:
    """The Pinocchio model as the compiled code takes it.

    Parents, joint types and placements, body inertias, and this run's gravity [m/s²].
    """
    model = gearbox.model
    joints = range(1, model.njoints)
    types, axes = [], []
    for j in joints:
        joint = model.joints[j]
        kind = joint.shortname()
        if kind in _ALIGNED:
            types.append(_ALIGNED[kind])
            axes.append(np.zeros(3))
        elif kind in _UNALIGNED:
            types.append(_UNALIGNED[kind])
            axes.append(np.asarray(joint.extract().axis, dtype=float))
        else:
            raise MalformedModel(
                gearbox.path,
                f'<joint name="{model.names[j]}">',
                f"Pinocchio made it a {kind}; only revolute bearings are supported",
            )
    inertias = [model.inertias[j] for j in joints]
    tree = _native.JointTree()
    tree.names = [model.names[j] for j in joints]
    tree.parent = [int(model.parents[j]) for j in joints]
    tree.type = types
    tree.axis = np.array(axes, dtype=float).reshape(-1, 3)
    tree.placement = [model.jointPlacements[j].homogeneous for j in joints]
    tree.mass = np.array([i.mass for i in inertias], dtype=float)
    tree.com = np.array([i.lever for i in inertias], dtype=float).reshape(-1, 3)
    tree.inertia = np.array([i.inertia for i in inertias], dtype=float).reshape(-1, 9)
    tree.armature = np.asarray(model.armature, dtype=float).copy()
    tree.gravity = np.asarray(gravity, dtype=float)
    return tree


def series_array(block: Result, name: str) -> np.ndarray:
    """The array of ``block`` that the compiled series ``name`` is written into, in place.

    ``_native.Series`` names each series as the Result does: an attribute, or a term of the
    energy ledger.
    """
    return block.energy[name] if name in block.energy else getattr(block, name)


#: Newton iterations of the static start at most, and the correction, relative to the
#: displacement, at which it stops: the stiffness follows the pairs in contact, so a start on a
#: pair change takes a few more iterations than the one a linear train needs.
EQUILIBRIUM_ITERATIONS = 30
EQUILIBRIUM_TOLERANCE = 1e-7
#: The static start's retries when the whole load at once does not converge: the applied
#: torques in this many equal steps, each solved from the last. A load well beyond the one a
#: model was made for (a generator fault's 3-6 times rated torque on the NREL 5 MW gearbox)
#: takes its planets' tilts and contacts out of Newton's reach from the undeflected pose.
EQUILIBRIUM_LOAD_STEPS = (4, 16, 64)
#: A static start that has not converged is refused (``StaticStartDiverged``) when its last
#: correction exceeds this share of its displacement and ``EQUILIBRIUM_ROUNDING`` [rad or m]: it
#: is not settling, and the run would start far from rest (on the NREL 5 MW gearbox standing
#: under 4.5 times rated torque the last correction is 4.7e-4 of the displacement and the first
#: sample accelerates at 0.26 m/s², under 5 times 0.15 and the start is 2.8 rad or m off). Below
#: that floor a correction is rounding (a mesh that rigid ones hold at zero deflection).
EQUILIBRIUM_DIVERGED = 1e-3
EQUILIBRIUM_ROUNDING = 1e-9


class CompiledStepper:
    """One run of the compiled step loop, writing into a Result's arrays.

    Args:
        gearbox: the model.
        samples: samples of the whole run (t = 0, dt, …); each ``run`` fills one block.
        q0, v0: initial angles [rad] and speeds [rad/s]; v0 is projected onto the constraints.
        dt: time step [s].
        gravity: gravity in world [m/s²].
        driver_index: velocity index of each speed driver and locked bearing, in row order.
        driver_names: their joint names, for messages.
        settings: the solve's settings (method, proxsuite's tolerances).
        meshes: the run's rigid and compliant meshes (``dynamics/compliant.py``).
        loads: the generator and rotor elements (``dynamics/elements.py``): their compiled specs,
            the rotors' inertia added to their joints, and the number of input columns.
        integrator: the time step (``dynamics/integrator.py``); default ``Integrator()``.
    """

    def __init__(
        self,
        gearbox: Gearbox,
        samples: int,
        q0: np.ndarray,
        v0: np.ndarray,
        *,
        dt: float,
        gravity: np.ndarray,
        driver_index: list[int],
        driver_names: list[str],
        settings: SolverSettings,
        meshes: MeshSetup,
        loads: LoadElements | None = None,
        integrator: Integrator | None = None,
    ):
        model = gearbox.model
        frames = gearbox.body_frames()
        spec = _native.StepperSpec()
        spec.tree = joint_tree(gearbox, gravity)
        spec.meshes = MeshSet(gearbox, meshes.meshes).constants
        spec.paths = meshes.paths
        fill_kinds(spec, RunElements(gearbox, meshes, loads, list(driver_index)))
        if loads is not None:
            spec.input_columns = loads.input_columns
            armature = np.array(spec.tree.armature, dtype=float)
            for index, inertia in loads.added_inertia.items():
                armature[index] += inertia
            spec.tree.armature = armature
        self.input_columns = loads.input_columns if loads is not None else 0
        spec.bearing_joints = [int(model.getJointId(n)) for n in gearbox.bearing_names]
        spec.frame_parent = [int(model.frames[f].parentJoint) for f in frames]
        spec.frame_placement = [model.frames[f].placement.homogeneous for f in frames]
        spec.dt = float(dt)
        spec.projection_tol = PROJECTION_TOL
        spec.rho_infinity = float((integrator or Integrator()).rho_infinity)
        solver = _native.SolverSettings()
        solver.eps_abs = float(settings.eps_abs)
        solver.eps_rel = float(settings.eps_rel)
        solver.max_iter = int(settings.max_iter)
        solver.iterative = settings.method == "proxsuite"
        spec.solver = solver
        self._stepper = _native.Stepper(
            spec, np.asarray(q0, dtype=float), np.asarray(v0, dtype=float), int(samples)
        )
        self.drivers = list(driver_names)
        # The output arrays of the last block: a caller stepping into one Result again and
        # again (a session's short blocks) is spared binding its ~50 arrays every call.
        self._out: tuple[Result, _native.OutputArrays] | None = None

    def run(
        self,
        start: int,
        stop: int,
        torque: np.ndarray,
        target: np.ndarray,
        block: Result,
        inputs: np.ndarray | None = None,
        stride: int = 1,
    ) -> int:
        """Step samples start:stop into rows 0 … stop − start − 1 of ``block``.

        Returns ``stop``, or raises with the samples before it final.

        Args:
            block: a Result of stop − start samples whose arrays are filled in place; with
                ``stride`` > 1, of the samples of start:stop that a run keeping every stride-th
                sample from 0 and its last one keeps (``simulate``'s ``keep``), the only ones
                recorded (the step loop skips the others' bearing reactions and outputs).
            torque: (stop − start, nv) applied joint torques at each sample's time [N·m].
            target: (stop − start + 1, drivers) driver speeds at those times and the next [rad/s].
            inputs: (stop − start, input_columns) the elements' inputs (wind speeds [m/s]).

        Raises:
            Diverged, SolverFailed, ConflictingConstraints: with ``.samples`` the number of final
            samples.
        """
        out = self.outputs(block)
        if inputs is None:
            inputs = np.zeros((stop - start, self.input_columns))
        status = self._stepper.run(
            start,
            stop,
            np.ascontiguousarray(torque),
            np.ascontiguousarray(target),
            out,
            np.ascontiguousarray(inputs, dtype=float),
            int(stride),
        )
        if status.code == _native.RunCode.completed:
            return status.sample
        raise self.error(status)

    def outputs(self, block: Result) -> _native.OutputArrays:
        """The compiled loop's handle on ``block``'s arrays (kept while the block stays)."""
        if self._out is not None and self._out[0] is block:
            return self._out[1]
        out = _native.OutputArrays()
        for member in _native.Series:
            out[member] = series_array(block, member.name)
        self._out = (block, out)
        return out

    def run_held(
        self,
        start: int,
        stop: int,
        torque: np.ndarray,
        target: np.ndarray,
        out: _native.OutputArrays,
        inputs: np.ndarray,
    ) -> int:
        """``run`` with arrays already as the compiled loop takes them: no conversion, no copy.

        For a caller that steps short blocks again and again (a session).

        Args:
            torque: (1, nv) applied torques held over the block [N·m], C-contiguous float64.
            target: (stop − start + 1, drivers) driver speeds [rad/s], likewise.
            out: ``outputs(block)``.
            inputs: (1, input_columns) the elements' inputs held over the block, likewise.
        """
        status = self._stepper.run(start, stop, torque, target, out, inputs, 1)
        if status.code == _native.RunCode.completed:
            return status.sample
        raise self.error(status)

    @property
    def saves_state(self) -> bool:
        """Whether the run's state can be saved (every element's kind copies its own)."""
        return bool(self._stepper.saves_state)

    def save(self) -> _native.StepperState:
        """The run's state before its next sample, for ``restore``, of the model's size.

        ``cpp/stepper.hpp`` StepperState: q, v, the generalized-α memory, the energy ledger,
        every element's and constraint's internal states, the solver's factorisations.
        """
        return self._stepper.save()

    def restore(self, state: _native.StepperState) -> None:
        """Takes the run back to ``state`` (``save``): the next ``run`` steps as it did then.

        Raises:
            InputError: a state another stepper saved.
        """
        try:
            self._stepper.restore(state)
        except ValueError as err:
            raise InputError(str(err)) from err

    def error(self, status: _native.RunStatus) -> Diverged | SolverFailed | ConflictingConstraints:
        """The error of a run that stopped, with ``.samples`` the number of final samples."""
        code = status.code
        step, time = status.step, status.time
        err: Diverged | SolverFailed | ConflictingConstraints
        if code == _native.RunCode.diverged:
            err = Diverged(step, time, status.what)
        elif code == _native.RunCode.solver_failed:
            err = SolverFailed(
                step,
                time,
                status.what,
                f"primal residual {status.primal:.3g}, dual residual {status.dual:.3g} "
                f"N·m after {status.iterations} iterations. Check for conflicting speed "
                "drivers (two drivers on joints that the gears couple) or a driver on a locked "
                "bearing.",
            )
        else:
            err = ConflictingConstraints(step, time, status.residual, self.drivers)
        err.samples = status.sample  # type: ignore[union-attr]  # read by simulate()
        return err

    def equilibrium(
        self,
        torque: np.ndarray,
        target: np.ndarray,
        inputs: np.ndarray | None = None,
        load_steps: int = 1,
    ) -> _native.EquilibriumStatus:
        """Move the start to static equilibrium under the first sample's loads.

        The compliant meshes and springs are deflected so that, at the first sample, they carry
        the forces that the same loads put on rigid meshes and locked springs while the whole
        train accelerates as one (``cpp/stepper.hpp`` Stepper::equilibrium derives it); the
        speeds are kept.

        Args:
            torque: (1, nv) applied joint torques at t = 0 [N·m].
            target: (2, drivers) driver speeds at t = 0 and t = dt [rad/s].
            inputs: (1, input_columns) the elements' inputs at t = 0 (wind speeds [m/s]).
            load_steps: take the torques in this many equal steps, each solved from the last
                (the displacement and the convergence are measured from the start).
        """
        if inputs is None:
            inputs = np.zeros((1, self.input_columns))
        return self._stepper.equilibrium(
            np.ascontiguousarray(torque, dtype=float),
            np.ascontiguousarray(target, dtype=float),
            np.ascontiguousarray(inputs, dtype=float),
            EQUILIBRIUM_ITERATIONS,
            EQUILIBRIUM_TOLERANCE,
            load_steps,
        )

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """Joint-space inertia at q from the compiled copy of the model [kg·m²]."""
        return self._stepper.mass_matrix(np.asarray(q, dtype=float))

    @property
    def constant_mass(self) -> bool:
        """Whether M(q) is the same at every q, from the model's structure.

        All joints revolute about parallel axes, at most one lever on each body's path
        (``cpp/joint_algorithms.hpp`` mass_is_constant): the step then takes M once, at its
        first assembly, instead of by CRBA at every step.
        """
        return bool(self._stepper.constant_mass)

    @property
    def mesh_frames(self) -> list[int]:
        """Per mesh, the joint whose frame carries its geometry if its row is constant, else -1.

        In the model's mesh order; 0 is the world. A mesh whose gears turn about parallel axes
        that the one frame holds (sun and planet on a carrier, two gears on fixed axes: the
        centre distance and the line of action fixed in it) has a row J in joint coordinates
        that does not depend on q, so γ = J̇ v = 0: the step takes it once
        (``cpp/stepper_assembly.cpp`` fixed_mesh_frames); -1: evaluated at every step.
        """
        return [int(f) for f in self._stepper.mesh_frames]

    def assemble(self, q: np.ndarray, v: np.ndarray) -> _native.Assembly:
        """The step's M, b, J and γ at angles q [rad] and speeds v [rad/s], without a step.

        The rows are the rigid meshes' (on their current flanks) in file order, then the speed
        drivers and locks, as the compiled step stacks them.
        """
        return self._stepper.assemble(np.asarray(q, dtype=float), np.asarray(v, dtype=float))

    def element_forces(self, q: np.ndarray, v: np.ndarray) -> _native.ElementForces:
        """The elements' generalised force, tangents and stored energy at (q, v).

        ``force`` is Σ f_e [N·m or N] on each joint coordinate, ``stiffness`` −∂f/∂q and
        ``damping`` −∂f/∂v as the step takes them (the elements' implicit weights), ``potential``
        Σ U_e [J]. Each element is built anew, as at a run's first sample (a contact is in
        contact wherever it overlaps), so that the values are those of the state alone: the
        force of a conservative element is −∂U/∂q, which finite differences check.
        """
        return self._stepper.element_forces(np.asarray(q, dtype=float), np.asarray(v, dtype=float))
