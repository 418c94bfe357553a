"""The flags of the commands that run: their text as scenario values, and their shared options.

Units at this edge are the ones drivetrain engineers type: N·m, rpm, µm, Hz. The flags become the
values of a scenario file (``pinwind/runs/scenario.py``), which builds the run from them; errors
in the text of a flag name the flag.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path
from typing import Annotated, Any

import typer

from pinwind.errors import ConflictingInputs, InputError


def parse_pairs(items: list[str] | None, option: str) -> dict[str, str]:
    """Repeated ``JOINT=VALUE`` options → {joint: value text}.

    Raises:
        InputError: an item without ``=``, name or value. ConflictingInputs: a joint twice.
    """
    out: dict[str, str] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise InputError(f'{option} "{item}" must look like JOINT=VALUE, e.g. carrier=1e6')
        name = name.strip()
        if name in out:
            raise ConflictingInputs(
                f'{option} gives joint "{name}" twice ({out[name]} and {value.strip()}); give '
                "each joint once (the values are not added, and neither wins silently)"
            )
        out[name] = value.strip()
    return out


def _disjoint(**given: dict) -> None:
    """Refuse a joint that two of the options name (e.g. --speed and --speed-sine)."""
    options = list(given.items())
    for i, (first, a) in enumerate(options):
        for second, b in options[i + 1 :]:
            both = sorted(set(a) & set(b))
            if both:
                raise ConflictingInputs(
                    f'joint "{both[0]}" is given both in {first} and in {second}; a joint has one '
                    "speed: give it in one of them"
                )


def parse_number(text: str, option: str, unit: str) -> float:
    """A finite number given to an option [unit].

    Raises:
        InputError: not a number, or not finite, naming the option and the unit.
    """
    try:
        value = float(text)
    except ValueError as err:
        raise InputError(f'{option}: "{text}" is not a number [{unit}]') from err
    if not math.isfinite(value):
        raise InputError(f"{option}: {text} is not finite; give a number [{unit}]")
    return value


def _number_or_signal(text: str, option: str, unit: str) -> float | str:
    """A number [unit], or a signal's text form (``sine(mean=..., ...)``, built by the scenario)."""
    return text if "(" in text else parse_number(text, option, unit)


def number_or_text(text: str) -> float | str:
    """A number, or the text for the scenario to read (``--wind``)."""
    try:
        return float(text)
    except ValueError:
        return text


def load_values(
    torque: list[str] | None,
    speed: list[str] | None,
    speed_sine: list[str] | None,
    initial_speed: list[str] | None = None,
) -> dict[str, Any]:
    """CLI load options → scenario values ``torque`` [N·m], ``speed``, ``initial_speed`` [rpm].

    Raises:
        InputError: a malformed or non-finite value.
        ConflictingInputs: a joint given twice in one option, in two speed options, or in
            --torque and a speed option.
    """
    torque_text = parse_pairs(torque, "--torque")
    torques = {k: _number_or_signal(v, "--torque", "N·m") for k, v in torque_text.items()}
    steady = parse_pairs(speed, "--speed")
    sines = parse_pairs(speed_sine, "--speed-sine")
    initial = parse_pairs(initial_speed, "--initial-speed")
    _disjoint(**{"--speed": steady, "--speed-sine": sines, "--initial-speed": initial})
    speeds: dict[str, float | str] = {
        k: _number_or_signal(v, "--speed", "rpm") for k, v in steady.items()
    }
    for name, value in sines.items():
        parts = value.split(",")
        if len(parts) != 3:
            raise InputError(
                f'--speed-sine "{name}={value}" must be JOINT=MEAN_RPM,AMPLITUDE_RPM,FREQUENCY_HZ'
            )
        mean, amplitude = (parse_number(p, "--speed-sine", "rpm") for p in parts[:2])
        frequency = parse_number(parts[2], "--speed-sine", "Hz")
        speeds[name] = f"sine(mean={mean!r}, amplitude={amplitude!r}, frequency={frequency!r})"
    for name in torques:
        if name in speeds:
            flag, text = ("--speed", steady) if name in steady else ("--speed-sine", sines)
            raise ConflictingInputs(
                f'joint "{name}" is given both --torque {name}={torque_text[name]} and '
                f"{flag} {name}={text[name]}; the speed driver would absorb the torque, which "
                f"then loads no gear (every mesh force 0): give the joint either --torque or {flag}"
            )
    values: dict[str, Any] = {}
    if torques:
        values["torque"] = torques
    if speeds:
        values["speed"] = speeds
    if initial:
        values["initial_speed"] = {
            k: parse_number(v, "--initial-speed", "rpm") for k, v in initial.items()
        }
    return values


