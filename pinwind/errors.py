"""Errors and warnings raised by pinwind.

Every error keeps the offending values as attributes and its message says what is wrong and how to
fix it. Library errors (XML parser, Pinocchio, proxsuite, mcap, rerun) are wrapped in these with
``raise ... from err`` so that users never have to read a traceback from deep inside a dependency.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from pinwind.known_names import nearest, unknown_message


class PinwindError(Exception):
    """Base class of every error pinwind raises on purpose.

    An error survives a pickle round trip with its message and its attributes (an error in a
    worker process reaches the command as the same one line): it is rebuilt from its message
    and attributes, not by calling its ``__init__`` again with the message alone, which most
    subclasses, taking the offending values, cannot take.
    """

    def __reduce__(self) -> tuple[object, ...]:
        return (_rebuilt, (type(self), self.args, self.__dict__))


def _rebuilt(cls: type[PinwindError], args: tuple, state: dict) -> PinwindError:
    """An error of ``cls`` with these ``args`` (its message) and attributes (unpickling)."""
    err = cls.__new__(cls)
    err.args = args
    err.__dict__.update(state)
    return err


class PinwindWarning(UserWarning):
    """Base class of pinwind's warnings."""


# --- model files -------------------------------------------------------------------------------


class ModelError(PinwindError):
    """A model file is malformed or physically inconsistent.

    Attributes:
        path: the model file (or ``"<string>"``).
        element: the XML element at fault, e.g. ``'<gear name="sun">'``.
    """

    def __init__(self, path: str, element: str, message: str):
        self.path = str(path)
        self.element = element
        super().__init__(f"{self.path}: {element}: {message}")


class MalformedModel(ModelError):
    """The file is not well-formed XML or misses a required element or attribute."""


class UnknownName(ModelError):
    """An element refers to a link, joint or gear that the model does not define."""

    def __init__(self, path: str, element: str, kind: str, name: str, known: Iterable[str]):
        self.kind = kind
        self.name = name
        self.known = sorted(known)
        super().__init__(
            path,
            element,
            f'unknown {kind} "{name}"; {kind}s in this model are: '
            f"{', '.join(self.known) or 'none'}",
        )


class UnknownAttribute(ModelError):
    """An attribute (or a child element) that the element does not take: a misspelling.

    ``<bearing radial_stifness="1e9"/>`` would leave the bearing rigid without a word, so it is
    refused, naming the nearest known name (``pinwind.known_names``).

    Attributes:
        name: the attribute or element as written.
        kind: ``"attribute"`` or ``"element"``.
        known: the names the element takes.
        nearest: the known name most like it, or None.
    """

    def __init__(
        self, path: str, element: str, name: str, known: Iterable[str], *, kind: str, tag: str
    ):
        self.name = name
        self.kind = kind
        self.known = list(known)
        self.nearest = nearest(name, self.known)
        of = f" of <{tag}>" if kind == "attribute" else f" in <{tag}>"
        super().__init__(path, element, unknown_message(name, self.known, kind, of))


class InvalidGearGeometry(ModelError):
    """Teeth, module, face width or pressure angle out of range, or a mesh that cannot exist."""


class InconsistentCentreDistance(ModelError):
    """The centre distance in the model differs from the one the gear data give."""

    def __init__(
        self, path: str, element: str, actual: float, expected: float, tolerance: float, hint: str
    ):
        self.actual = actual
        self.expected = expected
        self.tolerance = tolerance
        super().__init__(
            path,
            element,
            f"centre distance in the model is {actual * 1e3:.4f} mm but teeth, module and profile "
            f"shifts give {expected * 1e3:.4f} mm (difference "
            f"{abs(actual - expected) * 1e6:.1f} µm,"
            f" tolerance {tolerance * 1e6:.1f} µm); {hint}",
        )


class NonParallelAxes(ModelError):
    """Two meshing gears (or two sprung joints) whose axes are not parallel."""


class InvalidInertia(ModelError):
    """Non-positive mass, or an inertia tensor that is not physically possible."""


