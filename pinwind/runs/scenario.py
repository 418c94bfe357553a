"""Scenarios: everything a run needs, from a TOML file, ``pinwind simulate``'s flags or Python.

A ``Scenario`` is the run's inputs built: signals, generator laws (``loads.generator.LAWS``),
rotors, wind, meshes, position errors, in SI. ``build`` makes it once from plain values (building
is the check: an error names the key and its line, or the flag) and ``run`` hands those very
objects to ``simulate``; ``pinwind simulate``, ``run``, ``run --from-log``, ``rate`` and the
sweeps all take this one path.

``pinwind run scenarios/saleh2017_rated.toml`` runs a file; ``pinwind simulate`` turns its flags
into the same values. Keys (units at the edge, like the flags; ``-`` and ``_`` are the same)::

    model = "../models/saleh2017_planetary.urdf"   # relative to the scenario file
    duration = 60.0                                # [s]
    dt = 1e-3                                      # [s]
    torque = { carrier = 1e6 }                     # [N·m]: a number or a signal (loads/signals.py)
    speed = { carrier = "sine(mean=14.2, amplitude=1, frequency=0.1)" }   # [rpm]
    initial_speed = { carrier = 12.0 }             # [rpm]
    mesh = { all = "rigid" }                       # rigid | compliant
    position_error = { planet1 = [20.0, 0.0] }     # tangential, radial [µm]
    wind = "kaimal(mean=10, turbulence_intensity=0.1, seed=1)"   # [m/s]: a number or a signal
    rho_inf = 1.0                                  # time step's spectral radius ρ∞ (1 keeps energy)
    initial_deflection = "static"                  # static (loaded at t = 0) | none (undeflected)
    out = "saleh2017_rated.mcap"                   # log (a bare name goes in logs/)
    log_rate = 100.0                               # [Hz]
    force = false                                  # replace an existing log
    no_log = false

    [generator.sun]                                # one table per joint
    law = "linear-slip"                            # constant | linear-slip | variable-speed |
    slope = 1.26e6                                 #   induction | induction-dq
    sync_rpm = 83.94

    [rotor.carrier]
    preset = "saleh2017"                           # or radius, inertia, air_density, pitch_deg,
                                                   #   cp_scale, cp_table = {tsr, cp, pitch_deg}
                                                   #   ct_table = {tsr, ct, pitch_deg},
                                                   #   performance_file (ROSCO Cp_Ct_Cq.txt)
    hub_body = "carrier"                           # thrust, weight and shear moment on this
    hub_point = [0.0, 0.0, -1.0]                   #   body at the rotor centre [m] (none
    mass = 110000                                  #   without hub_body); [kg]
    shaft_tilt_deg = 5.0                           # rotor end up
    hub_height = 90.0                              # [m], with shear_exponent (0.2: IEC NWP)

The flags say the same: ``--generator "sun=linear-slip(slope=1.26e6, sync_rpm=83.94)"``,
``--rotor carrier=saleh2017`` (or ``"carrier=rotor(radius=42.85, inertia=5e6)"``), ``--wind 10``.

Every run from a scenario or from ``pinwind simulate`` stores its values in the log's metadata
(``scenario``), with the model file itself; ``pinwind run --from-log LOG`` repeats the run bit for
bit from them. A bad scenario gets one ``ScenarioError`` naming the file, the key, its line and
the valid choices.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pinwind.errors import InputError, LogError
from pinwind.known_names import check_keys, toml_keys
from pinwind.loads.generator import LAWS, GeneratorLaw
from pinwind.loads.hub_loads import (
    COMPONENTS,
    HubFrame,
    HubLoad,
    hub_load_from_openfast,
)
from pinwind.loads.input_files import InputFile, check_unchanged
from pinwind.loads.pitch_control import PITCH_PRESETS, PitchControl
from pinwind.loads.rotor import CpTable, CtTable, HeierCp, Rotor, RotorHub, performance_tables
from pinwind.loads.signal_text import signal_from_spec
from pinwind.loads.signals import Scaled, Signal
from pinwind.units import RAD_S_PER_RPM

if TYPE_CHECKING:
    from pinwind.dynamics.drivetrain import Drivetrain
    from pinwind.dynamics.integrator import Integrator
    from pinwind.dynamics.result import Result
    from pinwind.model.gearbox import Gearbox

#: Factors of the input units that are not SI (a generator law's ``sync_rpm``).
TO_SI = {"rpm": RAD_S_PER_RPM}

#: Scenario keys → (kind, unit or choices, what it is). Their names are ``pinwind simulate``'s
#: flags with ``_`` for ``-``.
KEYS: dict[str, tuple[str, str, str]] = {
    "model": ("path", "", "model file (URDF with <gearbox>)"),
    "duration": ("number", "s", "simulated time"),
    "dt": ("number", "s", "time step"),
    "torque": ("signals", "N·m", "joint torques"),
    "speed": ("signals", "rpm", "speed drivers"),
    "initial_speed": ("numbers", "rpm", "initial speeds"),
    "mesh": ("choices", "rigid, compliant", "mesh types"),
    "position_error": ("pairs", "µm", "gear position errors (tangential, radial)"),
    "generator": ("generators", "", "generator laws"),
    "rotor": ("rotors", "", "rotor aerodynamics"),
    "wind": ("signal", "m/s", "wind speed at the rotors"),
    "hub_load": (
        "hub_loads",
        "N, N·m",
        "six load components on bodies (thrust, shears, torque, bending), per body",
    ),
    "rho_inf": ("fraction", "0 to 1", "the time step's spectral radius ρ∞ (1 keeps energy)"),
    "initial_deflection": (
        "choice",
        "static, none",
        "compliant meshes and springs start deflected under the loads of t = 0, or undeflected",
    ),
    "out": ("path", "", "log file"),
    "log_rate": ("number", "Hz", "logged samples per second"),
    "pose_rate": ("number", "Hz", "logged link poses per second"),
    "view_rate": ("number", "Hz", "samples per second on the topics viewers plot"),
    "allow_large_log": ("bool", "", "write a log above the size limit"),
    "keep": ("keep", "all, last, auto or N", "samples the Result keeps in memory"),
    "skip_start": ("number", "s", "start-up span left out of the statistics and load sharing"),
    "force": ("bool", "", "replace an existing log"),
    "no_log": ("bool", "", "write no log"),
}

ROTOR_KEYS = (
    "preset", "radius", "inertia", "air_density", "pitch_deg", "cp_scale", "cp_table",
    "ct_table", "performance_file", "mass", "shaft_tilt_deg", "hub_height", "shear_exponent",
    "hub_body", "hub_point", "hub_up", "pitch_control",
)  # fmt: skip
#: The keys of a rotor's ``pitch_control`` table (``loads/pitch_control.py``), each with its
#: factor to SI: a preset to start from, then the speed set point [rpm], the gains on the rotor
#: speed error (K_P [s], K_I [-]), θ_K [deg], the filter's corner [Hz], the limits [deg] and the
#: largest rate [deg/s].
PITCH_CONTROL_KEYS: dict[str, float] = {
    "preset": 1.0,
    "speed_rpm": RAD_S_PER_RPM,
    "kp": 1.0,
    "ki": 1.0,
    "gain_angle_deg": math.pi / 180,
    "corner_hz": 2 * math.pi,
    "pitch_min_deg": math.pi / 180,
    "pitch_max_deg": math.pi / 180,
    "rate_deg_s": math.pi / 180,
}
#: The keys of a rotor's ``cp_table``: tip-speed ratios, power coefficients, pitch angles [deg].
CP_TABLE_KEYS = ("tsr", "cp", "pitch_deg")
#: The keys of a rotor's ``ct_table``: tip-speed ratios, thrust coefficients, pitch angles [deg].
CT_TABLE_KEYS = ("tsr", "ct", "pitch_deg")
ROTOR_PRESETS = {
    "saleh2017": Rotor.saleh2017,
    "jorgensen2014": Rotor.jorgensen2014,
    "nrel5mw": Rotor.nrel5mw,
}
#: The keys of a body's ``hub_load`` table: its six components (signals, N and N·m), or an
#: OpenFAST output's six channels (``openfast``, a file); the frame, point and up direction.
HUB_LOAD_KEYS = (*COMPONENTS, "openfast", "frame", "point", "up")


class ScenarioError(InputError):
    """A scenario file with an unknown key, a wrong type or unit, a missing model, ...

    Attributes:
        path: the scenario file (or ``"command line"``, ``"log LOG"``).
        key: the dotted key at fault.
        line: its line in the file (0 when unknown).
    """

    def __init__(self, path: str, key: str, line: int, message: str):
        self.path, self.key, self.line = str(path), key, line
        where = f"{self.path}:{line}" if line else self.path
        super().__init__(f"{where}: {key}: {message}")


def _norm(key: str) -> str:
    return key.replace("-", "_")


def key_line(text: str | None, path: tuple[str, ...]) -> int:
    """Line (1-based) of a dotted key in TOML text, or of its nearest parent; 0 if not found."""
    if not text:
        return 0
    best, depth = 0, 0
    header: tuple[str, ...] = ()
    found: tuple[str, ...]
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].strip()
        if not stripped:
            continue
        m = re.fullmatch(r"\[\s*([^\[\]]+?)\s*\]", stripped)
        if m:
            header = tuple(_norm(p.strip().strip("\"'")) for p in m.group(1).split("."))
            found = header
        else:
            m = re.match(r"([A-Za-z0-9_\-\.\"' ]+?)\s*=", stripped)
            if not m:
                continue
            found = header + tuple(_norm(p.strip().strip("\"'")) for p in m.group(1).split("."))
            # An inline table on this line: { carrier = ... }.
            rest = stripped[m.end() :]
            if found == path[: len(found)] and len(path) > len(found):
                if re.search(rf"[{{,]\s*{re.escape(path[len(found)])}\s*=", rest):
                    found = found + (path[len(found)],)
        if found == path[: len(found)] and len(found) > depth:
            best, depth = number, len(found)
    return best


def key_error(source: str, text: str | None, key: tuple[str, ...], message: str) -> ScenarioError:
    """The error of a TOML file's key: the file, the dotted key, its line in ``text``, a message.

    Every reader of a TOML file (scenarios, fatigue sets) says its errors with it.
    """
    return ScenarioError(source, ".".join(key), key_line(text, key), message)


@dataclass(frozen=True, kw_only=True)
class Scenario:
    """The inputs of one run, built (SI): what ``simulate`` takes, and the values they came from.

    Made once from plain values by ``build`` (scenario files, flags, logs), or directly in
    Python; ``run`` hands these very objects to ``simulate``.

    Attributes:
        duration: simulated time [s].
        dt: time step [s].
        torques: joint → torque [N·m], a signal or a number.
        speeds: joint → prescribed joint speed [rad/s], a signal or a number.
        initial_speeds: joint → initial speed [rad/s].
        meshes: mesh name (or ``"all"``) → ``"rigid"`` or ``"compliant"``.
        position_errors: gear → (tangential, radial) position error of its centre [m].
        generators: joint → generator law (``loads/generator.py``).
        rotors: joint → ``Rotor`` (``loads/rotor.py``).
        wind: wind speed at the rotors [m/s], or None.
        hub_loads: six load components on bodies (``loads/hub_loads.py``).
        integrator: the time step (``dynamics/integrator.py``), or None for the default.
        initial_deflection: ``"static"`` or ``"none"`` (``simulate``'s).
        values: the plain values it was built from, keys normalised: what the log records and
            ``--from-log`` rebuilds it from (also the log settings: ``out``, ``log_rate``,
            ``keep``, ...); empty for a scenario made in Python.
        source: where the values come from (a file name, ``"command line"``, ``"log LOG"``).
        base: folder that relative file names in the values are relative to.
        text: the TOML text, for line numbers in messages.
        input_files: the fingerprint of every file the scenario read (its own TOML file, the
            tables its signals read): the log records them, ``--from-log`` compares them.
    """

    duration: float = 1.0
    dt: float = 1e-3
    torques: Mapping[str, Signal | float] = field(default_factory=dict)
    speeds: Mapping[str, Signal | float] = field(default_factory=dict)
    initial_speeds: Mapping[str, float] = field(default_factory=dict)
    meshes: Mapping[str, str] = field(default_factory=dict)
    position_errors: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    generators: Mapping[str, GeneratorLaw] = field(default_factory=dict)
    rotors: Mapping[str, Rotor] = field(default_factory=dict)
    wind: Signal | float | None = None
    hub_loads: tuple[HubLoad, ...] = ()
    integrator: Integrator | None = None
    initial_deflection: str = "static"
    values: dict[str, Any] = field(default_factory=dict)
    source: str = "Python"
    base: Path = field(default_factory=Path.cwd)
    text: str | None = None
    input_files: tuple[InputFile, ...] = ()

    def fail(self, key: tuple[str, ...], message: str) -> ScenarioError:
        """The error for a key: file, key, line and the message."""
        return key_error(self.source, self.text, key, message)

    def check_joints(self, joints: list[str], fixed: list[str]) -> None:
        """Refuse loads on joints the model does not have, naming the key and the joints."""
        free = [j for j in joints if j not in fixed]
        loads: tuple[tuple[str, Mapping[str, Any]], ...] = (
            ("torque", self.torques), ("speed", self.speeds),
            ("initial_speed", self.initial_speeds), ("generator", self.generators),
            ("rotor", self.rotors),
        )  # fmt: skip
        for name, given in loads:
            for joint in given:
                if joint not in free:
                    why = "is a fixed mount" if joint in fixed else "is not a joint of the model"
                    raise self.fail((name, joint), f'"{joint}" {why}; joints are: '
                                    + ", ".join(free))  # fmt: skip

    def model_path(self) -> Path:
        """The model file, relative to ``base``.

        Raises:
            InputError: a scenario made in Python, which names no model file.
        """
        if "model" not in self.values:
            raise InputError("a scenario made in Python names no model file; give the gearbox")
        path = Path(self.values["model"])
        return path if path.is_absolute() else self.base / path

    def simulate_kwargs(self) -> dict[str, Any]:
        """Keyword arguments of ``pinwind.simulate`` (SI): the built signals and laws themselves."""
        kwargs: dict[str, Any] = {
            "duration": self.duration,
            "dt": self.dt,
            "torques": self.torques,
            "speeds": self.speeds,
            "initial_speeds": self.initial_speeds,
            "meshes": self.meshes,
            "position_errors": self.position_errors,
        }
        if self.generators:
            kwargs["generators"] = self.generators
        if self.rotors:
            kwargs["rotors"] = self.rotors
            kwargs["wind"] = self.wind
        if self.hub_loads:
            kwargs["hub_loads"] = self.hub_loads
        if self.integrator is not None:
            kwargs["integrator"] = self.integrator
        kwargs["initial_deflection"] = self.initial_deflection
        return kwargs

    def drivetrain(
        self,
        gearbox: Gearbox,
        *,
        meshes: Mapping[str, str] | None = None,
        held: tuple[str, ...] = (),
    ) -> Drivetrain:
        """The machine a run of this scenario steps (``dynamics/drivetrain.py``).

        What ``pinwind modes SCENARIO`` linearises.

        Args:
            meshes: the mesh choice, replacing the scenario's (default the scenario's).
            held: joints held besides the scenario's speed drivers.

        Raises:
            ScenarioError: a load on a joint the model does not have, naming the key.
        """
        from pinwind.dynamics.drivetrain import drivetrain

        self.check_joints(list(gearbox.joint_names), list(gearbox.locked_joints))
        return drivetrain(
            gearbox,
            torques=self.torques,
            speeds=self.speeds,
            initial_speeds=self.initial_speeds,
            generators=self.generators,
            rotors=self.rotors,
            wind=self.wind if self.rotors else None,
            hub_loads=self.hub_loads,
            meshes=self.meshes if meshes is None else meshes,
            held=held,
        )

    def load_model(self) -> Gearbox:
        """The model file the scenario names, loaded.

        Raises:
            ScenarioError: the file does not exist (naming the ``model`` key and its line).
        """
        from pinwind.model.gearbox import load

        path = self.model_path()
        if not path.is_file():
            raise self.fail(("model",), f"{path} does not exist")
        return load(path)

    def record(self) -> dict[str, Any]:
        """What the log stores: the values, where they come from, the base folder."""
        return {"values": copy.deepcopy(self.values), "source": self.source,
                "base": str(self.base.resolve())}  # fmt: skip


def build(
    values: Mapping[str, Any],
    *,
    source: str = "command line",
    base: Path | None = None,
    text: str | None = None,
    flags: Mapping[str, str] | None = None,
) -> Scenario:
    """Check plain values and build every signal and law once: the run's ``Scenario``.

    Args:
        values: the values (numbers, texts, tables) as in a scenario file, units at the edge.
        source: where they come from, for messages (a file name, ``"command line"``, ...).
        base: folder that relative file names are relative to (default: the working folder).
        text: the TOML text, for line numbers in messages.
        flags: key → the command-line option that gave it (``torque`` → ``--torque``): its
            signals' errors name the option, and numbers are left to ``simulate``'s checks,
            whose messages name the option too. None for files and logs.

    Raises:
        ScenarioError: the first problem found, naming the key (and its line).
        InputError: a bad signal given by a flag, naming the flag.
    """
    return _Builder(values, source, base or Path.cwd(), text, flags).scenario()


class _Builder:
    """Builds a ``Scenario`` from values; each error names the key (or the flag) at fault."""

    def __init__(
        self,
        values: Mapping[str, Any],
        source: str,
        base: Path,
        text: str | None,
        flags: Mapping[str, str] | None,
    ):
        self.values: dict[str, Any] = dict(values)
        self.source, self.base, self.text, self.flags = source, base, text, flags
        self.files: list[InputFile] = []

    def fail(self, key: tuple[str, ...], message: str) -> ScenarioError:
        return key_error(self.source, self.text, key, message)

    def scenario(self) -> Scenario:
        self.check()
        v = self.values
        # Built in the order the errors were always found in: laws, rotors, signals, wind.
        generators = self.generators()
        rotors = self.rotors()
        torques = self.signals("torque")
        speeds = {k: Scaled(s, RAD_S_PER_RPM) for k, s in self.signals("speed").items()}
        wind = self.wind()
        if wind is not None and not rotors:
            # It was dropped without a word, even a NaN (--wind nan).
            raise self.fail(("wind",), "is given but there is no rotor, the one element that "
                            "takes it; add a rotor ([rotor.JOINT], --rotor JOINT=PRESET) or "
                            "leave out the wind")  # fmt: skip
        hub_loads = self.hub_loads()
        return Scenario(
            duration=float(v.get("duration", 1.0)),
            dt=float(v.get("dt", 1e-3)),
            torques=torques,
            speeds=speeds,
            initial_speeds={
                k: float(x) * RAD_S_PER_RPM for k, x in v.get("initial_speed", {}).items()
            },
            meshes=dict(v.get("mesh", {})),
            position_errors={
                k: (p[0] * 1e-6, p[1] * 1e-6) for k, p in v.get("position_error", {}).items()
            },
            generators=generators,
            rotors=rotors,
            wind=wind,
            hub_loads=hub_loads,
            integrator=self.integrator(),
            initial_deflection=str(v.get("initial_deflection", "static")),
            values=v,
            source=self.source,
            base=self.base,
            text=self.text,
            input_files=tuple(self.files),
        )

    # --- checking ------------------------------------------------------------------------------

    def check(self) -> None:
        """Check keys and types (normalising the keys)."""
        values = toml_keys(self.values)
        check_keys((), values, KEYS, self.fail)
        self.values = values
        if "model" not in values:
            raise self.fail(("model",), "missing: give the model file, e.g. model = "
                            '"models/saleh2017_planetary.urdf"')  # fmt: skip
        for name, value in values.items():
            self._check_value(name, value)
        if "rotor" in values and "wind" not in values:
            raise self.fail(("wind",), "missing: a rotor needs the wind speed [m/s], a number "
                            "or a signal, e.g. wind = 10")  # fmt: skip

    def _check_value(self, name: str, value: Any) -> None:
        kind, unit, what = KEYS[name]
        key = (name,)
        if kind == "path" and not isinstance(value, str):
            raise self.fail(key, f"must be a file name (text); got {value!r}")
        if kind == "number":
            self._number(key, value, unit, positive=self.flags is None)
        if kind == "fraction" and not 0.0 <= self._number(key, value, unit) <= 1.0:
            raise self.fail(key, f"is {value}; give a number from {unit}")
        if kind == "choice" and value not in unit.split(", "):
            raise self.fail(key, f"is {value!r}; choose one of: {unit}")
        if kind == "bool" and not isinstance(value, bool):
            raise self.fail(key, f"must be true or false; got {value!r}")
        if kind == "keep" and not (
            value in ("all", "last", "auto")
            or (isinstance(value, int) and not isinstance(value, bool) and value >= 1)
        ):
            raise self.fail(key, f"is {value!r}; choose one of: {unit}")
        if kind in ("signals", "numbers", "choices", "pairs", "generators", "rotors", "hub_loads"):
            if not isinstance(value, Mapping):
                raise self.fail(key, f"must be a table of joint (or mesh, gear) names: {what}")
            for joint, item in value.items():
                sub = (name, joint)
                if kind == "numbers":
                    self._number(sub, item, unit)
                elif kind == "choices" and item not in unit.split(", "):
                    raise self.fail(sub, f"is {item!r}; choose one of: {unit}")
                elif kind == "pairs" and (
                    not isinstance(item, list) or len(item) != 2
                    or not all(isinstance(x, int | float) for x in item)
                ):  # fmt: skip
                    raise self.fail(sub, f"must be [tangential, radial] in {unit}; got {item!r}")
                elif kind in ("generators", "rotors", "hub_loads") and not isinstance(
                    item, Mapping
                ):
                    raise self.fail(sub, "must be a table of parameters")

    def _number(self, key, value, unit, positive=False) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(key, f"must be a number [{unit}]; got {value!r}")
        if not math.isfinite(value) or (positive and value <= 0):
            raise self.fail(key, f"is {value}; give a finite{' positive' if positive else ''} "
                            f"number [{unit}]")  # fmt: skip
        return float(value)

    # --- building -----------------------------------------------------------------------------

    def signals(self, name: str) -> dict[str, Signal]:
        """``torque`` or ``speed`` as signals, in the values' units."""
        flag = (self.flags or {}).get(name)
        out: dict[str, Signal] = {}
        for joint, spec in self.values.get(name, {}).items():
            files: list[InputFile] = []
            if flag is not None:  # the flag's own message, as the command line always said it
                out[joint] = signal_from_spec(spec, base=self.base, where=flag, files=files)
            else:
                try:
                    out[joint] = signal_from_spec(
                        spec, base=self.base, where=f"{name}.{joint}", files=files
                    )
                except InputError as err:
                    raise self.fail((name, joint), _strip(str(err), f"{name}.{joint}: ")) from err
            self.files += [dataclasses.replace(f, where=f"{name}.{joint}") for f in files]
        return out

    def integrator(self) -> Integrator | None:
        """The time step with ``rho_inf``, or None for the default."""
        if "rho_inf" not in self.values:
            return None
        from pinwind.dynamics.integrator import Integrator

        return Integrator(rho_infinity=float(self.values["rho_inf"]))

    def wind(self) -> Signal | None:
        """The wind signal [m/s], or None."""
        if "wind" not in self.values:
            return None
        try:
            return signal_from_spec(
                self.values["wind"], base=self.base, where="wind", files=self.files
            )
        except InputError as err:
            raise self.fail(("wind",), _strip(str(err), "wind: ")) from err

    def hub_loads(self) -> tuple[HubLoad, ...]:
        """A hub load per body: its components as signals (N, N·m), or an OpenFAST file's."""
        out = []
        for body, params in self.values.get("hub_load", {}).items():
            key = ("hub_load", body)
            params = toml_keys(params)
            check_keys(key, params, HUB_LOAD_KEYS, self.fail, kind="key", of=" of a hub load")
            frame = params.get("frame", "fixed")
            if frame not in [f.value for f in HubFrame]:
                raise self.fail(key + ("frame",), f"is {frame!r}; choose one of: "
                                + ", ".join(f.value for f in HubFrame))  # fmt: skip
            point = self._vector(key + ("point",), params.get("point", [0.0, 0.0, 0.0]), "m")
            up = params.get("up")
            up = None if up is None else self._vector(key + ("up",), up, "-")
            given = [c for c in COMPONENTS if c in params]
            if "openfast" in params:
                if given:
                    message = f"reads the six components; remove {', '.join(given)} or openfast"
                    raise self.fail(key + ("openfast",), message)
                file = Path(str(params["openfast"]))
                path = file if file.is_absolute() else self.base / file
                try:
                    load = hub_load_from_openfast(path, body, frame=frame, point=point, up=up)
                except InputError as err:
                    raise self.fail(key + ("openfast",), str(err)) from err
                self.files.append(InputFile.of(path, given=str(file), where=".".join(key)))
                out.append(load)
                continue
            components = []
            for name in COMPONENTS:
                files: list[InputFile] = []
                where = f"hub_load.{body}.{name}"
                try:
                    components.append(
                        signal_from_spec(
                            params.get(name, 0.0), base=self.base, where=where, files=files
                        )  # fmt: skip
                    )
                except InputError as err:
                    raise self.fail(key + (name,), _strip(str(err), f"{where}: ")) from err
                self.files += [dataclasses.replace(f, where=where) for f in files]
            out.append(HubLoad(body, tuple(components), HubFrame(frame), point, up))
        return tuple(out)

    def _vector(self, key, value, unit) -> tuple[float, float, float]:
        if not isinstance(value, list | tuple) or len(value) != 3:
            raise self.fail(key, f"must be three numbers [x, y, z] [{unit}]; got {value!r}")
        x, y, z = (self._number(key, item, unit) for item in value)
        return (x, y, z)

    def generators(self) -> dict[str, GeneratorLaw]:
        """Generator laws per joint, by their names in ``loads.generator.LAWS``."""
        out = {}
        for joint, params in self.values.get("generator", {}).items():
            key = ("generator", joint)
            params = toml_keys(params)
            law = params.pop("law", "induction" if "preset" in params else None)
            if law not in LAWS:
                raise self.fail(key + ("law",), f"is {law!r}; laws are: " + ", ".join(LAWS))
            kind = LAWS[law]
            kwargs: dict[str, Any] = {}
            check_keys(key, params, kind.keys, self.fail, kind="parameter", of=f" of {law}")
            for name, value in params.items():
                if name == "preset":
                    if value not in kind.presets:
                        raise self.fail(key + (name,), f"is {value!r}; presets are: "
                                        + ", ".join(kind.presets))  # fmt: skip
                    continue
                target, unit = kind.parameters[name]
                if kind.field_type(target) == "bool":
                    if not isinstance(value, bool):
                        raise self.fail(key + (name,), "must be true or false")
                    kwargs[target] = value
                    continue
                number = self._number(key + (name,), value, unit) * TO_SI.get(unit, 1.0)
                kwargs[target] = int(number) if kind.field_type(target) == "int" else number
            try:
                out[joint] = kind.build(params.get("preset"), **kwargs)
            except TypeError as err:
                missing = [k for k, (target, _) in kind.parameters.items() if target not in kwargs]
                raise self.fail(key, f"{law} needs {', '.join(missing)}") from err
            except InputError as err:
                raise self.fail(key, str(err)) from err
        return out

    def rotors(self) -> dict[str, Rotor]:
        """Rotors per joint."""
        out = {}
        for joint, params in self.values.get("rotor", {}).items():
            key = ("rotor", joint)
            params = toml_keys(params)
            kwargs: dict[str, Any] = {}
            check_keys(key, params, ROTOR_KEYS, self.fail, kind="parameter", of=" of a rotor")
            if "hub_body" not in params and {"hub_point", "hub_up"} & set(params):
                raise self.fail(key, "hub_point and hub_up place the rotor's loads on hub_body; "
                                "give hub_body, the body the rotor sits on")  # fmt: skip
            if "hub_body" in params:
                kwargs["hub"] = self._rotor_hub(key, params)
            for name, value in params.items():
                if name == "preset":
                    if value not in ROTOR_PRESETS:
                        raise self.fail(key + (name,), f"is {value!r}; presets are: "
                                        + ", ".join(ROTOR_PRESETS))  # fmt: skip
                elif name == "cp_table":
                    kwargs["cp"] = self._cp_table(key + (name,), value)
                elif name == "ct_table":
                    kwargs["ct"] = self._ct_table(key + (name,), value)
                elif name == "pitch_control":
                    kwargs["pitch_control"] = self._pitch_control(key + (name,), value)
                elif name == "performance_file":
                    kwargs["cp"], kwargs["ct"] = self._performance(key + (name,), value)
                elif name == "cp_scale":
                    kwargs["cp"] = HeierCp(self._number(key + (name,), value, "-"))
                elif name in ("pitch_deg", "shaft_tilt_deg"):
                    kwargs[name[:-4]] = math.radians(self._number(key + (name,), value, "deg"))
                elif name.startswith("hub_") and name != "hub_height":
                    continue
                else:
                    kwargs[name] = self._number(key + (name,), value, "SI")
            preset = params.get("preset")
            try:
                out[joint] = ROTOR_PRESETS[preset](**kwargs) if preset else Rotor(**kwargs)
            except TypeError as err:
                raise self.fail(key, "give a preset (" + ", ".join(ROTOR_PRESETS)
                                + ") or at least radius [m]") from err  # fmt: skip
            except InputError as err:
                raise self.fail(key, str(err)) from err
        return out

    def _pitch_control(self, key, value) -> PitchControl:
        """A preset's name, or a table of ``PITCH_CONTROL_KEYS`` (from a preset, or in full)."""
        table = {"preset": value} if isinstance(value, str) else value
        if not isinstance(table, Mapping):
            raise self.fail(key, 'must be a preset ("nrel5mw") or a table of ' +
                            ", ".join(PITCH_CONTROL_KEYS) + f"; got {value!r}")  # fmt: skip
        table = toml_keys(table)
        check_keys(key, table, tuple(PITCH_CONTROL_KEYS), self.fail, kind="parameter",
                   of=" of pitch_control")  # fmt: skip
        preset = table.get("preset")
        if preset is not None and preset not in PITCH_PRESETS:
            raise self.fail(key + ("preset",), f"is {preset!r}; presets are: "
                            + ", ".join(PITCH_PRESETS))  # fmt: skip
        kwargs: dict[str, Any] = {}
        for name, factor in PITCH_CONTROL_KEYS.items():
            if name == "preset" or name not in table:
                continue
            target = name.removesuffix("_deg_s").removesuffix("_deg").removesuffix("_hz")
            target = {"speed_rpm": "speed_set"}.get(name, target)
            kwargs[target] = self._number(key + (name,), table[name], "SI") * factor
        try:
            return PITCH_PRESETS[preset](**kwargs) if preset else PitchControl(**kwargs)
        except TypeError as err:
            needed = "speed_rpm, kp, ki, gain_angle_deg, corner_hz"
            presets = ", ".join(PITCH_PRESETS)
            raise self.fail(key, f"give a preset ({presets}) or every value: {needed}") from err
        except InputError as err:
            raise self.fail(key, str(err)) from err

    def _rotor_hub(self, key, params) -> RotorHub:
        body = params["hub_body"]
        if not isinstance(body, str):
            raise self.fail(key + ("hub_body",), f"must be a body name; got {body!r}")
        point = self._vector(key + ("hub_point",), params.get("hub_point", [0.0, 0.0, 0.0]), "m")
        up = params.get("hub_up")
        return RotorHub(
            body, point, None if up is None else self._vector(key + ("hub_up",), up, "-")
        )

    def _ct_table(self, key, value) -> CtTable:
        if not isinstance(value, Mapping) or not {"tsr", "ct"} <= set(value):
            raise self.fail(key, "must be { tsr = [...], ct = [...] } (and pitch_deg = [...])")
        check_keys(key, value, CT_TABLE_KEYS, self.fail)
        try:
            pitch = tuple(math.radians(p) for p in value.get("pitch_deg", [0.0]))
            return CtTable(tsr=tuple(value["tsr"]), ct=tuple(value["ct"]), pitch=pitch)
        except (InputError, TypeError, ValueError) as err:
            raise self.fail(key, str(err)) from err

    def _performance(self, key, value) -> tuple[CpTable, CtTable]:
        file = Path(str(value))
        path = file if file.is_absolute() else self.base / file
        try:
            tables = performance_tables(path)
        except InputError as err:
            raise self.fail(key, str(err)) from err
        self.files.append(InputFile.of(path, given=str(file), where=".".join(key)))
        return tables

    def _cp_table(self, key, value) -> CpTable:
        if not isinstance(value, Mapping) or not {"tsr", "cp"} <= set(value):
            raise self.fail(key, "must be { tsr = [...], cp = [...] } (and pitch_deg = [...])")
        check_keys(key, value, CP_TABLE_KEYS, self.fail)
        try:
            pitch = tuple(math.radians(p) for p in value.get("pitch_deg", [0.0]))
            return CpTable(tsr=tuple(value["tsr"]), cp=tuple(value["cp"]), pitch=pitch)
        except (InputError, TypeError, ValueError) as err:
            raise self.fail(key, str(err)) from err


