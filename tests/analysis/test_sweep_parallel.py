"""Parallel-stage design sweep (Saleh 2017 §5 applied to a spur or helical pair)."""

import math
import re
import subprocess
import sys

import pytest

from pinwind.analysis.sweep_design import SweepSettings
from pinwind.analysis.sweep_parallel import ParallelDesign, enumerate_parallel
from pinwind.analysis.sweep_table import query, read_table
from pinwind.errors import InputError
from pinwind.runs.sweep import evaluate, run_sweep

CENTRES_MM = (500, 530, 560, 600)
MODULES_MM = (8, 10, 12)
WINDOW = (3.4, 4.0)
ALPHA = math.radians(20.0)
SETTINGS = SweepSettings(input_torque=1.5e5, input_speed=85.2 * math.pi / 30,
                         pressure_angle=ALPHA, face_width_factor=8.0)  # fmt: skip


def _designs(helix_deg=0.0):
    return enumerate_parallel(
        [a / 1e3 for a in CENTRES_MM], [m / 1e3 for m in MODULES_MM], ratio_window=WINDOW,
        pressure_angle=ALPHA, helix_angle=math.radians(helix_deg),
    )  # fmt: skip


def test_spur_enumeration_is_every_whole_tooth_split_without_undercut_in_the_window():
    # Brute force, independent of the code: integer tooth sums 2a/m, every split, the open ratio
    # window, and no undercut of the pinion by the ISO 53 profile A hob (h_a0* 1.25, ρ_a0* 0.38):
    # z ≥ 2 (1.25 − 0.38 (1 − sin α)) / sin² α (DIN 3960).
    z_min = 2 * (1.25 - 0.38 * (1 - math.sin(ALPHA))) / math.sin(ALPHA) ** 2
    expected = []
    for m in MODULES_MM:
        for a in CENTRES_MM:
            if (2 * a) % m:
                continue
            total = 2 * a // m
            for pinion in range(1, total):
                wheel = total - pinion
                if WINDOW[0] < wheel / pinion < WINDOW[1] and pinion >= z_min:
                    expected.append((a, m, wheel, pinion))
    designs = _designs()
    got = [(round(d.centre_distance * 1e3), round(d.module * 1e3), d.wheel, d.pinion)
           for d in designs]  # fmt: skip
    assert got == expected
    assert len(expected) > 10
    assert [d.number for d in designs] == list(range(1, len(expected) + 1))


def test_a_helical_design_raises_its_helix_angle_to_sit_at_the_centre_distance():
    designs = _designs(helix_deg=10.0)
    assert designs
    for d in designs:
        total = d.wheel + d.pinion
        assert total == math.floor(2 * d.centre_distance * math.cos(math.radians(10)) / d.module)
        assert d.helix_angle >= math.radians(10) - 1e-12
        assert d.module * total / (2 * math.cos(d.helix_angle)) == pytest.approx(
            d.centre_distance, rel=1e-12
        )


@pytest.fixture(scope="module")
def swept():
    return run_sweep(_designs(), SETTINGS, workers=1).rows


@pytest.mark.parametrize("helix_deg", [0.0, 12.0])
def test_tangential_force_of_every_design_is_input_torque_over_wheel_pitch_radius(helix_deg):
    designs = _designs(helix_deg)[:6]
    for row, d in zip(run_sweep(designs, SETTINGS, workers=1).rows, designs, strict=True):
        assert row["status"] == "ok", row["reason"]
        r_wheel = d.module * d.wheel / (2 * math.cos(d.helix_angle))  # m_t z / 2
        assert row["tangential_force_kN"] * 1e3 == pytest.approx(1.5e5 / r_wheel, rel=1e-9)


def test_query_picks_the_smallest_centre_distance_with_a_safe_design(swept):
    safe = [r for r in swept if r["agma_SF_min"] > 1.0]
    assert 0 < len(safe) < len(swept)  # the criterion does separate designs here
    smallest = min(r["centre_distance_mm"] for r in safe)
    by_hand = [r["number"] for r in safe if r["centre_distance_mm"] == smallest]
    picked = query(swept, minimise="centre_distance_mm", min_sf=1.0)
    assert [r["number"] for r in picked] == by_hand
    at_600 = query(swept, centre_distance=0.600, module=0.010, ratio=3.6, ratio_tolerance=0.1)
    assert [(r["wheel"], r["pinion"]) for r in at_600] == [(94, 26)]  # 94/26 = 3.615