#: Load options shared by the commands that simulate (simulate, rate).
TorqueOption = Annotated[
    list[str] | None,
    typer.Option(
        "--torque",
        "-t",
        help="JOINT=N·m applied torque, a number or a signal: ramp(...), step(...), "
        "sine(...), csv(file=...), openfast(file=..., channel=..., scale=...), sums with + "
        "(repeatable).",
    ),
]
SpeedOption = Annotated[
    list[str] | None,
    typer.Option(
        "--speed", "-s", help="JOINT=RPM prescribed joint speed, a number or a signal [rpm]."
    ),
]
InitialSpeedOption = Annotated[
    list[str] | None,
    typer.Option(
        "--initial-speed",
        help="JOINT=RPM starting speed (repeatable); the other joints start at the speeds "
        "the gears impose.",
    ),
]
DurationOption = Annotated[float, typer.Option(help="Simulated time [s].")]
StepOption = Annotated[float, typer.Option(help="Time step [s].")]

MESH_CHOICES = ("rigid", "compliant")


def mesh_values(items: list[str] | None) -> dict[str, str]:
    """``--mesh NAME=rigid|compliant`` options → ``mesh`` values."""
    out = {}
    for name, value in parse_pairs(items, "--mesh").items():
        if value not in MESH_CHOICES:
            raise InputError(
                f'--mesh "{name}={value}": the type must be one of {", ".join(MESH_CHOICES)}'
            )
        out[name] = value
    return out


def parse_keep(text: str) -> str | int:
    """``--keep all|last|auto|N`` → ``simulate(keep=...)``."""
    text = text.strip().lower()
    if text in ("all", "last", "auto"):
        return text
    try:
        return int(text)
    except ValueError:
        raise InputError(
            f'--keep "{text}" must be all, last, auto or a whole number N ≥ 1 (every N-th sample)'
        ) from None


def position_error_values(items: list[str] | None) -> dict[str, list[float]]:
    """``--position-error GEAR=T_UM,R_UM`` options → ``position_error`` values [µm]."""
    out = {}
    for name, value in parse_pairs(items, "--position-error").items():
        parts = value.split(",")
        if len(parts) != 2:
            raise InputError(
                f'--position-error "{name}={value}" must be GEAR=TANGENTIAL_UM,RADIAL_UM'
            )
        out[name] = [parse_number(p, "--position-error", "µm") for p in parts]
    return out


def parse_position_errors(items: list[str] | None) -> dict[str, tuple[float, float]]:
    """``--position-error`` options → (tangential, radial) errors [m], as a run takes them."""
    from pinwind.runs import scenario as sc

    values = {"model": "", "position_error": position_error_values(items)}
    return dict(sc.build(values, flags=FLAGS).position_errors)


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


def generator_values(items: list[str] | None) -> dict[str, Any]:
    """``--generator JOINT=LAW(params)`` → ``generator`` values (``law``: linear-slip is a name)."""
    out = {}
    for joint, text in parse_pairs(items, "--generator").items():
        law, sep, rest = text.partition("(")
        call = parse_call("x(" + rest if sep else "x", "--generator", "law")
        call["law"] = law.strip()
        out[joint] = call
    return out


