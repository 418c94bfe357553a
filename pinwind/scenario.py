"""Scenario files: everything a run needs, in TOML, with the names of ``pinwind simulate``'s flags.

``pinwind run scenarios/saleh2017_rated.toml`` runs one; ``pinwind simulate`` turns its flags into
the same values. Keys (units at the edge, like the flags; ``-`` and ``_`` are the same)::

    model = "../models/saleh2017_planetary.urdf"   # relative to the scenario file
    duration = 60.0                                # [s]
    dt = 1e-3                                      # [s]
    torque = { carrier = 1e6 }                     # [N·m]: a number or a signal (loads/signals.py)
    speed = { carrier = "sine(mean=14.2, amplitude=1, frequency=0.1)" }   # [rpm]
    initial_speed = { carrier = 12.0 }             # [rpm]
    mesh = { all = "rigid" }                       # rigid | compliant
    position_error = { planet1 = [20.0, 0.0] }     # tangential, radial [µm]
    wind = "kaimal(mean=10, turbulence_intensity=0.1, seed=1)"   # [m/s]: a number or a signal
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

The flags say the same: ``--generator "sun=linear-slip(slope=1.26e6, sync_rpm=83.94)"``,
``--rotor carrier=saleh2017`` (or ``"carrier=rotor(radius=42.85, inertia=5e6)"``), ``--wind 10``.

Every run from a scenario or from ``pinwind simulate`` stores its values in the log's metadata
(``scenario``), with the model file itself; ``pinwind run --from-log LOG`` repeats the run bit for
bit from them. A bad scenario gets one ``ScenarioError`` naming the file, the key, its line and
the valid choices.
"""

from __future__ import annotations

import ast
import copy
import math
import re
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pinwind.errors import InputError
from pinwind.loads.generator import ConstantTorque, InductionMachine, LinearSlip, VariableSpeed
from pinwind.loads.rotor import CpTable, HeierCp, Rotor
from pinwind.loads.signal_text import signal_from_spec
from pinwind.loads.signals import Scaled, Signal

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

RPM = 2.0 * math.pi / 60.0

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
    "out": ("path", "", "log file"),
    "log_rate": ("number", "Hz", "logged samples per second"),
    "pose_rate": ("number", "Hz", "logged link poses per second"),
    "view_rate": ("number", "Hz", "samples per second on the topics viewers plot"),
    "allow_large_log": ("bool", "", "write a log above the size limit"),
    "keep": ("keep", "all, last, auto or N", "samples the Result keeps in memory"),
    "force": ("bool", "", "replace an existing log"),
    "no_log": ("bool", "", "write no log"),
}

#: Generator laws and their keys → (field of the law, factor to SI).
GENERATOR_LAWS: dict[str, dict[str, tuple[str, float]]] = {
    "constant": {"torque": ("torque", 1.0)},
    "linear-slip": {"slope": ("slope", 1.0), "sync_rpm": ("sync_speed", RPM)},
    "variable-speed": {"gain": ("gain", 1.0), "rated_power": ("rated_power", 1.0)},
    **{
        law: {
            key: (key, 1.0)
            for key in (
                "preset",
                "stator_resistance",
                "rotor_resistance",
                "stator_leakage",
                "rotor_leakage",
                "magnetizing",
                "voltage",
                "frequency",
                "poles",
                "steady_start",
            )  # fmt: skip
        }
        for law in ("induction", "induction-dq")
    },
}
GENERATOR_PRESETS = {"cart600": InductionMachine.cart600}
ROTOR_KEYS = ("preset", "radius", "inertia", "air_density", "pitch_deg", "cp_scale", "cp_table")
ROTOR_PRESETS = {"saleh2017": Rotor.saleh2017}


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


