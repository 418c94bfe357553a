"""Command-line interface: ``simulate``, ``run``, ``replay``, ``plot``, ``report``, ``build``, ...

Units at this edge are the ones drivetrain engineers type: rpm, mm, degrees; everything is turned
into SI before it reaches the library. ``simulate`` logs every run to an MCAP file (``logs/`` by
default) that ``replay`` and ``report`` read back on their own.
"""

from __future__ import annotations

import ast
import math
import shlex
import signal
import sys
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any, cast

import typer
from rich.console import Console
from rich.markup import escape

from pinwind.errors import (
    ConflictingInputs,
    InputError,
    LogWriteFailed,
    PinwindError,
    PinwindWarning,
)
from pinwind.loads.generator import LAWS
from pinwind.scenario import RPM_TO_RAD_PER_S

app = typer.Typer(
    name="pinwind",
    help="Loads inside wind-turbine gearboxes: gear-mesh forces and bearing reactions.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Help texts are plain: "[s]" and "[rpm]" are units, not rich markup.
    rich_markup_mode=None,
)
build_app = typer.Typer(
    help="Write parametric gearbox models.", no_args_is_help=True, rich_markup_mode=None
)
app.add_typer(build_app, name="build")
sweep_app = typer.Typer(
    help="Design sweeps: enumerate, simulate, rate, query.", no_args_is_help=True
)
app.add_typer(sweep_app, name="sweep")

# Tables fit 80 columns (a terminal's width; 80 in pipes); pipes get plain ASCII tables.
console = Console()
# Errors and warnings are one line each, never hard-wrapped, so they can be copied whole.
err_console = Console(stderr=True, soft_wrap=True)


def say(text: str) -> None:
    """Print a line of text whole (never hard-wrapped, so it can be copied)."""
    console.print(text, soft_wrap=True, highlight=False)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that the run stops cleanly and its log is finished."""


def _raise_terminated(signum, frame) -> None:
    raise Terminated(f"received {signal.Signals(signum).name}")


def _stamp(path: Path) -> tuple[int, int] | None:
    """Size and modification time of a file, None if it does not exist."""
    try:
        stat = path.stat()
    except OSError:
        return None
    return stat.st_size, stat.st_mtime_ns


def _pairs(items: list[str] | None, option: str) -> dict[str, str]:
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


def _float(text: str, option: str, unit: str) -> float:
    try:
        value = float(text)
    except ValueError as err:
        raise InputError(f'{option}: "{text}" is not a number [{unit}]') from err
    if not math.isfinite(value):
        raise InputError(f"{option}: {text} is not finite; give a number [{unit}]")
    return value


def _number_or_signal(text: str, option: str, unit: str) -> float | str:
    """A number [unit], or a signal's text form (``sine(mean=..., ...)``, built by the scenario)."""
    return text if "(" in text else _float(text, option, unit)


