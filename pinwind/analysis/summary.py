"""Statistics of a run and the printed summary of ``pinwind simulate``.

``statistics`` gives min, max, mean, RMS and final value of a series (the columns of
Kelso 2011 Tables 4-1/4-2). ``summary_tables`` lays them out for the terminal, in
engineering units (rpm, kN, kN·m) named in the column headers, in tables that fit 80 columns.
"""

from __future__ import annotations

import math
import textwrap
from typing import Any

import numpy as np
from rich import box
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.dynamics import series
from pinwind.dynamics._native import fold_columns
from pinwind.dynamics.result import FoldedStatistics, Result
from pinwind.units import rad_s_to_rpm


def statistics(values: np.ndarray) -> dict[str, float]:
    """min, max, mean, RMS and final value of a 1-D series (empty series give NaN).

    The same fold as ``RunningStatistics`` (``dynamics/cpp/column_statistics.hpp``).
    """
    values = np.asarray(values, dtype=float).reshape(-1)
    if values.size == 0:
        return {k: math.nan for k in ("min", "max", "mean", "rms", "final")}
    folded = np.empty((5, 1))
    fold_columns(values.reshape(-1, 1), folded)
    lo, hi, total, squares, final = folded[:, 0].tolist()
    n = values.size
    return {"min": lo, "max": hi, "mean": total / n, "rms": math.sqrt(squares / n), "final": final}


def _input_joint(res: Result) -> str | None:
    """The joint the ratios are taken to: the first with a speed, torque, rotor or generator.

    A wind-driven run has only a rotor and a generator.
    """
    for key in ("speeds", "torques"):
        names = list(res.metadata.get(key, {}))
        if names:
            return names[0]
    for names in (res.rotor_names, res.generator_names):
        if names:
            return names[0]
    return None


#: Table style on a terminal: a rule under the header, no vertical borders (narrow).
TERMINAL_BOX = box.SIMPLE_HEAD
#: The same in plain ASCII, for pipes and files.
PLAIN_BOX = box.Box("    \n    \n -- \n    \n    \n    \n    \n    \n", ascii=True)


def _fixed(value: float, places: int = 4) -> str:
    """A table number with ``places`` decimals; one that rounds to zero has no sign.

    The speed of a held ring or the torque of a planet's bearing is a solver's rounding
    (1e-13): "-0.0000" would print the noise's sign as if it were a value.
    """
    text = f"{value:.{places}f}"
    return text.lstrip("-") if float(text) == 0.0 else text


def _table(title: str, columns: tuple[str, ...], plain: bool) -> Table:
    """A table whose columns never cut a number: a cell too wide for the console folds."""
    table = Table(
        title=escape(title),
        box=PLAIN_BOX if plain else TERMINAL_BOX,
        title_style=None if plain else "bold",
        header_style=None if plain else "bold",
        show_edge=False,
    )
    for i, name in enumerate(columns):
        table.add_column(escape(name), justify="left" if i == 0 else "right", overflow="fold")
    return table


#: The console width every table is fitted to (a pipe's, and a terminal's by default).
WIDTH = 80


def _fitted(table: Table, width: int = WIDTH) -> Table:
    """The table with no cell folded: names and numbers whole, headers wrapped at spaces.

    Rich narrows the widest columns of a table wider than the console, header or not, and folds
    their cells: a bearing "stage1_planet1" printed as "stage1_planet" over "1". When the
    widest cells and headers do not fit ``width``, each header wider than its column's cells
    wraps at its spaces instead, and no column folds its cells.
    """
    cells = [[str(cell) for cell in column._cells] for column in table.columns]
    data = [max((len(c) for c in column), default=0) for column in cells]
    headers = [Text.from_markup(str(column.header)).plain for column in table.columns]
    natural = sum(max(d, len(h)) + 2 for d, h in zip(data, headers, strict=True))
    if natural + len(headers) - 1 <= width:  # padding 1 each side, a space between columns
        return table
    for column, d, header in zip(table.columns, data, headers, strict=True):
        words = max((len(w) for w in header.split()), default=0)
        column.header = escape("\n".join(textwrap.wrap(header, max(d, words))))
        column.no_wrap = True
    return table