@dataclass
class Scenario:
    """The values of a run, checked.

    Attributes:
        values: plain values (numbers, texts, tables) with normalised keys, as in the file.
        source: where they come from (a file name, ``"command line"``, ``"log ..."``).
        base: folder that relative file names in the values are relative to.
        text: the TOML text, for line numbers in messages.
    """

    values: dict[str, Any]
    source: str = "command line"
    base: Path = field(default_factory=Path.cwd)
    text: str | None = None

    # --- checking ------------------------------------------------------------------------------

    def fail(self, key: tuple[str, ...], message: str) -> ScenarioError:
        """The error for a key: file, key, line and the message."""
        return ScenarioError(self.source, ".".join(key), key_line(self.text, key), message)

    def check(self) -> Scenario:
        """Check keys and types; build every signal and law once so that errors name the key.

        Raises:
            ScenarioError: the first problem found.
        """
        values = {}
        for key, value in self.values.items():
            name = _norm(key)
            if name not in KEYS:
                raise self.fail((name,), f"unknown key; keys are: {', '.join(KEYS)}")
            values[name] = value
        self.values = values
        if "model" not in values:
            raise self.fail(("model",), "missing: give the model file, e.g. model = "
                            '"models/saleh2017_planetary.urdf"')  # fmt: skip
        for name, value in values.items():
            self._check_value(name, value)
        if "rotor" in values and "wind" not in values:
            raise self.fail(("wind",), "missing: a rotor needs the wind speed [m/s], a number "
                            "or a signal, e.g. wind = 10")  # fmt: skip
        self.generators()
        self.rotors()
        self.signals("torque")
        self.signals("speed")
        self.wind()
        return self

    def _check_value(self, name: str, value: Any) -> None:
        kind, unit, what = KEYS[name]
        key = (name,)
        if kind == "path" and not isinstance(value, str):
            raise self.fail(key, f"must be a file name (text); got {value!r}")
        if kind == "number":  # the command line leaves the checks to simulate()'s messages
            self._number(key, value, unit, positive=self.source != "command line")
        if kind == "bool" and not isinstance(value, bool):
            raise self.fail(key, f"must be true or false; got {value!r}")
        if kind == "keep" and not (
            value in ("all", "last", "auto")
            or (isinstance(value, int) and not isinstance(value, bool) and value >= 1)
        ):
            raise self.fail(key, f"is {value!r}; choose one of: {unit}")
        if kind in ("signals", "numbers", "choices", "pairs", "generators", "rotors"):
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
                elif kind in ("generators", "rotors") and not isinstance(item, Mapping):
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
        """``torque`` [N·m] or ``speed`` (rpm in the file, rad/s out) as signals."""
        out: dict[str, Signal] = {}
        for joint, spec in self.values.get(name, {}).items():
            try:
                signal = signal_from_spec(spec, base=self.base, where=f"{name}.{joint}")
            except InputError as err:
                raise self.fail((name, joint), _strip(str(err), f"{name}.{joint}: ")) from err
            out[joint] = Scaled(signal, RPM) if name == "speed" else signal
        return out

    def wind(self) -> Signal | None:
        """The wind signal [m/s], or None."""
        if "wind" not in self.values:
            return None
        try:
            return signal_from_spec(self.values["wind"], base=self.base, where="wind")
        except InputError as err:
            raise self.fail(("wind",), _strip(str(err), "wind: ")) from err

    def generators(self) -> dict[str, Any]:
        """Generator laws per joint."""
        out = {}
        for joint, params in self.values.get("generator", {}).items():
            key = ("generator", joint)
            params = {_norm(k): v for k, v in params.items()}
            law = params.pop("law", "induction" if "preset" in params else None)
            if law not in GENERATOR_LAWS:
                raise self.fail(key + ("law",), f"is {law!r}; laws are: "
                                + ", ".join(GENERATOR_LAWS))  # fmt: skip
            allowed = GENERATOR_LAWS[law]
            kwargs: dict[str, Any] = {}
            for name, value in params.items():
                if name not in allowed:
                    raise self.fail(key + (name,), f"{law} has no parameter {name!r}; its "
                                    f"parameters are: {', '.join(allowed)}")  # fmt: skip
                target, factor = allowed[name]
                if name == "preset":
                    if value not in GENERATOR_PRESETS:
                        raise self.fail(key + (name,), f"is {value!r}; presets are: "
                                        + ", ".join(GENERATOR_PRESETS))  # fmt: skip
                elif name == "steady_start":
                    if not isinstance(value, bool):
                        raise self.fail(key + (name,), "must be true or false")
                    kwargs[target] = value
                else:
                    kwargs[target] = self._number(key + (name,), value, "SI") * factor
            try:
                if law in ("induction", "induction-dq"):
                    dynamic = law == "induction-dq"
                    if "poles" in kwargs:
                        kwargs["poles"] = int(kwargs["poles"])
                    preset = params.get("preset")
                    if preset is not None:
                        out[joint] = GENERATOR_PRESETS[preset](dynamic=dynamic, **kwargs)
                    else:
                        out[joint] = InductionMachine(dynamic=dynamic, **kwargs)
                else:
                    cls = {"constant": ConstantTorque, "linear-slip": LinearSlip,
                           "variable-speed": VariableSpeed}[law]  # fmt: skip
                    out[joint] = cls(**kwargs)
            except TypeError as err:
                missing = [k for k in allowed if k != "preset" and allowed[k][0] not in kwargs]
                raise self.fail(key, f"{law} needs {', '.join(missing)}") from err
        return out

    def rotors(self) -> dict[str, Rotor]:
        """Rotors per joint."""
        out = {}
        for joint, params in self.values.get("rotor", {}).items():
            key = ("rotor", joint)
            params = {_norm(k): v for k, v in params.items()}
            kwargs: dict[str, Any] = {}
            for name, value in params.items():
                if name not in ROTOR_KEYS:
                    raise self.fail(key + (name,), "unknown parameter; rotor parameters are: "
                                    + ", ".join(ROTOR_KEYS))  # fmt: skip
                if name == "preset":
                    if value not in ROTOR_PRESETS:
                        raise self.fail(key + (name,), f"is {value!r}; presets are: "
                                        + ", ".join(ROTOR_PRESETS))  # fmt: skip
                elif name == "cp_table":
                    kwargs["cp"] = self._cp_table(key + (name,), value)
                elif name == "cp_scale":
                    kwargs["cp"] = HeierCp(self._number(key + (name,), value, "-"))
                elif name == "pitch_deg":
                    kwargs["pitch"] = math.radians(self._number(key + (name,), value, "deg"))
                else:
                    kwargs[name] = self._number(key + (name,), value, "SI")
            preset = params.get("preset")
            try:
                out[joint] = ROTOR_PRESETS[preset](**kwargs) if preset else Rotor(**kwargs)
            except TypeError as err:
                raise self.fail(key, 'give preset = "saleh2017" or at least radius [m]') from err
            except InputError as err:
                raise self.fail(key, str(err)) from err
        return out

    def _cp_table(self, key, value) -> CpTable:
        if not isinstance(value, Mapping) or not {"tsr", "cp"} <= set(value):
            raise self.fail(key, "must be { tsr = [...], cp = [...] } (and pitch_deg = [...])")
        try:
            pitch = tuple(math.radians(p) for p in value.get("pitch_deg", [0.0]))
            return CpTable(tsr=tuple(value["tsr"]), cp=tuple(value["cp"]), pitch=pitch)
        except (InputError, TypeError, ValueError) as err:
            raise self.fail(key, str(err)) from err

    def check_joints(self, joints: list[str], fixed: list[str]) -> None:
        """Refuse loads on joints the model does not have, naming the key and the joints."""
        free = [j for j in joints if j not in fixed]
        for name in ("torque", "speed", "initial_speed", "generator", "rotor"):
            for joint in self.values.get(name, {}):
                if joint not in free:
                    why = "is a fixed mount" if joint in fixed else "is not a joint of the model"
                    raise self.fail((name, joint), f'"{joint}" {why}; joints are: '
                                    + ", ".join(free))  # fmt: skip

    def model_path(self) -> Path:
        """The model file, relative to ``base``."""
        path = Path(self.values["model"])
        return path if path.is_absolute() else self.base / path

    def simulate_kwargs(self) -> dict[str, Any]:
        """Keyword arguments of ``pinwind.simulate`` (SI)."""
        v = self.values
        kwargs: dict[str, Any] = {
            "duration": float(v.get("duration", 1.0)),
            "dt": float(v.get("dt", 1e-3)),
            "torques": self.signals("torque"),
            "speeds": self.signals("speed"),
            "initial_speeds": {k: float(x) * RPM for k, x in v.get("initial_speed", {}).items()},
            "meshes": dict(v.get("mesh", {})),
            "position_errors": {
                k: (p[0] * 1e-6, p[1] * 1e-6) for k, p in v.get("position_error", {}).items()
            },  # fmt: skip
        }
        if "generator" in v:
            kwargs["generators"] = self.generators()
        if "rotor" in v:
            kwargs["rotors"] = self.rotors()
            kwargs["wind"] = self.wind()
        return kwargs

    def record(self) -> dict[str, Any]:
        """What the log stores: the values, where they come from, the base folder."""
        return {"values": copy.deepcopy(self.values), "source": self.source,
                "base": str(self.base.resolve())}  # fmt: skip