def _number_or_text(text: str) -> float | str:
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
        ConflictingInputs: a joint given twice in one option, or in two speed options.
    """
    torques = {
        k: _number_or_signal(v, "--torque", "N·m") for k, v in _pairs(torque, "--torque").items()
    }
    steady = _pairs(speed, "--speed")
    sines = _pairs(speed_sine, "--speed-sine")
    initial = _pairs(initial_speed, "--initial-speed")
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
        mean, amplitude = (_float(p, "--speed-sine", "rpm") for p in parts[:2])
        frequency = _float(parts[2], "--speed-sine", "Hz")
        speeds[name] = f"sine(mean={mean!r}, amplitude={amplitude!r}, frequency={frequency!r})"
    values: dict[str, Any] = {}
    if torques:
        values["torque"] = torques
    if speeds:
        values["speed"] = speeds
    if initial:
        values["initial_speed"] = {
            k: _float(v, "--initial-speed", "rpm") for k, v in initial.items()
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

#: Options shared by the sweep commands.
SweepTable = Annotated[
    Path, typer.Option("--output", "-o", help="Table to write (.csv or .parquet).")
]
SweepWorkers = Annotated[
    int | None, typer.Option(help="Local worker processes (default: all cores).")
]
SweepScheduler = Annotated[
    str | None, typer.Option(help="Dask scheduler address, e.g. tcp://head:8786.")
]

#: The time window of commands that read a log: --from T0 --to T1 [s], both inclusive.
WindowStart = Annotated[
    float | None, typer.Option("--from", help="Start of the window [s] (inclusive).")
]
WindowStop = Annotated[
    float | None, typer.Option("--to", help="End of the window [s] (inclusive).")
]

MESH_CHOICES = ("rigid", "compliant")


def mesh_values(items: list[str] | None) -> dict[str, str]:
    """``--mesh NAME=rigid|compliant`` options → ``mesh`` values."""
    out = {}
    for name, value in _pairs(items, "--mesh").items():
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
    for name, value in _pairs(items, "--position-error").items():
        parts = value.split(",")
        if len(parts) != 2:
            raise InputError(
                f'--position-error "{name}={value}" must be GEAR=TANGENTIAL_UM,RADIAL_UM'
            )
        out[name] = [_float(p, "--position-error", "µm") for p in parts]
    return out


def parse_position_errors(items: list[str] | None) -> dict[str, tuple[float, float]]:
    """``--position-error`` options → (tangential, radial) errors [m], as a run takes them."""
    from pinwind import scenario as sc

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
    for joint, text in _pairs(items, "--generator").items():
        law, sep, rest = text.partition("(")
        call = parse_call("x(" + rest if sep else "x", "--generator", "law")
        call["law"] = law.strip()
        out[joint] = call
    return out


def rotor_values(items: list[str] | None) -> dict[str, Any]:
    """``--rotor JOINT=PRESET`` or ``JOINT=rotor(params)`` → ``rotor`` values."""
    return {joint: parse_call(text, "--rotor", "preset")
            for joint, text in _pairs(items, "--rotor").items()}  # fmt: skip


#: Scenario keys whose signals come from these options: their errors name the option.
FLAGS = {"torque": "--torque", "speed": "--speed"}


@app.command()
def simulate(
    model: Annotated[Path, typer.Argument(help="Gearbox model file (URDF with <gearbox>).")],
    torque: TorqueOption = None,
    speed: SpeedOption = None,
    speed_sine: Annotated[
        list[str] | None,
        typer.Option(
            "--speed-sine", help="JOINT=MEAN_RPM,AMPLITUDE_RPM,FREQUENCY_HZ sinusoidal driver."
        ),
    ] = None,
    initial_speed: InitialSpeedOption = None,
    duration: DurationOption = 1.0,
    dt: StepOption = 1e-3,
    progress: Annotated[
        bool | None, typer.Option("--progress/--no-progress", help="Progress bar.")
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            "-o",
            help="MCAP log to write (a bare file name goes in logs/). Default: "
            "logs/<model>_<UTC time>.mcap.",
        ),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing log.")] = False,
    log_rate: Annotated[
        float | None,
        typer.Option("--log-rate", help="Logged samples per simulated second [Hz]; default all."),
    ] = None,
    no_log: Annotated[bool, typer.Option("--no-log", help="Do not write a log.")] = False,
    pose_rate: Annotated[
        float,
        typer.Option("--pose-rate", help="Logged link poses (/tf) per simulated second [Hz]."),
    ] = 100.0,
    view_rate: Annotated[
        float,
        typer.Option(
            "--view-rate",
            help="Samples per simulated second on the topics Rerun and Foxglove plot when they "
            "open the log [Hz] (pinwind reads every logged sample).",
        ),
    ] = 100.0,
    allow_large_log: Annotated[
        bool,
        typer.Option(
            "--allow-large-log",
            help="Write the log even if it would exceed 20 GB or the free disk space.",
        ),
    ] = False,
    mesh: Annotated[
        list[str] | None,
        typer.Option(
            "--mesh",
            help="MESH=rigid or MESH=compliant (MESH may be all; repeatable). Default: the model "
            "file's type of each mesh.",
        ),
    ] = None,
    keep: Annotated[
        str,
        typer.Option(
            "--keep",
            help="Samples kept in memory: all, last, auto (every sample while they fit in "
            "512 MB, else every N-th) or a number N (every N-th). The log holds every sample "
            "either way, and the summary's min / max / RMS are over every sample.",
        ),
    ] = "auto",
    position_error: Annotated[
        list[str] | None,
        typer.Option(
            "--position-error",
            help="GEAR=TANGENTIAL_UM,RADIAL_UM position error of a planet's centre [µm] "
            "(repeatable); compliant meshes share the load accordingly.",
        ),
    ] = None,
    generator: Annotated[
        list[str] | None,
        typer.Option(
            "--generator",
            help="JOINT=LAW(params): " + ", ".join(kind.usage for kind in LAWS.values()) + ".",
        ),
    ] = None,
    rotor: Annotated[
        list[str] | None,
        typer.Option(
            "--rotor",
            help="JOINT=saleh2017 or JOINT=rotor(radius=, inertia=, air_density=, pitch_deg=, "
            "cp_scale=): rotor aerodynamics driven by --wind.",
        ),
    ] = None,
    wind: Annotated[
        str | None,
        typer.Option(
            "--wind",
            help="Wind speed at the rotor [m/s]: a number or a signal, e.g. "
            "kaimal(mean=10, turbulence_intensity=0.1, seed=1).",
        ),
    ] = None,
) -> None:
    """Simulate a gearbox model, log it to MCAP, print speeds, mesh forces, bearing reactions."""
    import pinwind
    from pinwind import scenario as sc
    from pinwind.io.run import log_path

    values: dict[str, Any] = {"model": str(model), "duration": duration, "dt": dt}
    values |= load_values(torque, speed, speed_sine, initial_speed)
    optional = {
        "mesh": mesh_values(mesh),
        "position_error": position_error_values(position_error),
        "generator": generator_values(generator),
        "rotor": rotor_values(rotor),
        "wind": None if wind is None else _number_or_text(wind),
        "log_rate": log_rate,
        "pose_rate": pose_rate,
        "view_rate": view_rate,
        "allow_large_log": allow_large_log or None,
        "keep": None if (kept := parse_keep(keep)) == "auto" else kept,
    }
    values |= {k: v for k, v in optional.items() if v is not None and v != {}}
    scenario = sc.build(values, flags=FLAGS)
    with _warnings_as_lines():
        gearbox = pinwind.load(model)
    log = None if no_log else log_path(out if out is not None else True, gearbox.name)
    command = shlex.join(["pinwind", *sys.argv[1:]])
    _run_and_report(
        scenario, gearbox, str(model), log, command, progress=progress, force=force,
        check_joints=False,
    )  # fmt: skip


def _run_and_report(
    scenario,
    gearbox,
    label: str,
    log: Path | None,
    command: str,
    *,
    progress,
    force,
    check_joints: bool = True,
) -> None:
    """Run a scenario and print its tables (``simulate`` and ``run``)."""
    import numpy as np

    from pinwind import scenario as sc
    from pinwind.analysis import load_sharing
    from pinwind.analysis.summary import summary_tables

    before = _stamp(log) if log is not None else None
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        with _warnings_as_lines():
            res = sc.run(
                scenario, gearbox=gearbox, out=log, no_log=log is None, force=force,
                command=command, progress=progress, check_joints=check_joints,
            )  # fmt: skip
    except (KeyboardInterrupt, PinwindError) as err:
        written = not isinstance(err, LogWriteFailed)  # that message says what the file holds
        if written and log is not None and _stamp(log) not in (None, before):
            err_console.print(
                f"the run stopped early; its log up to that point is in {escape(str(log))}"
            )
        if isinstance(err, Terminated):
            err_console.print(f"terminated ({escape(str(err))})")
            raise typer.Exit(code=143) from err
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
    dt = res.metadata["dt"]
    say(f"[bold]{escape(gearbox.name)}[/bold] from {escape(label)}")
    steps = res.metadata["samples_simulated"] - 1
    residual = res.constraint_residual.max()
    if res.statistics is not None:
        residual = res.statistics.row("run", "", "constraint residual").max
    say(
        f"{steps} steps of {dt:g} s in {res.metadata['wall_time_s']:.2f} s "
        f"({res.metadata['wall_time_s'] / max(steps, 1) * 1e6:.0f} µs/step); "
        f"max |J v| = {residual:.2e}"
    )
    stride = res.metadata.get("keep_stride", 1)
    if stride > 1:
        say(
            f"values at the end below are of the last sample; min / max / RMS are over every "
            f"one of the {res.metadata['samples_simulated']} samples, of which the result "
            f"keeps {len(res)} (every {stride}-th, --keep)"
            + ("; the log holds them all (pinwind report LOG)" if log is not None else "")
        )
    for table in summary_tables(res, plain=not console.is_terminal):
        console.print()
        console.print(table)
    compliant = {n for n, m in res.metadata.get("meshes", {}).items() if m["type"] != "rigid"}
    for sharing in load_sharing(res, gearbox):
        # Rigid planets share equally by construction (minimum-norm multipliers).
        if np.isfinite(sharing.factor_max) and compliant & set(sharing.meshes):
            say(
                f"load sharing at the {sharing.gear}: K_γ = {sharing.mean_share.max():.4f} "
                f"(mean loads), {sharing.factor_max:.4f} "
                f"(worst {'kept ' if stride > 1 else ''}sample)"
            )
    if log is not None:
        say(f"log: {escape(str(log))} ({log.stat().st_size / 1e6:.2f} MB)")


@app.command("run")
def run_scenario(
    scenario_file: Annotated[
        Path | None, typer.Argument(help="Scenario file (TOML; keys named like simulate's flags).")
    ] = None,
    from_log: Annotated[
        Path | None,
        typer.Option("--from-log", help="Repeat the run a log holds, bit for bit."),
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option("--out", "-o", help="MCAP log to write (default: the scenario's out)."),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing log.")] = False,
    no_log: Annotated[bool, typer.Option("--no-log", help="Do not write a log.")] = False,
    progress: Annotated[
        bool | None, typer.Option("--progress/--no-progress", help="Progress bar.")
    ] = None,
) -> None:
    """Run a scenario file, or repeat a logged run with --from-log LOG."""
    import pinwind
    from pinwind import scenario as sc
    from pinwind.io.run import log_path

    if (scenario_file is None) == (from_log is None):
        raise InputError("give a scenario file or --from-log LOG (one of them)")
    with _warnings_as_lines():
        if from_log is not None:
            scenario, gearbox = sc.from_log(from_log)
            label = f"the run logged in {from_log}"
            target = out if out is not None else True  # never the logged file itself
        else:
            # Exactly one of scenario_file and from_log is given (checked above).
            scenario = sc.load_scenario(cast(Path, scenario_file))
            path = scenario.model_path()
            if not path.is_file():
                raise scenario.fail(("model",), f"{path} does not exist")
            gearbox = pinwind.load(path)
            label = str(scenario_file)
            target = out if out is not None else scenario.values.get("out", True)
    skip = no_log or (out is None and bool(scenario.values.get("no_log", False)))
    log = None if skip else log_path(target, gearbox.name)
    if from_log is not None and log is not None and log.resolve() == from_log.resolve():
        raise InputError(f"--out {log} is the log being repeated; choose another file")
    command = shlex.join(["pinwind", *sys.argv[1:]])
    _run_and_report(
        scenario, gearbox, label, log, command, progress=progress,
        force=force or bool(scenario.values.get("force", False)) and from_log is None,
    )  # fmt: skip


@contextmanager
def _warnings_as_lines() -> Iterator[None]:
    """Show pinwind warnings (a recovered log, ...) as one line on stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PinwindWarning)
        try:
            yield
        finally:
            shown = list(caught)
    for warning in shown:
        if issubclass(warning.category, PinwindWarning):
            err_console.print(
                f"[yellow]warning:[/yellow] {escape(str(warning.message))}", highlight=False
            )
        else:
            warnings.warn_explicit(
                warning.message, warning.category, warning.filename, warning.lineno
            )