class InvalidMount(ModelError):
    """Bodies and bearings that cannot work as written.

    A gear welded to a moving body, a mesh between gears on one rigid body, negative damping.
    """


class InvalidBearingRating(ModelError):
    """A bearing's ISO 281 data that give no life (``model/bearing.py``, ``life/bearing_life.py``).

    A type without an ISO 281 life exponent, a dynamic load rating C that is not a positive
    finite number, negative load factors, or a rating on a joint that is not a rolling bearing.

    Attributes:
        bearing: the joint the rating is for.
    """

    def __init__(self, bearing: str, message: str, *, path: str = "<python>"):
        self.bearing = bearing
        super().__init__(path, f'<bearing joint="{bearing}">', message)


class InvalidBearingLifeData(ModelError):
    """A bearing's life data that give no modified or reference life.

    Its lubrication, contamination, fatigue limit or internal geometry
    (``model/bearing_life_data.py``): a viscosity grade outside ISO 3448's list, a fatigue load
    limit C_u above C, a negative clearance without a preload.

    Attributes:
        attribute: the attribute at fault (``lubricant_vg``); value: its value as read.
    """

    def __init__(self, element: str, attribute: str, value: object, message: str, *, path: str):
        self.attribute = attribute
        self.value = value
        super().__init__(path, element, message)


class InvalidBearingFriction(ModelError):
    """A bearing's friction data that give no friction moment (``model/bearing_friction_data.py``).

    A friction model name pinwind does not know, a factor or load that is not a finite number
    ≥ 0, or a bearing with friction but no size (its mean diameter).

    Attributes:
        attribute: the attribute at fault (``friction_model``); value: its value as read.
    """

    def __init__(self, element: str, attribute: str, value: object, message: str, *, path: str):
        self.attribute = attribute
        self.value = value
        super().__init__(path, element, message)


class InvalidBearingCompliance(ModelError):
    """A compliant bearing's stiffness, damping or clearance that is negative or not a number.

    Attributes:
        bearing: the joint of the bearing.
        attribute: the attribute at fault (``radial_stiffness``).
        value: its value as read.
    """

    def __init__(self, bearing: str, attribute: str, value: float, message: str, *, path: str):
        self.bearing = bearing
        self.attribute = attribute
        self.value = value
        super().__init__(path, f'<bearing joint="{bearing}">', message)


class InvalidSupport(ModelError):
    """A support's mount or tower-mode value that is negative, zero or not a number.

    A mount's stiffness or damping, a tower mode's frequency, modal mass or damping ratio.

    Attributes:
        housing: the support's housing link.
        attribute: the attribute at fault (``stiffness_roll``, ``vertical mass``).
        value: its value as read.
    """

    def __init__(self, housing: str, attribute: str, value: float, message: str, *, path: str):
        self.housing = housing
        self.attribute = attribute
        self.value = value
        super().__init__(path, f'<support housing="{housing}">', message)


class UnheldMember(ModelError):
    """A floating member that nothing holds: a motion no mesh, spring or row resists.

    Attributes:
        bearing: the floating bearing's joint.
        motion: joint coordinate → its part of the free motion (unit vector) [m or rad].
    """

    def __init__(self, bearing: str, motion: dict[str, float], message: str, *, path: str):
        self.bearing = bearing
        self.motion = motion
        super().__init__(path, f'<bearing joint="{bearing}">', message)


class ImplausibleGear(PinwindWarning):
    """A gear's mass or inertia is far from the steel cylinder its teeth and face width imply."""


# --- run inputs --------------------------------------------------------------------------------


class EquilibriumNotReached(PinwindWarning):
    """The static start did not converge: the run starts from the last iterate."""

    def __init__(
        self, iterations: int, correction: float, displacement: float, load_steps: int = 1
    ):
        self.iterations, self.correction, self.displacement = iterations, correction, displacement
        self.load_steps = load_steps
        steps = f", the last try in {load_steps} load steps" if load_steps > 1 else ""
        super().__init__(
            f"the static start did not converge in {iterations} iterations{steps} (last "
            f"correction {correction:.3g} of a displacement {displacement:.3g} rad or m); the "
            "run starts there and its first samples carry some of the start-up vibration. Check "
            'the initial loads, or pass initial_deflection="none" (--initial-deflection none)'
        )