def _strip(message: str, prefix: str) -> str:
    return message[len(prefix) :] if message.startswith(prefix) else message


def read_toml(path: Path) -> tuple[str, dict[str, Any]]:
    """A TOML file's text and values.

    Raises:
        ScenarioError: the file cannot be read, or is not valid TOML (naming its line).
    """
    try:
        text = path.read_text()
    except OSError as err:
        raise ScenarioError(str(path), "-", 0, f"cannot read it: {err.strerror or err}") from err
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        m = re.search(r"line (\d+)", str(err))
        raise ScenarioError(str(path), "-", int(m.group(1)) if m else 0,
                            f"not valid TOML: {err}") from err  # fmt: skip


def load_scenario(path: str | Path, *, changes: Mapping[str, Any] | None = None) -> Scenario:
    """Read a scenario file and build it.

    Args:
        path: the TOML file.
        changes: values that replace the file's (e.g. ``{"duration": 5.0}`` for a short run);
            the log records the values as changed.

    Raises:
        ScenarioError: unreadable TOML, unknown key, wrong type, missing model, ...
    """
    path = Path(path)
    text, values = read_toml(path)
    scenario = build({**values, **(changes or {})}, source=str(path), base=path.parent, text=text)
    own = InputFile.of(path, where="scenario")
    return dataclasses.replace(scenario, input_files=(own, *scenario.input_files))


