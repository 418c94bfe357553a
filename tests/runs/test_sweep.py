"""Planetary design sweep: Table 5 of Saleh 2017, eq. 41 queries, backends, resume."""

import math
import socket
import subprocess
import sys
import time

import pytest

from pinwind.analysis.sweep_design import SweepSettings
from pinwind.analysis.sweep_planetary import TABLE_5_INCLUDE, PlanetaryDesign, enumerate_planetary
from pinwind.analysis.sweep_table import query, read_checkpoint, read_table
from pinwind.errors import InputError, SchedulerUnreachable
from pinwind.runs.sweep import evaluate, run_sweep

# Table 5 of Saleh 2017, transcribed from the seed text:
# (#, centre distance [mm], module [mm], sun, planet, ring).
TABLE_5 = [
    (1, 420, 5, 53, 115, 283), (2, 420, 5, 54, 114, 282), (3, 420, 5, 55, 113, 281),
    (4, 480, 5, 61, 131, 323), (5, 480, 5, 62, 130, 322), (6, 480, 5, 63, 129, 321),
    (7, 540, 5, 68, 148, 364), (8, 540, 5, 69, 147, 363), (9, 540, 5, 70, 146, 362),
    (10, 540, 5, 71, 145, 361), (11, 600, 5, 76, 164, 404), (12, 600, 5, 77, 163, 403),
    (13, 600, 5, 78, 162, 402), (14, 600, 5, 79, 161, 401), (15, 540, 6, 57, 123, 303),
    (16, 540, 6, 58, 122, 302), (17, 540, 6, 59, 121, 301), (18, 420, 7, 38, 82, 202),
    (19, 420, 7, 39, 81, 201), (20, 420, 8, 33, 72, 177), (21, 420, 8, 34, 71, 176),
    (22, 480, 8, 38, 82, 202), (23, 480, 8, 39, 81, 201), (24, 540, 8, 43, 92, 227),
    (25, 540, 8, 44, 91, 226), (26, 600, 8, 47, 103, 253), (27, 600, 8, 48, 102, 252),
    (28, 600, 8, 49, 101, 251), (29, 540, 9, 38, 82, 202), (30, 540, 9, 39, 81, 201),
    (31, 420, 10, 27, 57, 141), (32, 480, 10, 31, 65, 161), (33, 540, 10, 34, 74, 182),
    (34, 540, 10, 35, 73, 181), (35, 600, 10, 38, 82, 202), (36, 600, 10, 39, 81, 201),
    (37, 540, 12, 29, 61, 151), (38, 540, 15, 24, 48, 120), (39, 540, 15, 23, 49, 121),
]  # fmt: skip

CENTRES = [0.420, 0.480, 0.540, 0.600]
MODULES = [m / 1000 for m in (5, 6, 7, 8, 9, 10, 12, 15)]


def _designs(**kw):
    return enumerate_planetary(CENTRES, MODULES, ratio_window=(6.0, 6.4), planets=3, **kw)


def _rows(designs):
    return [(d.number, round(d.centre_distance * 1e3), round(d.module * 1e3), d.sun, d.planet,
             d.ring) for d in designs]  # fmt: skip


def test_enumeration_with_the_papers_inputs_is_exactly_table_5():
    designs = _designs(include=TABLE_5_INCLUDE)
    assert _rows(designs) == TABLE_5
    assert [d.number for d in designs if d.included] == [38]
    for d in designs:
        assert d.ring == d.sun + 2 * d.planet
        assert (d.sun + d.ring) % 3 == 0
        assert d.centre_distance == pytest.approx(d.module * (d.sun + d.planet) / 2, rel=1e-12)


def test_open_window_leaves_out_ratios_6_and_6_4_except_the_preliminary_design():
    plain = _designs()
    assert len(plain) == 38
    assert all(6.0 < d.ratio < 6.4 for d in plain)
    # Ratio exactly 6.4: 480 mm with 5 mm (60/132/324) and 10 mm (30/66/162) are not in Table 5.
    closed = enumerate_planetary(CENTRES, MODULES, ratio_window=(5.999, 6.401), planets=3)
    extra = {(d.sun, d.planet, d.ring) for d in closed} - {(d.sun, d.planet, d.ring) for d in plain}
    assert (60, 132, 324) in extra and (30, 66, 162) in extra
    assert sum(1 for d in closed if d.ratio == 6.0) == 17


@pytest.fixture(scope="module")
def swept():
    return run_sweep(_designs(include=TABLE_5_INCLUDE), SweepSettings(), workers=1).rows


def test_eq_41_queries_return_designs_35_and_31(swept):
    picked = query(swept, centre_distance=0.600, ratio=6.3, module=0.010, min_sf=1.0)
    assert [r["number"] for r in picked] == [35]
    smallest = query(swept, minimise="centre_distance_mm", min_sf=1.0)
    assert [r["number"] for r in smallest] == [31]


def test_sun_planet_force_of_every_design_is_carrier_torque_over_six_centre_distances(swept):
    for row in swept:
        assert row["status"] == "ok", row["reason"]
        f_t = 1e6 / (6 * row["centre_distance_mm"] * 1e-3)  # T_c/(N · 2 a), N = 3
        assert row["sun_planet_tangential_force_kN"] * 1e3 == pytest.approx(f_t, rel=1e-9)


def test_bending_safety_factors_follow_table_5_within_8_percent(swept):
    paper = {1: 0.54, 11: 0.77, 20: 0.85, 31: 1.07, 35: 1.51, 37: 1.65, 38: 2.10}
    for n, sf in paper.items():
        assert swept[n - 1]["agma_SF_bending_min"] == pytest.approx(sf, rel=0.08)


