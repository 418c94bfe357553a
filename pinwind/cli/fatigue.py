"""``pinwind fatigue``: gear-tooth contact and root damage over a site's wind from a fatigue set."""

from __future__ import annotations

import json
import math
import re
import signal
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich import box
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import (
    Terminated,
    app,
    console,
    err_console,
    raise_terminated,
    say,
    warnings_as_lines,
)

if TYPE_CHECKING:
    from pinwind.life.bearing_life import BearingLife
    from pinwind.life.damage_convergence import DamageDtCheck
    from pinwind.life.fatigue_set import FatigueSet
    from pinwind.life.set_damage import GearDamage, SetDamage
    from pinwind.runs.case_runner import FatigueRun


@app.command()
def fatigue(
    scenario: Annotated[Path, typer.Argument(help="Scenario file with a [fatigue] table.")],
    quick: Annotated[
        bool, typer.Option("--quick", help="Run the file's [fatigue.quick] short version.")
    ] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    figures: Annotated[
        Path | None,
        typer.Option(
            help="Folder for the PNG figures (Jørgensen 2014 Figs. 14-15; the LDD and LRD of the "
            "shafts, also as load_spectra.csv; the bearings' L10h, L_nmh and L10rh)."
        ),
    ] = None,
    workers: Annotated[
        int | None, typer.Option(help="Local worker processes (default: all cores).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address, e.g. tcp://head:8786.")
    ] = None,
    check_dt: Annotated[
        bool,
        typer.Option(
            "--check-dt",
            help="Run the set again at dt/2 (its cases beside the set's, resumable) and print "
            "the change of each gear's damage and largest stress.",
        ),
    ] = False,
) -> None:
    """Damage per gear per wind bin and per turbulence level (Jørgensen 2014 Tables 7-8).

    One compliant run per wind bin x turbulence x seed, each logged in the set's output folder;
    a rerun computes only the cases whose log is missing or incomplete.
    """
    # What the command has reached, for the one line an interruption prints (`_stopped_line`).
    state: dict[str, Any] = {"phase": "reading", "cases": 0, "total": 0, "out": None}
    previous = signal.signal(signal.SIGTERM, raise_terminated)
    try:
        _fatigue(scenario, quick, as_json, figures, workers, scheduler, check_dt, state)
    except KeyboardInterrupt as err:  # Ctrl-C, or SIGTERM raised as it: one line, no traceback
        err_console.print(_stopped_line(err, state), highlight=False, soft_wrap=True)
        raise typer.Exit(code=143 if isinstance(err, Terminated) else 130) from err
    finally:
        signal.signal(signal.SIGTERM, previous)


def _stopped_line(err: KeyboardInterrupt, state: dict[str, Any]) -> str:
    """The one line of an interrupted ``pinwind fatigue``: what is kept and how to go on.

    Typer turns a KeyboardInterrupt into exit 130 without a word; this says where the command
    was: reading the set, checking its kept cases, running them, or rating the finished set.
    """
    what = f"terminated ({err})" if isinstance(err, Terminated) else "interrupted"
    out = escape(str(state["out"]))
    phase = state["phase"]
    if phase == "reading":
        return (
            f"{what} while reading the set, before any case started: the same command starts "
            "it (cases kept from an earlier run are reused)"
        )
    if phase == "checking":
        return (
            f"{what} while checking which of the set's {state['total']} cases kept in {out} "
            "are finished, before any case started: the same command checks them again and "
            "computes the rest"
        )
    if phase == "cases":
        return (
            f"{what}: {state['cases']} of {state['total']} cases of the set are finished and "
            f"kept in {out}; the same command computes the rest"
        )
    return (
        f"{what} after the cases, while rating them: all {state['total']} cases of the set are "
        f"finished and kept in {out}; the same command reuses them and prints the results"
    )