class InputError(PinwindError):
    """An argument of a run (torques, speeds, dt, duration, ...) is invalid."""


class InvalidLossInput(InputError):
    """An argument of a loss formula outside its range (``pinwind/losses/``).

    Attributes:
        argument: the argument at fault; value: its value.
    """

    def __init__(self, argument: str, value: object, message: str):
        self.argument = argument
        self.value = value
        super().__init__(f"{argument} = {value}: {message}")


class UnknownJoint(InputError):
    """A torque or speed names a joint the gearbox does not have."""

    def __init__(self, name: str, where: str, known: Iterable[str]):
        self.name = name
        self.where = where
        self.known = list(known)
        super().__init__(f'unknown joint "{name}" in {where}; joints are: {", ".join(self.known)}')


class UnknownElement(InputError):
    """A result accessor was asked for a mesh, bearing or joint the run does not have."""

    def __init__(self, kind: str, name: str, known: Iterable[str]):
        self.kind = kind
        self.name = name
        self.known = list(known)
        plural = f"{kind}es" if kind.endswith(("sh", "s")) else f"{kind}s"
        super().__init__(f'no {kind} named "{name}"; {plural} are: {", ".join(self.known)}')


class NonFiniteInput(InputError):
    """A run input is NaN or infinite."""


class UnknownSessionName(InputError):
    """A session's input, output or start value names what the model does not have."""

    def __init__(self, kind: str, name: str, known: Iterable[str]):
        self.kind = kind
        self.name = name
        self.known = list(known)
        listed = ", ".join(self.known[:40]) + (", ..." if len(self.known) > 40 else "")
        like = nearest(name, self.known)
        hint = f' (did you mean "{like}"?)' if like else ""
        super().__init__(
            f'unknown {kind} "{name}"{hint}; the session\'s {kind}s are: {listed or "(none)"}'
        )


class StepNotOnGrid(InputError):
    """A communication point that is not a later whole number of internal steps dt."""

    def __init__(self, t_next: float, t_last: float, dt: float, duration: float):
        self.t_next = t_next
        self.t_last = t_last
        self.dt = dt
        self.duration = duration
        steps = (t_next - t_last) / dt
        super().__init__(
            f"cannot advance to t = {t_next:.10g} s from t = {t_last:.10g} s: a communication "
            f"step must be a positive whole number of internal steps dt = {dt:g} s (this one is "
            f"{steps:.6g} steps) and end by the scenario's duration {duration:g} s; the nearest "
            f"valid times are {t_last + max(1, math.floor(steps)) * dt:.10g} s and "
            f"{t_last + max(1, math.ceil(steps)) * dt:.10g} s"
        )


class RestoreBeyondLog(InputError):
    """A session with a log asked to go back before samples its log already holds."""

    def __init__(self, t_state: float, t_logged: float):
        self.t_state = t_state
        self.t_logged = t_logged
        super().__init__(
            f"cannot restore the state at t = {t_state:.10g} s: the session's log already holds "
            f"the samples to t = {t_logged:.10g} s; with a log, restore at most the state before "
            "the last advance (or open the session without a log)"
        )


class SessionClosed(InputError):
    """A session was stepped after ``close``."""

    def __init__(self, t_last: float):
        self.t_last = t_last
        super().__init__(
            f"the session was closed at t = {t_last:.10g} s; open a new Session to step again"
        )


class ForeignState(InputError):
    """A session asked to restore a state that another session (or model) saved."""

    def __init__(self, t_state: float, model: str, own_model: str):
        self.t_state = t_state
        self.model = model
        super().__init__(
            f"the state at t = {t_state:.10g} s was saved by another session (of model "
            f'"{model}"; this one steps "{own_model}"): a session restores only the states '
            "its own state() gave; open the state's session, or step this one to that time"
        )


