"""``pinwind rate``'s tables: 80 columns with no cell cut, and the standards they rate by named."""

from __future__ import annotations

import io

import pytest
from rich.console import Console

import pinwind
from pinwind.analysis.rating import rate
from pinwind.analysis.rating_table import rating_tables
from pinwind.errors import RatingAtZeroSpeed
from tests.conftest import MODELS

COLUMNS = 80


@pytest.fixture(scope="module")
def printed() -> dict[bool, str]:
    """The tables of Saleh's stage at 1 MN·m, as a terminal and as a pipe 80 columns wide."""
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = pinwind.simulate(gb, duration=0.01, dt=1e-3, torques={"carrier": 1e6, "sun": -1e6 / 6})
    with pytest.warns(RatingAtZeroSpeed):  # balanced, from rest: the stage stands still
        rating = rate(gb, res)
    out = {}
    for plain in (False, True):
        console = Console(
            file=io.StringIO(), width=COLUMNS, force_terminal=not plain, color_system=None
        )
        for table in rating_tables(rating, title="saleh2017_planetary at t = 0.01 s", plain=plain):
            console.print(table)
        out[plain] = console.file.getvalue()
    return out


def test_rating_tables_fit_80_columns_with_no_cell_cut(printed):
    for text in printed.values():
        assert max(len(line) for line in text.splitlines()) <= COLUMNS
        assert "…" not in text
        for whole in ("sun_planet1", "planet3_ring", "planet2", "σ_H MPa", "AGMA S_F"):
            assert whole in text, whole


def test_rating_tables_name_the_standards_editions_and_methods(printed):
    # What gears/rating_iso.py and gears/rating_agma.py implement (their module docstrings).
    text = " ".join(printed[True].split())  # captions wrap: compare words
    for named in (
        "ISO 6336-2",
        "ISO 6336-3",
        "method B",
        "ISO 6336-1:1996 method C",
        "AGMA 2001-D04",
        "AGMA 908-B89",
        "K_A = 1",
        "Q_v = 10",
        "reliability 99 %",
    ):
        assert named in text, named


def test_a_stage_the_run_leaves_unloaded_prints_its_huge_safety_factors_as_over_100():
    # The sun's torque balances the carrier's on the sun shaft itself: the parallel stages behind
    # it carry only their inertia's share (≈ 0), so σ → 0 and S = permissible / σ → ∞. Printed
    # whole these widen the table past 80 columns and every cell got cut to "…".
    import warnings

    gb = pinwind.load(MODELS / "saleh2017_drivetrain.urdf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the rating of a nearly unloaded stage is the point
        res = pinwind.simulate(
            gb, duration=0.01, dt=1e-3, torques={"carrier": 1e6, "sun": -1e6 / 6}
        )
        rating = rate(gb, res)
    stage = next(m for m in rating.meshes if m.mesh == "stage2")
    assert min(stage.iso.S_H) > 100 and min(stage.agma.S_F) > 100
    console = Console(file=io.StringIO(), width=COLUMNS, force_terminal=False)
    for table in rating_tables(rating, title="saleh2017_drivetrain at t = 0.01 s", plain=True):
        console.print(table)
    text = console.file.getvalue()
    assert max(len(line) for line in text.splitlines()) <= COLUMNS
    assert "…" not in text
    row = next(line.split() for line in text.splitlines() if line.startswith("stage2 "))
    assert row[0:2] == ["stage2", "stage2_pinion"] and ">100" in row