def _span(res: Result, stats: FoldedStatistics) -> str:
    """What the statistics cover.

    The run, its samples after a start-up span, or the kept samples of a Result that has no
    others.
    """
    skipped = res.metadata.get("statistics_from_s")
    if skipped:
        return f"t ≥ {skipped:g} s"
    if stats.count >= res.metadata.get("samples_simulated", stats.count):
        return "the run"
    return f"the {stats.count} kept samples"


def row_table(res: Result, gearbox: Any, *, plain: bool = False) -> Table | None:
    """The rows of the shafts' bearings at the end and at their largest (``bearing_rows``).

    None when the model's bearings have no rows.
    """
    from pinwind.analysis.bearing_rows import row_loads

    rows = row_loads(res, gearbox)
    if not rows:
        return None
    table = _table(
        f"Bearing rows at t = {res.time[-1]:.4g} s and their largest over the run "
        "(each rolling bearing's share of its shaft's bearing)",
        ("row", "bearing", "at [mm]", "radial [kN]", "axial [kN]", "max radial [kN]"),
        plain,
    )
    for row in rows:
        table.add_row(
            row.name,
            row.bearing,
            f"{row.position * 1e3:.1f}",
            f"{row.radial_magnitude[-1] / 1e3:.4f}",
            f"{row.axial[-1] / 1e3:.4f}",
            f"{float(np.max(row.radial_magnitude)) / 1e3:.4f}",
        )
    return _fitted(table)