class InvalidLogRate(InputError):
    """A log rate that is not positive, or above the sample rate 1/dt."""


class ConflictingInputs(InputError):
    """Two inputs contradict each other (one joint given twice, ...)."""


class SpeedOutOfRange(InputError):
    """A linearisation asked at a speed where it does not hold.

    A speed negative or not finite, a joint faster than a gear can turn, or one where the velocity
    terms that the modes leave out act (``modes/linearisation.py``).
    """


class TableNotUtf8(InputError):
    """A CSV table whose bytes are not UTF-8 (a Latin-1 or Windows-1252 export).

    Attributes:
        path: the file.
        position: offset of the first byte that is not UTF-8 [bytes].
        byte: that byte's value.
    """

    def __init__(self, path: str, position: int, byte: int):
        self.path = str(path)
        self.position = position
        self.byte = byte
        super().__init__(
            f"{self.path}: byte {position} (0x{byte:02x}) is not UTF-8, probably a Latin-1 or "
            "Windows-1252 export; save the table as UTF-8 (Excel: CSV UTF-8) or plain ASCII"
        )


class TableStartsLate(PinwindWarning):
    """A table starts after the run does: its first value is held until its first time.

    Attributes:
        source: the table's file.
        start: the table's first time [s].
        run_start: the run's first time [s].
        value: the value held before ``start``.
    """

    def __init__(self, where: str, source: str, start: float, run_start: float, value: float):
        self.source = source
        self.start = start
        self.run_start = run_start
        self.value = value
        super().__init__(
            f"{where}: {source} starts at t = {start:g} s but the run starts at "
            f"t = {run_start:g} s; its first value {value:g} is held until then. Add a row at "
            f"t = {run_start:g} s to say what it is before"
        )


class InputFileChanged(InputError):
    """A file a logged run read (a CSV or OpenFAST table) differs from the one the log recorded.

    Attributes:
        where: the input that read it (``torque.carrier``, ``wind``).
        path: the file, as the run was given it.
        recorded: the SHA-256 and size [bytes] the log recorded, as (hex, bytes).
        current: the file's SHA-256 and size now, or None when it is missing.
    """

    def __init__(
        self, where: str, path: str, recorded: tuple[str, int], current: tuple[str, int] | None
    ):
        self.where = where
        self.path = str(path)
        self.recorded = recorded
        self.current = current
        now = (
            "is missing now"
            if current is None
            else f"is sha256 {current[0]} ({current[1]} bytes) now"
        )
        super().__init__(
            f"{where}: {self.path} has changed since the run was logged: the log recorded sha256 "
            f"{recorded[0]} ({recorded[1]} bytes), the file {now}; restore the file to "
            "repeat the run, or pass --accept-changed-inputs to run with the file as it is"
        )


class SchedulerUnreachable(InputError):
    """The Dask scheduler given to a sweep cannot be reached.

    Attributes:
        address: the address as given (``--scheduler``).
        reason: what the connection attempt said.
    """

    def __init__(self, address: str, reason: str):
        self.address = address
        self.reason = reason
        super().__init__(
            f'--scheduler "{address}": cannot reach a Dask scheduler there ({reason}); start one '
            "(dask scheduler, it listens on tcp://HOST:8786) and give its address, or leave out "
            "--scheduler to sweep on this machine's cores"
        )


class TorquesUnbalanced(PinwindWarning):
    """The applied torques leave a net torque along a gear train that nothing holds.

    The train accelerates for the whole run (``dynamics/torque_balance.py``); the message names
    the net torque, at which joint, and the torque that balances it from the model's ratio.
    """


class SpringsWoundAtStart(PinwindWarning):
    """Initial speeds that differ across torsional springs: they wind up from t = 0.

    The message names each spring, its joints and their speeds, and the start-up transient to
    expect; speeds in the ratio of the meshes and springs (one speed given) start steady.
    """


class StepTooCoarse(PinwindWarning):
    """The time step leaves too few samples in the run, or does not resolve the model's modes."""


class InvalidGearTrain(InputError):
    """Builder arguments describe a gear train that cannot exist (teeth, module, layout)."""