def test_a_design_that_cannot_be_built_is_a_row_with_its_reason():
    steep = ParallelDesign(1, 0.5, 0.01, 70, 20, math.radians(50.0), 3.5)
    row = evaluate(steep, SETTINGS)
    assert row["status"] == "failed"
    assert row["reason"].startswith("building:") and "45" in row["reason"]
    assert math.isnan(row["agma_SF_min"])


def test_dask_local_cluster_gives_the_same_rows_as_the_local_run(swept):
    distributed = pytest.importorskip("distributed")
    designs = _designs()[:5]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:  # fmt: skip
        with distributed.Client(cluster) as client:
            run = run_sweep(designs, SETTINGS, scheduler=client)
    assert run.backend.startswith("dask")
    for row, ref in zip(run.rows, swept[:5], strict=True):
        assert {k: v for k, v in row.items() if k != "wall_time_s"} == {
            k: v for k, v in ref.items() if k != "wall_time_s"
        }


def test_a_rerun_reuses_every_finished_row(swept):
    again = run_sweep(_designs(), SETTINGS, workers=1, done=swept)
    assert again.computed == 0
    assert again.rows == swept


def test_parallel_command_writes_a_table_that_query_and_plot_read(tmp_path):
    def cli(*args):
        return subprocess.run([sys.executable, "-m", "pinwind", *args], capture_output=True,
                              text=True, timeout=300, cwd=tmp_path)  # fmt: skip

    out = cli("sweep", "parallel", "--center-distance", "500,600", "--module", "10", "--ratio",
              "3.4:4", "--torque", "1.5e5", "--face-width-factor", "8", "--workers", "1",
              "-o", "parallel.parquet")  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = read_table(tmp_path / "parallel.parquet")
    # 2a/m = 100 and 120 teeth; 3.4 < z_w/z_p < 4: z_p = 21, 22 and 25…27.
    assert [(r["wheel"], r["pinion"]) for r in rows] == [(79, 21), (78, 22), (95, 25), (94, 26),
                                                         (93, 27)]  # fmt: skip
    assert {r["stage"] for r in rows} == {"parallel"}
    picked = cli("sweep", "query", "parallel.parquet", "--center-distance", "600", "--ratio",
                 "3.62", "--ratio-tolerance", "0.01")  # fmt: skip
    assert picked.returncode == 0, picked.stderr
    assert picked.stdout.startswith("#4: a = 600 mm, m = 10 mm, teeth 94/26, u = 3.62")
    plots = cli("sweep", "plot", "parallel.parquet", "-o", "plots")
    assert plots.returncode == 0, plots.stderr
    assert sorted(p.name for p in (tmp_path / "plots").iterdir()) == [
        "bending_sf_min.png", "centre_distance.png", "contact_sf.png", "iso_sf_min.png",
        "speed_ratio.png",
    ]  # fmt: skip


def test_a_centre_distance_of_more_teeth_than_a_sweep_builds_is_refused():
    # 2a/m = 2 · 1e27 m / 0.015 m = 1.33e29 teeth: the enumeration over pinion counts never
    # returned (a centre distance of 1e30 mm).
    with pytest.raises(InputError, match=r"2a/m = 1\.33e\+29 teeth of pinion and wheel"):
        enumerate_parallel([1e27], [0.015], ratio_window=(3.0, 4.0),
                           pressure_angle=math.radians(20.0))  # fmt: skip


@pytest.mark.parametrize(
    "change, message",
    [
        ({"input_torque": math.nan}, "--torque is nan N·m"),
        ({"input_torque": 0.0}, "--torque is 0 N·m"),
        ({"input_speed": math.inf}, "(--carrier-speed, --input-speed) is inf rpm"),
        ({"input_speed": -2 * math.pi / 60}, "(--carrier-speed, --input-speed) is -1 rpm"),
    ],
)
def test_sweep_settings_without_a_finite_load_are_refused_before_any_row(change, message):
    # A NaN or infinite torque or speed ran every design to a table of NaN safety factors.
    with pytest.raises(InputError, match=re.escape(message)):
        SweepSettings(**change)
