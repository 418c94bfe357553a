"""``pinwind life``: every rolling bearing's lives from a logged run (ISO 281, ISO/TS 16281)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import app, console, say, warnings_as_lines
from pinwind.cli.flags import check_reliability_percent
from pinwind.errors import InputError


def _hours(value: float) -> str:
    if math.isnan(value):
        return "-"
    return "inf" if math.isinf(value) else f"{value:.3g}"


@app.command()
def life(
    log: Annotated[Path, typer.Argument(help="MCAP log written by pinwind simulate.")],
    model: Annotated[
        Path | None,
        typer.Option(
            "--model",
            help="Model file whose bearing data (lubricant, C_u, geometry) to use instead of "
            "the one the log holds; same joints and rows.",
        ),
    ] = None,
    reliability_percent: Annotated[
        float | None,
        typer.Option(
            "--reliability-percent",
            help="Reliability R [%] of L_nm (90 ≤ R ≤ 99.95, ISO 281); default 90.",
        ),
    ] = None,
    old_reliability: Annotated[
        float | None,
        typer.Option(
            "--reliability", hidden=True, help="The former name of --reliability-percent [%]."
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Each bearing's lives in a log: ISO 281 L10h, modified L_nmh, ISO/TS 16281 L10rh.

    Rows of a shaft's bearing (``<row>``) are rated at their positions from their share of the
    shaft's load, its tilting moment included; a whole bearing that carries a tilting moment is
    refused with the reason. Lives are hours at the run's mean speed, as if the run repeated.
    """
    from pinwind.io.log_reader import LogReader
    from pinwind.life.bearing_life import bearing_lives
    from pinwind.life.modified_life import RELIABILITY_PERCENT_RANGE
    from pinwind.life.row_life import LIFE_CHANNELS, row_lives
    from pinwind.model.gearbox import load as load_model
    from pinwind.model.gearbox import loads

    if old_reliability is not None and reliability_percent is not None:
        raise InputError(
            f"--reliability {old_reliability:g} and --reliability-percent "
            f"{reliability_percent:g}: --reliability is the former name of "
            "--reliability-percent; give one"
        )
    # The former name took the same unit, percent: it still works.
    option, percent = next(
        ((o, r) for o, r in (("--reliability-percent", reliability_percent),
                             ("--reliability", old_reliability)) if r is not None),
        ("--reliability-percent", 90.0),
    )  # fmt: skip
    check_reliability_percent(percent, *RELIABILITY_PERCENT_RANGE, open_low=False, option=option)
    with warnings_as_lines():
        with LogReader(log) as reader:
            res = reader.read(channels=LIFE_CHANNELS)
            text = reader.model_text
            problem = reader.model_problem
        if model is not None:
            gearbox = load_model(model)
        elif text:
            gearbox = loads(text, path=f"{log} (its model)")
        else:
            raise InputError(f"{log}: {problem}; give the model with --model")
        rows = row_lives(res, gearbox, reliability_percent=percent)
        whole = [b for b in bearing_lives(res, gearbox) if b.rating is not None]
    if as_json:
        out = {"rows": [r.as_dict() for r in rows], "bearings": [b.as_dict() for b in whole]}
        print(json.dumps(out, indent=1, allow_nan=False, default=str))
        return
    say(f"[bold]{escape(gearbox.name)}[/bold] — {escape(str(log))}: {res.time[-1]:g} s run")
    plain = not console.is_terminal
    if rows:
        # 80 columns (a pipe's): each bearing on a line of its own above its rows, the padding
        # between columns collapsed, headers escaped (rich reads a bare "[kN]" as a style and
        # drops it) and no cell cut short.
        table = Table(
            title=f"Rolling bearings (rows): lives in hours at the run's speed, R = {percent:g} %",
            box=None if plain else Table().box,
            collapse_padding=True,
            pad_edge=False,
        )
        for head in (
            "bearing\n  row",
            "type",
            "P\n[kN]",
            "L10h",
            "Lnmh",
            "L10rh",
            "Qmax\n[kN]",
            "zone\n[°]",
            "P<Pmin\n[%]",
        ):
            left = head in ("bearing\n  row", "type")
            table.add_column(escape(head), justify="left" if left else "right", no_wrap=not left)
        bearing = None
        for r in rows:
            if r.bearing != bearing:
                bearing = r.bearing
                table.add_row(escape(bearing))
            table.add_row(
                f"  {escape(r.name)}", r.kind.replace("_roller", "").replace("_", " "),
                f"{r.equivalent_load / 1e3:.4g}", _hours(r.l10h), _hours(r.lnmh), _hours(r.l10rh),
                "-" if math.isnan(r.max_element_load) else f"{r.max_element_load / 1e3:.4g}",
                "-" if math.isnan(r.load_zone_min) else f"{math.degrees(r.load_zone_min):.0f}",
                "-" if math.isnan(r.below_minimum) else f"{100 * r.below_minimum:.3g}",
            )  # fmt: skip
        console.print(table)
        say(
            "P<Pmin: the share of the time the row turned under less than the load it needs "
            "to roll, 0.02 C (roller) or 0.01 C (ball) by the catalogues (SKF 2018): skidding risk"
        )
        notes: dict[str, list[str]] = {}
        for r in rows:
            for note in r.notes:
                notes.setdefault(note, []).append(f"{r.bearing}/{r.name}")
            axial, tilt = r.not_carried
            # Worth a line: 1 % of P axially, a moment of 1 % of P at 0.1 m.
            parts = []
            if axial > 0.01 * r.equivalent_load:
                parts.append(f"axial up to {axial / 1e3:.4g} kN (ISO 281's P counts it by X, Y)")
            if tilt > 1e-3 * r.equivalent_load:
                parts.append(f"tilting up to {tilt / 1e3:.4g} kN·m")
            if parts:
                say(
                    f"{escape(r.bearing)}/{escape(r.name)}: not carried by its type in the "
                    f"reference life: {', '.join(parts)}"
                )
        for note, who in notes.items():
            where = "all rows" if len(who) == len(rows) else ", ".join(who)
            say(f"note ({escape(where)}): {escape(note)}")
    for b in whole:
        if b.refused:
            say(f"[bold red]{escape(b.joint)}: no life[/bold red]: {escape(b.refused)}")
        elif b.rated:
            say(f"{escape(b.joint)} ({b.rating.kind if b.rating else ''}): L10h {_hours(b.l10h)} h")
    if not rows and not whole:
        say("no rated bearings: give <bearing> or <row> elements a rating_c_kN")
