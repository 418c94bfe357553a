"""Time integration of a gearbox: assemble, solve, record, step.

Each step k, at state (q_k, v_k) and time t_k = k·dt:

1. assemble M (CRBA), b (RNEA at a = 0), τ (applied torques, springs, dampers) and the constraint
   rows J, γ: one row per mesh (``dynamics/mesh.py``), per speed driver and per locked bearing;
2. solve the equality QP with proxsuite (``dynamics/solver.py``): a_k and λ_k, the mesh forces
   [N] and driver torques [N·m] read from the duals through the name → row map;
3. bearing reactions by RNEA with the tooth forces at the pitch points (``dynamics/reactions.py``);
4. semi-implicit Euler: v_{k+1} = v_k + a_k dt, q_{k+1} = q_k ⊕ v_{k+1} dt. The rows ask for
   J a = γ + (target(t_{k+1}) − target(t_k))/dt: the acceleration the constraints demand, with the
   speed drivers' change over the step. When J v drifts from the target (J changed during the
   step, or rounding) by more than ``PROJECTION_TOL``, v is projected back onto J v = target in the
   metric of M before the next solve (post-stabilisation, 000_3b7c4a8fe52a6eee.txt §2.1.3).
   The drift is not fed back into the QP's right-hand side: redundant rows (several planets) must
   get a consistent right-hand side, or the multipliers of the redundant directions drift.

The energy ledger uses the mid-step speed (v_k + v_{k+1})/2, with which the kinetic-energy change
of a step equals the work of the step's forces exactly when M is constant.
"""

from __future__ import annotations

import math
import time as wallclock
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import pinocchio as pin
from scipy.spatial.transform import Rotation

from pinwind.dynamics.elements import ForceElements
from pinwind.dynamics.mesh import MeshRows, MeshSet, joint_placements
from pinwind.dynamics.reactions import BearingReactions
from pinwind.dynamics.result import Result
from pinwind.dynamics.solver import ConstrainedDynamicsSolver, SolverSettings
from pinwind.errors import (
    ConflictingConstraints,
    Diverged,
    InputError,
    NonFiniteInput,
    SolverFailed,
)
from pinwind.loads.inputs import JointLoad, Signal, joint_loads
from pinwind.model.gearbox import Gearbox

#: Constraint residual |J v − target| above which velocities are projected [m/s or rad/s].
PROJECTION_TOL = 1e-14


class RunObserver(Protocol):
    """Receives a run's samples as they are computed (the MCAP logger is one)."""

    def begin(self, gearbox: Gearbox, result: Result) -> None:
        """Called once before the first step; ``result`` holds preallocated arrays."""

    def samples(self, result: Result, start: int, stop: int) -> None:
        """Samples ``start:stop`` of ``result`` are final."""

    def end(self, result: Result, status: str) -> None:
        """Called once at the end, also after an error or an interrupt; status says why."""


def _check_positive(name: str, value: float, unit: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError) as err:
        raise InputError(f"{name} must be a number [{unit}]; got {value!r}") from err
    if not math.isfinite(value):
        raise NonFiniteInput(f"{name} is {value} {unit}; give a finite positive value")
    if value <= 0.0:
        raise InputError(f"{name} is {value:g} {unit}; it must be positive")
    return value


#: Work terms of the energy ledger, accumulated over steps [J].
_WORK_KEYS = (
    "work_applied",
    "work_drivers",
    "work_springs",
    "work_gravity",
    "work_constraints",
    "dissipated",
)


def _allocate(gearbox: Gearbox, n: int, body_names: list[str]) -> Result:
    nj = len(gearbox.joint_names)
    nm = len(gearbox.meshes)
    nb = len(body_names)

    def z(*shape):
        return np.zeros((n, *shape))

    return Result(
        time=np.zeros(n),
        joint_names=list(gearbox.joint_names),
        mesh_names=[m.name for m in gearbox.meshes],
        bearing_names=list(gearbox.joint_names),
        body_names=body_names,
        angle=z(nj),
        speed=z(nj),
        acceleration=z(nj),
        torque=z(nj),
        mesh_normal=z(nm),
        mesh_tangential=z(nm),
        mesh_radial=z(nm),
        mesh_axial=z(nm),
        mesh_flank=z(nm),
        transmission_error=z(nm),
        mesh_force_on_b=z(nm, 3),
        pitch_point=z(nm, 3),
        bearing_force=z(nj, 3),
        bearing_moment=z(nj, 3),
        bearing_force_local=z(nj, 3),
        bearing_moment_local=z(nj, 3),
        body_position=z(nb, 3),
        body_quaternion=z(nb, 4),
        constraint_residual=np.zeros(n),
        energy={k: np.zeros(n) for k in ("kinetic", *_WORK_KEYS, "potential_spring")},
    )