class PointedTeeth(InvalidGearTrain):
    """A gear's flanks meet below its tip circle: no rating method applies to such a tooth."""


class UndercutGear(PinwindWarning):
    """A rated gear is undercut: the bending ratings assume a full flank above the base circle."""


class RatingOfTransient(PinwindWarning):
    """A rating's loads and speed come from a run that accelerates at the rated sample."""


class RatingAtZeroSpeed(PinwindWarning):
    """A rating at pitch-line speed 0: the dynamic factors take their static value."""


class FactorNotInRun(InputError):
    """A load factor asked from a run that does not compute it (K_Hβ of a mesh without slices)."""


class PlanetsCollide(InvalidGearTrain):
    """Neighbouring planets' tip circles overlap."""

    def __init__(self, tip_radius: float, chord: float, planets: int, centre_distance: float):
        self.tip_radius = tip_radius
        self.chord = chord
        super().__init__(
            f"{planets} planets of tip diameter {2 * tip_radius * 1e3:.2f} mm on a "
            f"{centre_distance * 1e3:.2f} mm centre distance collide: the chord between "
            f"neighbouring planet centres is only {chord * 1e3:.2f} mm; use fewer or smaller "
            "planets"
        )


# --- fatigue life ------------------------------------------------------------------------------


class InvalidFatigueInput(InputError):
    """A fatigue input (an S-N curve, a wind site) with a parameter that cannot hold.

    Attributes:
        parameter: the parameter at fault, e.g. ``"slope exponent m"``.
        value: its value.
    """

    #: What the parameter belongs to, the message's first words.
    subject = "fatigue input"

    def __init__(self, parameter: str, value: object, requirement: str, fix: str):
        self.parameter = parameter
        self.value = value
        super().__init__(
            f"{self.subject}: {parameter} is {value!r} but must be {requirement}; {fix}"
        )


class InvalidSNCurve(InvalidFatigueInput):
    """An S-N curve parameter that cannot describe a fatigue curve."""

    subject = "S-N curve"


class InvalidWindSite(InvalidFatigueInput):
    """Wind-site data (Weibull parameters, bins, hours, turbulence) that cannot hold."""

    subject = "wind site"


class CaseFileDamaged(PinwindWarning):
    """A kept fatigue case's log or reduction is damaged (a flipped byte): the case is redone.

    The log differs from the one its reduction was made from (its SHA-256), or the reduction
    (``.npz``) fails its CRC check or cannot be read.
    """


# --- running -----------------------------------------------------------------------------------


class SolverFailed(PinwindError):
    """The constrained-dynamics QP of a step was not solved (direct Schur solve, or proxsuite)."""

    def __init__(self, step: int, time: float, status: str, detail: str = ""):
        self.step = step
        self.time = time
        self.status = status
        super().__init__(
            f"the constrained-dynamics QP failed at step {step} (t = {time:.6g} s): {status}. "
            f"{detail}".strip()
        )


class ConflictingConstraints(PinwindError):
    """Speed drivers and gear meshes ask for speeds that cannot all hold."""

    def __init__(self, step: int, time: float, residual: float, drivers: list[str]):
        self.step = step
        self.time = time
        self.residual = residual
        self.drivers = drivers
        super().__init__(
            f"at step {step} (t = {time:.6g} s) the speed drivers on {', '.join(drivers) or '-'} "
            f"conflict with the gear meshes (mismatch {residual:.3g}): these are conflicting "
            "speed drivers on one gear train. Drive one joint per train and load the others "
            "with torques."
        )


class Diverged(PinwindError):
    """The state became NaN or infinite during a run."""

    def __init__(self, step: int, time: float, what: str, cause: str = ""):
        self.step = step
        self.time = time
        self.what = what
        super().__init__(
            f"the run diverged at step {step} (t = {time:.6g} s): {what}. "
            + (f"{cause}. " if cause else "")
            + "Reduce dt, check the torques and spring stiffnesses for values that are far too "
            "large, or add damping."
        )


