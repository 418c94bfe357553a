"""Time integration of a gearbox: assemble, solve, record, step.

Each step k, at state (q_k, v_k) and time t_k = k·dt:

1. assemble M (CRBA), b (RNEA at a = 0), τ (applied torques, springs, dampers) and the constraint
   rows J, γ: one row per mesh (``dynamics/mesh.py``), per speed driver and per locked bearing
   (the compiled loop makes one pass over the joint placements, Pinocchio's
   computeJointJacobians, and runs CRBA and RNEA in world axes on what it gives);
2. solve the equality QP (``dynamics/solver.py``; by default directly through the Schur complement
   of its KKT system, or with proxsuite's proximal method when chosen): a_k and λ_k, the mesh forces
   [N] and driver torques [N·m] read from the duals through the name → row map (the meshes in
   file order, then the speed drivers, then the locked bearings);
3. bearing reactions by RNEA with the tooth forces at the pitch points;
4. the generalized-α step (``dynamics/integrator.py``, ``cpp/time_step.hpp``): a_k is the step's
   mean acceleration, v_{k+1} = v_k + a_k dt, q_{k+1} = q_k ⊕ Δq with Δq = (v_k + v_{k+1}) dt/2 for
   ρ∞ = 1, and the stiff elements' forces at the method's weighted state (mid-step for ρ∞ = 1):
   second order, with numerical dissipation of the unresolved modes set by ρ∞. The rows ask for
   J a = γ + (target(t_{k+1}) − target(t_k))/dt: the acceleration the constraints demand, with the
   speed drivers' change over the step. When J v drifts from the target (J changed during the
   step, or rounding) by more than ``PROJECTION_TOL``, v is projected back onto J v = target in the
   metric of M before the next solve (post-stabilisation, Saleh 2017 §2.1.3).
   The drift is not fed back into the QP's right-hand side: redundant rows (several planets) must
   get a consistent right-hand side, or the multipliers of the redundant directions drift.

The energy ledger uses the mid-step speed (v_k + v_{k+1})/2, with which the kinetic-energy change
of a step equals the work of the step's forces exactly when M is constant. The springs (torsional
and compliant meshes) store ``potential_spring``; what their forces' work over the steps misses of
its change is the integrator's own loss, ``numerical`` = −(ΔU_spring + W_springs) (zero to
rounding for constant-stiffness springs with ρ∞ = 1; with ρ∞ < 1 it also holds the work of the
method's inertia memory, its dissipation of the unresolved modes), so that

    Δkinetic + ΔU_spring
        = W_applied + W_drivers + W_gravity + W_constraints − dissipated − numerical.

The step loop itself is compiled (``dynamics/stepper.py``, ``dynamics/cpp/stepper.hpp``); this
module checks the inputs, evaluates the torque and speed signals, and hands the samples to the
observer chunk by chunk.
"""

from __future__ import annotations

import math
import sys
import time as wallclock
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from pinwind.dynamics import _native, series
from pinwind.dynamics.compliant import MeshSetup, mesh_setup, single_pair
from pinwind.dynamics.drivetrain import Drivetrain, drivetrain
from pinwind.dynamics.dt_advice import coarse_step_notes
from pinwind.dynamics.elements import LoadElements
from pinwind.dynamics.integrator import Integrator
from pinwind.dynamics.linear_model import check_held, linear_model
from pinwind.dynamics.result import Result
from pinwind.dynamics.run_settings import RunSettings
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import (
    EQUILIBRIUM_DIVERGED,
    EQUILIBRIUM_LOAD_STEPS,
    EQUILIBRIUM_ROUNDING,
    CompiledStepper,
)
from pinwind.dynamics.support_springs import from_ground, roll_share
from pinwind.dynamics.torque_balance import imbalances, representative_torque
from pinwind.dynamics.torsional_modes import highest_spring_mode
from pinwind.errors import (
    ConflictingInputs,
    Diverged,
    EquilibriumNotReached,
    InputError,
    NonFiniteInput,
    OutOfMemory,
    PinwindError,
    SpeedOutOfRange,
    SpringsWoundAtStart,
    StaticStartDiverged,
    StepTooCoarse,
    TorquesUnbalanced,
)
from pinwind.gears.face_load import AUTO_LINE_LOAD
from pinwind.interrupts import interrupts_deferred
from pinwind.loads.generator import GeneratorLaw
from pinwind.loads.hub_loads import HubLoad
from pinwind.loads.inputs import JointLoad, Signal
from pinwind.loads.rotor import Rotor
from pinwind.loads.signals import Constant, check_covers
from pinwind.loads.signals import Signal as TimeSignal
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox
from pinwind.units import rad_s_to_rpm
from pinwind.warning_site import user_stacklevel


class RunObserver(Protocol):
    """Receives a run's samples as they are computed (the MCAP logger and the run statistics).

    An observer may say, as ``holds``, how many later blocks it may still read a block during
    (its arrays must not change until then): 0 when it is done with a block once ``samples``
    returns. Without it (or None) it may keep the blocks, and the run gives it new arrays every
    block. An observer that reads no block (statistics folding nothing) may say so, after
    ``begin``, with ``reads`` False: when no observer reads the blocks, the run records the
    samples the Result keeps only (``keep``; the others are stepped, not recorded) and hands
    no block over.
    """

    def begin(self, gearbox: Gearbox, result: Result) -> None:
        """Called once before the first step; ``result`` has the names and metadata."""

    def samples(self, block: Result, start: int) -> None:
        """Samples start … start + len(block) − 1 are final; they are the rows of ``block``."""

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


#: The most steps a run takes: weeks of computing at the fastest step (≈ 1 µs), and far
#: below the compiled stepper's 64-bit sample count (a dt of 1e-30 s made 2e28 steps, which it
#: could not take: a TypeError from the binding).
MAX_STEPS = 10**12


def _step_count(duration: float, dt: float) -> int:
    """Number of steps of dt in duration; refuses a duration that dt does not divide."""
    if dt > duration:
        raise InputError(f"dt = {dt:g} s is longer than duration = {duration:g} s")
    if duration / dt > MAX_STEPS:
        raise InputError(
            f"dt = {dt:g} s makes {duration / dt:.3g} steps of the {duration:g} s run, more than "
            f"the {MAX_STEPS:.0e} a run can take (weeks even at 1 µs per step); give dt in "
            "seconds, at least "
            f"{duration / MAX_STEPS:.3g} s"
        )
    steps = round(duration / dt)
    if abs(steps * dt - duration) > 1e-9 * duration:
        below = math.floor(duration / dt) * dt
        raise InputError(
            f"duration = {duration:g} s is not a whole number of steps of dt = {dt:g} s "
            f"({duration / dt:.6g} steps); the nearest durations are {below:.10g} s and "
            f"{below + dt:.10g} s, or choose a dt that divides {duration:g} s"
        )
    return steps