@dataclass
class _Dynamics:
    """What one solve gives the recorder and the integrator."""

    v: np.ndarray
    residual: float
    mesh_rows: MeshRows
    mass: np.ndarray
    jac: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    tau_applied: np.ndarray
    tau_spring: np.ndarray
    tau_damp: np.ndarray
    gravity: np.ndarray


class _Stepper:
    """State and preallocated work of one run; ``step`` fills sample k."""

    def __init__(
        self,
        gearbox: Gearbox,
        *,
        dt: float,
        torques: list[JointLoad],
        speeds: list[JointLoad],
        settings: SolverSettings,
    ):
        self.gb = gearbox
        self.model = gearbox.model
        self.data = self.model.createData()
        self.dt = dt
        self.torques = torques
        self.drivers = speeds + [
            JointLoad(j, gearbox.v_index(j), 0.0) for j in gearbox.locked_joints
        ]
        self.driver_index = np.array([d.v_index for d in self.drivers], dtype=int)
        self.meshes = MeshSet(gearbox)
        self.elements = ForceElements(gearbox)
        self.reactions = BearingReactions(self.model, self.meshes.joint_a, self.meshes.joint_b)
        nv = self.model.nv
        self.nm = self.meshes.count
        self.rows = self.nm + len(self.drivers)
        self.driver_jac = np.zeros((len(self.drivers), nv))
        self.driver_jac[np.arange(len(self.drivers)), self.driver_index] = 1.0
        #: Name → row of the constraint system: mesh forces and driver torques are read from the
        #: multipliers through this map (meshes by name, drivers as "driver:JOINT").
        self.row_of = {name: i for i, name in enumerate(self.meshes.names)}
        self.row_of.update({f"driver:{d.joint}": self.nm + i for i, d in enumerate(self.drivers)})
        self.mesh_rows = np.array([self.row_of[n] for n in self.meshes.names], dtype=int)
        self.driver_rows = np.array(
            [self.row_of[f"driver:{d.joint}"] for d in self.drivers], dtype=int
        )
        self.solver = ConstrainedDynamicsSolver(nv, self.rows, settings)
        self.flank = np.ones(self.nm)
        self.wrench_local = np.zeros((self.model.njoints - 1, 6))
        self.wrench_world = np.zeros((self.model.njoints - 1, 6))
        self.te = np.zeros(self.nm)
        self._upper = np.triu(np.ones((nv, nv), dtype=bool))
        self._targets: dict[float, np.ndarray] = {}
        self.ledger_forces = np.zeros((len(_WORK_KEYS), nv))

    def driver_torque(self, lam: np.ndarray) -> np.ndarray:
        """Joint torques of the speed drivers and locks: their rows' multipliers [N·m]."""
        torque = np.zeros(self.model.nv)
        if len(self.drivers):
            np.add.at(torque, self.driver_index, lam[self.driver_rows])
        return torque

    # --- assembly ----------------------------------------------------------------------------

    def kinematics(self, q: np.ndarray, v: np.ndarray):
        pin.computeJointJacobiansTimeVariation(self.model, self.data, q, v)
        self.placements = joint_placements(self.model, self.data)
        self.meshes.set_velocity(v)
        return self.meshes.evaluate(self.model, self.data, self.placements)

    def targets(self, t: float) -> np.ndarray:
        """Right-hand sides of the velocity rows at t: 0 for meshes and locks, ω(t) for drivers."""
        cached = self._targets.get(t)
        if cached is not None:
            return cached
        target = np.zeros(self.rows)
        for i, d in enumerate(self.drivers):
            value = d(t)
            if not math.isfinite(value):
                raise NonFiniteInput(
                    f'speeds["{d.joint}"] is {value} rad/s at t = {t:.6g} s; the speed function '
                    "must return finite values"
                )
            target[self.nm + i] = value
        # Each step asks for t and t + dt; the next step asks for t + dt again.
        self._targets = {t: target}
        return target

    def constraint_matrix(self, mesh_rows) -> tuple[np.ndarray, np.ndarray]:
        jac_m, bias_m = self.meshes.combine(mesh_rows, self.flank)
        jac = np.vstack([jac_m, self.driver_jac]) if len(self.drivers) else jac_m
        bias = np.concatenate([bias_m, np.zeros(len(self.drivers))])
        return jac, bias

    def project(self, k, t, v, mass, jac, target) -> np.ndarray:
        """M-orthogonal projection of v onto J v = target (pseudo-inverse: redundant rows)."""
        minv_jt = np.linalg.solve(mass, jac.T)
        correction = np.linalg.pinv(jac @ minv_jt, rcond=1e-12) @ (jac @ v - target)
        projected = v - minv_jt @ correction
        residual = float(np.max(np.abs(jac @ projected - target), initial=0.0))
        scale = (
            1.0
            + float(np.abs(target).max(initial=0.0))
            + float(np.abs(jac).max(initial=0.0) * np.abs(v).max(initial=0.0))
        )
        if residual > 1e-9 * scale:
            raise ConflictingConstraints(k, t, residual, [d.joint for d in self.drivers])
        return projected

    def mass(self, q: np.ndarray) -> np.ndarray:
        m = np.reshape(pin.crba(self.model, self.data, q), self._upper.shape)
        # CRBA fills the upper triangle only.
        return np.where(self._upper, m, m.T)

    # --- one step ----------------------------------------------------------------------------

    def solve(self, k: int, t: float, q: np.ndarray, v: np.ndarray):
        """Dynamics at (q, v, t): returns everything the recorder and the integrator need."""
        mesh_rows = self.kinematics(q, v)
        mass = self.mass(q)
        jac, bias = self.constraint_matrix(mesh_rows)
        target_now = self.targets(t)
        residual = float(np.max(np.abs(jac @ v - target_now), initial=0.0))
        if residual > PROJECTION_TOL * (1.0 + float(np.max(np.abs(v), initial=0.0))):
            # Post-stabilisation: J changed over the last step, or the run starts off the
            # constraint manifold.
            v = self.project(k, t, v, mass, jac, target_now)
            mesh_rows = self.kinematics(q, v)
            jac, bias = self.constraint_matrix(mesh_rows)
            residual = float(np.max(np.abs(jac @ v - target_now), initial=0.0))
        target_next = self.targets(t + self.dt)
        gravity = pin.computeGeneralizedGravity(self.model, self.data, q)
        nle = pin.nonLinearEffects(self.model, self.data, q, v)
        tau_applied = np.zeros(self.model.nv)
        for load in self.torques:
            value = load(t)
            if not math.isfinite(value):
                raise NonFiniteInput(
                    f'torques["{load.joint}"] is {value} N·m at step {k} (t = {t:.6g} s); '
                    "the torque function must return finite values"
                )
            tau_applied[load.v_index] += value
        tau_spring = self.elements.elastic_torque(q)
        tau_damp = self.elements.damping_torque(v)
        force = tau_applied + tau_spring + tau_damp - nle
        rhs = -bias + (target_next - target_now) / self.dt
        if not math.isfinite(float(force @ force) + float(rhs @ rhs)):
            raise Diverged(k, t, "the joint forces or constraint terms are not finite")
        sol = self.solver.solve(mass, force, jac, rhs)
        self._check(k, t, sol)
        lam = sol.multipliers
        # A negative tooth force means the other flank carries the load: switch those rows to
        # it. With fixed axes the other flank's row is the opposite row and λ just flips sign;
        # otherwise solve again (a switch can move load between meshes, so repeat, a few times).
        for _ in range(4):
            negative = lam[self.mesh_rows] < 0.0
            if not negative.any():
                break
            free = self.meshes.flank_flip_is_free(mesh_rows)
            self.flank[negative] *= -1.0
            jac, bias = self.constraint_matrix(mesh_rows)
            if np.all(free[negative]):
                lam = lam.copy()
                lam[self.mesh_rows[negative]] *= -1.0
                break
            rhs = -bias + (target_next - target_now) / self.dt
            sol = self.solver.solve(mass, force, jac, rhs)
            self._check(k, t, sol)
            lam = sol.multipliers
        return _Dynamics(
            v,
            residual,
            mesh_rows,
            mass,
            jac,
            sol.acceleration,
            lam,
            tau_applied,
            tau_spring,
            tau_damp,
            gravity,
        )

    @staticmethod
    def _check(k: int, t: float, sol) -> None:
        if not (math.isfinite(sol.primal_residual) and math.isfinite(sol.dual_residual)):
            raise Diverged(k, t, "the constrained-dynamics QP returned non-finite values")
        if not sol.solved:
            raise SolverFailed(
                k,
                t,
                sol.status,
                f"primal residual {sol.primal_residual:.3g}, dual residual "
                f"{sol.dual_residual:.3g} N·m after {sol.iterations} iterations. Check for "
                "conflicting speed drivers (two drivers on joints that the gears couple) or "
                "a driver on a locked bearing.",
            )

    def reactions_of(self, q, v, a, mesh_rows, lam):
        normal = lam[self.mesh_rows]
        n = self.meshes.line_of_action(mesh_rows, self.flank)
        tangential = normal * self.meshes.cos_a
        # Helical teeth: the tooth line of a right-hand gear A runs along cos β k + sin β t at P,
        # so the tooth force on B, normal to it, has the axial part −s F_t tan β k.
        axial = tangential * np.abs(self.meshes.tan_beta)
        thrust = -(self.flank * tangential * self.meshes.tan_beta)[:, None] * mesh_rows.axis
        force_on_b = normal[:, None] * n + thrust
        fext = self.reactions.external_forces(self.placements, force_on_b, mesh_rows.pitch_point)
        self.reactions.evaluate(
            self.data, q, v, a, fext, self.placements, self.wrench_local, self.wrench_world
        )
        return normal, tangential, axial, force_on_b