def _fatigue(
    scenario: Path,
    quick: bool,
    as_json: bool,
    figures: Path | None,
    workers: int | None,
    scheduler: str | None,
    check_dt: bool,
    state: dict[str, Any],
) -> None:
    """The command's work (`fatigue`), saying in ``state`` how far it has come."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TaskID,
        TimeRemainingColumn,
    )

    from pinwind.errors import InputError
    from pinwind.io.folders import folder_problem
    from pinwind.life.set_bearing_life import set_bearing_lives, set_skidding
    from pinwind.life.set_damage import set_damage
    from pinwind.runs.case_runner import run_cases
    from pinwind.runs.executor import check_workers
    from pinwind.runs.fatigue_set_file import load_fatigue_set

    check_workers(workers)
    if figures is not None and (problem := folder_problem(figures)) is not None:
        raise InputError(
            f"--figures {figures}: {problem}; give a folder for the figures (it is made if missing)"
        )
    fset = load_fatigue_set(scenario, quick=quick)
    half = None
    if check_dt:
        from pinwind.life.damage_convergence import half_step_set

        half = half_step_set(fset)
    if not as_json:
        say(
            f"{len(fset.cases())} load cases ({len(fset.site.bins)} wind bins x "
            f"{len(fset.levels)} turbulence levels x {len(fset.seeds)} seeds, "
            f"{fset.duration:g} s each, counted from {fset.skip_start:g} s) in {fset.out}"
            + ("" if half is None else f", and again at dt/2 in {half.out}")
        )
    columns = (BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
    sets = [("cases", fset)] + ([] if half is None else [("cases at dt/2", half)])
    runs: dict[str, FatigueRun] = {}
    # No bar in a pipe: it would only leave empty lines in the output.
    hidden = as_json or not err_console.is_terminal
    with (
        warnings_as_lines(),
        Progress(*columns, console=err_console, transient=True, disable=hidden) as bar,
    ):
        for label, each in sets:
            total = len({c.name for c in each.cases()})
            state.update(phase="checking", cases=0, total=total, out=each.out)
            task = bar.add_task(label, total=total)

            def advance(n: int, total: int, task: TaskID = task) -> None:
                bar.update(task, completed=n)
                state.update(phase="cases", cases=n, total=total)

            runs[label] = run_cases(each, workers=workers, scheduler=scheduler, progress=advance)
    state.update(phase="rating", total=runs["cases"].total, out=fset.out)
    run = runs["cases"]
    damage = set_damage(fset)
    check = None
    if half is not None:
        from pinwind.life.damage_convergence import damage_dt_check

        half_damage = set_damage(half)
        check = damage_dt_check(damage, half_damage, dt=fset.dt, out=half.out)
    bearings = set_bearing_lives(fset)
    skidding = set_skidding(fset, _reference_level(damage))
    paths = []
    if figures is not None:
        from pinwind.life.life_figures import (
            plot_bearing_lives,
            plot_damage_vs_turbulence,
            plot_load_spectra,
            plot_range_cycles,
        )
        from pinwind.runs.set_load_spectra import set_load_spectra, write_load_spectra_csv

        level = _reference_level(damage)
        spectra = set_load_spectra(fset, level)
        about = _set_caption(fset, run.total)
        mark = _quick_title(fset, run.total) if quick else ""
        paths = [
            plot_damage_vs_turbulence(
                damage, figures / "damage_vs_turbulence.png", about=about, mark=mark
            ),
            plot_range_cycles(
                damage, figures / "range_cycles.png", level=level, about=about, mark=mark
            ),
            plot_load_spectra(
                spectra,
                figures / "load_spectra.png",
                title=f"turbulence {damage.levels[level]}",
                about=about,
                mark=mark,
            ),
            write_load_spectra_csv(spectra, figures / "load_spectra.csv"),
            plot_bearing_lives(
                bearings[level],
                figures / "bearing_lives.png",
                hours=float(damage.hours.sum()),
                title=f"turbulence {damage.levels[level]}",
                about=about,
                mark=mark,
            ),
        ]
    if as_json:
        report = _as_dict(fset, run, damage, paths)
        report["bearings"] = [[life.as_dict() for life in level] for level in bearings]
        report["share_below_minimum_load"] = {
            "level": damage.levels[_reference_level(damage)],
            "per_bin": {j: [None if math.isnan(x) else x for x in v] for j, v in skidding.items()},
        }
        if check is not None:
            half_run = runs["cases at dt/2"]
            report["check_dt"] = check.as_dict() | {
                "computed": half_run.computed,
                "backend": half_run.backend,
                "wall_time_s": half_run.wall_time,
                "damage": _by_variant(half_damage.damage),
                "root_damage": _by_variant(half_damage.root_damage),
            }
        print(json.dumps(report, indent=1))
        return
    for label, done in runs.items():
        say(
            f"{label}: {len(done.computed)} computed on {done.backend} in "
            f"{done.wall_time:.1f} s, {done.total - len(done.computed)} reused"
        )
    _print_tables(damage)
    _print_bearings(damage, bearings)
    _print_skidding(damage, skidding)
    if check is not None:
        _print_dt_check(check)
    for path in paths:
        say(f"wrote {path}")


def _set_caption(fset: FatigueSet, cases: int) -> str:
    """The set a figure comes from: its file, its cases and their length, where they are."""
    return (
        f"Set: {Path(fset.source).name}, {cases} cases x {fset.duration:g} s "
        f"(counted from {fset.skip_start:g} s) in {fset.out}"
    )


def _quick_title(fset: FatigueSet, cases: int) -> str:
    """The mark of a ``--quick`` figure: a short set, a first look, not the set's result."""
    return f"quick set ({cases} cases x {fset.duration:g} s): a first look"


