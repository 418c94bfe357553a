"""The commands that read a log: ``replay``, ``plot``, ``report`` and ``export``."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from pinwind.cli.app import app, console, err_console, say, warnings_as_lines
from pinwind.cli.flags import GrpcPortOption, SaveOption, ServeOption, WebPortOption
from pinwind.errors import InputError


def _finite_time(option: str) -> Callable[[float | None], float | None]:
    """A check of a window's end: a finite time (``--to -inf`` was an OverflowError)."""

    def check(value: float | None) -> float | None:
        if value is not None and math.isinf(value):
            raise InputError(
                f"{option} {value} s is not a time; give a finite time [s], or leave out "
                f"{option} for the log's {'start' if option == '--from' else 'end'}"
            )
        return value

    return check


#: The time window of commands that read a log: --from T0 --to T1 [s], both inclusive.
WindowStart = Annotated[
    float | None,
    typer.Option("--from", help="Start of the window [s] (inclusive).",
                 callback=_finite_time("--from")),
]  # fmt: skip
WindowStop = Annotated[
    float | None,
    typer.Option("--to", help="End of the window [s] (inclusive).", callback=_finite_time("--to")),
]


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
    save: SaveOption = None,
    serve: ServeOption = False,
    web_port: WebPortOption = None,
    grpc_port: GrpcPortOption = None,
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

    with warnings_as_lines(), _reading(log, "reading") as progress:
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

    with warnings_as_lines(), _reading(log, "reading") as progress:
        paths = plot_log(log, out_dir, start=start, stop=stop, format=fmt, progress=progress)
    for path in paths:
        say(f"wrote {escape(str(path))}")


@app.command()
def report(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    start: WindowStart = None,
    stop: WindowStop = None,
    all_rows: Annotated[
        bool,
        typer.Option(
            "--all",
            help="Every quantity, axis and statistic (RMS too), not only the engineer's table.",
        ),
    ] = False,
) -> None:
    """Min, max, mean and final value of the speeds, torques and forces in a log (--all: all).

    The default table has each joint's speed and torque, each mesh's forces and each bearing's
    radial and axial force, tilting moment, |F| and, apart, the torque its shaft transmits;
    --all adds every axis, the world moment, angle, acceleration and the RMS. --json always
    gives everything, in SI units.
    """
    from pinwind.io.report import report_dict, report_log, report_tables

    with warnings_as_lines(), _reading(log, "reading") as progress:
        res = report_log(log, start, stop, progress=progress)  # only the window, bounded memory
    if as_json:
        print(json.dumps(report_dict(res), indent=1))
        return
    # Two lines: the log's path (as long as it is) apart, so that the run's line fits 80 columns.
    say(f"[bold]{escape(str(res.metadata.get('model_name')))}[/bold] — {escape(str(log))}")
    say(
        f"{escape(res.status)}; dt = {res.metadata.get('dt'):g} s, logged every "
        f"{res.metadata['log']['stride']} sample(s); model sha256 "
        f"{str(res.metadata.get('model_sha256'))[:12]}"
    )
    tables = report_tables(res, start, stop, plain=not console.is_terminal, all_rows=all_rows)
    for table in tables:
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
    with warnings_as_lines(), _reading(log, "exporting") as progress:
        rows, columns = export_log(
            log, out, format=fmt, start=start, stop=stop, channels=picked, overwrite=force,
            progress=progress,
        )  # fmt: skip
    say(f"wrote {escape(str(out))} ({rows} rows × {columns} columns)")
