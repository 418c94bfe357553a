"""Statistics of every logged quantity, from the log file alone (``pinwind report``).

For each quantity of each joint, mesh and bearing: min, max, mean, RMS and final value over a time
window (``analysis/run_statistics``; the columns of Kelso 2011 Tables 4-1/4-2), in
SI units (``report_dict``, ``--json``); the printed tables use the units of ``pinwind
simulate``: rpm, kN, kN·m (a slide's joint rows: µm, m/s, m/s², kN). Vectors give one row per
world or joint-frame component plus one for the magnitude. By default the printed tables are
the engineer's: the series of each element that ``Series.headline`` marks (speeds, torques,
mesh forces, bearing radial and axial forces and tilting moments about the bearing axis with
the shaft's torque apart, and the bearing force |F|), vectors by their magnitude only, and no
row that is zero throughout; ``all_rows`` (``pinwind report --all``) prints every
row and every statistic.
Body poses are geometry, not loads, and are left out (``pinwind.read_log`` has them).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np
from rich.markup import escape
from rich.table import Table

from pinwind.analysis.run_statistics import STATISTICS, Row, RunningStatistics
from pinwind.analysis.table_numbers import WIDTH, column_scale, column_texts
from pinwind.dynamics import series
from pinwind.dynamics.result import Result
from pinwind.errors import InputError


def window(res: Result, start: float | None = None, stop: float | None = None) -> np.ndarray:
    """Indices of the samples with start ≤ t ≤ stop [s] (open ends when None).

    Raises:
        InputError: the window holds no sample; the message gives the time span of the log.
    """
    t = res.time
    mask = np.ones(len(t), dtype=bool)
    if start is not None:
        mask &= t >= start
    if stop is not None:
        mask &= t <= stop
    rows = np.flatnonzero(mask)
    if not len(rows):
        _no_sample(start, stop, (t[0], t[-1]) if len(t) else None)
    return rows


def _no_sample(start, stop, span: tuple[float, float] | None):
    covers = f"t = {span[0]:.6g} to {span[1]:.6g} s" if span else "no samples"
    raise InputError(
        f"no logged sample between --from {start} and --to {stop} s; the log covers {covers}"
    )


@dataclass(frozen=True)
class Report:
    """Statistics of every quantity over a window, with what they were computed from.

    Attributes:
        rows: one per series (``Row``).
        first, last: times of the first and last sample of the window [s].
        samples: samples in the window.
        metadata: the run metadata of the log (``Result.metadata``).
        status: how the run ended.
    """

    rows: list[Row]
    first: float
    last: float
    samples: int
    metadata: dict
    status: str


def report(res: Result, start: float | None = None, stop: float | None = None) -> Report:
    """Statistics of every quantity of a Result over the window start ≤ t ≤ stop [s].

    Raises:
        InputError: the window holds no sample.
    """
    rows = window(res, start, stop)
    stats = RunningStatistics()
    stats.add(res, rows)
    return Report(stats.rows(), stats.first, stats.last, stats.count, res.metadata, res.status)


#: Samples per block when a report streams a log (about 40 MB of arrays for the drivetrain).
REPORT_BLOCK = 20_000


def report_log(
    path,
    start: float | None = None,
    stop: float | None = None,
    *,
    block: int = REPORT_BLOCK,
    progress: Callable[[float, float], None] | None = None,
) -> Report:
    """Statistics of every quantity of a log over start ≤ t ≤ stop [s], in bounded memory.

    Only the chunks that overlap the window are read, ``block`` samples at a time, and body poses
    (``/tf``) are not read at all. ``progress`` gets (simulated time read, of the window) [s]
    before each block (``LogReader.blocks``).

    Raises:
        InputError: the window holds no sample; the message gives the time span of the log.
        LogError: the log cannot be read (``pinwind.io.log_reader.LogReader``).
    """
    from pinwind.io.log_channels import CHANNELS
    from pinwind.io.log_reader import LogReader

    channels = [topic for topic in CHANNELS if topic != "/tf"]
    stats = RunningStatistics()
    metadata: dict = {}
    status = ""
    with LogReader(path) as log:
        blocks = log.blocks(block, start=start, stop=stop, channels=channels, progress=progress)
        for res in blocks:
            stats.add(res)
            metadata, status = res.metadata, res.status
        span = log.span
    if not stats.count:
        _no_sample(start, stop, span)
    return Report(stats.rows(), stats.first, stats.last, stats.count, metadata, status)


def report_rows(res: Result, start: float | None = None, stop: float | None = None) -> list[Row]:
    """Statistics of every quantity over the window start ≤ t ≤ stop [s]."""
    return report(res, start, stop).rows


def _as_report(res: Result | Report, start: float | None, stop: float | None) -> Report:
    return res if isinstance(res, Report) else report(res, start, stop)


def report_dict(
    res: Result | Report, start: float | None = None, stop: float | None = None
) -> dict[str, object]:
    """The report as plain data (``pinwind report --json``); NaN becomes null."""
    rep = _as_report(res, start, stop)

    def clean(value):
        return None if isinstance(value, float) and not math.isfinite(value) else value

    meta = rep.metadata
    return {
        "log": meta.get("log", {}).get("path"),
        "model": meta.get("model_name"),
        "model_sha256": meta.get("model_sha256"),
        "status": rep.status,
        "window": {"from": rep.first, "to": rep.last, "samples": rep.samples},
        "quantities": [{k: clean(v) for k, v in asdict(row).items()} for row in rep.rows],
    }


_TITLES = {
    "joint": "Bearings (joints): angle, speed, acceleration, torque",
    "mesh": "Gear meshes: tooth forces and transmission error",
    "bearing": "Bearing reactions on the child body",
    "load": "Generators and rotors",
    "run": "Run: constraint residual and energy ledger [kJ]",
}


#: SI unit of a report row → (unit printed by ``pinwind report``, factor), the units of
#: ``pinwind simulate``'s summary: rpm, kN, kN·m, µm, kJ.
DISPLAY_UNITS = {
    "rad/s": ("rpm", 60.0 / (2.0 * math.pi)),
    "N": ("kN", 1e-3),
    "N*m": ("kN·m", 1e-3),
    "m": ("µm", 1e6),
    "J": ("kJ", 1e-3),
    "W": ("kW", 1e-3),
    "rad/s^2": ("rad/s²", 1.0),
    "m/s^2": ("m/s²", 1.0),
    "1": ("-", 1.0),
    "m/s or rad/s": ("m/s, rad/s", 1.0),
}

#: Statistics of the engineer's table (the final value last, as in ``--all``).
HEADLINE_STATISTICS = ("min", "max", "mean", "final")
#: Characters of a number cell (``table_numbers.WIDTH``); with the widest label the tables fit
#: 80 columns.
NUMBER_WIDTH = WIDTH


def _labels() -> dict[str, str]:
    """Short labels of the quantities in the printed tables (``Series.short``).

    The JSON keeps the long ones.
    """
    return {s.title: s.short for s in series.schema() if s.short}


def _headline() -> dict[tuple[str, str], bool]:
    """(report group, statistics label) → in the engineer's table (``Series.headline``)."""
    groups = {"generator": "load", "rotor": "load"}
    return {(groups.get(s.family, s.family), s.title): s.headline for s in series.schema()}