def cell(value: float) -> str:
    """A damage or life in at most 6 characters (``--json`` keeps every digit).

    Whole numbers from 100 to 99999 (``7645``); otherwise three significant digits where they
    fit, fewer for the tiny ISO 6336 damages (``2.6e-8``).
    """
    if 100 <= abs(value) < 1e5:
        return f"{value:.0f}"  # a load rating or a life: every digit fits
    for digits in (3, 2, 1):
        text = re.sub(r"e\+?(-?)0*(\d)", r"e\1\2", f"{value:.{digits}g}")
        if len(text) <= 6:
            return text
    return text


#: A mean speed within this fraction of the table's fastest is zero to round-off [-]: a joint
#: fixed to its parent (a ring) comes out at 1e-13 rpm beside 150 rpm, where double precision
#: leaves about 1e-16 of the speeds it subtracts.
ROUND_OFF_SPEED = 1e-9


def speed_cell(rpm: float, fastest: float) -> str:
    """A mean speed [rpm] as `cell`, and ``0`` when it is zero to round-off beside ``fastest``."""
    if math.isfinite(rpm) and abs(rpm) <= ROUND_OFF_SPEED * fastest:
        return "0"
    return cell(rpm)


def table(title: str, *columns: str, left: int = 1) -> Table:
    """A table of ``columns``: the first ``left`` ones text, the others numbers.

    Ten 6-character cells fit 80 columns (no vertical rules); a longer cell wraps, never cut.
    The table is at least as wide as its title up to 80 columns, so that a narrow table's title
    reads on one or two lines, not in a column of 26 ("Largest stress [MPa]: von / Mises ...").
    """
    grid = Table(  # escaped: rich reads "[m/s]" as a closing tag and drops it
        title=escape(title),
        box=box.SIMPLE_HEAD,
        show_edge=False,
        pad_edge=False,
        collapse_padding=True,
        min_width=min(len(title), 80),
    )
    for i, name in enumerate(columns):  # escaped: rich reads "[kN]" as a style
        grid.add_column(escape(name), justify="left" if i < left else "right", overflow="fold")
    return grid


def _reference_level(damage: SetDamage) -> int:
    """The level nearest 10 % turbulence (Jørgensen 2014 Table 7's)."""
    return min(range(len(damage.levels)), key=lambda k: abs(damage.intensities[k] - 0.10))