class StaticStartDiverged(PinwindError):
    """The static start's Newton iteration diverged (nothing was stepped).

    No start near static equilibrium lies within the model's reach under the loads of t = 0.
    """

    def __init__(self, correction: float, displacement: float, joint: str, load_steps: int):
        self.correction, self.displacement = correction, displacement
        self.joint, self.load_steps = joint, load_steps
        share = correction / displacement if displacement else math.inf
        super().__init__(
            f"the static start diverged under the loads of t = 0, even with the torques taken in "
            f"{load_steps} steps: its last correction, {correction:.3g} rad or m, is {share:.2g} "
            f'of the displacement, {displacement:.3g} rad or m (largest at joint "{joint}"), so '
            "it is not settling. The model cannot carry these loads near its pose (a torque far "
            "beyond its rating, a unit slip, a bearing or spring far too soft). Check the loads, "
            'or start undeflected with initial_deflection="none" (--initial-deflection none) to '
            "see how the run moves"
        )


class OutOfMemory(PinwindError):
    """The arrays of a run's results do not fit in memory."""

    def __init__(self, samples: int, duration: float, dt: float):
        self.samples = samples
        self.duration = duration
        self.dt = dt
        super().__init__(
            f"memory ran out allocating the results of {samples} samples (duration = "
            f"{duration:g} s at dt = {dt:g} s); shorten the duration, increase dt, or run it in "
            "several parts"
        )


class LogError(PinwindError):
    """A log file is missing, truncated, corrupted or not a pinwind log."""

    def __init__(self, path: str, message: str):
        self.path = str(path)
        super().__init__(f"{self.path}: {message}")


class LogExists(LogError):
    """The log file to write already exists (pinwind never overwrites a log silently)."""

    def __init__(self, path: str):
        super().__init__(
            path,
            "the file already exists; choose another name, or pass --force (CLI) / "
            "overwrite=True (Python) to replace it",
        )


class LogRecovered(PinwindWarning):
    """A log was cut short (crash, kill, full disk); the samples before the cut were recovered."""


class LogBeingWritten(PinwindWarning):
    """A log read while its run is still writing it: it holds the samples written so far."""


class SamplesNotLogged(LogRecovered):
    """A log's end record counts samples the run simulated that never reached the log."""


class LogTooLargeToWrite(LogError):
    """A run's log would be larger than the limit for one log or the free disk space.

    Attributes:
        log_bytes: estimated size of the log [bytes].
        limit_bytes: the limit it exceeds [bytes].
        limit: which limit (``"the limit for one log"`` or ``"the free space on its disk"``).
        result_bytes: memory of the Result the run keeps [bytes].
        samples: samples the log would hold.
        fitting_rate: a log rate [Hz] whose log would fit.
    """

    def __init__(
        self,
        path: str,
        *,
        log_bytes: float,
        limit_bytes: float,
        limit: str,
        result_bytes: float,
        samples: int,
        fitting_rate: float,
    ):
        self.log_bytes = log_bytes
        self.limit_bytes = limit_bytes
        self.limit = limit
        self.result_bytes = result_bytes
        self.samples = samples
        self.fitting_rate = fitting_rate
        rate = f" {fitting_rate:g} (log_rate=) would fit" if fitting_rate > 0 else " HZ"
        super().__init__(
            path,
            f"the log of this run would take about {log_bytes / 1e9:.3g} GB ({samples} samples), "
            f"more than {limit} ({limit_bytes / 1e9:.3g} GB); the Result kept in memory needs "
            f"{result_bytes / 1e6:.3g} MB. Log less: --log-rate{rate}, --no-log (log=None) or a "
            "shorter --duration; or write it anyway with --allow-large-log (allow_large_log=True)",
        )


