"""``pinwind report``: the engineer's table by default, everything with --all, 80 columns whole."""

from __future__ import annotations

import io

from rich.console import Console

from pinwind.io.report import report_log, report_tables
from tests.io.test_cli_log import run

#: The issue's bounds: a planetary run's default report in at most 150 lines, 80 columns.
MAX_LINES = 150
COLUMNS = 80


def printed(path, **options) -> list[str]:
    """The report tables as a terminal 80 columns wide shows them (rich styles and rules)."""
    console = Console(file=io.StringIO(), width=COLUMNS, force_terminal=True, color_system=None)
    for table in report_tables(report_log(path), **options):
        console.print(table)
    return console.file.getvalue().splitlines()


def labels(lines: list[str]) -> set[str]:
    """The first cell of every row: the text before the first run of two spaces after it."""
    return {line.strip().split("  ")[0] for line in lines if line.strip()}


def test_default_report_of_a_planetary_run_is_at_most_150_lines(logged_run):
    out = run("report", str(logged_run.path))
    assert out.returncode == 0, out.stderr
    assert len(out.stdout.splitlines()) <= MAX_LINES


def test_default_report_has_speeds_torques_mesh_and_bearing_forces_and_no_angles(logged_run):
    shown = labels(printed(logged_run.path))
    for wanted in (
        "speed [rpm]",
        "torque [kN·m]",
        "normal [kN]",
        "tangential [kN]",
        "F radial [kN]",
        "T axis [kN·m]",
        "F world |.| [kN]",
    ):
        assert wanted in shown, wanted
    for unwanted in ("angle [rad]", "flank [-]", "F world x [kN]", "RMS"):
        assert not any(label.startswith(unwanted) for label in shown), unwanted


def test_all_option_adds_every_axis_angle_and_the_rms(logged_run):
    out = run("report", str(logged_run.path), "--all")
    assert out.returncode == 0, out.stderr
    for wanted in ("angle [rad]", "flank [-]", "F world x [kN]", "M joint z [kN·m]", "RMS"):
        assert wanted in out.stdout, wanted


def test_report_tables_fit_80_columns_with_every_label_and_number_whole(logged_run):
    for options in ({}, {"all_rows": True}, {"all_rows": True, "plain": True}):
        lines = printed(logged_run.path, **options)
        assert max(len(line) for line in lines) <= COLUMNS, options
        assert not any("…" in line for line in lines), options
    # Labels in one piece: the longest energy term and the bearing's tilting moment.
    text = "\n".join(printed(logged_run.path, all_rows=True))
    for label in ("work_constraints", "potential_spring", "M tilting [kN·m]", "T axis [kN·m]"):
        assert label in text, label


def test_report_command_fits_80_columns_but_for_the_line_naming_the_log(logged_run):
    out = run("report", str(logged_run.path))
    assert out.returncode == 0, out.stderr
    first, *rest = out.stdout.splitlines()
    assert str(logged_run.path) in first  # a path is as long as it is: on a line of its own
    assert max(len(line) for line in rest) <= COLUMNS
    assert not any("…" in line for line in rest)
    assert rest[0].startswith("completed; dt = 0.001 s")


def test_one_precision_per_quantity_and_the_locked_ring_s_speed_is_zero(logged_run):
    import numpy as np

    from pinwind.units import rad_s_to_rpm

    (joints, *_) = report_tables(report_log(logged_run.path), plain=True)
    res = logged_run.result
    speeds = {}  # element → its speed cells
    element = ""
    for label, *cells in _rows(joints):
        if not any(cells):
            element = label.strip()
        elif label.strip().replace("\\[", "[") == "speed [rpm]":  # rich's escaped markup
            speeds[element] = cells
    # The fastest shaft's largest |speed|, by hand from the run: its integer digits leave
    # 6 − digits decimals to every speed of the table.
    fastest = float(np.max(np.abs(rad_s_to_rpm(res.speed))))
    places = 6 - len(str(int(fastest)))
    for row in speeds.values():
        for cell in row:
            assert len(cell.split(".")[1]) == places, (row, places)
    # The ring is held: its speed is the solver's rounding, below 1e-9 of the fastest shaft's.
    ring = rad_s_to_rpm(res.joint("ring").speed)
    assert np.max(np.abs(ring)) < 1e-9 * fastest
    ring_row = speeds["ring"]
    assert ring_row == ["0." + "0" * places] * len(ring_row)


def _rows(table) -> list[list[str]]:
    """The cells of a rich table, row by row."""
    columns = [list(column.cells) for column in table.columns]
    return [list(row) for row in zip(*columns, strict=True)]