def test_a_design_that_cannot_be_built_is_a_row_with_its_reason():
    crowded = PlanetaryDesign(1, 0.198, 0.006, 6, 60, 126, 3, 22.0)
    row = evaluate(crowded, SweepSettings())
    assert row["status"] == "failed"
    assert row["reason"].startswith("building:") and "collide" in row["reason"]
    assert math.isnan(row["agma_SF_min"])


def test_interrupted_sweep_keeps_finished_rows_and_a_rerun_skips_them(tmp_path, swept):
    designs = _designs(include=TABLE_5_INCLUDE)[:8]
    checkpoint = tmp_path / "designs.csv.partial.jsonl"

    def stop_after_three(done, total):
        if done == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(designs, SweepSettings(), workers=1, checkpoint=checkpoint,
                  progress=stop_after_three)  # fmt: skip
    kept = read_checkpoint(checkpoint)
    assert [r["number"] for r in kept] == [1, 2, 3]
    again = run_sweep(designs, SweepSettings(), workers=1, checkpoint=checkpoint, done=kept)
    assert again.computed == 5
    assert [r["number"] for r in again.rows] == list(range(1, 9))
    _assert_same(again.rows, swept[:8])


def _assert_same(rows, reference):
    assert len(rows) == len(reference)
    for row, ref in zip(rows, reference, strict=True):
        for key, value in ref.items():
            if key == "wall_time_s":
                continue
            if isinstance(value, float) and math.isnan(value):
                assert math.isnan(row[key])
            else:
                assert row[key] == value, key


def test_dask_local_cluster_gives_the_same_rows_as_the_local_run(swept):
    distributed = pytest.importorskip("distributed")
    designs = _designs(include=TABLE_5_INCLUDE)[30:36]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:  # fmt: skip
        with distributed.Client(cluster) as client:
            run = run_sweep(designs, SweepSettings(), scheduler=client)
    assert run.backend.startswith("dask")
    _assert_same(run.rows, swept[30:36])


def test_sweep_command_writes_a_table_that_query_reads(tmp_path):
    def cli(*args):
        return subprocess.run([sys.executable, "-m", "pinwind", *args], capture_output=True,
                              text=True, timeout=300, cwd=tmp_path)  # fmt: skip

    out = cli("sweep", "planetary", "--center-distance", "420,600", "--module", "10", "--ratio",
              "6:6.4", "--workers", "1", "-o", "designs.parquet", "--no-compare")  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = read_table(tmp_path / "designs.parquet")
    assert [(r["sun"], r["planet"], r["ring"]) for r in rows] == [
        (27, 57, 141),
        (38, 82, 202),
        (39, 81, 201),
    ]
    picked = cli("sweep", "query", "designs.parquet", "--minimise", "center-distance",
                 "--min-sf", "1")  # fmt: skip
    assert picked.returncode == 0 and picked.stdout.startswith("#1: a = 420 mm")
    none = cli("sweep", "query", "designs.parquet", "--min-sf", "5")
    assert none.returncode == 1 and "no design" in none.stdout


def test_comparison_names_its_source_and_prints_each_design_whole(swept, monkeypatch):
    # The title said "beside 000 Table 5" (a file name, not a source) and a pipe's 80 columns cut
    # each design to "600/10/38/82/2…".
    import io

    from rich.console import Console

    import pinwind.cli.sweep as sweep_cli

    printed = io.StringIO()
    monkeypatch.setattr(sweep_cli, "console", Console(width=80, file=printed, color_system=None))
    sweep_cli._print_table_5_comparison(swept)
    text = printed.getvalue()
    assert "beside Saleh 2017 Table 5" in text and "…" not in text
    for _, a, m, sun, planet, ring in TABLE_5:  # the paper's designs, each on one line
        assert f" {a}/{m}/{sun}/{planet}/{ring} " in text


def test_query_with_an_unknown_safety_factor_column_is_one_line_naming_the_columns(tmp_path):
    (tmp_path / "t.csv").write_text(
        "number,status,centre_distance_mm,module_mm,ratio,agma_SF_min,iso_S_min\n"
        "1,ok,420,10,6.2,1.5,1.3\n"
    )
    with pytest.raises(InputError, match='--sf "agma_SF_mn": not a column'):
        query(read_table(tmp_path / "t.csv"), min_sf=1, sf_column="agma_SF_mn")
    out = subprocess.run([sys.executable, "-m", "pinwind", "sweep", "query", "t.csv", "--min-sf",
                          "1", "--sf", "agma_SF_mn"], capture_output=True, text=True,
                         timeout=300, cwd=tmp_path)  # fmt: skip
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "columns are agma_SF_min, iso_S_min" in " ".join(out.stderr.split())


def test_unreachable_dask_scheduler_fails_at_once_in_one_line():
    with socket.socket() as probe:  # a port nothing listens on once closed
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    started = time.perf_counter()
    with pytest.raises(SchedulerUnreachable, match=f'"tcp://127.0.0.1:{port}": cannot reach'):
        run_sweep(_designs()[:1], SweepSettings(), scheduler=f"tcp://127.0.0.1:{port}")
    assert time.perf_counter() - started < 5.0  # Dask's own retries took 30 s


def test_a_planetary_centre_distance_of_more_teeth_than_a_sweep_builds_is_refused():
    # 2a/m = 2 · 810 mm / 1e-30 mm = 1.62e33 teeth: the enumeration over sun counts never
    # returned (--module 1e-30).
    with pytest.raises(InputError, match=r"2a/m = 1\.62e\+33 teeth of sun and planet"):
        enumerate_planetary([0.81], [1e-33], ratio_window=(5.0, 7.0))
