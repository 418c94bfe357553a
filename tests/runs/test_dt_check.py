"""The dt-convergence check's reruns (``runs/dt_check.py``): its values against a plain run's
statistics, its window, and the ``--check-dt`` command line."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.runs.dt_check import check_dt
from tests.conftest import MODELS, two_gear_urdf

ALPHA = math.radians(20.0)
R_BA, R_BB = 0.020 * math.cos(ALPHA), 0.040 * math.cos(ALPHA)


def _pair_run_kwargs():
    # A compliant pair under balanced torques: it swings about 1000 N, damped.
    return dict(
        duration=0.01,
        torques={"a": 1000.0 * R_BA, "b": 1000.0 * R_BB},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e8, variation="constant", damping_ratio=0.05)},
    )


def test_values_at_dt_are_a_plain_runs_statistics_over_the_window():
    gb = loads(two_gear_urdf(), "pair.urdf")
    dt, window = 2e-5, (0.004, 0.008)
    check = check_dt(gb, dt=dt, window=window, progress=False, **_pair_run_kwargs())
    assert check.window == pytest.approx(window, rel=1e-12)
    plain = pinwind.simulate(gb, dt=dt, keep="all", **_pair_run_kwargs())
    inside = (plain.time >= window[0] - 1e-9) & (plain.time <= window[1] + 1e-9)
    normal = plain.mesh("m").normal[inside]
    single = plain.mesh("m").single_tooth_force[inside]
    rows = {(r.element, r.quantity): r for r in check.rows}
    np.testing.assert_allclose(
        rows["m", "normal force RMS"].values[0], np.sqrt(np.mean(normal**2)), rtol=1e-12
    )
    np.testing.assert_allclose(rows["m", "normal force max"].values[0], normal.max(), rtol=1e-12)
    np.testing.assert_allclose(
        rows["m", "single-tooth force max"].values[0], single.max(), rtol=1e-12
    )
    for bearing in plain.bearing_names:
        force = np.linalg.norm(plain.bearing(bearing).force[inside], axis=1)
        np.testing.assert_allclose(rows[bearing, "|force| max"].values[0], force.max(), rtol=1e-12)
        np.testing.assert_allclose(
            rows[bearing, "|force| RMS"].values[0], np.sqrt(np.mean(force**2)), rtol=1e-12
        )


def test_a_window_outside_the_run_is_refused_naming_the_run():
    gb = loads(two_gear_urdf(), "pair.urdf")
    with pytest.raises(InputError, match=r"--check-window.*0:0\.01 s"):
        check_dt(gb, dt=2e-5, window=(0.005, 0.02), progress=False, **_pair_run_kwargs())


def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *args],
        capture_output=True,
        text=True,
        env={**os.environ, "COLUMNS": "80"},
        timeout=300,
    )


SIMULATE = (
    "simulate", str(MODELS / "saleh2017_planetary.urdf"), "--torque", "sun=1e5",
    "--speed", "carrier=0", "--mesh", "all=compliant", "--duration", "0.004", "--dt", "2e-5",
)  # fmt: skip


def test_check_dt_prints_the_table_of_every_mesh_and_exits_0():
    out = _cli(*SIMULATE, "--check-dt")
    assert out.returncode == 0, out.stderr
    assert "dt check over 0.0036–0.004 s at dt = 2e-05, 1e-05 and 5e-06 s" in out.stdout
    for mesh in ("sun_planet1", "planet3_ring"):
        assert mesh in out.stdout
    assert "F_1 max" in out.stdout and "|F| max" in out.stdout
    # the unit of the tables' numbers (rich once read "[kN]" as markup and dropped it)
    assert "mesh forces over the window [kN]" in out.stdout


def test_check_window_outside_the_run_exits_2_naming_the_option_and_the_span():
    out = _cli(*SIMULATE, "--check-dt", "--check-window", "0.003:0.01")
    assert out.returncode == 2
    assert "--check-window" in out.stderr and "0:0.004 s" in out.stderr


def test_a_scenario_file_takes_the_same_check(tmp_path):
    scenario = tmp_path / "short.toml"
    scenario.write_text(
        f'model = "{MODELS / "saleh2017_planetary.urdf"}"\n'
        "duration = 0.004\ndt = 2e-5\ntorque = { sun = 1e5 }\nspeed = { carrier = 0.0 }\n"
        'mesh = { all = "compliant" }\n'
    )
    out = _cli("run", str(scenario), "--check-dt", "--check-window", "0.002:0.004", "--json")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    assert report["window"] == pytest.approx([0.002, 0.004], rel=1e-12)
    assert report["steps"] == pytest.approx([2e-5, 1e-5, 5e-6], rel=1e-12)
    assert {row["element"] for row in report["rows"] if row["group"] == "mesh"} == {
        f"{a}_{b}" for a, b in (("sun", "planet1"), ("sun", "planet2"), ("sun", "planet3"),
                                ("planet1", "ring"), ("planet2", "ring"), ("planet3", "ring"))
    }  # fmt: skip


def test_the_default_window_widens_to_three_mesh_periods():
    gb = loads(two_gear_urdf(), "pair.urdf")
    speed = 100.0  # gear B [rad/s]: a mesh period is 2π / (40 × 100) s, 1.57 ms
    period = 2 * math.pi / (40 * speed)
    check = check_dt(
        gb, dt=2e-5, duration=0.01, torques={"a": 1.0}, speeds={"b": speed},
        gravity=np.zeros(3), meshes={"all": "compliant"}, progress=False,
    )  # fmt: skip
    start, end = check.window
    assert end == pytest.approx(0.01, rel=1e-12)
    # The last 10 % (1 ms) holds less than one period; the window starts at the tooth change
    # three periods before the end's last one: between 3 and 4 periods long.
    assert 3 * period - 2e-5 <= end - start <= 4 * period + 2e-5