def _strip(message: str, prefix: str) -> str:
    return message[len(prefix) :] if message.startswith(prefix) else message


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file.

    Raises:
        ScenarioError: unreadable TOML, unknown key, wrong type, missing model, ...
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise ScenarioError(str(path), "-", 0, f"cannot read it: {err.strerror or err}") from err
    try:
        values = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        m = re.search(r"line (\d+)", str(err))
        raise ScenarioError(str(path), "-", int(m.group(1)) if m else 0,
                            f"not valid TOML: {err}") from err  # fmt: skip
    return Scenario(values, source=str(path), base=path.parent, text=text).check()


def from_record(record: Mapping[str, Any], source: str) -> Scenario:
    """The scenario a log stored (``Scenario.record``)."""
    return Scenario(dict(record["values"]), source=source, base=Path(record["base"])).check()


# --- the command line's flags as scenario values ------------------------------------------------


def parse_call(text: str, option: str, default_key: str) -> dict[str, Any]:
    """``name(key=value, ...)`` or ``name`` → ``{default_key: name, key: value, ...}``."""
    try:
        node = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as err:
        raise InputError(f'{option}: cannot read "{text}": {err.msg}') from err
    if isinstance(node, ast.Name):
        return {default_key: node.id}
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.args:
        out: dict[str, Any] = {} if node.func.id == "rotor" else {default_key: node.func.id}
        for kw in node.keywords:
            if kw.arg is None:  # **{...}
                raise InputError(
                    f'{option}: in "{text}", give the parameters as key=value, not as **{{...}}'
                )
            try:
                out[kw.arg] = ast.literal_eval(kw.value)
            except ValueError as err:
                raise InputError(
                    f'{option}: in "{text}", {kw.arg} must be a number or a quoted text'
                ) from err
        return out
    raise InputError(f'{option}: "{text}" must look like NAME(key=value, ...)')