def from_record(record: Mapping[str, Any], source: str) -> Scenario:
    """The scenario a log stored (``Scenario.record``)."""
    return build(dict(record["values"]), source=source, base=Path(record["base"]))


def run(
    scenario: Scenario,
    *,
    gearbox: Gearbox | None = None,
    out: str | Path | None = None,
    force: bool | None = None,
    no_log: bool | None = None,
    command: str | None = None,
    progress: bool | None = None,
    check_joints: bool = True,
    statistics: bool | None = None,
    keep_series: Sequence[str] | None = None,
    keep: str | int | None = None,
    observer: Any = None,
) -> Result:
    """Run a scenario: load its model (unless given), simulate, log it with its values.

    Args:
        gearbox: the model, if already loaded (``--from-log`` passes the logged model).
        out, force, no_log: override the scenario's ``out``, ``force`` and ``no_log``.
        command: the command line to record.
        check_joints: refuse loads on unknown joints here, naming the scenario key (the command
            line leaves that to ``simulate``, whose message names the option).
        statistics: fold every sample into ``result.statistics`` (``pinwind.runs.run.simulate``;
            default: when the Result does not keep every sample).
        keep_series: the series the Result holds (default all; the log has every one).
        keep: which samples the Result holds, instead of the scenario's ``keep`` (the log
            records the scenario's).
        observer: observers of the run besides its log (``RunObserver``, one or a sequence),
            as ``pinwind.runs.run.simulate`` takes them.

    Returns:
        The ``Result``.
    """
    from pinwind.io.log_writer import POSE_RATE, VIEW_RATE
    from pinwind.model.gearbox import load
    from pinwind.runs.run import log_path, simulate

    v = scenario.values
    if gearbox is None:
        path = scenario.model_path()
        if not path.is_file():
            raise scenario.fail(("model",), f"{path} does not exist")
        gearbox = load(path)
    if check_joints:
        scenario.check_joints(list(gearbox.joint_names), list(gearbox.locked_joints))
    skip = v.get("no_log", False) if no_log is None else no_log
    target = out if out is not None else v.get("out")
    log = None if skip else log_path(target if target is not None else True, gearbox.name)
    return simulate(
        gearbox,
        log=log,
        log_rate=v.get("log_rate"),
        pose_rate=v.get("pose_rate", POSE_RATE),
        view_rate=v.get("view_rate", VIEW_RATE),
        allow_large_log=v.get("allow_large_log", False),
        keep=v.get("keep", "auto") if keep is None else keep,
        keep_series=keep_series,
        observer=observer,
        skip_start=v.get("skip_start", 0.0),
        statistics=statistics,
        overwrite=v.get("force", False) if force is None else force,
        command=command,
        progress=progress,
        metadata={
            "scenario": scenario.record(),
            "input_files": [f.record() for f in scenario.input_files],
        }
        if v
        else None,
        **scenario.simulate_kwargs(),
    )