#: Samples per block handed to the observer (the log: a chunk of columns per block) in a long
#: run. A log read back decompresses and places a chunk per reading thread at a time: blocks of
#: 5000 samples read 20-25 % faster than blocks of 1000 (benchmarks/read_log.py).
CHUNK = 5000
#: The fewest samples per block. A run ends by waiting for its log's writer to compress the
#: last block (0.4-0.8 µs per sample): blocks are a twentieth of a shorter run, so that this
#: wait stays a few per cent of the run (benchmarks/log_overhead.py).
MIN_CHUNK = 1000


#: A run no observer watches steps its kept rows in blocks that last about this long [s] once
#: the first block has measured the step: the Python around each block (signals, checks, the
#: derived series) costs ~0.5 ms whatever its length, a tenth of a 1000-sample rigid block.
#: Ctrl-C waits for the block in hand, so blocks stay short in time.
UNWATCHED_BLOCK_S = 0.1
#: The most samples per block of a run no observer watches: per-block temporaries (the signal
#: tables, the derived series' inputs) stay a few MB.
UNWATCHED_BLOCK_MAX = 50_000


def block_samples(samples: int) -> int:
    """Samples per block of a run of ``samples`` samples.

    A twentieth of the run, at least ``MIN_CHUNK`` and at most ``CHUNK``.
    """
    return max(MIN_CHUNK, min(CHUNK, samples // 20))


#: Speed [rad/s; m/s for a slide] above which a run is stopped as diverged (≈ 955 000 rpm: no
#: gear survives it; a 10 mm pinion would have a pitch-line speed of 1000 m/s).
MAX_PLAUSIBLE_SPEED = 1e5


def _check_start_speeds(train: Drivetrain) -> None:
    """Refuse start speeds (given, or through the gear ratios) beyond ``MAX_PLAUSIBLE_SPEED``.

    A run beyond it is stopped as diverged; started there (``initial_speeds`` of 1e30 rpm) the
    compiled step did not return at all.

    Raises:
        SpeedOutOfRange: naming the fastest joint, its speed and the inputs that set it.
    """
    v = train.operating_speed()
    if not v.size or float(np.max(np.abs(v))) <= MAX_PLAUSIBLE_SPEED:
        return
    gearbox = train.gearbox
    j = int(np.argmax(np.abs(v)))
    name = next(n for n in gearbox.joint_names if gearbox.v_index(n) == j)
    given = ", ".join(
        f'{where}["{ld.joint}"] = {ld(0.0):.4g} rad/s ({ld(0.0) * 30 / math.pi:.4g} rpm)'
        for where, lds in (("initial_speeds", train.initial_speeds), ("speeds", train.drivers))
        for ld in lds
    )
    raise SpeedOutOfRange(
        f'at the start joint "{name}" turns at {v[j]:.4g} rad/s ({v[j] * 30 / math.pi:.4g} rpm) '
        f"from {given}: beyond the {MAX_PLAUSIBLE_SPEED:.0e} rad/s a gear can turn at (a run "
        "beyond it is stopped as diverged); give a lower speed (in rpm at the command line "
        "and in scenario files, in rad/s in Python)"
    )


def _implausible(block: Result, samples: np.ndarray) -> tuple[int, str] | None:
    """First sample whose joint speed is beyond ``MAX_PLAUSIBLE_SPEED``.

    ``block``'s first rows hold ``samples`` (increasing indices). Returns (sample, what) or
    None; the C++ loop only stops on NaN or infinity, by which time the log holds speeds of
    1e146 rad/s.
    """
    recorded = block.speed[: len(samples)]
    # Two reductions without a temporary first: a block of plausible speeds (every block but
    # the last of a diverging run) costs no more. A NaN (where the compiled loop stops) fails
    # them and is left to the test below, which passes it.
    if not recorded.size or (
        recorded.max() <= MAX_PLAUSIBLE_SPEED and recorded.min() >= -MAX_PLAUSIBLE_SPEED
    ):
        return None
    speeds = np.abs(recorded)
    bad = np.flatnonzero((speeds > MAX_PLAUSIBLE_SPEED).any(axis=1))
    if not bad.size:
        return None
    row = int(bad[0])
    k = int(samples[row])
    j = int(np.argmax(np.abs(block.speed[row])))
    value = block.speed[row, j]
    if block.joint_kinds[j] == "prismatic":
        return k, (
            f'slide "{block.joint_names[j]}" moves at {value:.3g} m/s, beyond the plausible '
            f"{MAX_PLAUSIBLE_SPEED:.0e} m/s"
        )
    return k, (
        f'joint "{block.joint_names[j]}" turns at {value:.3g} rad/s '
        f"({rad_s_to_rpm(value):.3g}"
        f" rpm), beyond the plausible {MAX_PLAUSIBLE_SPEED:.0e} rad/s"
    )


#: Work terms of the energy ledger, accumulated over steps [J].
def _allocate(
    gearbox: Gearbox,
    n: int,
    body_names: list[str],
    elements: LoadElements,
    schema: series.Schema,
    slices: list[str],
    *,
    empty: bool = False,
) -> Result:
    """A Result of n samples, one array per series of ``schema``, views of one buffer.

    One large buffer rather than thirty: numpy asks the kernel for huge pages for buffers of
    4 MB and more, so that filling a long run's arrays takes a page fault per 2 MB instead of
    one per 4 kB (page faults were a sixth of a drivetrain run's time). ``elements`` gives the
    generator and rotor columns, ``slices`` the slice columns (``MeshSetup.slice_names``).
    """
    names = _names(gearbox, body_names, elements, slices)
    shapes = _sample_shapes(names, schema)
    sizes = {k: n * math.prod(shape) for k, shape in shapes.items()}
    buffer = (np.empty if empty else np.zeros)(sum(sizes.values()))
    arrays: dict[str, Any] = {}
    at = 0
    for key, shape in shapes.items():
        arrays[key] = buffer[at : at + sizes[key]].reshape(n, *shape)
        at += sizes[key]
    return Result(
        **names,
        energy={t.name: arrays.pop(f"energy/{t.name}") for t in series.ENERGY_TERMS},
        schema=schema,
        **arrays,
    )


def _names(
    gearbox: Gearbox, body_names: list[str], elements: LoadElements, slices: list[str]
) -> dict[str, Any]:
    """The element names of every family of a run (``series.NAMES_OF``).

    ``slices``: the sliced meshes' slices (``MeshSetup.slice_names``).
    """
    return {
        "joint_names": list(gearbox.joint_names),
        "joint_kinds": gearbox.joint_kinds,
        "mesh_names": [m.name for m in gearbox.meshes],
        "bearing_names": list(gearbox.bearing_names),
        "body_names": body_names,
        "generator_names": list(elements.generator_names),
        "rotor_names": list(elements.rotor_names),
        "row_names": list(gearbox.row_names),
        "slice_names": list(slices),
    }


def _sample_shapes(names: dict[str, list], schema: series.Schema) -> dict[str, tuple[int, ...]]:
    """The shape of one sample of every series of ``schema`` and energy term (``energy/TERM``)."""
    shapes: dict[str, tuple[int, ...]] = {}
    for s in schema.series:
        count = len(names[series.NAMES_OF[s.family]]) if s.family != "run" else 1
        shapes[s.name] = s.shape(count)
    shapes.update({f"energy/{t.name}": () for t in series.ENERGY_TERMS})
    return shapes


#: (sample, load, the non-finite value or the exception its function raised)
_BadSample = tuple[int, JointLoad, float | Exception]


def _signal_table(
    loads: list[JointLoad], start: int, stop: int, dt: float, columns: list[int], width: int
) -> tuple[np.ndarray, _BadSample | None]:
    """Values of time signals at t_k = k·dt, k in start:stop, as a (stop − start, width) table.

    Column ``columns[i]`` gets load i (added, so two loads on one joint sum). Returns the table
    and the first sample whose value is not finite or whose function raised, as (k, load,
    value or exception), or None.
    """
    table = np.zeros((stop - start, width))
    times = np.arange(start, stop) * dt
    first_bad: _BadSample | None = None
    for load, column in zip(loads, columns, strict=True):
        bad: _BadSample | None
        if isinstance(load.signal, TimeSignal):  # evaluated for the whole block at once
            values = np.asarray(load.signal.values(times), dtype=float)
            bad = None
        elif callable(load.signal):
            values = np.full(len(times), np.nan)
            for i, t in enumerate(times):
                try:
                    values[i] = load(t)
                except Exception as err:  # the user's function: report it with its step
                    bad = (start + i, load, err)
                    break
            else:
                bad = None
        else:
            values = np.full(len(times), float(load.signal))
            bad = None
        table[:, column] += values
        nonfinite = np.flatnonzero(~np.isfinite(values))
        if bad is None and nonfinite.size:
            bad = (start + int(nonfinite[0]), load, float(values[nonfinite[0]]))
        if bad is not None and (first_bad is None or bad[0] < first_bad[0]):
            first_bad = bad
    return table, first_bad


def _held_torques(loads: list[JointLoad], columns: list[int], width: int) -> np.ndarray | None:
    """The torques as one row (1, width) [N·m] when every load is a finite constant, else None.

    The compiled loop holds a single row over the block: no table of identical rows to fill
    and read for the usual constant load case.
    """
    row = np.zeros((1, width))
    for load, column in zip(loads, columns, strict=True):
        if isinstance(load.signal, TimeSignal) or callable(load.signal):
            return None
        value = float(load.signal)
        if not math.isfinite(value):
            return None  # the table reports it at its first sample
        row[0, column] += value
    return row


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
    integrator: Integrator | None = None,
    progress: bool | None = None,
    observer: RunObserver | Sequence[RunObserver] | None = None,
    chunk: int | None = None,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    position_errors: Mapping[str, tuple[float, float]] | None = None,
    keep: str | int | None = None,
    keep_series: Sequence[str] | None = None,
    generators: Mapping[str, GeneratorLaw] | None = None,
    rotors: Mapping[str, Rotor] | None = None,
    wind: float | TimeSignal | None = None,
    hub_loads: Sequence[HubLoad] | None = None,
    initial_deflection: str | None = None,
    metadata: Mapping[str, object] | None = None,
    settings: RunSettings | None = None,
) -> Result:
    """Simulate a gearbox under joint torques and speed drivers.

    The run is ``drivetrain`` (the machine: the gearbox, its loads and laws) → ``prepare`` (the
    compiled stepper at the start, the Result's arrays) → ``PreparedRun.run`` (the blocks of
    samples stepped and handed to the observers, then ``finish``), each usable alone.

    Args:
        gearbox: the model (``pinwind.load``).
        duration: simulated time [s] (> 0).
        dt: fixed time step [s] (> 0).
        torques: joint name → torque [N·m] about the joint axis, number or callable(t).
        speeds: joint name → prescribed joint speed [rad/s], number or callable(t); the driving
            torque is the multiplier of the driver's row (``res.joint(name).torque``).
        initial_speeds: joint name → initial speed [rad/s]; the other joints start at the speeds
            the gear meshes and springs impose (``Drivetrain.operating_speed``).
        gravity: gravity vector in world [m/s²]; default the model's.
        solver: the QP's settings (``RunSettings.solver``).
        integrator: the time step and its numerical dissipation (``RunSettings.integrator``;
            default ``Integrator()``: generalized-α with ρ∞ = 1, the trapezoidal rule).
        progress: show a progress bar (``RunSettings.progress``; default: for runs over
            20 000 steps on a terminal).
        observer: one or several observers that receive the samples as they are computed:
            the MCAP logger (``io/log_writer.McapLogger``), the run statistics
            (``analysis/run_statistics.StatisticsObserver``; ``pinwind.simulate`` adds it).
        chunk: samples per observer call (``RunSettings.chunk``); default ``block_samples``:
            1000 to 5000, a twentieth of the run.
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a
            ``MeshCompliance``, replacing the model file's choice (``dynamics/compliant.py``).
        position_errors: gear name → (tangential, radial) position error of its centre [m]
            (planet pin errors), replacing the model file's.
        keep: which samples the returned Result holds (``RunSettings.keep``; default
            ``"auto"``); the run itself streams block by block to the observer (the log) in
            memory for one block.
        keep_series: the series the returned Result holds (``RunSettings.keep_series``;
            default every series); the observers (the log) get every series.
        generators: joint name → generator law (``loads/generator.py``), compiled.
        rotors: joint name → ``Rotor`` (``loads/rotor.py``), compiled; its inertia is added to
            the joint.
        wind: wind speed at the rotors [m/s]: a number or a ``pinwind.loads.signals.Signal``
            (``KaimalWind``, a table, ...), evaluated block by block and handed to the compiled
            loop as a per-sample input.
        hub_loads: six load components each on a body at a point (thrust, shear forces,
            torque, bending moments; ``pinwind.loads.hub_loads.HubLoad``), in the fixed or the
            rotating shaft frame; evaluated block by block like the wind. The bearings carry
            them (their reactions include them).
        initial_deflection: ``"static"`` (default): the compliant meshes and springs start
            deflected under the loads of t = 0, carrying the forces rigid meshes would carry
            (``CompiledStepper.equilibrium``), so that maxima and load factors describe the
            operation, not a start-up impact; ``"none"``: they start undeflected (the bodies at
            the model's pose), the start-up transient included. ``metadata["initial_deflection"]``
            records how the static start went.
        metadata: extra entries for ``result.metadata`` and the log (e.g. the scenario).
        settings: the run settings as one object (``RunSettings``), instead of ``solver``,
            ``integrator``, ``progress``, ``chunk``, ``keep``, ``keep_series`` and
            ``initial_deflection``.

    Torques and speeds given as ``pinwind.loads.signals.Signal`` are evaluated for a whole block
    at once; plain Python callables are called once per sample, the slow path.

    Returns:
        Result with the kept samples of t = 0, dt, ..., duration (``metadata["keep_stride"]``
        says which). If the run raises or is interrupted, the observer's ``end`` still gets
        the samples computed so far and the reason.

    Raises:
        InputError: unknown joint names, non-finite values, dt or duration not positive, a
            duration that dt does not divide, a torque or speed on a fixed mount, a load
            function that raises (its exception is the ``__cause__``).
        ConflictingInputs: a joint given both a torque and a speed; ``settings`` given with
            one of the keywords it holds.
        ConflictingConstraints: initial or driver speeds that contradict the gear ratios.
        SolverFailed, Diverged: the run cannot go on; the message names the step and time.
            Diverged also when a joint turns faster than ``MAX_PLAUSIBLE_SPEED`` at a recorded
            sample (the kept ones only when no observer reads the blocks).
        OutOfMemory: the result arrays do not fit in memory.
    """
    duration = _check_positive("duration", duration, "s")
    dt = _check_positive("dt", dt, "s")
    _step_count(duration, dt)
    run_settings = _run_settings(
        settings,
        solver=solver,
        integrator=integrator,
        progress=progress,
        chunk=chunk,
        keep=keep,
        keep_series=None if keep_series is None else tuple(keep_series),
        initial_deflection=initial_deflection,
    )
    train = drivetrain(
        gearbox,
        torques=torques,
        speeds=speeds,
        initial_speeds=initial_speeds,
        generators=generators,
        rotors=rotors,
        wind=wind,
        hub_loads=hub_loads,
        meshes=meshes,
        gravity=gravity,
    )
    run = prepare(
        train,
        duration=duration,
        dt=dt,
        settings=run_settings,
        position_errors=position_errors,
        metadata=metadata,
    )
    return run.run(observers_of(observer))


def _run_settings(settings: RunSettings | None, **given: object) -> RunSettings:
    """``settings``, or one built from ``simulate``'s keywords of the same names."""
    named = {k: v for k, v in given.items() if v is not None}
    if settings is None:
        return RunSettings(**named)  # type: ignore[arg-type]
    if not isinstance(settings, RunSettings):
        raise InputError(f"settings={settings!r}: give a pinwind.dynamics.RunSettings")
    if named:
        raise ConflictingInputs(
            "the run settings are given twice: settings=RunSettings(...) and "
            + ", ".join(f"{k}={v!r}" for k, v in named.items())
            + "; give them in the RunSettings alone"
        )
    return settings


def prepare(
    train: Drivetrain,
    *,
    duration: float,
    dt: float,
    settings: RunSettings | None = None,
    position_errors: Mapping[str, tuple[float, float]] | None = None,
    metadata: Mapping[str, object] | None = None,
) -> PreparedRun:
    """A run of ``train`` ready to step: the checks, the compiled stepper at the start, the Result.

    Checks that the loads cover ``duration`` [s], sets up the meshes (their mass and loaded
    flanks from the machine's linearisation), warns of unbalanced torques, a step too coarse
    for the stiffest spring and springs wound at the start, allocates the Result the run keeps
    with its metadata, builds the compiled stepper at the model's pose and the operating speeds,
    and takes the static start (``RunSettings.initial_deflection``). Nothing is stepped yet.

    Raises:
        InputError, OutOfMemory: as ``simulate``.
    """
    settings = settings if settings is not None else RunSettings()
    duration = _check_positive("duration", duration, "s")
    dt = _check_positive("dt", dt, "s")
    steps = _step_count(duration, dt)
    gearbox = train.gearbox
    torque_loads, speed_loads, init = train.torques, train.drivers, train.initial_speeds
    for where, lds in (("torques", torque_loads), ("speeds", speed_loads)):
        for ld in lds:
            check_covers(ld.signal, duration, f'{where}["{ld.joint}"]')
    elements = train.loads if train.loads is not None else LoadElements()
    if elements.wind is not None:
        check_covers(elements.wind, duration, "wind")
    model = gearbox.model
    method = settings.integrator
    # Rows after the meshes: the speed drivers, then the locked bearings (held at zero speed).
    drivers = train.rows
    # The machine the run steps, linearised: its mass (the rotors' inertias in), the flanks the
    # static load presses (the mesh modes' rows), and a floating member nothing holds refused,
    # naming its free motion.
    _check_start_speeds(train)
    linear = linear_model(train, at=train.operating_speed())
    check_held(gearbox, linear)
    meshes = mesh_setup(
        gearbox,
        train.meshes,
        driver_index=[d.v_index for d in drivers],
        dt=dt,
        position_errors=position_errors,
        scheme=method,
        mass=linear.mass,
        flank=linear.flanks.flank,
    )
    _warn_if_unbalanced(gearbox, torque_loads, speed_loads, elements, duration)
    spring_mode = highest_spring_mode(train)
    for note in coarse_step_notes(duration, dt, spring_mode):
        warnings.warn(StepTooCoarse(note), stacklevel=user_stacklevel())
    frames = gearbox.body_frames()
    body_names = [model.frames[f].name for f in frames]
    samples = steps + 1
    stride = _keep_stride(
        settings.keep,
        samples,
        _bytes_per_sample(gearbox, body_names, elements, meshes.slice_names()),
    )
    kept = _kept_samples(samples, stride)
    chunk = settings.chunk if settings.chunk is not None else block_samples(samples)
    try:
        # The run's schema: the one of its start, kept whatever is declared while it runs.
        res = _allocate(
            gearbox, len(kept), body_names, elements, series.current(), meshes.slice_names()
        )
    except MemoryError as err:
        raise OutOfMemory(len(kept), duration, dt) from err
    if settings.keep_series is not None:
        try:
            res.schema.only(settings.keep_series)
        except KeyError as err:
            raise InputError(f"keep_series: {err.args[0]}") from None
    res.metadata = {
        "model_name": gearbox.name,
        "model_path": str(gearbox.path),
        "model_sha256": gearbox.sha256,
        "dt": dt,
        "duration": duration,
        "steps": steps,
        "gravity": list(map(float, train.gravity)),
        "torques": {ld.joint: ld.description for ld in torque_loads},
        "speeds": {ld.joint: ld.description for ld in speed_loads},
        "initial_speeds": {ld.joint: ld.description for ld in init},
        "locked_joints": list(gearbox.locked_joints),
        "solver": settings.solver.as_dict(),
        "integrator": method.as_dict(),
        "meshes": _mesh_metadata(meshes),
        "highest_mesh_mode_hz": meshes.highest_mode,
        "highest_mesh_mode_damping_ratio": meshes.highest_mode_damping,
        "samples_simulated": samples,
        "keep_stride": stride,
        **elements.metadata,
        **(metadata or {}),
    }
    if position_errors:
        res.metadata["position_errors"] = {
            k: list(map(float, v)) for k, v in position_errors.items()
        }

    q = gearbox.neutral()
    # The machine turning: the given speeds, the others through the meshes and the springs.
    v = train.operating_speed()
    _warn_if_wound(gearbox, v)
    stepper = CompiledStepper(
        gearbox,
        samples,
        q,
        v,
        dt=dt,
        gravity=train.gravity,
        driver_index=[d.v_index for d in drivers],
        driver_names=[d.joint for d in drivers],
        settings=settings.solver,
        meshes=meshes,
        loads=elements,
        integrator=method,
    )
    res.metadata["initial_deflection"] = {"mode": settings.initial_deflection}
    if settings.initial_deflection == "static" and (
        meshes.compliant or gearbox.springs or gearbox.slide_joints
    ):
        res.metadata["initial_deflection"].update(
            _static_start(gearbox, stepper, torque_loads, drivers, elements, dt)
        )
    return PreparedRun(
        train=train,
        settings=settings,
        dt=dt,
        steps=steps,
        chunk=chunk,
        stride=stride,
        kept=kept,
        result=res,
        stepper=stepper,
        body_names=body_names,
        elements=elements,
    )


@dataclass
class BlockOutcome:
    """What stepping one block gave (``PreparedRun.step_block``).

    Attributes:
        done: the samples before this one are final [-] (the block's end, or where it stopped).
        error: why the block stopped early (a non-finite or failing load, the solver, a
            divergence), raised once its final samples are handed over; None if it did not.
    """

    done: int
    error: BaseException | None = None


@dataclass
class PreparedRun:
    """A run ready to step (``prepare``): its machine, settings, compiled stepper and Result.

    ``step_block`` steps one block of samples into arrays, ``run`` steps them all and hands
    them to the observers, ``finish`` closes the Result (its status, and the samples up to
    where the run stopped).

    Attributes:
        train: the machine the run steps.
        settings: its run settings.
        dt: time step [s]; steps: steps of the run [-].
        chunk: samples per block [-]; stride: the Result keeps every stride-th sample [-].
        kept: the samples the Result keeps (indices from 0).
        result: the Result's arrays, filled as the run goes, with its metadata.
        stepper: the compiled stepper, at the start state until the first block.
        body_names: the links whose poses are recorded.
        elements: the compiled load elements (generators, rotors, wind).
    """

    train: Drivetrain
    settings: RunSettings
    dt: float
    steps: int
    chunk: int
    stride: int
    kept: np.ndarray
    result: Result
    stepper: CompiledStepper
    body_names: list[str]
    elements: LoadElements

    @property
    def gearbox(self) -> Gearbox:
        """The model the run steps."""
        return self.train.gearbox

    @property
    def samples(self) -> int:
        """Samples of the whole run, t = 0 … duration [-]."""
        return self.steps + 1

    def step_block(
        self,
        start: int,
        stop: int,
        block: Result,
        *,
        stride: int = 1,
        held: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> BlockOutcome:
        """Steps samples [start, stop) into ``block``'s rows (every ``stride``-th from 0 only).

        Evaluates the torque and speed signals and the wind over the block, stopping before
        the first sample where one is not finite or raises; then steps the compiled loop and
        checks the speeds it recorded (``MAX_PLAUSIBLE_SPEED``). The samples before
        ``BlockOutcome.done`` are final whatever happened.

        ``held`` gives the applied joint torques (nv,) [N·m], constant over the block, and the
        driver speeds at t_start … t_stop (stop − start + 1, rows) [rad/s] instead, when the
        caller knows them and they are finite (a session's held inputs, ``runs/session.py``):
        the values every signal would give.
        """
        dt, gearbox = self.dt, self.gearbox
        nv = gearbox.model.nv
        bad_torque: _BadSample | None = None
        bad_target: _BadSample | None = None
        if held is not None:
            torque = from_ground(gearbox, roll_share(gearbox), held[0][None, :])
            torque = np.broadcast_to(torque, (stop - start, nv))
            target = held[1]
        else:
            drivers, torque_loads = self.train.rows, self.train.torques
            columns = [ld.v_index for ld in torque_loads]
            held_row = _held_torques(torque_loads, columns, nv)
            if held_row is None:
                torque, bad_torque = _signal_table(torque_loads, start, stop, dt, columns, nv)
            else:
                torque = held_row
            torque = from_ground(gearbox, roll_share(gearbox), torque)
            # Step k asks for the driver speeds at t_k and t_{k+1}.
            target, bad_target = _signal_table(
                drivers, start, stop + 1, dt, list(range(len(drivers))), len(drivers)
            )
        error: BaseException | None = None
        if bad_torque is not None:
            k, load, cause = bad_torque
            stop = k
            error = _signal_error("torques", load, k, dt, cause, "N·m")
            error.__cause__ = cause if isinstance(cause, Exception) else None
        if bad_target is not None and max(bad_target[0] - 1, 0) < stop:
            k, load, cause = bad_target
            stop = max(k - 1, 0)
            error = _signal_error("speeds", load, k, dt, cause, "rad/s")
            error.__cause__ = cause if isinstance(cause, Exception) else None
        fast = _driven_too_fast(self.train.rows, target, start, stop, dt)
        if fast is not None:
            stop, error = fast
        inputs = self.elements.inputs(np.arange(start, stop) * dt)
        if inputs is not None:
            bad = np.argwhere(~np.isfinite(inputs))
            if bad.size and start + int(bad[0, 0]) < stop:
                row, column = (int(x) for x in bad[0])
                k = start + row
                stop = k
                name, unit = self.elements.input_names[column]
                error = NonFiniteInput(
                    f"{name} is {inputs[row, column]} {unit} at step {k} "
                    f"(t = {k * dt:.6g} s); it must be finite"
                )
            inputs = inputs[: stop - start]
        lo, hi = (int(i) for i in np.searchsorted(self.kept, [start, stop]))
        rows = hi - lo if stride > 1 else stop - start
        if rows < len(block):  # stopped early: the rows of the samples stepped
            block = block.rows(0, rows)
        done = start
        failure: PinwindError | None = None
        try:
            done = self.stepper.run(
                start, stop, torque[: stop - start], target[: stop - start + 1], block, inputs,
                stride=stride,
            )  # fmt: skip
        except PinwindError as err:
            done = getattr(err, "samples", start)
            failure = err
        # The sample of each row of the block.
        recorded = self.kept[lo:hi] if stride > 1 else np.arange(start, stop)
        absurd = _implausible(block, recorded[recorded < done])
        if absurd is not None:
            diverged = _diverged(absurd, dt)
            diverged.__cause__ = failure
            return BlockOutcome(absurd[0], diverged)
        if failure is not None:
            return BlockOutcome(done, failure)
        return BlockOutcome(done, error)

    def run(self, observers: Sequence[RunObserver] = ()) -> Result:
        """Steps every block, hands each to the observers, and returns ``finish``'s Result.

        The observers' ``end`` is called whatever stops the run (an error, Ctrl-C).
        """
        gearbox, res, kept, chunk = self.gearbox, self.result, self.kept, self.chunk
        samples, stride, dt = self.samples, self.stride, self.dt
        observers = list(observers)
        begun: list[RunObserver] = []  # the observers to end, whatever stops the run
        holds = [getattr(o, "holds", None) for o in observers]
        status = "completed"
        done = 0
        spring0 = None
        direct = stride == 1  # every sample kept: the Result's own rows are the blocks
        # Buffers for blocks the Result does not keep: one more than the blocks an observer
        # may still read while the loop steps into the next (the statistics' thread folds two
        # behind).
        spares: list[Result] = []
        names = self.kept_names
        progress = self.settings.progress
        if progress is None:
            progress = self.steps > 20_000 and sys.stderr.isatty()
        bar = _progress_bar(self.steps, gearbox.name) if progress else None
        started = wallclock.perf_counter()
        try:
            for o in observers:
                # begun and listed at once: a Ctrl-C in between would leave a log never ended
                with interrupts_deferred():
                    o.begin(gearbox, res)
                    begun.append(o)
            read = any(getattr(o, "reads", True) for o in observers)
            # No observer reads the blocks: the compiled loop records the kept samples alone,
            # into the Result's own rows (keep="last" keeps the last sample but not the first:
            # blocks).
            sparse = not direct and not read and stride < samples
            # Blocks that are views of the Result's rows cost no memory: a run whose blocks no
            # observer reads takes them longer once the first has timed the step.
            grows = not read and self.settings.chunk is None and (direct or sparse)
            start = 0
            while start < samples:
                block_started = wallclock.perf_counter()
                # A block is stepped and handed to the observers whole: Ctrl-C or SIGTERM waits
                # for the hand-over (it used to drop the block between the step and the log:
                # samples counted as simulated that no log held). The compiled step checks no
                # signal anyway.
                with interrupts_deferred():
                    stop = min(start + chunk, samples)
                    lo, hi = (int(i) for i in np.searchsorted(kept, [start, stop]))
                    if direct or sparse:  # the compiled loop writes the kept arrays in place
                        block = res.rows(lo, hi)
                    elif None not in holds:  # blocks dropped once observed: buffers in turn
                        if not spares:
                            spares = [
                                self._block(chunk)
                                for _ in range(
                                    1 + max((h for h in holds if h is not None), default=0)
                                )
                            ]
                        block = spares[start // chunk % len(spares)].rows(0, stop - start)
                    else:  # an observer keeps the blocks (the log's writer thread): new arrays
                        block = self._block(stop - start)
                    done = start
                    outcome = self.step_block(start, stop, block, stride=stride if sparse else 1)
                    done = outcome.done
                    recorded = kept[lo:hi] if sparse else np.arange(start, stop)
                    # Samples start:done are final whatever happened: keep and hand them over.
                    final_rows = int(np.searchsorted(recorded, done))
                    if done > start and final_rows:
                        part = block if final_rows == len(block) else block.truncated(final_rows)
                        if spring0 is None:
                            spring0 = float(part.energy["potential_spring"][0])
                        _numerical_loss(part.energy, spring0)
                        # A Result of some series only may lack a derived series' inputs:
                        # its blocks are derived whole before the copy.
                        subset = self.settings.keep_series is not None
                        if direct or sparse or read or subset:
                            _derive(part, gearbox)
                        if not (direct or sparse):
                            lo, hi = _keep(res, part, start, kept, names)
                            if not (read or subset) and hi > lo:  # keep="last": the last only
                                _derive(res.rows(lo, hi), gearbox)
                        if not sparse:
                            for o in observers:
                                o.samples(part, start)
                    if outcome.error is not None:
                        raise outcome.error
                    if bar is not None:
                        bar.advance(stop - start)
                if grows:
                    per_sample = (wallclock.perf_counter() - block_started) / (stop - start)
                    chunk = _unwatched_block(per_sample, self.chunk)
                start = stop
        except KeyboardInterrupt:
            status = f"interrupted at step {done} (t = {done * dt:.6g} s)"
            raise
        except Exception as err:
            status = f"failed at step {done} (t = {done * dt:.6g} s): {err}"
            raise
        finally:
            if bar is not None:
                bar.close()
            res.metadata["wall_time_s"] = wallclock.perf_counter() - started
            final = self.finish(done, status)
            _end_all(begun, final, status)
        return final

    def finish(self, done: int, status: str) -> Result:
        """The run's Result: its status and the kept samples before ``done`` [-].

        ``status`` is ``"completed"`` or why the run stopped; the metadata records it and
        the samples simulated.
        """
        res = self.result
        res.metadata["status"] = status
        res.metadata["samples_simulated"] = done
        res.status = status
        names = self.settings.keep_series
        if names is not None:  # the series kept: views of the Result's (the others unwritten)
            poses = bool({"body_position", "body_quaternion"} & set(names))
            res = res.series_of(res.schema.only(names), poses=poses)
        if status == "completed":
            return res
        return res.truncated(int(np.searchsorted(self.kept, done)))

    @property
    def kept_names(self) -> tuple[str, ...]:
        """The series the Result keeps (``RunSettings.keep_series``; all by default)."""
        names = self.settings.keep_series
        if names is None:
            return tuple(self.result.ARRAYS)
        return tuple(self.result.schema.only(names).names)

    def _block(self, samples: int) -> Result:
        """New arrays for a block of that many samples."""
        return _allocate(
            self.gearbox,
            samples,
            self.body_names,
            self.elements,
            self.result.schema,
            self.result.slice_names,
            empty=True,
        )


def _warn_if_wound(gearbox: Gearbox, v: np.ndarray) -> None:
    """Warn (``SpringsWoundAtStart``) for each torsional spring the start speeds ``v`` twist.

    The start takes the speeds the meshes and the springs give (``Drivetrain.operating_speed``:
    a rotor's speed carries across a coupling to the generator, a ring on its torsional support
    starts at rest); only speeds given on both sides of a spring out of ratio twist it.
    """
    nv = gearbox.model.nv
    wound = []
    for spring in gearbox.springs:
        rate = float(spring.twist_row(nv) @ v)
        if abs(rate) > 1e-9 * (1.0 + float(np.abs(v).max())):
            sides = f'"{spring.joint_1}" {v[spring.v_index_1]:.6g} rad/s'
            if spring.v_index_2 is not None:
                sides += f', "{spring.joint_2}" {v[spring.v_index_2]:.6g} rad/s'
            else:
                sides += " against its parent at rest"
            wound.append(f'"{spring.name}" ({sides}: twisting at {rate:.6g} rad/s)')
    if wound:
        warnings.warn(
            SpringsWoundAtStart(
                "the initial speeds differ across the torsional spring"
                + ("s " if len(wound) > 1 else " ")
                + "; ".join(wound)
                + ": each winds up from t = 0, a start-up transient in the speeds and the mesh "
                "forces at the spring's own frequency; give one speed per train (the others "
                "follow the ratios and springs) for a steady start"
            ),
            stacklevel=user_stacklevel(),
        )


def _static_start(
    gearbox: Gearbox,
    stepper: CompiledStepper,
    torque_loads: list[JointLoad],
    drivers: list[JointLoad],
    elements: LoadElements,
    dt: float,
) -> dict[str, object]:
    """Moves the stepper's start to static equilibrium under the loads of t = 0.

    When the whole load at once does not converge, the start is taken again from the
    undeflected pose with the torques in ``EQUILIBRIUM_LOAD_STEPS`` equal steps (a continuation).

    Returns what ``metadata["initial_deflection"]`` records: iterations (over every attempt),
    whether it converged, the load steps of the last attempt, the largest joint displacement
    [rad or m], the flank switches and the last linear solve's relative residual. Warns
    (``EquilibriumNotReached``) when it did not converge; raises ``StaticStartDiverged`` when it
    is not even settling (``EQUILIBRIUM_DIVERGED``).
    """
    nv = gearbox.model.nv
    torque, _ = _signal_table(torque_loads, 0, 1, dt, [ld.v_index for ld in torque_loads], nv)
    torque = from_ground(gearbox, roll_share(gearbox), torque)
    target, _ = _signal_table(drivers, 0, 2, dt, list(range(len(drivers))), len(drivers))
    inputs = elements.inputs(np.zeros(1))
    undeflected = stepper.save() if stepper.saves_state else None
    status = stepper.equilibrium(torque, target, inputs)
    iterations, steps = status.iterations, 1
    for n in EQUILIBRIUM_LOAD_STEPS:
        if undeflected is None or status.converged or status.correction <= EQUILIBRIUM_ROUNDING:
            break  # no start to go back to, or steps cannot help (rounding)
        stepper.restore(undeflected)
        status = stepper.equilibrium(torque, target, inputs, load_steps=n)
        iterations, steps = iterations + status.iterations, n
    settling = status.correction <= max(
        EQUILIBRIUM_DIVERGED * status.displacement, EQUILIBRIUM_ROUNDING
    )
    if not status.converged and not settling:  # NaN too
        raise StaticStartDiverged(
            status.correction,
            status.displacement,
            next(
                (n for n in gearbox.joint_names if gearbox.v_index(n) == status.largest),
                f"coordinate {status.largest}",
            ),
            steps,
        )
    if not status.converged:
        warnings.warn(
            EquilibriumNotReached(
                iterations, status.correction, status.displacement, load_steps=steps
            ),
            stacklevel=user_stacklevel(),
        )
    return {
        "iterations": int(iterations),
        "converged": bool(status.converged),
        "load_steps": int(steps),
        "displacement": float(status.displacement),
        "flank_switches": int(status.flank_switches),
        "residual": float(status.residual),
    }


def _warn_if_unbalanced(
    gearbox: Gearbox,
    torque_loads: list[JointLoad],
    speed_loads: list[JointLoad],
    elements: LoadElements,
    duration: float,
) -> None:
    """Warn when the applied torques leave a net torque along a mode nothing holds.

    Speed drivers, generators, rotors and damped bearings hold (or resist) the modes they act
    on (``dynamics/torque_balance.py``); a torque signal counts by its ``representative_torque``.
    """
    held = [ld.joint for ld in speed_loads] + elements.rotor_names
    held += [n for n in gearbox.joint_names if gearbox.model.damping[gearbox.v_index(n)] > 0.0]
    torques: dict[str, float] = {}
    averaged = any(
        isinstance(ld.signal, TimeSignal) and not isinstance(ld.signal, Constant)
        for ld in torque_loads
    )
    for ld in torque_loads:
        value = representative_torque(ld.signal, duration)
        if not math.isfinite(value):
            return  # the run itself reports the non-finite torque with its step
        torques[ld.joint] = torques.get(ld.joint, 0.0) + value
    for spec, name in zip(elements.generators, elements.generator_names, strict=True):
        if spec.law == _native.GeneratorLaw.constant:  # T_gen > 0 generating brakes the joint
            torques[name] = torques.get(name, 0.0) - spec.torque
        else:  # a law whose torque grows with the speed holds the train at some speed
            held.append(name)
    for imbalance in imbalances(gearbox, torques, held=held, averaged=averaged):
        warnings.warn(TorquesUnbalanced(imbalance.text()), stacklevel=user_stacklevel())


def _end_all(observers: list[RunObserver], final: Result, status: str) -> None:
    """Ends every observer, even when one raises (a log is always closed).

    Then raises the first error, unless the run itself failed (its own error is the one to
    report).
    """
    errors = []
    for o in observers:
        try:
            o.end(final, status)
        except Exception as err:
            errors.append(err)
    if errors and status == "completed":
        raise errors[0]


def observers_of(observer: RunObserver | Sequence[RunObserver] | None) -> list[RunObserver]:
    """The observers given as None, one, or a sequence, as a list."""
    if observer is None:
        return []
    if all(hasattr(observer, m) for m in ("begin", "samples", "end")):
        return [observer]  # type: ignore[list-item]  # one observer
    return list(observer)  # type: ignore[arg-type]  # a sequence of them


def _unwatched_block(per_sample: float, least: int) -> int:
    """Samples of the next block of a run no observer watches [-].

    About ``UNWATCHED_BLOCK_S`` at ``per_sample`` [s] a sample, between ``least`` (the run's
    chunk) and ``UNWATCHED_BLOCK_MAX``.
    """
    if per_sample <= 0.0:
        return UNWATCHED_BLOCK_MAX
    return int(min(UNWATCHED_BLOCK_MAX, max(least, UNWATCHED_BLOCK_S / per_sample)))


def _numerical_loss(energy: dict[str, np.ndarray], spring0: float) -> None:
    """Fills ``numerical`` of a block [J], the integrator's own loss.

    It is the stored energy's change that no force's work and no change of stiffness explains:
    W_parametric − (U_spring − U_spring(t=0) + W_springs).
    """
    energy["numerical"][:] = energy["work_parametric"] - (
        energy["potential_spring"] - spring0 + energy["work_springs"]
    )


def _derive(block: Result, gearbox: Gearbox) -> None:
    """Fills the series computed in Python (``Series.derive``) of a block, in place."""
    for s in block.schema.series:
        if s.derive is not None:
            getattr(block, s.name)[...] = s.derive(block, gearbox)


#: Bytes of kept samples above which ``keep="auto"`` keeps every N-th sample only.
KEEP_BUDGET = 512 * 2**20


def _bytes_per_sample(
    gearbox: Gearbox, body_names: list[str], elements: LoadElements, slices: list[str]
) -> int:
    """Bytes a Result holds per sample (float64 arrays of every series and energy term)."""
    shapes = _sample_shapes(_names(gearbox, body_names, elements, slices), series.current())
    return 8 * sum(math.prod(shape) for shape in shapes.values())


def _keep_stride(keep: str | int, samples: int, per_sample: int) -> int:
    """Every how many samples the Result keeps one (``simulate``'s ``keep``)."""
    if keep == "all":
        return 1
    if keep == "last":
        return max(samples, 1)
    if keep == "auto":
        return max(1, math.ceil(samples * per_sample / KEEP_BUDGET))
    if isinstance(keep, int) and not isinstance(keep, bool) and keep >= 1:
        return keep
    raise InputError(
        f'keep is {keep!r}; give "all", "auto", "last" or a whole number N ≥ 1 (every N-th sample)'
    )


def _kept_samples(samples: int, stride: int) -> np.ndarray:
    """Indices of the kept samples: every stride-th from 0, and the last.

    Only the last when the stride spans the run.
    """
    if stride >= samples:
        return np.arange(max(samples - 1, 0), samples)
    kept = np.arange(0, samples, stride)
    if samples and kept[-1] != samples - 1:
        kept = np.append(kept, samples - 1)
    return kept


def _keep(
    res: Result, block: Result, start: int, kept: np.ndarray, names: Iterable[str]
) -> tuple[int, int]:
    """Copies the kept samples of a block (samples start … start + len(block) − 1) into res.

    Copies the series ``names`` and the energy terms. Returns the rows lo:hi of res that they
    fill.
    """
    lo, hi = (int(i) for i in np.searchsorted(kept, [start, start + len(block)]))
    if hi == lo:
        return lo, hi
    picked = kept[lo:hi] - start
    step = int(picked[1] - picked[0]) if hi - lo > 1 else 1
    rows: slice | np.ndarray = picked
    if np.all(np.diff(picked) == step):  # every N-th sample: a strided copy, twice as fast
        rows = slice(int(picked[0]), int(picked[-1]) + 1, step)
    for name in names:
        getattr(res, name)[lo:hi] = getattr(block, name)[rows]
    for name, values in block.energy.items():
        res.energy[name][lo:hi] = values[rows]
    return lo, hi


def _mesh_metadata(setup: MeshSetup) -> dict[str, dict]:
    """How each mesh was modelled in a run, for the log's metadata (SI units)."""
    out: dict[str, dict] = {m.name: {"type": "rigid"} for m in setup.meshes}
    for spec in setup.compliant:
        mesh, c = setup.compliance(spec)
        out[mesh.name] = {
            "type": "compliant",
            "single_pair_stiffness": single_pair(mesh),
            "mean_stiffness": spec.stiffness,
            "variation": "table" if c.pair_stiffness is not None else c.variation,
            "damping": spec.damping,
            "damping_ratio": c.damping_ratio if c.damping is None else None,
            "backlash": spec.backlash,
            "friction_coefficient": (
                spec.friction if c.friction_law == "constant" else c.friction_law
            ),
            "position_error_offsets": [spec.tangential_offset, spec.radial_offset],
            "slices": c.slice_number,
        }
        if spec.slices > 1:
            # the face position of each slice column (MeshSetup.slice_names): its centre from
            # the face centre along gear A's axis [m]
            out[mesh.name]["slice_positions"] = [float(z) for z in spec.slice_offset]
        if c.slice_rule is not None:
            # slices="auto": the rule's inputs (pinwind.gears.face_load.slice_count).
            out[mesh.name]["slice_rule"] = {
                "misalignment": c.slice_rule[0],
                "deflection": c.slice_rule[1],
                "line_load": AUTO_LINE_LOAD,
            }
        if c.friction_law != "constant" and c.oil is not None:
            out[mesh.name]["friction_data"] = {
                "oil_grade": c.oil.grade,
                "oil_temperature": c.oil.temperature,
                "dynamic_viscosity": c.oil.dynamic_viscosity(),
                "roughness": c.roughness,
                "base_oil": c.base_oil,
            }
    return out


#: Likely causes of a run whose speeds become absurd, for the message.
DIVERGENCE_CAUSES = (
    "Likely causes: a load whose torque grows with the speed (a generator law with a negative "
    "gain or slope), negative damping, or a torque with nothing to hold the speed (no "
    "generator load or speed driver)"
)


def _diverged(absurd: tuple[int, str], dt: float) -> Diverged:
    k, what = absurd
    return Diverged(k, k * dt, what, cause=DIVERGENCE_CAUSES)


def _driven_too_fast(
    drivers: Sequence[Any], target: np.ndarray, start: int, stop: int, dt: float
) -> tuple[int, SpeedOutOfRange] | None:
    """(new stop, error) when a speed driver asks for more than ``MAX_PLAUSIBLE_SPEED``.

    ``target`` holds the driver speeds at t_start … t_stop (rows) [rad/s]; step k asks for
    t_(k+1). A driver at 1e30 rpm (``--speed-sine sun=10,1e30,1``) never returned from the
    compiled step: it is stopped before the step that asks for it, as a non-finite speed is.
    """
    if not len(drivers) or not target.size:
        return None
    over = np.flatnonzero((np.abs(target) > MAX_PLAUSIBLE_SPEED).any(axis=1))
    if not over.size or max(start + int(over[0]) - 1, 0) >= stop:
        return None
    row = int(over[0])
    k = start + row
    column = int(np.argmax(np.abs(target[row])))
    value = float(target[row, column])
    return max(k - 1, 0), SpeedOutOfRange(
        f'speeds["{drivers[column].joint}"] is {value:.4g} rad/s ({value * 30 / math.pi:.4g} '
        f"rpm) at t = {k * dt:.6g} s, beyond the {MAX_PLAUSIBLE_SPEED:.0e} rad/s a gear can "
        f"turn at (the run stopped before step {max(k - 1, 0)}); give a lower speed"
    )


def _signal_error(where: str, load: JointLoad, k: int, dt: float, value, unit: str) -> InputError:
    """The error for a torque or speed function that raised or returned a non-finite value."""
    if isinstance(value, Exception):
        step = max(k - 1, 0) if where == "speeds" else k
        return InputError(
            f'{where}["{load.joint}"] raised {type(value).__name__}: {value} at t = {k * dt:.6g} '
            f"s (step {step}); fix the function. The samples before step {step} are kept"
        )
    if where == "speeds":  # step k − 1 asks for the speed at t_k
        return NonFiniteInput(
            f'speeds["{load.joint}"] is {value} rad/s at t = {k * dt:.6g} s; the speed function '
            f"must return finite values (the run stopped before step {max(k - 1, 0)})"
        )
    return NonFiniteInput(
        f'{where}["{load.joint}"] is {value} {unit} at step {k} (t = {k * dt:.6g} s); the '
        "torque function must return finite values"
    )


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

    def advance(self, steps: int) -> None:
        self._progress.advance(self._task, steps)

    def close(self) -> None:
        self._progress.stop()