def summary_tables(res: Result, *, plain: bool = False) -> list[Table]:
    """Tables of joint speeds and ratios, slide displacements, mesh forces, bearing loads.

    The bearing loads are those a bearing engineer reads (``dynamics/bearing_load.py``): radial
    and axial force and tilting moment about the bearing's own axis, with the torque the shaft
    transmits apart (a shaft's torque, not a load on the bearing); then the largest of each
    over the run and of the resultant force |F|; then the generators' torques and the rotors'
    torque, power, λ, C_p, thrust and C_t, each family in a table of its own.

    Each table fits 80 columns with the shipped models' names: a table that would not wraps its
    headers at their spaces (``_fitted``); names and numbers are never cut. Units are in the
    column headers.

    Args:
        plain: ASCII rules and no styles, for pipes and files.
    """
    tables = []
    stats = res.statistics or RunningStatistics.of(res)
    ref = _input_joint(res)
    ref_speed = res.joint(ref).speed[-1] if ref else 0.0
    final = f"t = {res.time[-1]:.4g} s"

    joints = _table(
        f"Bearings (joints) at {final}: speed, ratio and net torque",
        ("joint", "speed [rpm]", f"ratio to {ref or '-'} [-]", "torque [kN·m]"),
        plain,
    )
    locked = set(res.metadata.get("locked_joints", []))
    kinds = dict(zip(res.joint_names, res.joint_kinds, strict=True))
    slides = [name for name in res.joint_names if kinds[name] == "prismatic"]
    for name in (n for n in res.joint_names if kinds[n] == "revolute"):
        js = res.joint(name)
        speed = js.speed[-1]
        ratio = speed / ref_speed if abs(ref_speed) > 1e-12 else math.nan
        if name in locked:
            ratio_text = "0 (fixed)"  # held by a row: its speed is rounding noise
        else:
            ratio_text = f"{ratio:.6g}" if math.isfinite(ratio) else "-"
        joints.add_row(
            name,
            _fixed(rad_s_to_rpm(speed)),
            ratio_text,
            _fixed(js.torque[-1] / 1e3),
        )
    tables.append(joints)
    if slides:  # their joint series are a length, a speed along the axis and a force
        moves = _table(
            f"Slides (compliant bearings, support) at {final}",
            ("slide", "displacement [µm]", "speed [mm/s]", "force [kN]"),
            plain,
        )
        for name in slides:
            js = res.joint(name)
            moves.add_row(
                name,
                _fixed(js.angle[-1] * 1e6),
                _fixed(js.speed[-1] * 1e3),
                _fixed(js.torque[-1] / 1e3),
            )
        tables.append(moves)

    if res.mesh_names:
        forces = _table(
            f"Tooth forces at {final} (normal, tangential, radial, axial)",
            ("mesh", "Fn [kN]", "Ft [kN]", "Fr [kN]", "Fa [kN]", "flank [-]"),
            plain,
        )
        history = _table(
            f"Gear meshes over {_span(res, stats)}: normal force and transmission error",
            ("mesh", "min [kN]", "max [kN]", "RMS [kN]", "max |TE| [µm]"),
            plain,
        )
        for name in res.mesh_names:
            ms = res.mesh(name)
            s = stats.row("mesh", name, "normal")
            te = stats.row("mesh", name, "transmission error")
            forces.add_row(
                name,
                _fixed(ms.normal[-1] / 1e3),
                _fixed(ms.tangential[-1] / 1e3),
                _fixed(ms.radial[-1] / 1e3),
                _fixed(ms.axial[-1] / 1e3),
                f"{int(ms.flank[-1]):+d}",
            )
            history.add_row(
                name,
                _fixed(s.min / 1e3),
                _fixed(s.max / 1e3),
                _fixed(s.rms / 1e3),
                f"{max(abs(te.min), abs(te.max)) * 1e6:.2e}",
            )
        tables += [forces, history]

    # The loads of ``dynamics/bearing_load.py`` (the series bearing_radial, ...), as the
    # report, the export and the plots give them: the shaft's torque apart from the loads.
    at_end = _table(
        f"Bearing loads on the child body at {final}, about the bearing axis",
        ("bearing", "radial [kN]", "axial [kN]", "tilting |M| [kN·m]", "torque [kN·m]"),
        plain,
    )
    peaks = _table(
        f"Bearing loads over {_span(res, stats)}: largest values",
        ("bearing", "radial [kN]", "|axial| [kN]", "tilting [kN·m]", "|F| max [kN]"),
        plain,
    )
    # The statistics' labels of the series: "radial force", "axial force", "tilting moment".
    label = {q: series.get(f"bearing_{q}").title for q in ("radial", "axial", "tilting", "force")}
    for name in res.bearing_names:
        b = res.bearing(name)
        at_end.add_row(
            name,
            _fixed(b.radial[-1] / 1e3),
            _fixed(b.axial[-1] / 1e3),
            _fixed(b.tilting[-1] / 1e3),
            _fixed(b.torque[-1] / 1e3),
        )
        axial = stats.row("bearing", name, label["axial"])
        peaks.add_row(
            name,
            _fixed(stats.row("bearing", name, label["radial"]).max / 1e3),
            _fixed(max(abs(axial.min), abs(axial.max)) / 1e3),
            _fixed(stats.row("bearing", name, label["tilting"]).max / 1e3),
            _fixed(stats.row("bearing", name, label["force"], "|.|").max / 1e3),
        )
    tables += [at_end, peaks]

    # Generators and rotors apart: one table of both, with the generators' rows of dashes,
    # is too wide for 80 columns, and its cells folded (a thrust printed as "170.106" over "0").
    if res.generator_names:
        generators = _table(
            f"Generators at {final}, and their means over {_span(res, stats)}",
            ("generator", "torque [kN·m]", "mean [kN·m]"),
            plain,
        )
        for name in res.generator_names:
            torque = res.generator(name).torque
            mean = stats.row("load", f"generator {name}", "torque").mean
            generators.add_row(name, _fixed(torque[-1] / 1e3), _fixed(mean / 1e3))
        tables.append(generators)
    if res.rotor_names:
        rotors = _table(
            f"Rotors at {final}, and their means over {_span(res, stats)}",
            ("rotor", "torque [kN·m]", "mean [kN·m]", "power [kW]", "λ [-]", "Cp [-]",
             "thrust [kN]", "Ct [-]"),
            plain,
        )  # fmt: skip
        for name in res.rotor_names:
            r = res.rotor(name)
            rotors.add_row(
                name,
                _fixed(r.torque[-1] / 1e3),
                f"{stats.row('load', f'rotor {name}', 'torque').mean / 1e3:.4f}",
                f"{r.power[-1] / 1e3:.2f}",
                _fixed(r.tip_speed_ratio[-1]),
                _fixed(r.power_coefficient[-1]),
                _fixed(r.thrust[-1] / 1e3),
                _fixed(r.thrust_coefficient[-1]),
            )
        tables.append(rotors)
    return [_fitted(table) for table in tables]
