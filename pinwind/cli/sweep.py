"""The design sweeps: ``sweep planetary``, ``sweep parallel``, ``sweep query``, ``sweep plot``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from pinwind.cli.app import console, err_console, sweep_app
from pinwind.cli.flags import parse_number
from pinwind.errors import InputError
from pinwind.units import RAD_S_PER_RPM

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


def _numbers(text: str, option: str, unit: str) -> list[float]:
    """Comma-separated numbers, e.g. 420,480,540, as floats."""
    return [parse_number(p, option, unit) for p in text.split(",") if p.strip()]


def _range(text: str, option: str) -> tuple[float, float]:
    """LOW:HIGH, e.g. 6:6.4, as (6.0, 6.4); a single number x gives (x, x)."""
    low, sep, high = text.partition(":")
    lo = parse_number(low, option, "-")
    return (lo, parse_number(high, option, "-") if sep else lo)


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
        float, typer.Option(help="Face width of every design [mm] (Saleh 2017: 380).")
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
            "Default 24/48/120@15 (Saleh 2017's preliminary design #38) when the window starts "
            "at 6."
        ),
    ] = None,
    no_include: Annotated[
        bool, typer.Option("--no-include", help="Do not add the preliminary design.")
    ] = False,
    output: SweepTable = Path("designs.csv"),
    workers: SweepWorkers = None,
    scheduler: SweepScheduler = None,
    plots: Annotated[
        Path | None, typer.Option(help="Folder for PNG plots like Figs. 14-19 of Saleh 2017.")
    ] = None,
    compare: Annotated[
        bool, typer.Option("--compare/--no-compare", help="Print AGMA SFs beside Table 5.")
    ] = True,
) -> None:
    """Enumerate, build, simulate and rate every planetary design; write a table.

    An interrupted sweep keeps its finished rows in OUTPUT.partial.jsonl; running the same
    command again computes only the missing designs.
    """
    from pinwind.analysis.sweep_design import SweepSettings
    from pinwind.analysis.sweep_planetary import TABLE_5_INCLUDE, enumerate_planetary

    window = _range(ratio, "--ratio")
    extra = _include(include)
    if not extra and not no_include and window[0] == 6.0:
        extra = list(TABLE_5_INCLUDE)
    designs = enumerate_planetary(
        [a * 1e-3 for a in _numbers(center_distance, "--center-distance", "mm")],
        [m / 1e3 for m in _numbers(module, "--module", "mm")],
        ratio_window=window,
        planets=planets,
        include=extra,
    )
    settings = SweepSettings(
        input_torque=torque,
        input_speed=carrier_speed * RAD_S_PER_RPM,
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

    from pinwind.analysis.sweep_table import read_checkpoint, read_table, write_table
    from pinwind.runs.sweep import run_sweep

    if not designs:
        # It wrote an empty table (exit 0), which the same command then could not read.
        raise InputError(
            f"no design ({note}): no tooth counts of these centre distances and modules have a "
            "ratio in the window; give a centre distance that holds whole teeth of the modules "
            "(2a/m) and a wider --ratio"
        )
    checkpoint = output.with_name(output.name + ".partial.jsonl")
    done = read_table(output) if output.exists() else []
    done += read_checkpoint(checkpoint)
    console.print(
        f"{len(designs)} designs; {note}"
        + (f"; {len(done)} rows from an earlier run" if done else "")
    )
    columns = (BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    with Progress(*columns, console=err_console, transient=True) as bar:
        task = bar.add_task("designs", total=len(designs))
        run = run_sweep(
            designs, settings, workers=workers, scheduler=scheduler, checkpoint=checkpoint,
            done=done, progress=lambda n, total: bar.update(task, completed=n),
        )  # fmt: skip
    write_table(run.rows, output)
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

    Saleh 2017 §5: the planetary procedure applied to a parallel stage. Tooth sums fit the centre
    distance exactly (spur: 2a/m whole; helical: the helix angle is raised to fit), the ratio
    z_wheel/z_pinion lies strictly inside the window and the pair passes the geometry checks.
    The default load is the 1.4 MW case's second stage: 1 MN·m / 6 at 85.2 rpm. An interrupted
    sweep keeps its rows in OUTPUT.partial.jsonl; the same command again computes only the rest.
    """
    from pinwind.analysis.sweep_design import SweepSettings
    from pinwind.analysis.sweep_parallel import enumerate_parallel

    window = _range(ratio, "--ratio")
    alpha = math.radians(pressure_angle)
    designs = enumerate_parallel(
        [a * 1e-3 for a in _numbers(center_distance, "--center-distance", "mm")],
        [m / 1e3 for m in _numbers(module, "--module", "mm")],
        ratio_window=window,
        pressure_angle=alpha,
        helix_angle=math.radians(helix_angle),
    )
    settings = SweepSettings(
        input_torque=torque,
        input_speed=input_speed * RAD_S_PER_RPM,
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
    table = Table(
        title="AGMA safety factors beside Saleh 2017 Table 5 (ours / paper, relative diff.)"
    )
    for column in ("#", "a/m/sun/planet/ring", "S_H sun–planet", "S_H planet–ring", "S_F min"):
        # the design whole ("540/10/34/74/182", not "540/10/34/74/1…"); the factors wrap
        table.add_column(column, justify="right", no_wrap=column.startswith(("#", "a/")))
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
    """Pick designs (Saleh 2017 eq. 41): centre distance ∪ ratio ∪ module ∪ SF, maybe minimised."""
    from pinwind.analysis.sweep_table import best_found, query, read_table, stage_of

    columns = {"center-distance": "centre_distance_mm", "centre-distance": "centre_distance_mm",
               "module": "module_mm", "ratio": "ratio"}  # fmt: skip
    table_rows = read_table(table)
    distance_m = None if center_distance is None else center_distance * 1e-3
    module_m = None if module is None else module * 1e-3
    rows = query(
        table_rows, centre_distance=distance_m, ratio=ratio, ratio_tolerance=ratio_tolerance,
        module=module_m, min_sf=min_sf, sf_column=sf,
        minimise=columns.get(minimise, minimise) if minimise else None,
    )  # fmt: skip
    if not rows:
        console.print("no design satisfies every criterion; each alone finds:", highlight=False)
        found = best_found(
            table_rows, centre_distance=distance_m, ratio=ratio, ratio_tolerance=ratio_tolerance,
            module=module_m, min_sf=min_sf, sf_column=sf,
        )  # fmt: skip
        for line in found:
            console.print(f"  {line}", highlight=False, soft_wrap=True)
        raise typer.Exit(code=1)
    for r in rows:
        console.print(
            f"#{int(r['number'])}: {stage_of(r).describe(r)}, AGMA SF min "
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
    """PNG plots of a sweep (planetary or parallel) against the module (Saleh 2017 Figs. 14-19)."""
    from pinwind.analysis.sweep_plots import plot_sweep
    from pinwind.analysis.sweep_table import read_table

    for path in plot_sweep(read_table(table), out_dir):
        console.print(f"wrote {path}")
