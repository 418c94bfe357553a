"""``pinwind sweep query`` when no design meets every criterion: the best of each, alone."""

from __future__ import annotations

import subprocess
import sys

#: Three designs: none has a safety factor above 1, and the one near ratio 3.5 failed.
TABLE = (
    "number,status,centre_distance_mm,module_mm,ratio,agma_SF_min,iso_S_min\n"
    "1,ok,420,10,6.2,0.977,1.3\n"
    "2,ok,600,8,3.6,0.62,0.9\n"
    "3,failed,600,10,3.5,,\n"
)


def query(tmp_path, *criteria: str) -> subprocess.CompletedProcess:
    (tmp_path / "designs.csv").write_text(TABLE)
    return subprocess.run(
        [sys.executable, "-m", "pinwind", "sweep", "query", "designs.csv", *criteria],
        capture_output=True, text=True, timeout=300, cwd=tmp_path,
    )  # fmt: skip


def test_no_design_meeting_every_criterion_names_the_best_value_of_each(tmp_path):
    out = query(tmp_path, "--minimise", "center-distance", "--min-sf", "1", "--ratio", "3.5")
    assert out.returncode == 1
    text = " ".join(out.stdout.split())
    assert "no design satisfies every criterion" in text
    # The largest SF of the designs that ran is design 1's 0.977; none exceeds 1.
    assert "the largest agma_SF_min is 0.977 (#1); 0 design(s) exceed 1" in text
    # Design 3 (ratio 3.5) failed: the nearest ratio that ran is design 2's 3.6.
    assert "the nearest ratio is 3.6 (#2); 0 design(s) within ±0.05" in text


def test_the_best_of_a_criterion_that_some_designs_meet_counts_them(tmp_path):
    out = query(tmp_path, "--center-distance", "600", "--module", "10")
    assert out.returncode == 1
    text = " ".join(out.stdout.split())
    assert "--center-distance 600: the nearest is 600 mm (#2); 1 design(s) at it" in text
    assert "--module 10: the nearest is 10 mm (#1); 1 design(s) at it" in text


def test_an_empty_table_is_one_line_exit_2_naming_it(tmp_path):
    # A sweep of no design wrote an empty designs.csv; reading it was pyarrow's traceback.
    (tmp_path / "designs.csv").write_text("")
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "sweep", "query", "designs.csv"],
        capture_output=True, text=True, timeout=300, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 2, out.stderr
    assert "designs.csv: not a sweep table (Empty CSV file)" in out.stderr
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr


def test_a_sweep_of_no_design_exits_2_and_writes_no_table(tmp_path):
    # 2a/m = 2 · 810 mm / 1e30 mm: no whole tooth; it wrote an empty table, exit 0.
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "sweep", "planetary", "--center-distance", "810",
         "--module", "1e30", "--ratio", "5:7", "--no-compare", "--workers", "1"],
        capture_output=True, text=True, timeout=300, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 2, out.stderr
    assert "error: no design (ratio window (5, 7) open): no tooth counts" in out.stderr
    assert out.stderr.count("\n") == 1 and not (tmp_path / "designs.csv").exists()