def variant_notes(damage: SetDamage) -> list[str]:
    """Which of the three S-N variants to believe, one line each, and where the docs say why.

    ``iso 6336`` is the standard's design basis; ``limit`` is Jørgensen 2014's own method (eq.
    23 with Table 5's endurance limits), zero when every counted stress range is below them;
    ``no limit`` is the same line without the limit, an upper bound: every tooth pass counts.
    Its ratio to Jørgensen 2014's Table 8 is the sun's total at the reference level
    (`_reference_level`) over the paper's at that intensity, when the paper has it.
    """
    from pinwind.life.set_damage import JORGENSEN_2014_TABLE_8, PAPER

    level = _reference_level(damage)
    zero = {
        location: all(
            d.total == 0.0 for by_level in table.get("limit", []) for d in by_level.values()
        )
        for location, table in (("contact", damage.damage), ("root", damage.root_damage))
    }
    limit = "limit: Jørgensen 2014's Table 5 method (eq. 23 with its endurance limits)"
    if zero["contact"] and zero["root"]:
        limit += "; 0 here because every stress range is below its endurance limit"
    elif zero["contact"]:
        limit += "; contact 0 here because every contact stress range is below its limit"
    no_limit = (
        "no limit: the same line without the limit, an upper bound, as every tooth pass counts"
    )
    intensity = round(damage.intensities[level], 4)
    sun = damage.by_kind("no limit", level).get("sun")
    if sun is not None and intensity in JORGENSEN_2014_TABLE_8["turbulence"]:
        paper = JORGENSEN_2014_TABLE_8["sun"][JORGENSEN_2014_TABLE_8["turbulence"].index(intensity)]
        label = damage.levels[level]
        no_limit += (
            f": the sun's {cell(sun[1])} at {label} is {sun[1] / paper:.0f}x {PAPER}'s Table 8 "
            f"({paper:g})"
        )
    return [
        'Which S-N variant to believe (docs/fatigue.md, "What differs from Jørgensen 2014, '
        'and why"):',
        "  iso 6336: ISO 6336-2 and -3's curves of each gear's material, the standard's design "
        "basis",
        f"  {limit}",
        f"  {no_limit}",
    ]


def _print_tables(damage: SetDamage) -> None:
    """Jørgensen 2014's Table 7 (per bin) and Table 8 (per level) shapes with its rows beside.

    Also which S-N variant to believe (`variant_notes`), the root damage and largest stresses.
    """
    import numpy as np

    from pinwind.life.set_damage import (
        JORGENSEN_2014_TABLE_7,
        JORGENSEN_2014_TABLE_8,
        PAPER,
        VARIANTS,
    )

    level = _reference_level(damage)
    paper_speeds = np.arange(6.0, 21.0, 2.0)
    for variant in VARIANTS:
        grid = table(
            f"Contact damage per wind bin [m/s] at turbulence {damage.levels[level]}, "
            f"S-N {variant} (Jørgensen 2014 Table 7 shape; worst tooth flank, planet = mean of "
            "the planets)",
            "gear",
            *(f"{speed:g}" for speed in damage.speeds),
            "Σ",
        )
        for kind, (per_bin, total) in damage.by_kind(variant, level).items():
            grid.add_row(kind, *(cell(d) for d in per_bin), cell(total))
            paper = JORGENSEN_2014_TABLE_7.get(kind)
            if paper and np.array_equal(damage.speeds, paper_speeds) and variant == "limit":
                grid.add_row(f"  {PAPER}", *(cell(d) for d in paper[0]), cell(paper[1]))
        console.print(grid)
    grid = table(
        "Total contact damage per turbulence level (Jørgensen 2014 Table 8 shape)",
        "gear",
        "S-N",
        *damage.levels,
        left=2,
    )
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
            grid.add_row(kind, variant, *(cell(t) for t in totals))
        if kind in ("sun", "planet", "ring"):
            paper_totals = JORGENSEN_2014_TABLE_8[kind]
            grid.add_row("", PAPER, *("" if i is None else cell(paper_totals[i]) for i in paper_at))
    console.print(grid)
    grid = table(
        "Root damage per turbulence level (worst fillet; ISO 6336-3 root stress unless "
        "a table is given; Jørgensen 2014 §4.1: none)",
        "gear",
        "S-N",
        *damage.levels,
        left=2,
    )
    for kind in damage.by_kind("limit", 0, location="root") if damage.root_damage else ():
        for variant in VARIANTS:
            totals = [
                damage.by_kind(variant, k, location="root")[kind][1]
                for k in range(len(damage.levels))
            ]
            grid.add_row(kind, variant, *(cell(t) for t in totals))
    console.print(grid)
    grid = table(
        "Largest stress [MPa]: von Mises contact (Jørgensen 2014: 600-700 at 20 m/s, 10 %) and "
        "root (Jørgensen 2014: about 60)",
        "gear",
        "stress",
        *damage.levels,
        left=2,
    )
    for gear in damage.gears:
        for location, by_level in (("contact", damage.damage), ("root", damage.root_damage)):
            if not by_level or gear not in by_level["limit"][0]:
                continue
            peaks = [by_level["limit"][k][gear].peak_stress for k in range(len(damage.levels))]
            grid.add_row(gear, location, *(f"{p / 1e6:.0f}" for p in peaks))
    console.print(grid)
    for line in variant_notes(damage):
        say(line)