def from_log(path: str | Path, *, accept_changed_inputs: bool = False) -> tuple[Scenario, Any]:
    """The scenario and the model a log stored: repeat the run with ``run(scenario, gearbox=...)``.

    The model is rebuilt from the file the log holds (not from the model path, which may have
    changed since). The files the signals read are compared with the fingerprints the log
    recorded (``input_files``) before anything is built; the scenario file itself is not read
    again (its values are in the log). A log written before fingerprints were recorded is
    repeated without that check.

    Args:
        accept_changed_inputs: repeat the run with the files as they are now, even when they
            differ from the recorded ones (the new log records the new fingerprints).

    Raises:
        LogError: not a pinwind log, its model attachment is damaged or missing, or its
            ``pinwind.run`` record fails its checksum; InputError: a log written without a
            scenario (before scenarios existed, or by ``pinwind.simulate`` from Python).
        InputFileChanged: a file the run read has changed or is gone since.
    """
    from pinwind.io.log_reader import LogReader
    from pinwind.model.gearbox import loads

    with LogReader(path) as reader:
        run_meta = reader.metadata["pinwind.run"]
        attachments = reader.attachments
        model_problem = reader.model_problem
        if "pinwind.run" in reader.failed_records:
            raise LogError(
                str(path),
                f"the 'pinwind.run' metadata record {reader.failed_records['pinwind.run']}: "
                "the scenario, dt and loads it holds may not be the run's; it cannot be "
                "repeated from this file, restore it from a copy",
            )
    record = run_meta.get("scenario")
    if not record:
        raise InputError(
            f"{path}: the log holds no scenario (written from Python, or by an older pinwind); "
            "only runs of `pinwind simulate` and `pinwind run` can be repeated"
        )
    if not attachments:
        raise LogError(str(path), f"{model_problem}; the run cannot be repeated without it")
    if not accept_changed_inputs:
        check_unchanged(list(run_meta.get("input_files", [])), skip=("scenario",))
    text = next(iter(attachments.values())).decode("utf-8")
    gearbox = loads(text, path=str(run_meta.get("model_path", "model.urdf")))
    return from_record(record, source=f"log {path}"), gearbox