def _in_headline(row: Row, headline: dict[tuple[str, str], bool]) -> bool:
    """A row of the engineer's table: a headline series, a vector's magnitude, not all zero."""
    if not headline.get((row.group, row.quantity), True):
        return False
    if row.component and row.component != "|.|":
        return False
    return not (row.min == 0.0 and row.max == 0.0)


def report_tables(
    res: Result | Report,
    start: float | None = None,
    stop: float | None = None,
    *,
    plain: bool = False,
    all_rows: bool = False,
) -> list[Table]:
    """The report as rich tables, one per group, in the units of ``pinwind simulate``.

    Speeds in rpm, forces in kN, torques and moments in kN·m, transmission error in µm, energy
    in kJ; each element's name heads its rows, and each row names its quantity, axis and unit
    ("F world x [kN]"). The numbers of one quantity (every element's, every statistic) share
    one precision, and its rounding noise prints as 0 (``analysis/table_numbers.py``).
    ``report_dict`` stays SI. Neither numbers nor labels are ever cut, and
    the tables fit 80 columns.

    Args:
        res: a Result (statistics over the window) or a streamed ``report_log`` Report.
        plain: ASCII rules and no styles, for pipes and files.
        all_rows: every row and statistic; by default the engineer's table (min, max, mean,
            final of the ``Series.headline`` series, vectors by magnitude, no all-zero row).
    """
    from pinwind.analysis.summary import PLAIN_BOX, TERMINAL_BOX

    rep = _as_report(res, start, stop)
    span = f"t = {rep.first:.6g} to {rep.last:.6g} s, {rep.samples} samples"
    statistics = STATISTICS if all_rows else HEADLINE_STATISTICS
    headline = _headline()
    labels = _labels()
    tables = []
    for group, title in _TITLES.items():
        members = [
            r for r in rep.rows if r.group == group and (all_rows or _in_headline(r, headline))
        ]
        if not members:
            continue
        # (label, the quantity's key, numbers in the display unit); no numbers: an element
        shown: list[tuple[str, tuple[str, str], list[float]]] = []
        element = None
        for r in members:
            if r.element != element and group != "run":
                element = r.element
                shown.append((element, ("", ""), []))
            unit, factor = DISPLAY_UNITS.get(r.unit, (r.unit, 1.0))
            label = labels.get(r.quantity, r.quantity)
            if group == "run" and r.quantity == "energy":
                text = f"  {r.element}"  # the title gives the unit: kJ
            else:
                axis = f" {r.component}" if r.component else ""
                text = f"  {label}{axis} [{unit}]"
            numbers = [getattr(r, stat) * factor for stat in statistics]
            shown.append((text, (r.quantity, unit), numbers))
        # One precision per quantity of the table (every element's, every statistic), its
        # rounding noise as 0 (``analysis/table_numbers.py``).
        scales: dict[tuple[str, str], float] = {}
        for _, key, numbers in shown:
            scales[key] = max(scales.get(key, 0.0), column_scale(numbers))
        cells = [
            (text, column_texts(numbers, scales[key]) if numbers else [])
            for text, key, numbers in shown
        ]
        table = Table(
            title=escape(f"{title} ({span})"),
            box=PLAIN_BOX if plain else TERMINAL_BOX,
            show_edge=False,
            pad_edge=False,
            title_style=None if plain else "bold",
            header_style=None if plain else "bold",
        )
        # The widest label, then 9 characters a number, a space either side of each column and
        # a rule between: 20 + 5 × 9 + 15 (--all) or 32 + 4 × 9 + 12 within 80 columns.
        width = max(len("element/quantity"), *(len(text) for text, _ in cells))
        table.add_column("element/quantity", width=width, no_wrap=True)
        for stat in statistics:
            name = "RMS" if stat == "rms" else stat
            table.add_column(name, justify="right", width=NUMBER_WIDTH, no_wrap=True)
        for text, numbers in cells:
            table.add_row(escape(text), *(numbers or [""] * len(statistics)))
        tables.append(table)
    return tables