def _as_dict(
    fset: FatigueSet, run: FatigueRun, damage: SetDamage, figures: list[Path]
) -> dict[str, Any]:
    """The whole result as plain values (units in the keys)."""
    from pinwind.life.set_damage import (
        JORGENSEN_2014_TABLE_7,
        JORGENSEN_2014_TABLE_8,
        LOCATIONS,
        VARIANTS,
    )

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
        "damage": _by_variant(damage.damage),
        "root_damage": _by_variant(damage.root_damage),
        "root_stress": {gear: model.describe() for gear, model in fset.root_stress.items()},
        "jorgensen_2014": {
            "table_7": {
                k: {"per_bin": list(v[0]), "total": v[1]} for k, v in JORGENSEN_2014_TABLE_7.items()
            },
            "table_8": {k: list(v) for k, v in JORGENSEN_2014_TABLE_8.items()},
        },  # fmt: skip
        "figures": [str(p) for p in figures],
        "variant_notes": [line.strip() for line in variant_notes(damage)],
    }


def _by_variant(table: dict[str, list[dict[str, GearDamage]]]) -> dict[str, Any]:
    """Variant → level → gear → its damage as plain values (units in the keys)."""
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


def _print_dt_check(check: DamageDtCheck) -> None:
    """Each gear's damage and largest stress at dt/2 and their change from dt, per level."""
    from pinwind.life.damage_convergence import NEGLIGIBLE_DAMAGE, judged

    for location in ("contact", "root"):
        table = Table(  # no markup in the title: "[MPa]" is text
            title=escape(
                f"The same set at dt/2 = {check.dt / 2:g} s: {location} damage and largest "
                f"{location} stress [MPa] at dt/2 (change from dt = {check.dt:g} s; converged "
                f"within {100 * check.tolerance:g} %)"
            )
        )
        table.add_column("gear")
        table.add_column("figure")
        for label in check.levels:
            table.add_column(label, justify="right")
        first = [row for row in check.rows[0] if row.group == location] if check.rows else []
        for i, row in enumerate(first):
            cells = []
            for rows in check.rows:
                same = [r for r in rows if r.group == location][i]
                value = same.values[1] / 1e6 if same.unit == "Pa" else same.values[1]
                text = f"{value:.0f}" if same.unit == "Pa" else f"{value:.3g}"
                mark = "" if same.converged or not judged(same) else " !"
                cells.append(f"{text} ({_percent(same.change_half)}){mark}")
            table.add_row(row.element, row.quantity, *cells)
        if first:
            console.print(table)
    say(
        f"!: changes by more than {100 * check.tolerance:g} % (damage below "
        f"{NEGLIGIBLE_DAMAGE:g} at both steps is not judged)"
    )
    say(f"dt check: {check.verdict}")


