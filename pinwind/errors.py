"""Errors and warnings raised by pinwind.

Every error keeps the offending values as attributes and its message says what is wrong and how to
fix it. Library errors (XML parser, Pinocchio, proxsuite, mcap, rerun) are wrapped in these with
``raise ... from err`` so that users never have to read a traceback from deep inside a dependency.
"""

from __future__ import annotations

from collections.abc import Iterable


class PinwindError(Exception):
    """Base class of every error pinwind raises on purpose."""


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


class ImplausibleGear(PinwindWarning):
    """A gear's mass or inertia is far from the steel cylinder its teeth and face width imply."""


# --- run inputs --------------------------------------------------------------------------------


class InputError(PinwindError):
    """An argument of a run (torques, speeds, dt, duration, ...) is invalid."""


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


class InvalidLogRate(InputError):
    """A log rate that is not positive, or above the sample rate 1/dt."""


class ConflictingInputs(InputError):
    """Two inputs contradict each other (one joint given twice, ...)."""


class InvalidGearTrain(InputError):
    """Builder arguments describe a gear train that cannot exist (teeth, module, layout)."""


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


# --- running -----------------------------------------------------------------------------------


class SolverFailed(PinwindError):
    """proxsuite did not solve the constrained-dynamics QP of a step."""

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
