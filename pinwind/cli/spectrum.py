"""``pinwind spectrum``: Welch PSD of logged series, peaks listed, mesh frequencies marked."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich import box
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import app, console, say, warnings_as_lines
from pinwind.cli.logs import WindowStart, WindowStop


@app.command()
def spectrum(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    series: Annotated[
        list[str] | None,
        typer.Option(
            "--series",
            help="NAME[:ELEMENT]: a series of docs/series.md (mesh_normal, bearing_force, "
            "speed, ...), for one element or all; repeatable. Default: mesh_normal.",
        ),
    ] = None,
    png: Annotated[
        Path | None, typer.Option("--png", help="Write the PSDs with the markers to this file.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    segment: Annotated[
        float | None,
        typer.Option(help="Welch segment length [s]; resolution 1/segment. Default: window/4."),
    ] = None,
    peaks: Annotated[int, typer.Option(help="Peaks listed per spectrum.")] = 5,
    rainflow: Annotated[
        Path | None,
        typer.Option(
            "--rainflow",
            help="Also write each series' rainflow matrix (range x mean, ASTM E1049) to this CSV.",
        ),
    ] = None,
    rainflow_bins: Annotated[
        int, typer.Option("--rainflow-bins", help="Range and mean bins of the rainflow matrix.")
    ] = 10,
    start: WindowStart = None,
    stop: WindowStop = None,
) -> None:
    """Spectra of a log's series: Welch PSD peaks (Hz, amplitude), mesh and shaft frequencies.

    A peak's amplitude is that of the sinusoid A sin(2πft) of the same power, in the series' SI
    unit. Mesh frequency = teeth × speed relative to the line of centres (the carrier).
    """
    from pinwind.io.log_spectrum import spectrum_of_log, write_figure

    with warnings_as_lines():
        report = spectrum_of_log(
            log, series=series or (), start=start, stop=stop, segment=segment, peaks=peaks
        )
        matrices = None
        if rainflow is not None:
            from pinwind.life.log_rainflow import log_rainflow_matrices, write_rainflow_csv

            chosen = series or [s.series + (f":{s.element}" if s.element else "")
                                for s in report.spectra]  # fmt: skip
            matrices = log_rainflow_matrices(
                log, list(dict.fromkeys(chosen)), start=start, stop=stop, bins=rainflow_bins
            )
            write_rainflow_csv(matrices, rainflow)
    written = write_figure(report, png) if png is not None else None
    if as_json:
        print(json.dumps(report.as_dict(), indent=1))
        return
    say(
        f"{escape(str(log))}: t = {report.span[0]:.6g} to {report.span[1]:.6g} s at "
        f"{report.sample_rate:.6g} Hz; Welch segment {report.segment:.6g} s, "
        f"Δf = {report.resolution:.4g} Hz; amplitude: A of A sin(2πft) of the peak's power"
    )
    plain = not console.is_terminal
    markers = Table(
        title="gearbox frequencies at the window's mean speeds",
        box=box.ASCII if plain else box.SIMPLE_HEAD,
    )
    for column in ("kind", "frequency [Hz]", "meshes / shaft"):
        markers.add_column(column, justify="right" if "Hz" in column else "left")
    for m in report.markers:
        markers.add_row(m.kind, f"{m.frequency:.6g}", escape(", ".join(m.names)))
    if report.markers:
        console.print(markers)
    table = Table(title="spectral peaks", box=box.ASCII if plain else box.SIMPLE_HEAD)
    for column in ("series", "element", "frequency [Hz]", "amplitude", "unit", "near"):
        table.add_column(column, justify="right" if column in ("frequency [Hz]", "amplitude")
                         else "left")  # fmt: skip
    for s in report.spectra:
        for p in s.peaks:
            table.add_row(
                s.series, escape(s.label), f"{p.frequency:.6g}", f"{p.amplitude:.4g}", s.unit,
                escape(p.near),
            )  # fmt: skip
    console.print(table)
    if written is not None:
        say(f"wrote {escape(str(written))}")
    if rainflow is not None and matrices is not None:
        say(f"wrote {escape(str(rainflow))}: {len(matrices)} rainflow matrices")
