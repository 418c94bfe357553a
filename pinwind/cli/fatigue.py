"""``pinwind fatigue``: gear-tooth contact and root damage over a site's wind from a fatigue set."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import app, console, err_console, say

if TYPE_CHECKING:
    from pinwind.life.bearing_life import BearingLife
    from pinwind.life.life_damage import GearDamage, SetDamage
    from pinwind.life.load_cases import FatigueRun, FatigueSet


@app.command()
def fatigue(
    scenario: Annotated[Path, typer.Argument(help="Scenario file with a [fatigue] table.")],
    quick: Annotated[
        bool, typer.Option("--quick", help="Run the file's [fatigue.quick] short version.")
    ] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    figures: Annotated[
        Path | None, typer.Option(help="Folder for the PNG figures (003 Figs. 14-15).")
    ] = None,
    workers: Annotated[
        int | None, typer.Option(help="Local worker processes (default: all cores).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address, e.g. tcp://head:8786.")
    ] = None,
) -> None:
    """Damage per gear per wind bin and per turbulence level (Jørgensen 2014 Tables 7-8).

    One compliant run per wind bin x turbulence x seed, each logged in the set's output folder;
    a rerun computes only the cases whose log is missing or incomplete.
    """
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    from pinwind.life.life_damage import set_damage
    from pinwind.life.load_cases import load_fatigue_set, run_cases
    from pinwind.life.set_bearing_life import set_bearing_lives

    fset = load_fatigue_set(scenario, quick=quick)
    if not as_json:
        say(
            f"{len(fset.cases())} load cases ({len(fset.site.bins)} wind bins x "
            f"{len(fset.levels)} turbulence levels x {len(fset.seeds)} seeds, "
            f"{fset.duration:g} s each, counted from {fset.skip_start:g} s) in {fset.out}"
        )
    columns = (BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    with Progress(*columns, console=err_console, transient=True, disable=as_json) as bar:
        task = bar.add_task("cases", total=len({c.name for c in fset.cases()}))
        run = run_cases(
            fset,
            workers=workers,
            scheduler=scheduler,
            progress=lambda n, total: bar.update(task, completed=n),
        )
    damage = set_damage(fset)
    bearings = set_bearing_lives(fset)
    paths = []
    if figures is not None:
        from pinwind.life.life_figures import plot_damage_vs_turbulence, plot_range_cycles

        level = _reference_level(damage)
        paths = [
            plot_damage_vs_turbulence(damage, figures / "damage_vs_turbulence.png"),
            plot_range_cycles(damage, figures / "range_cycles.png", level=level),
        ]
    if as_json:
        report = _as_dict(fset, run, damage, paths)
        report["bearings"] = [[life.as_dict() for life in level] for level in bearings]
        print(json.dumps(report, indent=1))
        return
    say(
        f"{len(run.computed)} computed on {run.backend} in {run.wall_time:.1f} s, "
        f"{run.total - len(run.computed)} reused"
    )
    _print_tables(damage)
    _print_bearings(damage, bearings)
    for path in paths:
        say(f"wrote {path}")


def _reference_level(damage: SetDamage) -> int:
    """The level nearest 10 % turbulence (003 Table 7's)."""
    return min(range(len(damage.levels)), key=lambda k: abs(damage.intensities[k] - 0.10))


def _print_tables(damage: SetDamage) -> None:
    """Table 7 (per bin, reference level) and Table 8 (per level) shapes, 003's rows beside."""
    import numpy as np

    from pinwind.life.life_damage import (
        JORGENSEN_2014_TABLE_7,
        JORGENSEN_2014_TABLE_8,
        VARIANTS,
    )

    level = _reference_level(damage)
    paper_speeds = np.arange(6.0, 21.0, 2.0)
    for variant in VARIANTS:
        table = Table(
            title=f"Contact damage per wind bin at turbulence {damage.levels[level]}, "
            f"S-N {variant} (003 Table 7 shape; worst tooth flank, planet = mean of the planets)"
        )
        table.add_column("gear")
        for speed in damage.speeds:
            table.add_column(f"{speed:g}", justify="right")
        table.add_column("Σ", justify="right")
        for kind, (per_bin, total) in damage.by_kind(variant, level).items():
            table.add_row(kind, *(f"{d:.3g}" for d in per_bin), f"{total:.3g}")
            paper = JORGENSEN_2014_TABLE_7.get(kind)
            if paper and np.array_equal(damage.speeds, paper_speeds) and variant == "limit":
                table.add_row("  003", *(f"{d:.3g}" for d in paper[0]), f"{paper[1]:.3g}")
        console.print(table)
    table = Table(title="Total contact damage per turbulence level (003 Table 8 shape)")
    table.add_column("gear")
    table.add_column("S-N")
    for label in damage.levels:
        table.add_column(label, justify="right")
    kinds = list(damage.by_kind("limit", 0))
    paper_at = [
        JORGENSEN_2014_TABLE_8["turbulence"].index(round(i, 4))
        if round(i, 4) in JORGENSEN_2014_TABLE_8["turbulence"]
        else None
        for i in damage.intensities
    ]
    for kind in kinds:
        for variant in VARIANTS:
            totals = [damage.by_kind(variant, k)[kind][1] for k in range(len(damage.levels))]
            table.add_row(kind, variant, *(f"{t:.3g}" for t in totals))
        if kind in ("sun", "planet", "ring"):
            totals_003 = JORGENSEN_2014_TABLE_8[kind]
            table.add_row(
                "", "003", *("" if i is None else f"{totals_003[i]:.3g}" for i in paper_at)
            )
    console.print(table)
    table = Table(
        title="Root damage per turbulence level (worst fillet; ISO 6336-3 root stress unless "
        "a table is given; 003 §4.1: none)"
    )
    table.add_column("gear")
    table.add_column("S-N")
    for label in damage.levels:
        table.add_column(label, justify="right")
    for kind in damage.by_kind("limit", 0, location="root") if damage.root_damage else ():
        for variant in VARIANTS:
            totals = [
                damage.by_kind(variant, k, location="root")[kind][1]
                for k in range(len(damage.levels))
            ]
            table.add_row(kind, variant, *(f"{t:.3g}" for t in totals))
    console.print(table)
    table = Table(
        title="Largest stress [MPa]: von Mises contact (003: 600-700 at 20 m/s, 10 %) and root "
        "(003: about 60)"
    )
    table.add_column("gear")
    table.add_column("stress")
    for label in damage.levels:
        table.add_column(label, justify="right")
    for gear in damage.gears:
        for location, by_level in (("contact", damage.damage), ("root", damage.root_damage)):
            if not by_level or gear not in by_level["limit"][0]:
                continue
            peaks = [by_level["limit"][k][gear].peak_stress for k in range(len(damage.levels))]
            table.add_row(gear, location, *(f"{p / 1e6:.0f}" for p in peaks))
    console.print(table)


def _as_dict(
    fset: FatigueSet, run: FatigueRun, damage: SetDamage, figures: list[Path]
) -> dict[str, Any]:
    """The whole result as plain values (units in the keys)."""
    from pinwind.life.life_damage import (
        JORGENSEN_2014_TABLE_7,
        JORGENSEN_2014_TABLE_8,
        LOCATIONS,
        VARIANTS,
    )

    def by_variant(table: dict[str, list[dict[str, GearDamage]]]) -> dict[str, Any]:
        return {
            variant: [
                {
                    gear: {
                        "per_bin": d.per_bin.tolist(),
                        "total": d.total,
                        "tooth": d.tooth,
                        "flank": d.flank,
                        "peak_stress_MPa": d.peak_stress / 1e6,
                    }
                    for gear, d in level.items()
                }
                for level in levels
            ]
            for variant, levels in table.items()
        }

    return {
        "scenario": fset.source,
        "out": str(fset.out),
        "cases": run.total,
        "computed": run.computed,
        "backend": run.backend,
        "wall_time_s": run.wall_time,
        "speeds_m_s": damage.speeds.tolist(),
        "hours": damage.hours.tolist(),
        "levels": list(damage.levels),
        "intensities": list(damage.intensities),
        "variants": VARIANTS,
        "stresses": LOCATIONS,
        "damage": by_variant(damage.damage),
        "root_damage": by_variant(damage.root_damage),
        "root_stress": {gear: model.describe() for gear, model in fset.root_stress.items()},
        "jorgensen_2014": {
            "table_7": {
                k: {"per_bin": list(v[0]), "total": v[1]} for k, v in JORGENSEN_2014_TABLE_7.items()
            },
            "table_8": {k: list(v) for k, v in JORGENSEN_2014_TABLE_8.items()},
        },  # fmt: skip
        "figures": [str(p) for p in figures],
    }


def _print_bearings(damage: SetDamage, bearings: list[list[BearingLife]]) -> None:
    """Each bearing's ISO 281 life over the site's hours, per turbulence level."""
    import numpy as np

    hours = float(damage.hours.sum())
    for label, lives in zip(damage.levels, bearings, strict=True):
        table = Table(
            title=f"Bearing life (ISO 281) over the site's {hours:.0f} h at turbulence {label}: "
            "P_eq revolution-weighted over the bins"
        )
        columns = ("C [kN]", "P_eq [kN]", "mean rpm", "L10 [10⁶ rev]", "L10h [h]")
        table.add_column("bearing")
        table.add_column("type")
        for column in columns:  # escaped: rich reads "[kN]" as a style
            table.add_column(escape(column), justify="right")
        for life in lives:
            rating = life.rating
            if rating is None or rating.dynamic_load_rating is None:
                kind = rating.kind if rating else "-"
                load = "" if np.isnan(life.equivalent_load) else f"{life.equivalent_load / 1e3:.3g}"
                table.add_row(life.joint, kind, "not rated", load, f"{life.mean_speed_rpm:.4g}")
                continue
            table.add_row(
                life.joint,
                rating.kind,
                f"{rating.dynamic_load_rating / 1e3:.4g}",
                f"{life.equivalent_load / 1e3:.3g}",
                f"{life.mean_speed_rpm:.4g}",
                f"{life.l10:.4g}",
                f"{life.l10h:.4g}",
            )
        console.print(table)