@contextmanager
def _reading(log: Path, what: str) -> Iterator[Callable[[float, float], None]]:
    """A progress bar over the simulated time of a log as it is read (stderr, a terminal only).

    Yields the callback that ``LogReader.blocks`` takes: (simulated time read, of the window) [s].
    """
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    if not err_console.is_terminal:  # piped: nothing to redraw, and stderr stays the messages
        yield lambda done, total: None
        return
    columns = (
        TextColumn(f"{what} {escape(log.name)}"),
        BarColumn(),
        TextColumn("{task.fields[simulated]}"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=err_console, transient=True) as bar:
        task = bar.add_task(what, total=None, simulated="")

        def advance(done: float, total: float) -> None:
            simulated = f"{done:.1f}/{total:.1f} s simulated"
            bar.update(task, completed=done, total=total, simulated=simulated)

        yield advance


@app.command()
def replay(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    save: Annotated[
        Path | None, typer.Option("--save", help="Write a Rerun .rrd file instead of viewing.")
    ] = None,
    serve: Annotated[
        bool, typer.Option("--serve", help="Serve the Rerun web viewer instead of spawning one.")
    ] = False,
    web_port: Annotated[
        int | None, typer.Option(help="Web viewer port (with --serve; default 9090).")
    ] = None,
    grpc_port: Annotated[
        int | None, typer.Option(help="Data (gRPC) port (with --serve; default 9876).")
    ] = None,
    start: Annotated[
        float | None, typer.Option("--from", help="Send every sample from this time on [s].")
    ] = None,
    stop: Annotated[
        float | None, typer.Option("--to", help="Send every sample up to this time [s].")
    ] = None,
    points: Annotated[
        int, typer.Option("--points", help="Samples per plotted series in the overview.")
    ] = 2000,
) -> None:
    """Show a log in Rerun: gears turning, force arrows and plots, from the file alone.

    The whole run comes as an overview (the smallest and largest sample of each series in each
    of --points/2 time spans); --from/--to add every sample of that window.
    """
    from pinwind.io.replay import replay as run_replay

    with _warnings_as_lines(), _reading(log, "reading") as progress:
        out = run_replay(
            log, save=save, serve=serve, web_port=web_port, grpc_port=grpc_port,
            start=start, stop=stop, points=points, announce=say, progress=progress,
        )  # fmt: skip
    if out is not None:
        say(f"wrote {escape(str(out))}")


@app.command()
def plot(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    out_dir: Annotated[
        Path, typer.Option("--out-dir", "-o", help="Folder for the figures.")
    ] = Path("figures"),
    start: WindowStart = None,
    stop: WindowStop = None,
    fmt: Annotated[
        str, typer.Option("--format", help="png, svg or pdf (the files' extension).")
    ] = "png",
) -> None:
    """Figures of a log for reports: speeds, torques, forces, load sharing, energy (PNG)."""
    from pinwind.io.figures import plot_log

    with _warnings_as_lines(), _reading(log, "reading") as progress:
        paths = plot_log(log, out_dir, start=start, stop=stop, format=fmt, progress=progress)
    for path in paths:
        say(f"wrote {escape(str(path))}")


@app.command()
def report(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    start: WindowStart = None,
    stop: WindowStop = None,
) -> None:
    """Min, max, mean, RMS and final value of every quantity in a log."""
    import json

    from pinwind.io.report import report_dict, report_log, report_tables

    with _warnings_as_lines(), _reading(log, "reading") as progress:
        res = report_log(log, start, stop, progress=progress)  # only the window, bounded memory
    if as_json:
        print(json.dumps(report_dict(res), indent=1))
        return
    say(
        f"[bold]{escape(str(res.metadata.get('model_name')))}[/bold] — {escape(str(log))}: "
        f"{escape(res.status)}; dt = {res.metadata.get('dt'):g} s, logged every "
        f"{res.metadata['log']['stride']} sample(s); model sha256 "
        f"{str(res.metadata.get('model_sha256'))[:12]}"
    )
    for table in report_tables(res, start, stop, plain=not console.is_terminal):
        console.print()
        console.print(table)


@app.command()
def export(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    out: Annotated[Path, typer.Option("--out", "-o", help="Table to write (.parquet or .csv).")],
    fmt: Annotated[
        str | None,
        typer.Option("--format", help="parquet or csv (default: from the suffix of --out)."),
    ] = None,
    start: WindowStart = None,
    stop: WindowStop = None,
    channels: Annotated[
        list[str] | None,
        typer.Option(
            "--channels",
            help="Topics to export, comma-separated or repeated (/meshes/normal, /bearings, "
            "/joints, /tf, ...); default all.",
        ),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing table.")] = False,
) -> None:
    """Write a log as a Parquet or CSV table: time_s, then one column per series (SI units)."""
    from pinwind.io.export import export_log

    picked = [c for item in channels for c in item.split(",") if c.strip()] if channels else None
    with _warnings_as_lines(), _reading(log, "exporting") as progress:
        rows, columns = export_log(
            log, out, format=fmt, start=start, stop=stop, channels=picked, overwrite=force,
            progress=progress,
        )  # fmt: skip
    say(f"wrote {escape(str(out))} ({rows} rows × {columns} columns)")


@app.command()
def info(model: Annotated[Path, typer.Argument(help="Gearbox model file.")]) -> None:
    """Load a model, check it, and list its bearings, gears and meshes."""
    import pinwind

    with _warnings_as_lines():
        gb = pinwind.load(model)
    say(repr(gb))
    say("bearings (joints): " + ", ".join(gb.joint_names))
    if gb.locked_joints:
        say("locked (fixed mounts): " + ", ".join(gb.locked_joints))
    from pinwind.dynamics.ratios import speed_ratio

    free = [j for j in gb.joint_names if j not in gb.locked_joints]
    if free:
        try:
            ratios = {j: speed_ratio(gb, j, free[0]) for j in free}
        except InputError as err:
            say(f"speed ratios: {err}")
        else:
            say(
                f"speed ratios to {free[0]} (joint speeds, relative to the parent body): "
                + ", ".join(f"{j} {r:.6g}" for j, r in ratios.items())
            )
    for m in gb.meshes:
        a, b = m.gear_a.spec, m.gear_b.spec
        say(
            f"mesh {m.name}: {a.name} ({a.teeth}) – {b.name} ({b.teeth}"
            f"{', internal' if b.internal else ''}), a_w = {m.centre_distance * 1e3:.4f} mm, "
            f"α_w = {math.degrees(m.working_pressure_angle):.4f}°"
        )


@build_app.command("planetary")
def build_planetary(
    sun: Annotated[int, typer.Option(help="Sun teeth.")],
    planet: Annotated[int, typer.Option(help="Planet teeth.")],
    ring: Annotated[int, typer.Option(help="Ring teeth.")],
    planets: Annotated[int, typer.Option(help="Number of planets.")] = 3,
    module: Annotated[float, typer.Option(help="Module [mm].")] = 15.0,
    pressure_angle: Annotated[float, typer.Option(help="Pressure angle [deg].")] = 20.0,
    face_width: Annotated[float, typer.Option(help="Face width [mm].")] = 200.0,
    parallel: Annotated[
        list[str] | None,
        typer.Option(help="Parallel stage WHEEL/PINION teeth, e.g. 83/23 (repeatable)."),
    ] = None,
    name: Annotated[str, typer.Option(help="Model name.")] = "planetary",
    output: Annotated[Path, typer.Option("--output", "-o", help="Output URDF file.")] = Path(
        "planetary.urdf"
    ),
) -> None:
    """Write a planetary stage (+ parallel stages) with inertias from steel geometry."""
    from pinwind.model.builder import write_planetary

    stages = []
    for item in parallel or []:
        wheel, sep, pinion = item.partition("/")
        try:
            stages.append((int(wheel), int(pinion)))
        except ValueError as err:
            raise InputError(f'--parallel "{item}" must be WHEEL/PINION teeth, e.g. 83/23') from err
        if not sep:
            raise InputError(f'--parallel "{item}" must be WHEEL/PINION teeth, e.g. 83/23')
    path = write_planetary(
        output,
        sun=sun,
        planet=planet,
        ring=ring,
        planets=planets,
        module=module * 1e-3,
        pressure_angle=math.radians(pressure_angle),
        face_width=face_width * 1e-3,
        parallel=stages,
        name=name,
    )
    say(f"wrote {escape(str(path))}")


@app.command()
def rate(
    model: Annotated[Path, typer.Argument(help="Gearbox model file (URDF with <gearbox>).")],
    torque: TorqueOption = None,
    speed: SpeedOption = None,
    initial_speed: InitialSpeedOption = None,
    material: Annotated[
        list[str] | None,
        typer.Option(
            "--material",
            help="GEAR=NAME (18CrNiMo7-6, 42CrMo4, 34CrNiMo6; GEAR may be all); default "
            "18CrNiMo7-6.",
        ),
    ] = None,
    duration: DurationOption = 0.05,
    dt: StepOption = 1e-3,
    at: Annotated[str, typer.Option(help="Load level: last, max or mean of the run.")] = "last",
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Rate every mesh (ISO 6336, AGMA 2001, Hertz) from the forces of a short simulation."""
    import json

    import pinwind
    from pinwind import scenario as sc
    from pinwind.analysis.rating import rate as rate_result
    from pinwind.analysis.rating_table import rating_tables

    values = {"model": str(model), "duration": duration, "dt": dt}
    scenario = sc.build(values | load_values(torque, speed, None, initial_speed), flags=FLAGS)
    gearbox = pinwind.load(model)
    materials = _pairs(material, "--material")
    if "all" in materials:
        chosen = materials.pop("all")
        materials = {g: chosen for g in gearbox.gears} | materials
    with _warnings_as_lines():
        res = sc.run(scenario, gearbox=gearbox, no_log=True, check_joints=False)
    rating = rate_result(gearbox, res, at=at, materials=materials)
    if as_json:
        print(json.dumps(rating.as_dict(), indent=1))
        return
    for table in rating_tables(rating, title=f"{gearbox.name} at t = {res.time[-1]:g} s"):
        console.print(table)
    console.print("all meshes pass" if rating.passes else "[bold red]some meshes fail[/bold red]")


def _numbers(text: str, option: str, unit: str) -> list[float]:
    """Comma-separated numbers, e.g. 420,480,540, as floats."""
    return [_float(p, option, unit) for p in text.split(",") if p.strip()]


def _range(text: str, option: str) -> tuple[float, float]:
    """LOW:HIGH, e.g. 6:6.4, as (6.0, 6.4); a single number x gives (x, x)."""
    low, sep, high = text.partition(":")
    lo = _float(low, option, "-")
    return (lo, _float(high, option, "-") if sep else lo)


def _include(items: list[str] | None) -> list[tuple[int, int, int, float]]:
    """``--include SUN/PLANET/RING@MODULE_MM`` → (sun, planet, ring, module [m])."""
    out = []
    for item in items or []:
        teeth, sep, module = item.partition("@")
        parts = teeth.split("/")
        try:
            sun, planet, ring = (int(p) for p in parts)
            out.append((sun, planet, ring, float(module) * 1e-3))
        except ValueError as err:
            raise InputError(
                f'--include "{item}" must be SUN/PLANET/RING@MODULE_MM, e.g. 24/48/120@15'
            ) from err
        if not sep:
            raise InputError(f'--include "{item}" must be SUN/PLANET/RING@MODULE_MM')
    return out


@sweep_app.command("planetary")
def sweep_planetary(
    center_distance: Annotated[
        str, typer.Option("--center-distance", help="Centre distances [mm], e.g. 420,480,540,600.")
    ],
    module: Annotated[str, typer.Option(help="Modules [mm], e.g. 5,6,7,8,9,10,12,15.")],
    ratio: Annotated[
        str, typer.Option(help="Speed-ratio window LOW:HIGH, both ends excluded, e.g. 6:6.4.")
    ],
    planets: Annotated[int, typer.Option(help="Number of planets.")] = 3,
    torque: Annotated[float, typer.Option(help="Carrier (input) torque [N·m].")] = 1e6,
    carrier_speed: Annotated[float, typer.Option(help="Carrier speed [rpm].")] = 14.2,
    pressure_angle: Annotated[float, typer.Option(help="Pressure angle [deg].")] = 24.5,
    face_width: Annotated[
        float, typer.Option(help="Face width of every design [mm] (000: 380).")
    ] = 380.0,
    face_width_factor: Annotated[
        str | None,
        typer.Option(
            help="Face width k·π·m instead of --face-width: k, or LOW:HIGH for the middle k."
        ),
    ] = None,
    material: Annotated[str, typer.Option(help="Gear material.")] = "18CrNiMo7-6",
    include: Annotated[
        list[str] | None,
        typer.Option(
            help="Extra design SUN/PLANET/RING@MODULE_MM kept whatever its ratio (repeatable). "
            "Default 24/48/120@15 (000's preliminary design #38) when the window starts at 6."
        ),
    ] = None,
    no_include: Annotated[
        bool, typer.Option("--no-include", help="Do not add the preliminary design.")
    ] = False,
    output: SweepTable = Path("designs.csv"),
    workers: SweepWorkers = None,
    scheduler: SweepScheduler = None,
    plots: Annotated[
        Path | None, typer.Option(help="Folder for PNG plots like Figs. 14-19 of 000.")
    ] = None,
    compare: Annotated[
        bool, typer.Option("--compare/--no-compare", help="Print AGMA SFs beside Table 5.")
    ] = True,
) -> None:
    """Enumerate, build, simulate and rate every planetary design; write a table.

    An interrupted sweep keeps its finished rows in OUTPUT.partial.jsonl; running the same
    command again computes only the missing designs.
    """
    from pinwind.analysis import sweep as sw

    window = _range(ratio, "--ratio")
    extra = _include(include)
    if not extra and not no_include and window[0] == 6.0:
        extra = list(sw.TABLE_5_INCLUDE)
    designs = sw.enumerate_planetary(
        [a * 1e-3 for a in _numbers(center_distance, "--center-distance", "mm")],
        [m / 1e3 for m in _numbers(module, "--module", "mm")],
        ratio_window=window,
        planets=planets,
        include=extra,
    )
    settings = sw.SweepSettings(
        input_torque=torque,
        input_speed=carrier_speed * RPM_TO_RAD_PER_S,
        pressure_angle=math.radians(pressure_angle),
        face_width=face_width * 1e-3,
        face_width_factor=_face_width_factor(face_width_factor),
        material=material,
    )
    note = f"ratio window ({window[0]:g}, {window[1]:g}) open" + (
        f", plus {len(extra)} included" if extra else ""
    )
    rows = _run_sweep(designs, settings, note=note, output=output, workers=workers,
                      scheduler=scheduler, plots=plots)  # fmt: skip
    if compare:
        _print_table_5_comparison(rows)


def _face_width_factor(text: str | None) -> float | None:
    """The factor of --face-width-factor: one value k, or the middle of LOW:HIGH."""
    if text is None:
        return None
    low, high = _range(text, "--face-width-factor")
    return 0.5 * (low + high)


def _run_sweep(designs, settings, *, note: str, output: Path, workers, scheduler, plots) -> list:
    """Run a sweep of any stage kind with a progress bar; write, report and plot its table.

    An interrupted sweep keeps its finished rows in OUTPUT.partial.jsonl; a re-run reads them
    (and OUTPUT, if it exists) and computes only the missing designs.
    """
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    from pinwind.analysis import sweep as sw

    checkpoint = output.with_name(output.name + ".partial.jsonl")
    done = sw.read_table(output) if output.exists() else []
    done += sw.read_checkpoint(checkpoint)
    console.print(
        f"{len(designs)} designs; {note}"
        + (f"; {len(done)} rows from an earlier run" if done else "")
    )
    columns = (BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    with Progress(*columns, console=err_console, transient=True) as bar:
        task = bar.add_task("designs", total=len(designs))
        run = sw.run_sweep(
            designs, settings, workers=workers, scheduler=scheduler, checkpoint=checkpoint,
            done=done, progress=lambda n, total: bar.update(task, completed=n),
        )  # fmt: skip
    sw.write_table(run.rows, output)
    checkpoint.unlink(missing_ok=True)
    failed = [r for r in run.rows if r["status"] != "ok"]
    console.print(
        f"wrote {output}: {len(run.rows)} designs ({run.computed} computed on {run.backend} in "
        f"{run.wall_time:.2f} s, {len(failed)} failed)"
    )
    for row in failed:
        console.print(f"  #{row['number']}: {row['reason']}", highlight=False)
    if plots is not None:
        from pinwind.analysis.sweep_plots import plot_sweep

        paths = plot_sweep(run.rows, plots)
        console.print(f"plots: {', '.join(str(p) for p in paths)}")
    return run.rows


@sweep_app.command("parallel")
def sweep_parallel(
    center_distance: Annotated[
        str, typer.Option("--center-distance", help="Centre distances [mm], e.g. 500,560,630.")
    ],
    module: Annotated[str, typer.Option(help="Normal modules [mm], e.g. 8,10,12.")],
    ratio: Annotated[
        str, typer.Option(help="Speed-ratio window LOW:HIGH (wheel/pinion), ends excluded.")
    ],
    torque: Annotated[
        float, typer.Option(help="Input (wheel shaft) torque [N·m]; default 1 MN·m / 6.")
    ] = 1e6 / 6.0,
    input_speed: Annotated[float, typer.Option(help="Input (wheel shaft) speed [rpm].")] = 85.2,
    pressure_angle: Annotated[float, typer.Option(help="Normal pressure angle [deg].")] = 20.0,
    helix_angle: Annotated[
        float,
        typer.Option(help="Nominal helix angle [deg], 0 for spur; raised per design to fit."),
    ] = 0.0,
    face_width: Annotated[float, typer.Option(help="Face width of every design [mm].")] = 250.0,
    face_width_factor: Annotated[
        str | None,
        typer.Option(
            help="Face width k·π·m instead of --face-width: k, or LOW:HIGH for the middle k."
        ),
    ] = None,
    material: Annotated[str, typer.Option(help="Gear material.")] = "18CrNiMo7-6",
    output: SweepTable = Path("parallel_designs.csv"),
    workers: SweepWorkers = None,
    scheduler: SweepScheduler = None,
    plots: Annotated[Path | None, typer.Option(help="Folder for PNG plots.")] = None,
) -> None:
    """Enumerate, build, simulate and rate every parallel (spur/helical) stage; write a table.

    000 §5: the planetary procedure applied to a parallel stage. Tooth sums fit the centre
    distance exactly (spur: 2a/m whole; helical: the helix angle is raised to fit), the ratio
    z_wheel/z_pinion lies strictly inside the window and the pair passes the geometry checks.
    The default load is the 1.4 MW case's second stage: 1 MN·m / 6 at 85.2 rpm. An interrupted
    sweep keeps its rows in OUTPUT.partial.jsonl; the same command again computes only the rest.
    """
    from pinwind.analysis import sweep as sw

    window = _range(ratio, "--ratio")
    alpha = math.radians(pressure_angle)
    designs = sw.enumerate_parallel(
        [a * 1e-3 for a in _numbers(center_distance, "--center-distance", "mm")],
        [m / 1e3 for m in _numbers(module, "--module", "mm")],
        ratio_window=window,
        pressure_angle=alpha,
        helix_angle=math.radians(helix_angle),
    )
    settings = sw.SweepSettings(
        input_torque=torque,
        input_speed=input_speed * RPM_TO_RAD_PER_S,
        pressure_angle=alpha,
        face_width=face_width * 1e-3,
        face_width_factor=_face_width_factor(face_width_factor),
        material=material,
    )
    note = f"ratio window ({window[0]:g}, {window[1]:g}) open, undercut and other errors left out"
    _run_sweep(designs, settings, note=note, output=output, workers=workers,
               scheduler=scheduler, plots=plots)  # fmt: skip


def _print_table_5_comparison(rows: list[dict]) -> None:
    from rich.table import Table

    from pinwind.analysis.sweep_reference import comparison

    entries = [e for e in comparison(rows) if not e["missing"]]
    if not entries:
        return
    table = Table(title="AGMA safety factors beside 000 Table 5 (ours / paper, relative diff.)")
    for column in ("#", "a/m/sun/planet/ring", "S_H sun–planet", "S_H planet–ring", "S_F min"):
        table.add_column(column, justify="right")
    for e in entries:
        table.add_row(
            str(e["number"]),
            e["design"],
            f"{e['SF_C25']:.2f} / {e['paper_SF_C25']:.2f} ({e['diff_C25']:+.0%})",
            f"{e['SF_C51']:.2f} / {e['paper_SF_C51']:.2f} ({e['diff_C51']:+.0%})",
            f"{e['SF_B']:.2f} / {e['paper_SF_B_root']:.2f} ({e['diff_B_root']:+.0%})",
        )
    console.print(table)


@sweep_app.command("query")
def sweep_query(
    table: Annotated[Path, typer.Argument(help="Sweep table (.csv or .parquet).")],
    center_distance: Annotated[
        float | None, typer.Option("--center-distance", help="Required centre distance [mm].")
    ] = None,
    ratio: Annotated[float | None, typer.Option(help="Required speed ratio.")] = None,
    ratio_tolerance: Annotated[float, typer.Option(help="Ratio match tolerance.")] = 0.05,
    module: Annotated[float | None, typer.Option(help="Required module [mm].")] = None,
    min_sf: Annotated[
        float | None, typer.Option("--min-sf", help="Keep designs whose safety factor > this.")
    ] = None,
    sf: Annotated[
        str, typer.Option("--sf", help="Safety-factor column: agma_SF_min or iso_S_min, ...")
    ] = "agma_SF_min",
    minimise: Annotated[
        str | None,
        typer.Option(help="Minimise: center-distance, module, ratio or any column name."),
    ] = None,
) -> None:
    """Pick designs (000 eq. 41): centre distance ∪ ratio ∪ module ∪ SF, optionally minimised."""
    from pinwind.analysis import sweep as sw

    columns = {"center-distance": "centre_distance_mm", "centre-distance": "centre_distance_mm",
               "module": "module_mm", "ratio": "ratio"}  # fmt: skip
    rows = sw.query(
        sw.read_table(table),
        centre_distance=None if center_distance is None else center_distance * 1e-3,
        ratio=ratio,
        ratio_tolerance=ratio_tolerance,
        module=None if module is None else module * 1e-3,
        min_sf=min_sf,
        sf_column=sf,
        minimise=columns.get(minimise, minimise) if minimise else None,
    )
    if not rows:
        console.print("no design satisfies every criterion")
        raise typer.Exit(code=1)
    for r in rows:
        console.print(
            f"#{int(r['number'])}: {sw.stage_of(r).describe(r)}, AGMA SF min "
            f"{float(r['agma_SF_min']):.2f}, ISO S min {float(r['iso_S_min']):.2f}",
            highlight=False,
        )


@sweep_app.command("plot")
def sweep_plot(
    table: Annotated[Path, typer.Argument(help="Sweep table (.csv or .parquet).")],
    out_dir: Annotated[Path, typer.Option("--out-dir", "-o", help="Folder for PNGs.")] = Path(
        "plots"
    ),
) -> None:
    """PNG plots of a sweep (planetary or parallel) against the module (like 000 Figs. 14-19)."""
    from pinwind.analysis.sweep import read_table
    from pinwind.analysis.sweep_plots import plot_sweep

    for path in plot_sweep(read_table(table), out_dir):
        console.print(f"wrote {path}")


def main() -> None:
    """Entry point: run the CLI and turn pinwind errors into one clear line and exit code 2."""
    try:
        app()
    except PinwindError as err:
        # soft_wrap: one line whatever its length (a long path must not be broken in two).
        err_console.print(
            f"[bold red]error:[/bold red] {escape(str(err))}", highlight=False, soft_wrap=True
        )
        sys.exit(2)
    except KeyboardInterrupt:
        err_console.print("interrupted")
        sys.exit(130)


if __name__ == "__main__":
    main()