class LogWriteFailed(LogError):
    """Writing a log failed during a run (disk full, file deleted): the run was stopped.

    Attributes:
        cause: what the operating system said.
        failed_at: simulation time of the first sample that could not be written [s].
        samples_logged: samples in the file, complete chunks only.
        last_time: time of the last of them [s] (NaN if none).
        kept: the file is still there (False when it was deleted during the run).
    """

    def __init__(
        self,
        path: str,
        *,
        cause: str,
        failed_at: float,
        samples_logged: int,
        last_time: float,
        kept: bool = True,
    ):
        self.cause = cause
        self.failed_at = failed_at
        self.samples_logged = samples_logged
        self.last_time = last_time
        self.kept = kept
        when = f" at t = {failed_at:.6g} s" if failed_at == failed_at else ""
        if not kept:
            holds = "the samples logged so far went with the file"
        elif samples_logged:
            holds = (
                f"the file holds the {samples_logged} samples logged before "
                f"(t ≤ {last_time:.6g} s), readable with pinwind.read_log or pinwind report"
            )
        else:
            holds = "the file holds no samples"
        super().__init__(
            path,
            f"writing the log failed{when} ({cause}), so the run was stopped; {holds}. Free "
            "some disk space or log less (--log-rate, --no-log)",
        )


class OutputFailed(PinwindError):
    """An output file (a table, a figure) could not be written; no partial file is left.

    A missing folder, a file where a folder should be, no permission, a full disk.

    Attributes:
        path: the file asked for.
        cause: what the operating system said.
    """

    #: What was being written, and what is left and how to fix it (the message's words).
    what = "the output"
    advice = "nothing was written. Give a path in an existing folder you can write to"

    def __init__(self, path: str, cause: str):
        self.path = str(path)
        self.cause = cause
        super().__init__(f"{self.path}: cannot write {self.what} ({cause}); {self.advice}")


class ExportFailed(OutputFailed):
    """A table could not be written (``pinwind export``); nothing is left at its path."""

    what = "the table"
    advice = (
        "nothing was written. Give --out a path in an existing folder you can write to, with "
        "free space"
    )


class FmuExportFailed(OutputFailed):
    """An FMU could not be written (``pinwind fmu``): PythonFMU missing or failing."""

    what = "the FMU"
    advice = "install the fmi extra (pip install 'pinwind[fmi]') and give a writable path"


class FigureFailed(OutputFailed):
    """A figure could not be written (``pinwind plot``); no partial file is left at its path."""

    what = "the figure"
    advice = (
        "the figures written before it are kept. Give --out-dir a folder you can write to, with "
        "free space"
    )


# --- checks (pinwind.testing) ------------------------------------------------------------------


class CheckFailed(PinwindError):
    """A check of ``pinwind.testing`` measured a value beyond its tolerance.

    Attributes:
        check: the check's name (``ledger_closure``, ``element_tangents``, ...).
        compared: what was compared with what, in words.
        measured: the measured value (relative unless ``compared`` says otherwise).
        tolerance: the tolerance it exceeds.
        detail: where the worst value was (sample, joint, mode) and what to look at.
    """

    def __init__(
        self, check: str, compared: str, measured: float, tolerance: float, detail: str = ""
    ):
        self.check = check
        self.compared = compared
        self.measured = measured
        self.tolerance = tolerance
        self.detail = detail
        super().__init__(
            f"{check}: {compared}: {measured:.3g} exceeds the tolerance {tolerance:.3g}"
            + (f"; {detail}" if detail else "")
        )


# --- replay --------------------------------------------------------------------------------------


class PortInUse(InputError):
    """A port that ``pinwind replay --serve`` needs is taken."""

    def __init__(self, port: int, option: str):
        self.port = port
        self.option = option
        super().__init__(
            f"port {port} ({option}) is taken, probably by another viewer or replay; stop it, "
            f"or give a free port: {option} {port + 1}"
        )


class ServeFailed(PinwindError):
    """Rerun could not start its servers."""


class NoViewer(PinwindError):
    """``pinwind replay``/``view`` cannot open the Rerun viewer: no display, or no viewer binary."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(
            f"cannot open the Rerun viewer: {reason}; write a recording with --save run.rrd "
            "(open it with `rerun run.rrd` on a machine with a display) or serve the web "
            "viewer with --serve (then open the address it prints in a browser)"
        )
