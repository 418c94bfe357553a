"""Command-line interface: ``pinwind simulate``, ``replay``, ``report``, ``build``, ``info``.

Units at this edge are the ones drivetrain engineers type: rpm, mm, degrees; everything is turned
into SI before it reaches the library. ``simulate`` logs every run to an MCAP file (``logs/`` by
default) that ``replay`` and ``report`` read back on their own.
"""

from __future__ import annotations

import math
import shlex
import signal
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from pinwind.errors import InputError, LogWriteFailed, PinwindError, PinwindWarning

app = typer.Typer(
    name="pinwind",
    help="Loads inside wind-turbine gearboxes: gear-mesh forces and bearing reactions.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
build_app = typer.Typer(help="Write parametric gearbox models.", no_args_is_help=True)
app.add_typer(build_app, name="build")

# Tables of mesh forces need ~120 columns; pipes and CI logs get that width instead of 80.
console = Console() if Console().is_terminal else Console(width=130)
err_console = Console(stderr=True, soft_wrap=True)  # one error, one line, whatever its length

RPM_TO_RAD_PER_S = 2.0 * math.pi / 60.0


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
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise InputError(f'{option} "{item}" must look like JOINT=VALUE, e.g. carrier=1e6')
        out[name.strip()] = value.strip()
    return out


def _float(text: str, option: str, unit: str) -> float:
    try:
        value = float(text)
    except ValueError as err:
        raise InputError(f'{option}: "{text}" is not a number [{unit}]') from err
    if not math.isfinite(value):
        raise InputError(f"{option}: {text} is not finite; give a number [{unit}]")
    return value


class SineSpeed:
    """Ω(t) = mean + amplitude · sin(2π f t) [rad/s] (002_bb0c67d52fe8a188.txt eq. 2-1)."""

    def __init__(self, mean: float, amplitude: float, frequency: float):
        self.mean = mean
        self.amplitude = amplitude
        self.frequency = frequency
        self.description = (
            f"{mean / RPM_TO_RAD_PER_S:g} rpm + {amplitude / RPM_TO_RAD_PER_S:g} rpm · "
            f"sin(2π·{frequency:g} Hz·t)"
        )

    def __call__(self, t: float) -> float:
        """Ω(t) [rad/s]."""
        return self.mean + self.amplitude * math.sin(2.0 * math.pi * self.frequency * t)


def parse_loads(
    torque: list[str] | None, speed: list[str] | None, speed_sine: list[str] | None
) -> tuple[dict, dict]:
    """CLI load options → (torques [N·m], speeds [rad/s]) for ``pinwind.simulate``."""
    torques = {k: _float(v, "--torque", "N·m") for k, v in _pairs(torque, "--torque").items()}
    speeds: dict = {
        k: _float(v, "--speed", "rpm") * RPM_TO_RAD_PER_S
        for k, v in _pairs(speed, "--speed").items()
    }
    for name, value in _pairs(speed_sine, "--speed-sine").items():
        parts = value.split(",")
        if len(parts) != 3:
            raise InputError(
                f'--speed-sine "{name}={value}" must be JOINT=MEAN_RPM,AMPLITUDE_RPM,FREQUENCY_HZ'
            )
        mean, amp = (_float(p, "--speed-sine", "rpm") * RPM_TO_RAD_PER_S for p in parts[:2])
        speeds[name] = SineSpeed(mean, amp, _float(parts[2], "--speed-sine", "Hz"))
    return torques, speeds


MESH_CHOICES = ("rigid", "compliant")


def parse_meshes(items: list[str] | None) -> dict[str, str]:
    """``--mesh NAME=rigid|compliant`` options → ``simulate(meshes=...)``."""
    out = {}
    for name, value in _pairs(items, "--mesh").items():
        if value not in MESH_CHOICES:
            raise InputError(
                f'--mesh "{name}={value}": the type must be one of {", ".join(MESH_CHOICES)}'
            )
        out[name] = value
    return out


def parse_position_errors(items: list[str] | None) -> dict[str, tuple[float, float]]:
    """``--position-error GEAR=T_UM,R_UM`` options → (tangential, radial) errors [m]."""
    out = {}
    for name, value in _pairs(items, "--position-error").items():
        parts = value.split(",")
        if len(parts) != 2:
            raise InputError(
                f'--position-error "{name}={value}" must be GEAR=TANGENTIAL_UM,RADIAL_UM'
            )
        tangential, radial = (_float(p, "--position-error", "µm") * 1e-6 for p in parts)
        out[name] = (tangential, radial)
    return out


@app.command()
def simulate(
    model: Annotated[Path, typer.Argument(help="Gearbox model file (URDF with <gearbox>).")],
    torque: Annotated[
        list[str] | None,
        typer.Option("--torque", "-t", help="JOINT=N·m applied torque (repeatable)."),
    ] = None,
    speed: Annotated[
        list[str] | None,
        typer.Option("--speed", "-s", help="JOINT=RPM prescribed joint speed (repeatable)."),
    ] = None,
    speed_sine: Annotated[
        list[str] | None,
        typer.Option(
            "--speed-sine", help="JOINT=MEAN_RPM,AMPLITUDE_RPM,FREQUENCY_HZ sinusoidal driver."
        ),
    ] = None,
    duration: Annotated[float, typer.Option(help="Simulated time [s].")] = 1.0,
    dt: Annotated[float, typer.Option(help="Time step [s].")] = 1e-3,
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
    position_error: Annotated[
        list[str] | None,
        typer.Option(
            "--position-error",
            help="GEAR=TANGENTIAL_UM,RADIAL_UM position error of a planet's centre [µm] "
            "(repeatable); compliant meshes share the load accordingly.",
        ),
    ] = None,
) -> None:
    """Simulate a gearbox model, log it to MCAP, print speeds, mesh forces, bearing reactions."""
    import numpy as np

    import pinwind
    from pinwind.analysis import load_sharing
    from pinwind.analysis.summary import summary_tables
    from pinwind.io.run import log_path

    torques, speeds = parse_loads(torque, speed, speed_sine)
    meshes = parse_meshes(mesh)
    errors = parse_position_errors(position_error)
    gearbox = pinwind.load(model)
    log = None if no_log else log_path(out if out is not None else True, gearbox.name)
    command = shlex.join(["pinwind", *sys.argv[1:]])
    before = _stamp(log) if log is not None else None
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        with _warnings_as_lines():
            res = pinwind.simulate(
                gearbox, duration=duration, dt=dt, torques=torques, speeds=speeds,
                progress=progress, log=log, log_rate=log_rate, overwrite=force,
                command=command, meshes=meshes, position_errors=errors,
                pose_rate=pose_rate, allow_large_log=allow_large_log,
            )  # fmt: skip
    except (KeyboardInterrupt, PinwindError) as err:
        written = not isinstance(err, LogWriteFailed)  # that message says what the file holds
        if written and log is not None and _stamp(log) not in (None, before):
            err_console.print(f"the run stopped early; its log up to that point is in {log}")
        if isinstance(err, Terminated):
            err_console.print(f"terminated ({err})")
            raise typer.Exit(code=143) from err
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
    console.print(
        f"[bold]{gearbox.name}[/bold] from {model}: {len(res) - 1} steps of {dt:g} s "
        f"in {res.metadata['wall_time_s']:.2f} s "
        f"({res.metadata['wall_time_s'] / max(len(res) - 1, 1) * 1e6:.0f} µs/step); "
        f"max |J v| = {res.constraint_residual.max():.2e}"
    )
    for table in summary_tables(res):
        console.print(table)
    for sharing in load_sharing(res, gearbox):
        if np.isfinite(sharing.factor_max):
            shares = ", ".join(
                f"{m} {s:.4f}" for m, s in zip(sharing.meshes, sharing.mean_share, strict=True)
            )
            console.print(
                f"load sharing at the {sharing.gear}: K_γ = {sharing.mean_share.max():.4f} from "
                f"the mean loads ({shares}); largest at one sample {sharing.factor_max:.4f}",
                highlight=False,
            )
    if log is not None:
        console.print(f"log: {log} ({log.stat().st_size / 1e6:.2f} MB)")


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
            err_console.print(f"[yellow]warning:[/yellow] {warning.message}", highlight=False)
        else:
            warnings.warn_explicit(
                warning.message, warning.category, warning.filename, warning.lineno
            )


@app.command()
def replay(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    save: Annotated[
        Path | None, typer.Option("--save", help="Write a Rerun .rrd file instead of viewing.")
    ] = None,
    serve: Annotated[
        bool, typer.Option("--serve", help="Serve the Rerun web viewer instead of spawning one.")
    ] = False,
    web_port: Annotated[int | None, typer.Option(help="Web viewer port (with --serve).")] = None,
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

    with _warnings_as_lines():
        out = run_replay(
            log, save=save, serve=serve, web_port=web_port, start=start, stop=stop,
            points=points, announce=console.print,
        )  # fmt: skip
    if out is not None:
        console.print(f"wrote {out}")


@app.command()
def report(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    start: Annotated[
        float | None, typer.Option("--from", help="Start of the window [s] (inclusive).")
    ] = None,
    stop: Annotated[
        float | None, typer.Option("--to", help="End of the window [s] (inclusive).")
    ] = None,
) -> None:
    """Min, max, mean, RMS and final value of every quantity in a log."""
    import json

    from pinwind.io.report import report_dict, report_log, report_tables

    with _warnings_as_lines():
        res = report_log(log, start, stop)  # reads only the window, in bounded memory
    if as_json:
        print(json.dumps(report_dict(res), indent=1))
        return
    console.print(
        f"[bold]{res.metadata.get('model_name')}[/bold] — {log}: {res.status}; "
        f"dt = {res.metadata.get('dt'):g} s, logged every {res.metadata['log']['stride']} "
        f"sample(s); model sha256 {str(res.metadata.get('model_sha256'))[:12]}…"
    )
    for table in report_tables(res):
        console.print(table)


@app.command()
def export(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    out: Annotated[Path, typer.Option("--out", "-o", help="Table to write (.parquet or .csv).")],
    fmt: Annotated[
        str | None,
        typer.Option("--format", help="parquet or csv (default: from the suffix of --out)."),
    ] = None,
    start: Annotated[
        float | None, typer.Option("--from", help="Start of the window [s] (inclusive).")
    ] = None,
    stop: Annotated[
        float | None, typer.Option("--to", help="End of the window [s] (inclusive).")
    ] = None,
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
    with _warnings_as_lines():
        rows, columns = export_log(
            log, out, format=fmt, start=start, stop=stop, channels=picked, overwrite=force
        )
    console.print(f"wrote {out} ({rows} rows × {columns} columns)")


@app.command()
def info(model: Annotated[Path, typer.Argument(help="Gearbox model file.")]) -> None:
    """Load a model, check it, and list its bearings, gears and meshes."""
    import pinwind

    gb = pinwind.load(model)
    console.print(repr(gb))
    console.print("bearings (joints): " + ", ".join(gb.joint_names))
    if gb.locked_joints:
        console.print("locked (fixed mounts): " + ", ".join(gb.locked_joints))
    from pinwind.dynamics.ratios import speed_ratio

    free = [j for j in gb.joint_names if j not in gb.locked_joints]
    if free:
        try:
            ratios = {j: speed_ratio(gb, j, free[0]) for j in free}
        except InputError as err:
            console.print(f"speed ratios: {err}")
        else:
            console.print(
                f"speed ratios to {free[0]} (joint speeds, relative to the parent body): "
                + ", ".join(f"{j} {r:.6g}" for j, r in ratios.items())
            )
    for m in gb.meshes:
        a, b = m.gear_a.spec, m.gear_b.spec
        console.print(
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
    console.print(f"wrote {path}")


def main() -> None:
    """Entry point: run the CLI and turn pinwind errors into one clear line and exit code 2."""
    try:
        app()
    except PinwindError as err:
        err_console.print(f"[bold red]error:[/bold red] {err}", highlight=False)
        sys.exit(2)
    except KeyboardInterrupt:
        err_console.print("interrupted")
        sys.exit(130)


if __name__ == "__main__":
    main()