def rotor_values(items: list[str] | None) -> dict[str, Any]:
    """``--rotor JOINT=PRESET`` or ``JOINT=rotor(params)`` → ``rotor`` values."""
    return {joint: parse_call(text, "--rotor", "preset")
            for joint, text in parse_pairs(items, "--rotor").items()}  # fmt: skip


def hub_load_values(items: list[str] | None) -> dict[str, Any]:
    """``--hub-load`` options → ``hub_load`` values (a scenario's ``[hub_load.BODY]`` keys).

    Each is ``BODY=hub_load(force_x=, ..., point=(x, y, z))`` or ``BODY=openfast(file=)``.
    """
    out = {}
    for body, text in parse_pairs(items, "--hub-load").items():
        call = parse_call(text, "--hub-load", "kind")
        kind = call.pop("kind")
        if kind == "openfast":
            if "file" not in call:
                raise InputError(f'--hub-load "{body}={text}": give openfast(file="run.outb")')
            call["openfast"] = call.pop("file")
        elif kind != "hub_load":
            raise InputError(
                f'--hub-load "{body}={text}": give BODY=hub_load(force_x=..., moment_y=..., '
                'point=(x, y, z), up=(x, y, z), frame="fixed") or BODY=openfast(file=...)'
            )
        out[body] = {k: list(v) if isinstance(v, tuple) else v for k, v in call.items()}
    return out


def parse_window(text: str) -> tuple[float, float]:
    """``--check-window A:B`` → (A, B) [s]."""
    start, sep, end = text.partition(":")
    if not sep:
        raise InputError(f'--check-window "{text}" must look like START:END in seconds, e.g. 9:10')
    return parse_number(start, "--check-window", "s"), parse_number(end, "--check-window", "s")


CheckDtOption = Annotated[
    bool,
    typer.Option(
        "--check-dt",
        help="Instead of one run, rerun at dt, dt/2 and dt/4 and print, over a window, how the "
        "mesh and bearing forces change and the observed order: is the run converged in dt? "
        "No log is written.",
    ),
]
CheckWindowOption = Annotated[
    str | None,
    typer.Option(
        "--check-window",
        help="START:END window [s] that --check-dt compares; default the last 10 % of the run "
        "(at least 3 mesh periods).",
    ),
]
JsonOption = Annotated[
    bool, typer.Option("--json", help="With --check-dt: print JSON instead of the table.")
]


#: Scenario keys whose signals come from these options: their errors name the option.
FLAGS = {"torque": "--torque", "speed": "--speed"}


# The Rerun viewer's options, shared by `replay` and `view`.
SaveOption = Annotated[
    Path | None, typer.Option("--save", help="Write a Rerun .rrd file instead of viewing.")
]
ServeOption = Annotated[
    bool,
    typer.Option(
        "--serve",
        "--web",
        help="Serve the Rerun web viewer instead of spawning one: open the address it prints "
        "in a browser, here or over an SSH tunnel to both ports (a machine without a display).",
    ),
]
WebPortOption = Annotated[
    int | None, typer.Option(help="Web viewer port (with --serve; default 9090).")
]
GrpcPortOption = Annotated[
    int | None, typer.Option(help="Data (gRPC) port (with --serve; default 9876).")
]


def check_reliability_percent(
    value: float, low: float, high: float, *, open_low: bool, option: str = "--reliability-percent"
) -> None:
    """Refuse a reliability [%] outside [low, high] % ((low, high] with ``open_low``).

    The message names the value and the range; a value in (0, 1] is named as the fraction it
    probably is, with its percent.

    Raises:
        InputError: the value is outside the range (or not a number).
    """
    inside = (low < value if open_low else low <= value) and value <= high
    if inside:
        return
    bound = f"{low:g} < R ≤ {high:g}" if open_low else f"{low:g} ≤ R ≤ {high:g}"
    hint = (
        f" ({value:g} looks like a fraction: {100 * value:g} % is --reliability-percent "
        f"{100 * value:g})"
        if 0.0 < value <= 1.0
        else ""
    )
    raise InputError(f"{option} {value:g}: give a reliability R in percent, {bound} %{hint}")
