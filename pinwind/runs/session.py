"""A run held open and stepped from outside: the session a co-simulation master drives.

``Session(gearbox, scenario, inputs=["torque.carrier", "torque.sun"])`` prepares the scenario's
run (``dynamics/simulate.prepare``) with the named inputs left open: each is a held,
piecewise-constant signal whose value ``advance`` sets. ``advance(t_next, values)`` steps the
compiled loop to ``t_next`` and returns the outputs at ``t_next`` (speeds, angles, joint torques,
mesh and bearing loads, by name).

Timing (the one rule, exact and tested against ``simulate``): sample k of a run records the
state at t_k and the forces of the solve at t_k, then steps to t_{k+1} with the loads of t_k.
A session records sample 0 with the inputs' start values when it opens; ``advance(t_next, u)``
then steps samples k_prev + 1 … k_next with u held, so that its outputs are those of sample
k_next: the state at t_next, and the forces at t_next under u. It equals ``simulate`` with
the input signal u_i on (t_{i−1}, t_i] (value at t_0 the start value) at every sample.

Inputs are ``torque.JOINT`` [N·m] (replacing the scenario's torque on that joint),
``speed.JOINT`` [rad/s] (a speed driver) and ``wind`` [m/s] (the rotors'). A step asks for a
driver's speed at its end, which the master has not given yet at a communication point: a held
speed u applies one sample later than a torque, from sample k_prev + 2 (the step from k_prev + 1
takes the driver from the old speed to u), and equals ``simulate`` with u on
(t_{i−1} + dt, t_i + dt] (tested).
A communication step must be a whole number of internal steps dt (``StepNotOnGrid`` names the
nearest ones).

``state()`` / ``restore(state)``: the compiled stepper saves its state (``cpp/stepper.hpp``
StepperState: q, v, the generalized-α memory, the energy ledger, every element's internal
states: contact flanks, bearing rows' contacts, generator fluxes, pitch controller, torque
predictions; the solver's factorisations and warm start) in a copy of the model's size, and
takes it back: ``restore`` steps nothing again (``samples_stepped``), whatever the state's time,
and the next ``advance`` repeats the first bit for bit (the same compiled code on the same
numbers). A model with an element whose kind keeps no copy (``saves_state`` False) falls back
to a replay: the inputs of each communication step, stepped again from t = 0. A state from
another session is refused (``ForeignState``).

The log: ``log=PATH`` writes the session's samples to one MCAP file like any run (``pinwind
replay`` and ``read_log`` read it). The samples of the last ``advance`` stay out of the log
until the next ``advance`` or ``close``, so that a master may ``restore`` the state before its
last step and step again; restoring further back than that, with a log, is refused
(``RestoreBeyondLog``), and so is a state ahead of the session's time (a branch the log has
not taken).

Overhead: with every load held or constant, a block takes the torques and inputs as one row
each, computed when an input changes, the block's arrays are bound once per block length, and
the outputs are read with one index into the block's buffer (``benchmarks/session_overhead.py``).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.dynamics.result import Result
from pinwind.dynamics.run_settings import RunSettings
from pinwind.dynamics.simulate import (
    MAX_PLAUSIBLE_SPEED,
    PreparedRun,
    _derive,
    _diverged,
    _implausible,
    _numerical_loss,
    prepare,
)
from pinwind.dynamics.support_springs import from_ground, roll_share
from pinwind.errors import (
    ForeignState,
    InputError,
    NonFiniteInput,
    PinwindError,
    RestoreBeyondLog,
    SessionClosed,
    StepNotOnGrid,
    UnknownSessionName,
)
from pinwind.loads.hub_loads import COMPONENTS, HubLoad
from pinwind.loads.inputs import JointLoad
from pinwind.loads.signals import Constant, Signal
from pinwind.model.gearbox import Gearbox
from pinwind.runs.scenario import Scenario

#: Input kinds: name prefix → unit (``hub.BODY.force_x`` … in N, ``hub.BODY.moment_x`` … in N·m).
INPUT_KINDS = {"torque": "N*m", "speed": "rad/s", "wind": "m/s", "hub": "N or N*m"}

#: The series an output can name (``SERIES.ELEMENT``), with every joint's, mesh's, ... value.
#: Three-component series (bearing forces) are named ``SERIES.ELEMENT.x`` (y, z).
#: The bearings' default outputs are their force in world axes (``bearing_force``, computed in
#: the step loop); the radial and axial loads (``bearing_radial``, ``bearing_axial``) are
#: computed in Python from it and cost ~0.1 ms per communication point when asked for.
DEFAULT_OUTPUT_SERIES = (
    "speed",
    "angle",
    "torque",
    "mesh_normal",
    "bearing_force",
    "generator_torque",
    "rotor_torque",
)

#: Samples the log gets per chunk from a session (``simulate.MIN_CHUNK``).
LOG_CHUNK = 1000


class HeldInput(Signal):
    """A value held until it is set again: a session's open input (piecewise constant).

    ``values`` gives ``previous`` at the samples before ``since`` and ``value`` from it on;
    the session sets them (``hold``) before it steps the samples it holds over.

    Args:
        name: the input's name.
        value: its start value [SI].
        dt: the run's step [s]: times are read as samples k = t / dt.
        delay: samples after a communication step's first one at which a new value applies
            (1 for a speed driver: its step asks for the speed at the step's end).
    """

    def __init__(self, name: str, value: float, *, dt: float, delay: int = 0):
        self.name = name
        self.value = self.previous = float(value)
        self.since = 0
        self.dt = dt
        self.delay = delay

    def hold(self, value: float, first: int) -> None:
        """Holds ``value`` from sample ``first`` (+ ``delay``); the samples before keep theirs."""
        self.previous, self.value, self.since = self.value, float(value), first + self.delay

    def values(self, t: np.ndarray) -> np.ndarray:
        """The held value at each time [the input's unit]."""
        k = np.rint(np.asarray(t, dtype=float) / self.dt)
        return np.where(k >= self.since, self.value, self.previous)

    def spec(self) -> dict[str, Any]:
        """``{"type": "held", "input": name}``: set by the master, not a formula."""
        return {"type": "held", "input": self.name}

    @property
    def description(self) -> str:
        """Says that the master sets it."""
        return f"held input {self.name!r} (set by the co-simulation master)"


@dataclass(frozen=True, eq=False)
class SessionState:
    """Where a session is: enough to step it again to the same numbers (``Session.restore``).

    Attributes:
        sample: the next sample to step (samples before it are final) [-].
        held: each open input's (name, value, previous value, sample its value holds from).
        outputs: the outputs at the state's time, (name, value) [SI].
        start: the inputs' start values (sample 0).
        session: the number of the session that saved it (a session restores only its own).
        model: that session's model name, for the message refusing another's.
        point: the number of its communication point in the session (a log's check).
        compiled: the compiled run's state (``_native.StepperState``: q, v, the generalized-α
            memory, the energy ledger, every element's internal states, the solver's), of the
            model's size; None for a model with an element whose kind keeps no copy, whose
            state is then ``history``.
        history: without ``compiled``, each communication step so far as (its last sample, the
            inputs held over it), stepped again from t = 0 by ``restore``; else None.
    """

    sample: int
    held: tuple[tuple[str, float, float, int], ...]
    outputs: tuple[tuple[str, float], ...]
    start: tuple[tuple[str, float], ...]
    session: int
    model: str
    point: int
    compiled: Any = None
    history: tuple[tuple[int, tuple[tuple[str, float], ...]], ...] | None = None

    @property
    def inputs(self) -> dict[str, float]:
        """The inputs held last (the start values before any step)."""
        return {name: value for name, value, _, _ in self.held}


#: Numbers of sessions and of communication points (SessionState.session, point).
_SESSIONS = itertools.count(1)
_POINTS = itertools.count(1)


class Session:
    """A run of a gearbox held open, stepped by ``advance`` (module docstring).

    Args:
        gearbox: the model (``pinwind.load``).
        scenario: the run's loads, laws, dt and duration (``runs/scenario.py``); its duration is
            the session's end: ``advance`` refuses times after it. Default ``Scenario()``.
        inputs: the open inputs, ``torque.JOINT``, ``speed.JOINT`` or ``wind``.
        start: start values of the inputs (sample 0); default the scenario's value at t = 0 of
            what the input replaces, else 0.
        outputs: the outputs ``advance`` returns (``SERIES.ELEMENT``); default every element's
            value of ``DEFAULT_OUTPUT_SERIES``. ``available_outputs`` lists the choices.
        log: MCAP file the session writes (``runs/run.log_path`` rules), or None.
        overwrite: replace an existing log.

    Raises:
        UnknownSessionName: an input or output the model does not have (the message lists them).
        InputError: as ``simulate`` for the scenario's values.
    """

    def __init__(
        self,
        gearbox: Gearbox,
        scenario: Scenario | None = None,
        *,
        inputs: Sequence[str] = (),
        start: Mapping[str, float] | None = None,
        outputs: Sequence[str] | None = None,
        log: str | os.PathLike | bool | None = None,
        overwrite: bool = False,
    ):
        self.gearbox = gearbox
        self.scenario = scenario if scenario is not None else Scenario()
        self.dt = float(self.scenario.dt)
        self.input_names = list(dict.fromkeys(inputs))
        self._check_inputs()
        given = dict(start or {})
        for name in given:
            if name not in self.input_names:
                raise UnknownSessionName("start value", name, self.input_names)
        self._start = tuple(
            (n, _finite(n, given.get(n, self._scenario_value(n)))) for n in self.input_names
        )
        self._history: list[tuple[int, tuple[tuple[str, float], ...]]] = []
        self._id = next(_SESSIONS)
        #: Samples the compiled loop has stepped, each once however often: a restore costs none
        #: with compiled states, every sample to the state's time when it replays (``restore``).
        self.samples_stepped = 0
        self._held = self._held_inputs()
        self._run = self._prepare()
        self._saves = self._run.stepper.saves_state
        self.output_names = list(outputs) if outputs is not None else self._default_outputs()
        self._outputs = [self._output_getter(n) for n in self.output_names]
        wanted = {series for series, _, _ in self._outputs}
        # per series, the flat indices of its outputs in one sample (outputs() gathers them)
        groups: dict[str, list[tuple[str, int]]] = {}
        for name, (series_name, index, component) in zip(
            self.output_names, self._outputs, strict=True
        ):
            flat = index if component is None else 3 * index + component
            groups.setdefault(series_name, []).append((name, flat))
        self._gather = [(k, [f for _, f in v]) for k, v in groups.items()]
        self._gather_names = [n for v in groups.values() for n, _ in v]
        schema = self._run.result.schema
        self._derived = [s for s in schema.series if s.derive is not None and s.name in wanted]
        self._buffers: dict[int, Result] = {}
        # per block length: its buffer and the flat offsets of the outputs at its last sample
        self._gathers: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._observers: list[Any] = []
        self.log_path = None
        if log is not None and log is not False:
            from pinwind.io.log_writer import McapLogger
            from pinwind.runs.run import describe_call, log_path

            self.log_path = log_path(log, gearbox.name)
            self._observers.append(
                McapLogger(
                    self.log_path,
                    overwrite=overwrite,
                    command=describe_call(gearbox, {"session_inputs": self.input_names}),
                )
            )
        self._pending: tuple[int, Result] | None = None  # the last advance's block, not logged
        self._log_block: Result | None = None
        self._log_rows = 0
        self._chunk_first = 0
        self._logged = 0  # samples handed to the log (or queued for it): before this, final
        self._spring0: float | None = None
        self.closed = False
        for o in self._observers:
            o.begin(gearbox, self._run.result)
        self._sample = 0
        self._now = self._step(0, 1)
        # the communication point the session is at and the one before the last advance
        self._point: int = next(_POINTS)
        self._before: int | None = None

    # --- set-up --------------------------------------------------------------------------------

    def _check_inputs(self) -> None:
        joints = [j for j in self.gearbox.joint_names if j not in self.gearbox.locked_joints]
        choices = [f"{kind}.{j}" for kind in ("torque", "speed") for j in joints]
        if self.scenario.rotors:
            choices.append("wind")
        model = self.gearbox.model
        bodies = [model.frames[f].name for f in self.gearbox.body_frames()]
        choices += [f"hub.{b}.{c}" for b in bodies for c in COMPONENTS]
        for name in self.input_names:
            if name not in choices:
                raise UnknownSessionName("input", name, choices)

    def _held_inputs(self) -> dict[str, HeldInput]:
        """The open inputs at their start values (a speed's new value one sample later)."""
        return {
            n: HeldInput(n, v, dt=self.dt, delay=1 if n.startswith("speed.") else 0)
            for n, v in self._start
        }

    def _scenario_value(self, name: str) -> float:
        kind, _, joint = name.partition(".")
        if kind == "hub":
            body, _, component = joint.partition(".")
            for load in self.scenario.hub_loads:
                if load.body == body:
                    return float(
                        load.values(np.zeros(1), check=False)[0, COMPONENTS.index(component)]
                    )
            return 0.0
        given: Any = {"torque": self.scenario.torques, "speed": self.scenario.speeds}.get(kind, {})
        value = self.scenario.wind if kind == "wind" else given.get(joint)
        if value is None:
            return 0.0
        return float(value(0.0)) if callable(value) else float(value)

    def _prepare(self) -> PreparedRun:
        """The scenario's run with the open inputs replaced by the held signals, at sample 0."""
        s = self.scenario
        torques = dict(s.torques)
        speeds = dict(s.speeds)
        wind = s.wind
        hub_loads = list(s.hub_loads)
        for name, held in self._held.items():
            kind, _, joint = name.partition(".")
            if kind == "torque":
                torques[joint] = held
                speeds.pop(joint, None)
            elif kind == "speed":
                speeds[joint] = held
                torques.pop(joint, None)
            elif kind == "hub":
                hub_loads = _hold_hub_component(hub_loads, joint, held)
            else:
                wind = held
        scenario = dataclasses.replace(
            s, torques=torques, speeds=speeds, wind=wind, hub_loads=tuple(hub_loads)
        )
        train = scenario.drivetrain(self.gearbox)
        settings = RunSettings(keep="last", initial_deflection=s.initial_deflection)
        if s.integrator is not None:
            settings = dataclasses.replace(settings, integrator=s.integrator)
        self._plan = _plan(train.torques, train.rows)
        metadata = {"session": {"inputs": self.input_names, "start": dict(self._start)}}
        run = prepare(train, duration=s.duration, dt=self.dt, settings=settings, metadata=metadata)
        # Every load held or constant: the compiled loop takes one row of torques and inputs
        # per block, set when the inputs change (_held_arrays), instead of a row per sample.
        elements = run.elements
        self._fast = (
            self._plan is not None
            and (elements.wind is None or _constant(elements.wind) is not None)
            and all(_constant(c) is not None for h in elements.hub_loads for c in h.components)
        )
        self._share = roll_share(run.gearbox)
        self._held_key: tuple[float, ...] | None = None
        self._targets: dict[int, np.ndarray] = {}
        return run

    def _default_outputs(self) -> list[str]:
        res = self._run.result
        names = []
        for s in res.schema.series:
            if s.name in DEFAULT_OUTPUT_SERIES:
                three = s.shape(1)[1:] == (3,)
                for e in res.names(s.family):
                    names += [f"{s.name}.{e}.{c}" for c in "xyz"] if three else [f"{s.name}.{e}"]
        # an input's own value is not also an output (torque.JOINT is both a series and an input)
        return [n for n in names if n not in self.input_names]

    @property
    def available_outputs(self) -> dict[str, str]:
        """Every output a session of this model can give, name → unit."""
        res = self._run.result
        out: dict[str, str] = {}
        for s in res.schema.series:
            if s.family in ("run", "body"):
                continue
            shape = s.shape(1)
            for i, e in enumerate(res.names(s.family)):
                unit = res.unit(s, i)
                if len(shape) == 1:
                    out[f"{s.name}.{e}"] = unit
                elif shape[1:] == (3,):
                    out.update({f"{s.name}.{e}.{c}": unit for c in "xyz"})
        return out

    def input_unit(self, name: str) -> str:
        """The unit of an input (SI)."""
        kind, _, rest = name.partition(".")
        if kind == "hub":
            return "N" if rest.partition(".")[2].startswith("force") else "N*m"
        return INPUT_KINDS[kind]

    def _output_getter(self, name: str):
        available = self.available_outputs
        if name in self.input_names:
            raise InputError(
                f'"{name}" is an input of the session; an output of the same name would carry '
                "the input's own value: leave it out of the outputs"
            )
        if name not in available:
            raise UnknownSessionName("output", name, list(available))
        # element names may hold dots themselves (a bearing row's "shaft.A")
        series_name, _, element = name.partition(".")
        res = self._run.result
        series = res.schema[series_name]
        component = None
        if series.shape(1)[1:] == (3,):
            element, _, axis = element.rpartition(".")
            component = "xyz".index(axis)
        index = res.names(series.family).index(element)
        return series_name, index, component

    # --- stepping ------------------------------------------------------------------------------

    @property
    def time(self) -> float:
        """The time of the last sample recorded: the last communication point [s]."""
        return (self._sample - 1) * self.dt

    def _step(self, start: int, stop: int) -> dict[str, float]:
        """Steps samples [start, stop) with the held values; returns the outputs at stop − 1.

        The block is a buffer the session steps into again (one per block length): the log
        has copied the previous block's samples (``_commit``) before it is overwritten.
        """
        run = self._run
        if self._observers:
            self._commit()
        block = self._buffers.get(stop - start)
        if block is None:
            block = self._buffers[stop - start] = run._block(stop - start)
            self._gathers[stop - start] = _last_sample_offsets(block, self._gather)
        if self._fast:
            done, error = self._step_held(start, stop, block)
        else:
            outcome = run.step_block(start, stop, block, held=self._held_rows(start, stop))
            done, error = outcome.done, outcome.error
        self.samples_stepped += done - start
        if error is not None:
            self._sample = done
            raise error
        if self._spring0 is None:
            self._spring0 = float(block.energy["potential_spring"][0])
        self._sample = stop
        if self._observers:
            self._pending = (start, block)
        if self._derived:  # the outputs' series computed in Python: at the last sample only
            _derive_last(block, run.gearbox, self._derived)
        root, offsets = self._gathers[stop - start]
        return dict(zip(self._gather_names, root[offsets].tolist(), strict=True))

    def _step_held(self, start: int, stop: int, block: Result) -> tuple[int, BaseException | None]:
        """``PreparedRun.step_block`` for loads all held or constant.

        The compiled loop takes the torques and inputs as one row each (``_held_arrays``), the
        block's arrays bound once. Returns the samples final and the error that stopped the
        block, or None.
        """
        torque, inputs = self._held_arrays(start)
        stepper = self._run.stepper
        error: BaseException | None = None
        try:
            done = stepper.run_held(
                start, stop, torque, self._driver_rows(start, stop), stepper.outputs(block), inputs
            )
        except PinwindError as err:
            done, error = getattr(err, "samples", start), err
        speeds = block.speed[: done - start]
        if speeds.size and not np.abs(speeds).max() < MAX_PLAUSIBLE_SPEED:
            absurd = _implausible(block, np.arange(start, done))
            if absurd is not None:
                diverged = _diverged(absurd, self.dt)
                diverged.__cause__ = error
                return absurd[0], diverged
        return done, error

    def _held_arrays(self, start: int) -> tuple[np.ndarray, np.ndarray]:
        """The applied torques (1, nv) [N·m] and elements' inputs (1, columns) held from ``start``.

        Computed again only when a held value changed.
        """
        key = tuple(h.value for h in self._held.values())
        if key != self._held_key:
            torque_plan, _ = self._plan  # type: ignore[misc]  # _fast: a plan
            run = self._run
            torque = np.zeros((1, run.gearbox.model.nv))
            for index, value in torque_plan:
                torque[0, index] += value.value if isinstance(value, HeldInput) else value
            torque = np.ascontiguousarray(from_ground(run.gearbox, self._share, torque))
            inputs = run.elements.inputs(np.array([start * self.dt]))
            if inputs is None:
                inputs = np.zeros((1, run.stepper.input_columns))
            self._held_now = (torque, np.ascontiguousarray(inputs, dtype=float))
            self._held_key = key
        return self._held_now

    def _driver_rows(self, start: int, stop: int) -> np.ndarray:
        """The driver speeds at t_start … t_stop (stop − start + 1, drivers) [rad/s]."""
        _, driver_plan = self._plan  # type: ignore[misc]  # _fast: a plan
        rows = stop - start + 1
        if not driver_plan:
            target = self._targets.get(rows)
            if target is None:
                target = self._targets[rows] = np.zeros((rows, 0))
            return target
        return self._held_rows(start, stop)[1]  # type: ignore[index]  # a plan: rows

    def _held_rows(self, start: int, stop: int) -> tuple[np.ndarray, np.ndarray] | None:
        """The held torques (nv,) and driver speeds (start … stop, rows), or None.

        Given when every load is held or constant (the torques constant over the block); None
        when a load is another signal of time: ``step_block`` then evaluates them all.
        """
        if self._plan is None:
            return None
        torque_plan, driver_plan = self._plan
        torque = np.zeros(self.gearbox.model.nv)
        for index, value in torque_plan:
            torque[index] += value.value if isinstance(value, HeldInput) else value
        rows = stop - start + 1
        target = np.empty((rows, len(driver_plan)))
        for i, v in enumerate(driver_plan):
            if isinstance(v, HeldInput):  # its new value from sample v.since on
                target[:, i] = v.value
                target[: max(0, min(rows, v.since - start)), i] = v.previous
            else:
                target[:, i] = v
        return torque, target

    def advance(self, t_next: float, inputs: Mapping[str, float] | None = None) -> dict[str, float]:
        """Steps to ``t_next`` [s] with ``inputs`` (name → value, SI) held since the last time.

        Inputs not given keep their last value. Returns the outputs at ``t_next`` (name → value,
        SI; ``output_names``).

        Raises:
            UnknownSessionName: an input the session does not have.
            NonFiniteInput: an input that is NaN or infinite.
            StepNotOnGrid: ``t_next`` is not after the last time by a whole number of steps dt,
                or after the scenario's duration.
        """
        if self.closed:
            raise SessionClosed(self.time)
        values = {}
        for name, value in (inputs or {}).items():
            if name not in self._held:
                raise UnknownSessionName("input", name, self.input_names)
            values[name] = _finite(name, value)
        k_next = self._sample_of(t_next)
        held = tuple((n, values.get(n, h.value)) for n, h in self._held.items())
        for name, value in held:
            self._held[name].hold(value, self._sample)
        self._now = self._step(self._sample, k_next + 1)
        self._before, self._point = self._point, next(_POINTS)
        if not self._saves:  # the states are replays (restore)
            self._history.append((k_next, held))
        return dict(self._now)

    def _sample_of(self, t_next: float) -> int:
        """The sample of ``t_next``, checked: after the last, on the grid, within the run."""
        try:
            t = float(t_next)
        except (TypeError, ValueError) as err:
            raise InputError(f"t_next must be a time [s]; got {t_next!r}") from err
        if not math.isfinite(t):
            raise NonFiniteInput(f"t_next is {t} s; give a finite time")
        k = round(t / self.dt)
        last = self._sample - 1
        if abs(k * self.dt - t) > 1e-9 * max(abs(t), self.dt) or k <= last or k > self._run.steps:
            raise StepNotOnGrid(t, self.time, self.dt, self.scenario.duration)
        return k

    def outputs(self) -> dict[str, float]:
        """The outputs at the last communication point (name → value, SI)."""
        return dict(self._now)

    # --- state ---------------------------------------------------------------------------------

    def state(self) -> SessionState:
        """The session's state, for ``restore`` (a master that retries a step).

        With compiled states (every element's kind copies its own: ``saves_state``), a copy of
        the compiled run's state, of the model's size and cost whatever the time; else the
        inputs of each communication step so far, which ``restore`` steps again.
        """
        return SessionState(
            sample=self._sample,
            held=tuple((n, h.value, h.previous, h.since) for n, h in self._held.items()),
            outputs=tuple(self._now.items()),
            start=self._start,
            session=self._id,
            model=self.gearbox.name,
            point=self._point,
            compiled=self._run.stepper.save() if self._saves else None,
            history=None if self._saves else tuple(self._history),
        )

    @property
    def saves_state(self) -> bool:
        """Whether ``state`` copies the compiled run's state (else: the inputs to replay).

        With it, ``restore`` costs the same whatever the state's time.
        """
        return self._saves

    def restore(self, state: SessionState) -> None:
        """Goes back to ``state`` (from ``state()`` of this session).

        The compiled run takes back its saved state: no step is taken again, whatever the
        time (``samples_stepped`` is unchanged). Without compiled states (``saves_state``), the
        run is prepared anew and stepped again from t = 0 through the same communication steps
        with the same inputs, which reproduces the state bit for bit at a cost that grows with
        the state's time.

        Raises:
            ForeignState: a state another session saved (another model, or the same model).
            RestoreBeyondLog: the log already holds samples after the state, or, with a log,
                the state is neither the session's point nor the one before its last advance
                (a point of a branch the master discarded: the log holds another).
        """
        if self.closed:
            raise SessionClosed(self.time)
        if state.session != self._id:
            raise ForeignState((state.sample - 1) * self.dt, state.model, self.gearbox.name)
        if state.sample < self._logged or (
            self._observers and state.point not in (self._point, self._before)
        ):
            raise RestoreBeyondLog(
                state.sample * self.dt - self.dt, self._logged * self.dt - self.dt
            )
        if self._pending is not None and self._pending[0] >= state.sample:
            self._pending = None
        if state.point != self._point:
            self._point, self._before = state.point, None
        if state.compiled is not None:
            self._run.stepper.restore(state.compiled)
            for name, value, previous, since in state.held:
                h = self._held[name]
                h.value, h.previous, h.since = value, previous, since
            self._sample = state.sample
            self._now = dict(state.outputs)
            return
        self._replay(state)

    def _replay(self, state: SessionState) -> None:
        """``restore`` by stepping the run again from t = 0 (a model without compiled states)."""
        history = state.history or ()
        self._held = self._held_inputs()
        self._run = self._prepare()
        self._spring0 = None
        observers, self._observers = self._observers, []  # the replay is not logged again
        try:
            self._now = self._step(0, 1)
            for k_next, held in history:
                for name, value in held:
                    self._held[name].hold(value, self._sample)
                self._now = self._step(self._sample, k_next + 1)
        finally:
            self._observers = observers
        self._history = list(history)

    # --- the log -------------------------------------------------------------------------------

    def _commit(self) -> None:
        """Hands the pending block to the log's chunk (the full chunk to the log)."""
        if self._pending is None:
            return
        start, block = self._pending
        self._pending = None
        _numerical_loss(block.energy, self._spring0)  # type: ignore[arg-type]  # set by _step
        _derive(block, self._run.gearbox)  # every series, for the log
        n = len(block)
        at = 0
        while at < n:
            if self._log_block is None:
                self._log_block = self._run._block(LOG_CHUNK)
                self._log_rows = 0
                self._chunk_first = start + at
            take = min(n - at, LOG_CHUNK - self._log_rows)
            rows = slice(self._log_rows, self._log_rows + take)
            for name in self._log_block.ARRAYS:
                getattr(self._log_block, name)[rows] = getattr(block, name)[at : at + take]
            for name, values in block.energy.items():
                self._log_block.energy[name][rows] = values[at : at + take]
            self._log_rows += take
            at += take
            if self._log_rows == LOG_CHUNK:
                self._flush()
        self._logged = start + n

    def _flush(self) -> None:
        """Hands the log's chunk to the log."""
        if self._log_block is None or not self._log_rows:
            return
        part = self._log_block.rows(0, self._log_rows)
        for o in self._observers:
            o.samples(part, self._chunk_first)
        self._log_block = None
        self._log_rows = 0

    def close(self, status: str | None = None) -> dict[str, Any]:
        """Logs the last samples and closes the log; returns the run's metadata.

        ``status`` is what the log's end record says: by default ``"completed"`` at the
        scenario's end, else that the master closed the session and when.
        """
        if self.closed:
            return self._run.result.metadata
        self.closed = True
        if status is None:
            status = (
                "completed"
                if self._sample == self._run.samples
                else (f"closed by the master at t = {self.time:.10g} s")
            )
        if self._observers:
            self._commit()
            self._flush()
            final = self._run.finish(self._sample, status)
            for o in self._observers:
                o.end(final, status)
        return self._run.result.metadata

    def __enter__(self) -> Session:
        return self

    def __exit__(self, kind, err, tb) -> None:
        self.close(None if err is None else f"stopped at t = {self.time:.10g} s: {err}")


def _constant(signal: Any) -> HeldInput | float | None:
    """A held input, or a load's constant value [SI], or None for a signal of time."""
    if isinstance(signal, HeldInput):
        return signal
    if isinstance(signal, Constant):
        return float(signal.value)
    if isinstance(signal, (int, float)) and not isinstance(signal, bool):
        return float(signal)
    return None


def _hold_hub_component(loads: list[HubLoad], name: str, held: HeldInput) -> list[HubLoad]:
    """``loads`` with the component ``name`` (``BODY.force_x`` …) held.

    The scenario's load on the body gets that component replaced; without one, a new load at
    the body's origin in the fixed frame (loads/hub_loads.py) carries that component alone.
    """
    body, _, component = name.partition(".")
    i = COMPONENTS.index(component)
    at = next((k for k, load in enumerate(loads) if load.body == body), None)
    if at is None:
        loads = [*loads, HubLoad(body, (0.0,) * 6)]
        at = len(loads) - 1
    components = list(loads[at].components)
    components[i] = held
    return [*loads[:at], dataclasses.replace(loads[at], components=tuple(components)),
            *loads[at + 1 :]]  # fmt: skip


def _plan(torques: Sequence[JointLoad], rows: Sequence[JointLoad]):
    """Each torque's (velocity index, held input or value) and each row's, or None.

    None when one load is a signal of time other than a held input or a constant.
    """
    torque_plan = [(ld.v_index, _constant(ld.signal)) for ld in torques]
    driver_plan = [_constant(ld.signal) for ld in rows]
    if any(v is None for _, v in torque_plan) or any(v is None for v in driver_plan):
        return None
    return torque_plan, driver_plan


def _last_sample_offsets(
    block: Result, gather: list[tuple[str, list[int]]]
) -> tuple[np.ndarray, np.ndarray]:
    """The buffer every array of ``block`` views, and the outputs' offsets at its last sample.

    ``simulate._allocate`` makes every array a view of one buffer; ``gather`` gives, per
    series, the outputs' flat indices within one sample. One fancy index then reads them all.
    """
    root = block.speed
    while root.base is not None:
        root = root.base
    offsets = []
    for series_name, flat in gather:
        last = getattr(block, series_name)[-1].reshape(-1)
        first = (last.ctypes.data - root.ctypes.data) // root.itemsize
        if not 0 <= first < root.size:
            raise RuntimeError(f"series {series_name} is not a view of the block's buffer")
        offsets += [first + f * (last.strides[0] // root.itemsize) for f in flat]
    return root, np.array(offsets, dtype=np.intp)


def _derive_last(block: Result, gearbox: Gearbox, derived: list) -> None:
    """Fills the derived series ``derived`` (``Series.derive``) at the block's last sample.

    In schema order, as ``simulate._derive``; the other derived series are left unfilled.
    """
    last = block.rows(len(block) - 1, len(block))
    for s in derived:
        getattr(last, s.name)[...] = s.derive(last, gearbox)


def _finite(name: str, value: Any) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError) as err:
        raise InputError(f'input "{name}" must be a number; got {value!r}') from err
    if not math.isfinite(value):
        raise NonFiniteInput(f'input "{name}" is {value}; give a finite value (SI units)')
    return value