def simulate(
    gearbox: Gearbox,
    *,
    duration: float,
    dt: float,
    torques: Mapping[str, Signal] | None = None,
    speeds: Mapping[str, Signal] | None = None,
    initial_speeds: Mapping[str, float] | None = None,
    gravity: np.ndarray | None = None,
    solver: SolverSettings | None = None,
    progress: bool | None = None,
    observer: RunObserver | None = None,
    chunk: int = 1000,
) -> Result:
    """Simulate a gearbox under joint torques and speed drivers.

    Args:
        gearbox: the model (``pinwind.load``).
        duration: simulated time [s] (> 0).
        dt: fixed time step [s] (> 0).
        torques: joint name → torque [N·m] about the joint axis, number or callable(t).
        speeds: joint name → prescribed joint speed [rad/s], number or callable(t); the driving
            torque is the multiplier of the driver's row (``res.joint(name).torque``).
        initial_speeds: joint name → initial speed [rad/s]; projected onto the constraints.
        gravity: gravity vector in world [m/s²]; default the model's.
        solver: proxsuite settings.
        progress: show a progress bar (default: for runs over 20 000 steps on a terminal).
        observer: receives samples as they are computed (e.g. the MCAP logger).
        chunk: samples per observer call.

    Returns:
        Result with samples at t = 0, dt, ..., duration. If the run raises or is interrupted, the
        observer's ``end`` still gets the samples computed so far and the reason.

    Raises:
        InputError: unknown joint names, non-finite values, dt or duration not positive.
        SolverFailed, Diverged: the run cannot go on; the message names the step and time.
    """
    duration = _check_positive("duration", duration, "s")
    dt = _check_positive("dt", dt, "s")
    if dt > duration:
        raise InputError(f"dt = {dt:g} s is longer than duration = {duration:g} s")
    steps = int(round(duration / dt))
    index = {name: gearbox.v_index(name) for name in gearbox.joint_names}
    free = {k: i for k, i in index.items() if k not in gearbox.locked_joints}
    probe = (0.0, 0.5 * duration, duration)
    torque_loads = joint_loads(
        torques, where="torques", joint_index=index, unit="N·m", probe_times=probe
    )
    for name in list(speeds or {}) + list(initial_speeds or {}):
        if name in gearbox.locked_joints:
            raise InputError(
                f'joint "{name}" is a fixed mount (a gear on a fixed joint, held at zero speed); '
                "it cannot be driven or given a speed. Drive one of: " + ", ".join(free)
            )
    speed_loads = joint_loads(
        speeds, where="speeds", joint_index=free, unit="rad/s", probe_times=probe
    )
    init = joint_loads(initial_speeds, where="initial_speeds", joint_index=free, unit="rad/s")
    model = gearbox.model
    saved_gravity = pin.Motion(model.gravity)
    if gravity is not None:
        g = np.asarray(gravity, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise NonFiniteInput(f"gravity must be three finite numbers [m/s²]; got {gravity!r}")
        model.gravity = pin.Motion(g, np.zeros(3))
    else:
        model.gravity = pin.Motion(gearbox.gravity, np.zeros(3))

    settings = solver or SolverSettings()
    st = _Stepper(gearbox, dt=dt, torques=torque_loads, speeds=speed_loads, settings=settings)
    body_frames = [f for f in range(model.nframes) if model.frames[f].type == pin.FrameType.BODY]
    body_names = [model.frames[f].name for f in body_frames]
    res = _allocate(gearbox, steps + 1, body_names)
    res.metadata = {
        "model_name": gearbox.name,
        "model_path": str(gearbox.path),
        "model_sha256": gearbox.sha256,
        "dt": dt,
        "duration": duration,
        "steps": steps,
        "gravity": list(map(float, model.gravity.linear)),
        "torques": {ld.joint: ld.description for ld in torque_loads},
        "speeds": {ld.joint: ld.description for ld in speed_loads},
        "locked_joints": list(gearbox.locked_joints),
        "solver": settings.as_dict(),
        "integrator": "semi-implicit Euler with velocity projection",
    }

    q = gearbox.neutral()
    v = np.zeros(model.nv)
    for ld in init:
        v[ld.v_index] = ld(0.0)
    for ld in speed_loads:
        v[ld.v_index] = ld(0.0)

    if progress is None:
        import sys

        progress = steps > 20_000 and sys.stderr.isatty()
    bar = _progress_bar(steps, gearbox.name) if progress else None
    if observer is not None:
        observer.begin(gearbox, res)

    status = "completed"
    written = 0
    k = 0
    started = wallclock.perf_counter()
    # Overflow in a diverging run is reported by the finiteness checks below, by step and time.
    errstate = np.errstate(over="ignore", invalid="ignore")
    errstate.__enter__()
    kinetic = res.energy["kinetic"]
    work = np.zeros((steps + 1, len(_WORK_KEYS)))
    try:
        for k in range(steps + 1):
            t = k * dt
            dyn = st.solve(k, t, q, v)
            v, mesh_rows, mass, jac, a, lam = (
                dyn.v,
                dyn.mesh_rows,
                dyn.mass,
                dyn.jac,
                dyn.a,
                dyn.lam,
            )
            tau_applied, tau_spring, tau_damp, grav = (
                dyn.tau_applied,
                dyn.tau_spring,
                dyn.tau_damp,
                dyn.gravity,
            )
            if not math.isfinite(float(a @ a) + float(lam @ lam)):
                raise Diverged(k, t, "the accelerations or constraint forces are not finite")
            normal, tangential, axial, force_on_b = st.reactions_of(q, v, a, mesh_rows, lam)

            res.time[k] = t
            res.angle[k] = q
            res.speed[k] = v
            res.acceleration[k] = a
            driver_torque = st.driver_torque(lam)
            res.torque[k] = tau_applied + driver_torque
            if st.nm:
                res.mesh_normal[k] = normal
                res.mesh_tangential[k] = tangential
                res.mesh_radial[k] = normal * st.meshes.sin_a
                res.mesh_axial[k] = axial
                res.mesh_flank[k] = st.flank
                res.transmission_error[k] = st.te
                res.mesh_force_on_b[k] = force_on_b
                res.pitch_point[k] = mesh_rows.pitch_point
            res.bearing_force_local[k] = st.wrench_local[:, :3]
            res.bearing_moment_local[k] = st.wrench_local[:, 3:]
            res.bearing_force[k] = st.wrench_world[:, :3]
            res.bearing_moment[k] = st.wrench_world[:, 3:]
            res.constraint_residual[k] = dyn.residual
            kinetic[k] = 0.5 * v @ mass @ v
            if k == steps:
                break

            v_next = v + a * dt
            # Work of each force over the step, at the mid-step speed (module docstring).
            forces = st.ledger_forces
            forces[0] = tau_applied
            forces[1] = driver_torque
            forces[2] = tau_spring
            forces[3] = -grav
            forces[4] = lam[st.mesh_rows] @ jac[st.mesh_rows]
            forces[5] = -tau_damp
            work[k + 1] = forces @ ((0.5 * dt) * (v + v_next))
            if st.nm:
                st.te = st.te + (
                    st.meshes.cos_a[:, None] * mesh_rows.jac_t
                    + (st.meshes.sin_a * st.meshes.eps)[:, None] * mesh_rows.jac_r
                ) @ (v_next * dt)
            q = pin.integrate(model, q, v_next * dt)
            v = v_next
            if not math.isfinite(float(q @ q) + float(v @ v)):
                raise Diverged(k + 1, t + dt, "the joint angles or speeds are not finite")

            if observer is not None and (k + 1) % chunk == 0:
                _finish_samples(model, st, res, work, kinetic, body_frames, written, k + 1)
                observer.samples(res, written, k + 1)
                written = k + 1
            if bar is not None:
                bar.advance()
    except KeyboardInterrupt:
        status = f"interrupted at step {k} (t = {k * dt:.6g} s)"
        raise
    except Exception as err:
        status = f"failed at step {k} (t = {k * dt:.6g} s): {err}"
        raise
    finally:
        errstate.__exit__(None, None, None)
        model.gravity = saved_gravity
        if bar is not None:
            bar.close()
        done = steps + 1 if status == "completed" else k
        res.metadata["wall_time_s"] = wallclock.perf_counter() - started
        res.metadata["status"] = status
        res.status = status
        if status != "completed":
            final = res.truncated(done)
        else:
            final = res
        _finish_samples(model, st, final, work, kinetic, body_frames, written, done)
        if observer is not None:
            if done > written:
                observer.samples(final, written, done)
            observer.end(final, status)
        _finished = final
    return _finished


def _finish_samples(model, st, res: Result, work, kinetic, frames, start: int, stop: int) -> None:
    """Fill what is computed per chunk for samples start:stop: energy sums, spring energy, poses."""
    if stop <= start:
        return
    for i, key in enumerate(_WORK_KEYS):
        before = res.energy[key][start - 1] if start > 0 else 0.0
        res.energy[key][start:stop] = before + np.cumsum(work[start:stop, i])
    for k in range(start, stop):
        res.energy["potential_spring"][k] = st.elements.spring_energy(res.angle[k])
    _poses(model, st.data, res, frames, start, stop)


def _poses(model, data, res: Result, frames: list[int], start: int, stop: int) -> None:
    """World poses of the link frames for samples start:stop, from the recorded angles.

    Each link is rigid on a joint: its pose is the joint's placement times a constant one.
    """
    parents = np.array([model.frames[f].parentJoint for f in frames], dtype=int)
    local = np.array([model.frames[f].placement.homogeneous for f in frames]).reshape(-1, 4, 4)
    joints = np.empty((stop - start, model.njoints, 4, 4))
    for k in range(start, stop):
        pin.forwardKinematics(model, data, res.angle[k])
        for j in range(model.njoints):
            joints[k - start, j] = data.oMi[j].homogeneous
    world = np.einsum("kjab,jbc->kjac", joints[:, parents], local)
    res.body_position[start:stop] = world[:, :, :3, 3]
    rotations = world[:, :, :3, :3].reshape(-1, 3, 3)
    quaternions = Rotation.from_matrix(rotations).as_quat()  # x, y, z, w
    res.body_quaternion[start:stop] = quaternions.reshape(stop - start, len(frames), 4)


class _progress_bar:
    """A rich progress bar over the steps of a run."""

    def __init__(self, steps: int, name: str):
        from rich.progress import (
            BarColumn,
            Progress,
            TextColumn,
            TimeRemainingColumn,
        )

        self._progress = Progress(
            TextColumn(f"simulating {name}"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total} steps"),
            TimeRemainingColumn(),
            transient=True,
        )
        self._progress.start()
        self._task = self._progress.add_task("run", total=steps)
        self._count = 0

    def advance(self) -> None:
        self._count += 1
        if self._count % 200 == 0:
            self._progress.update(self._task, completed=self._count)

    def close(self) -> None:
        self._progress.stop()