def generator_values(items: Mapping[str, str], option: str = "--generator") -> dict[str, Any]:
    """``JOINT=LAW(params)`` → ``generator`` values (``law`` first: linear-slip is a name)."""
    out = {}
    for joint, text in items.items():
        law, sep, rest = text.partition("(")
        call = parse_call("x(" + rest if sep else "x", option, "law")
        call["law"] = law.strip()
        out[joint] = call
    return out


def rotor_values(items: Mapping[str, str], option: str = "--rotor") -> dict[str, Any]:
    """``JOINT=PRESET`` or ``JOINT=rotor(params)`` → ``rotor`` values."""
    return {joint: parse_call(text, option, "preset") for joint, text in items.items()}


def run(
    scenario: Scenario,
    *,
    gearbox: Any = None,
    out: str | Path | None = None,
    force: bool | None = None,
    no_log: bool | None = None,
    command: str | None = None,
    progress: bool | None = None,
    check_joints: bool = True,
) -> Any:
    """Run a scenario: load its model (unless given), simulate, log it with its values.

    Args:
        gearbox: the model, if already loaded (``--from-log`` passes the logged model).
        out, force, no_log: override the scenario's ``out``, ``force`` and ``no_log``.
        command: the command line to record.
        check_joints: refuse loads on unknown joints here, naming the scenario key (the command
            line leaves that to ``simulate``, whose message names the option).

    Returns:
        The ``Result``.
    """
    import pinwind
    from pinwind.io.log_writer import POSE_RATE, VIEW_RATE
    from pinwind.io.run import log_path

    v = scenario.values
    if gearbox is None:
        path = scenario.model_path()
        if not path.is_file():
            raise scenario.fail(("model",), f"{path} does not exist")
        gearbox = pinwind.load(path)
    if check_joints:
        scenario.check_joints(list(gearbox.joint_names), list(gearbox.locked_joints))
    skip = v.get("no_log", False) if no_log is None else no_log
    target = out if out is not None else v.get("out")
    log = None if skip else log_path(target if target is not None else True, gearbox.name)
    return pinwind.simulate(
        gearbox,
        log=log,
        log_rate=v.get("log_rate"),
        pose_rate=v.get("pose_rate", POSE_RATE),
        view_rate=v.get("view_rate", VIEW_RATE),
        allow_large_log=v.get("allow_large_log", False),
        keep=v.get("keep", "auto"),
        overwrite=v.get("force", False) if force is None else force,
        command=command,
        progress=progress,
        metadata={"scenario": scenario.record()},
        **scenario.simulate_kwargs(),
    )