def _percent(change: float) -> str:
    """A relative change in percent, ``+1.2 %`` (``+inf %``: from zero)."""
    percent = 100 * change
    if not math.isfinite(percent) or abs(percent) >= 10:
        return f"{percent:+.0f} %"
    return f"{percent:+.2g} %"


def _print_bearings(damage: SetDamage, bearings: list[list[BearingLife]]) -> None:
    """Each bearing's and row's lives over the site's hours, per turbulence level.

    ISO 281 basic L10 and modified L_nm (90 %), ISO/TS 16281 reference L10r, each from its
    sums added over the wind bins (``life/set_bearing_life.py``); ``-`` where not computed.
    """
    hours = float(damage.hours.sum())
    for label, lives in zip(damage.levels, bearings, strict=True):
        fastest = max((abs(life.mean_speed_rpm) for life in lives), default=0.0)
        grid = table(
            f"Bearing lives over the site's {hours:.0f} h at turbulence {label}: ISO 281 L10h "
            "and L_nmh (90 %), ISO/TS 16281 L10rh, loads revolution-weighted over the bins",
            "bearing",
            "type",
            "C [kN]",
            "P_eq [kN]",
            "rpm",
            "L10h [h]",
            "L_nmh [h]",
            "L10rh [h]",
            left=2,
        )
        for life in lives:
            rating = life.rating
            kind = _kind(rating.kind) if rating and rating.kind else "-"
            speed = speed_cell(life.mean_speed_rpm, fastest)
            if rating is None or rating.dynamic_load_rating is None:
                load = "" if math.isnan(life.equivalent_load) else cell(life.equivalent_load / 1e3)
                grid.add_row(life.joint, kind, "not rated", load, speed)
                continue
            grid.add_row(
                life.joint,
                kind,
                cell(rating.dynamic_load_rating / 1e3),
                cell(life.equivalent_load / 1e3),
                speed,
                cell(life.l10h),
                _life_cell(life.lnmh),
                _life_cell(life.l10rh),
            )
        console.print(grid)
    say(
        "-: not computed. L_nm needs the bearing's size_mm (d_m) and fatigue_limit_kN or "
        "rating_c0_kN in the model; L10r needs size_mm or its rollers and roller_mm, and a "
        "single angular row (tapered, angular contact) finds no equilibrium when its axial load "
        "is below its induced thrust (docs/bearing_life.md). Lubricant and cleanliness: the "
        "model's, else VG 320 at 70 °C, normal cleanliness."
    )


def _kind(kind: str) -> str:
    """A bearing type in a table cell: ``cylindrical`` for cylindrical_roller, ``… ball``."""
    return kind.replace("_roller", "").replace("_ball", " ball").replace("_", " ")


def _life_cell(value: float) -> str:
    """A life as `cell`, ``-`` when not computed (NaN)."""
    return "-" if math.isnan(value) else cell(value)


def _print_skidding(damage: SetDamage, skidding: dict[str, list[float]]) -> None:
    """Each rated bearing's share of the time below its minimum load, per wind bin [%]."""
    from pinwind.life.skidding import MINIMUM_LOAD_BALL, MINIMUM_LOAD_ROLLER

    rated = {
        joint: shares for joint, shares in skidding.items() if not all(map(math.isnan, shares))
    }
    if not rated:
        return
    level = damage.levels[_reference_level(damage)]
    grid = table(
        f"Skidding risk: share of the time each bearing turns under less than the load it needs "
        f"to roll ({MINIMUM_LOAD_ROLLER:g} C roller, {MINIMUM_LOAD_BALL:g} C ball; SKF 2018), per "
        f"wind bin [m/s] at turbulence {level} [%]",
        "bearing",
        *(f"{speed:g}" for speed in damage.speeds),
    )
    for joint, shares in rated.items():
        grid.add_row(joint, *("-" if math.isnan(x) else cell(100 * x) for x in shares))
    console.print(grid)
