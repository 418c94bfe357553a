"""``pinwind modes``: mode classes and repeated frequencies, the animation, bad input."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys

import numpy as np

from pinwind.io.mode_animation import AMPLITUDE
from tests.conftest import MODELS
from tests.dynamics.test_gyroscopic_modes import ROTORS, TILT, rotor_urdf, whirl_frequencies
from tests.io.conftest import rrd_columns


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *args], capture_output=True, text=True, timeout=300
    )


def test_modes_of_a_three_planet_stage_list_one_double_planet_mode():
    # Lin & Parker: with N = 3 torsional planets, one planet mode of multiplicity N − 1 = 2.
    model = str(MODELS / "saleh2017_planetary.urdf")
    kinds = [m["kind"] for m in json.loads(run("modes", model, "--json").stdout)]
    assert kinds.count("planet") == 2
    assert set(kinds) == {"rotational", "planet"}
    table = run("modes", model).stdout
    assert "planet ×2" in table
    assert "rotational ×" not in table


def _turn_about_z(rrd_column) -> np.ndarray:
    """Rotation angles about z [rad] of a Transform3D quaternion column (x, y, z, w)."""
    q = np.array([row[0] for row in rrd_column[0].to_pylist()], dtype=float)
    return 2.0 * np.arctan2(q[:, 2], q[:, 3])


def test_the_animated_planet_mode_swings_the_planets_against_each_other(tmp_path):
    # Mode 3 of the three-planet stage is a planet mode: sun and carrier still, the planets'
    # angles sum to zero. The animation swings them as A sin(2π t) φ, one period per second,
    # the largest angle AMPLITUDE rad (every coordinate is a rotation).
    rrd = tmp_path / "mode3.rrd"
    model = str(MODELS / "saleh2017_planetary.urdf")
    out = run("modes", model, "--animate", "3", "--save", str(rrd))
    assert out.returncode == 0, out.stderr
    assert f"wrote {rrd}" in out.stdout.replace("\n", "")
    columns = rrd_columns(rrd)
    for body in ("sun", "carrier", "planet1", "planet2", "planet3", "ring"):
        assert f"/gearbox/{body}" in columns
    time = np.array([t.total_seconds() for t in columns["/gearbox/planet1"]["time"][0].to_pylist()])
    angles = np.array(
        [_turn_about_z(columns[f"/gearbox/planet{i}"]["Transform3D:quaternion"]) for i in (1, 2, 3)]
    )
    np.testing.assert_allclose(time[-1], 3.0, rtol=1e-9)  # three periods
    np.testing.assert_allclose(angles.sum(axis=0), 0.0, atol=1e-6)
    np.testing.assert_allclose(np.abs(angles).max(), AMPLITUDE, rtol=1e-3)
    shape = angles[:, np.argmax(np.abs(angles).max(axis=0))]  # the planets at a crest
    np.testing.assert_allclose(
        angles, np.outer(shape, np.sin(2 * np.pi * time)) / np.sin(2 * np.pi * 0.25), atol=1e-5
    )
    for body in ("sun", "carrier"):
        turn = _turn_about_z(columns[f"/gearbox/{body}"]["Transform3D:quaternion"])
        np.testing.assert_allclose(turn, 0.0, atol=1e-6)


def test_animate_without_save_or_beyond_the_last_mode_is_refused_in_one_line(tmp_path):
    model = str(MODELS / "saleh2017_planetary.urdf")
    for args, message in [
        (("--animate", "2"), "--animate N and --save FILE.rrd go together"),
        (("--animate", "9", "--save", str(tmp_path / "m.rrd")), "has modes 1 to 5"),
    ]:
        out = run("modes", model, *args)
        assert out.returncode == 2
        assert message in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_modes_at_a_speed_outside_the_range_of_validity_exit_2_in_one_line():
    model = str(MODELS / "saleh2017_planetary.urdf")
    for speed, message in [
        ("carrier=-10", "give 0 or more"),
        ("carrier=1e7", "beyond the 1e+05 rad/s"),
    ]:
        out = run("modes", model, "--speed", speed)
        assert out.returncode == 2
        assert message in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_modes_of_a_spinning_rotor_list_its_forward_and_backward_whirl(tmp_path):
    # The Jeffcott closed form of tests/dynamics/test_gyroscopic_modes.py at 3000 rpm.
    polar, transverse = ROTORS[0]
    model = tmp_path / "rotor.urdf"
    model.write_text(rotor_urdf(polar, transverse))
    out = run("modes", str(model), "--speed", "rotor=3000", "--json")
    assert out.returncode == 0, out.stderr
    found = {m["whirl"]: m["frequency_hz"] for m in json.loads(out.stdout) if m["whirl"]}
    forward, backward = whirl_frequencies(polar, transverse, 3000 * 2 * math.pi / 60)
    np.testing.assert_allclose(found["forward"], forward / (2 * math.pi), rtol=1e-6)
    np.testing.assert_allclose(found["backward"], backward / (2 * math.pi), rtol=1e-6)
    table = run("modes", str(model), "--speed", "rotor=3000").stdout
    assert "forward" in table and "backward" in table


def test_campbell_of_a_spinning_rotor_writes_the_whirl_of_each_crossing(tmp_path):
    polar, transverse = ROTORS[0]
    model = tmp_path / "rotor.urdf"
    model.write_text(rotor_urdf(polar, transverse))
    csv_path = tmp_path / "crossings.csv"
    out = run("campbell", str(model), "--joint", "rotor", "--speed-range", "0:2500",
              "--points", "21", "--csv", str(csv_path))  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = list(csv.DictReader(csv_path.open()))
    rpm = {r["whirl"]: float(r["speed_rpm"]) for r in rows if r["whirl"]}
    per_rpm = 60 / (2 * math.pi)
    np.testing.assert_allclose(
        rpm["forward"], math.sqrt(TILT / (transverse - polar)) * per_rpm, rtol=1e-9
    )
    np.testing.assert_allclose(
        rpm["backward"], math.sqrt(TILT / (transverse + polar)) * per_rpm, rtol=1e-9
    )