def cli_values(
    *,
    model: str,
    torque: Mapping[str, str],
    speed: Mapping[str, str],
    speed_sine: Mapping[str, str],
    initial_speed: Mapping[str, str],
    mesh: Mapping[str, str],
    position_error: Mapping[str, str],
    generator: Mapping[str, str],
    rotor: Mapping[str, str],
    wind: str | None,
    duration: float,
    dt: float,
    log_rate: float | None,
    pose_rate: float | None = None,
    view_rate: float | None = None,
    allow_large_log: bool = False,
    keep: str | int = "auto",
) -> dict[str, Any]:
    """``pinwind simulate``'s flags (already split into JOINT → text) as scenario values."""

    def value(text: str) -> Any:
        try:
            return float(text)
        except ValueError:
            return text

    values: dict[str, Any] = {"model": model, "duration": duration, "dt": dt}
    if torque:
        values["torque"] = {k: value(t) for k, t in torque.items()}
    speeds = {k: value(t) for k, t in speed.items()}
    for joint, text in speed_sine.items():
        mean, amplitude, frequency = (float(x) for x in text.split(","))
        speeds[joint] = f"sine(mean={mean!r}, amplitude={amplitude!r}, frequency={frequency!r})"
    if speeds:
        values["speed"] = speeds
    if initial_speed:
        values["initial_speed"] = {k: float(t) for k, t in initial_speed.items()}
    if mesh:
        values["mesh"] = dict(mesh)
    if position_error:
        values["position_error"] = {
            k: [float(x) for x in t.split(",")] for k, t in position_error.items()
        }
    if generator:
        values["generator"] = generator_values(generator)
    if rotor:
        values["rotor"] = rotor_values(rotor)
    if wind is not None:
        values["wind"] = value(wind)
    if log_rate is not None:
        values["log_rate"] = log_rate
    if pose_rate is not None:
        values["pose_rate"] = pose_rate
    if view_rate is not None:
        values["view_rate"] = view_rate
    if allow_large_log:
        values["allow_large_log"] = True
    if keep != "auto":
        values["keep"] = keep
    return values


def from_log(path: str | Path) -> tuple[Scenario, Any]:
    """The scenario and the model a log stored: repeat the run with ``run(scenario, gearbox=...)``.

    The model is rebuilt from the file the log holds (not from the model path, which may have
    changed since); files the signals read are checked against the sha256 the log keeps.

    Raises:
        LogError: not a pinwind log; InputError: a log written without a scenario (before
            scenarios existed, or by ``pinwind.simulate`` from Python).
    """
    from pinwind.io.log_reader import LogReader
    from pinwind.model.gearbox import loads

    with LogReader(path) as reader:
        run_meta = reader.metadata["pinwind.run"]
        attachments = reader.attachments
    record = run_meta.get("scenario")
    if not record:
        raise InputError(
            f"{path}: the log holds no scenario (written from Python, or by an older pinwind); "
            "only runs of `pinwind simulate` and `pinwind run` can be repeated"
        )
    if not attachments:
        raise InputError(f"{path}: the log holds no model file")
    text = next(iter(attachments.values())).decode("utf-8")
    gearbox = loads(text, path=str(run_meta.get("model_path", "model.urdf")))
    return from_record(record, source=f"log {path}"), gearbox
