"""The command line: the main job prints a summary, bad input gives one clear line."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pinwind
from tests.conftest import MODELS


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    # simulate logs to ./logs by default: keep the runs' logs out of the repository.
    monkeypatch.chdir(tmp_path)


def run(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    """``pinwind ARGS`` in a child process (in ``cwd`` if given), its output captured."""
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=cwd,
    )


def test_simulate_prints_speeds_ratios_mesh_forces_and_bearings():
    out = run(
        "simulate",
        str(MODELS / "saleh2017_planetary.urdf"),
        "--torque",
        "carrier=1e6",
        "--torque",
        "sun=-166666.6666666667",
        "--duration",
        "0.05",
        "--dt",
        "1e-3",
    )
    assert out.returncode == 0, out.stderr
    text = out.stdout
    for name in ("sun_planet1", "planet3_ring", "carrier", "ring"):
        assert name in text
    # Balanced torques: the sun mesh carries T_s/(3 r_s cos α) = 339.1814 kN.
    expected_kn = 1e6 / 6 / (3 * 0.18 * math.cos(math.radians(24.5))) / 1e3
    assert f"{expected_kn:.4f}" in text
    assert "ratio to carrier" in text
    # The ring is a fixed mount: its ratio is exactly 0, not the rounding noise of its speed.
    ring_row = next(line for line in text.splitlines() if line.strip("│ ").startswith("ring "))
    assert "0 (fixed)" in ring_row


def test_speed_option_is_in_rpm():
    out = run(
        "simulate",
        str(MODELS / "saleh2017_planetary.urdf"),
        "--speed",
        "carrier=14.2",
        "--duration",
        "0.01",
        "--dt",
        "1e-3",
    )
    assert out.returncode == 0, out.stderr
    assert "85.2000" in out.stdout  # sun speed [rpm] = 6 × 14.2 (Saleh 2017)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--torque", "sunn=1"], 'unknown joint "sunn" in torques; joints are: carrier'),
        (["--torque", "sun"], "must look like JOINT=VALUE"),
        (["--torque", "sun=abc"], '"abc" is not a number'),
        (["--dt", "0"], "dt is 0 s; it must be positive"),
        (["--speed", "sun=abc"], '"abc" is not a number [rpm]'),  # the unit survives rich
    ],
)
def test_bad_options_exit_2_with_one_line(args, message):
    out = run("simulate", str(MODELS / "saleh2017_planetary.urdf"), *args)
    assert out.returncode == 2
    assert message in out.stderr
    assert "Traceback" not in out.stderr


def test_missing_model_file_is_named():
    out = run("simulate", "models/nope.urdf")
    assert out.returncode == 2
    assert "models/nope.urdf" in out.stderr and "cannot read" in out.stderr


def test_build_planetary_writes_a_model_with_the_requested_geometry(tmp_path):
    target = tmp_path / "out.urdf"
    out = run(
        "build",
        "planetary",
        "--sun",
        "24",
        "--planet",
        "48",
        "--ring",
        "120",
        "--planets",
        "3",
        "--module",
        "15",
        "--pressure-angle",
        "24.5",
        "--face-width",
        "380",
        "--parallel",
        "83/23",
        "-o",
        str(target),
    )
    assert out.returncode == 0, out.stderr
    gb = pinwind.load(target)
    assert sorted(gb.joint_names) == sorted(
        ["carrier", "sun", "planet1", "planet2", "planet3", "ring", "stage1_pinion"]
    )
    # Centre distance m (z_s + z_p) / 2 = 15 mm × 72 / 2.
    assert math.isclose(gb.mesh("sun_planet1").centre_distance, 0.540, rel_tol=1e-12)
    assert math.isclose(
        gb.mesh("stage1").centre_distance,
        gb.gears["stage1_wheel"].spec.module * (83 + 23) / 2,
        rel_tol=1e-12,
    )


def test_info_lists_the_speed_ratios_of_a_one_degree_of_freedom_train():
    out = run("info", str(MODELS / "saleh2017_drivetrain.urdf"))
    assert out.returncode == 0, out.stderr
    # 6 × 83/23 × 103/26 from the tooth counts (Saleh 2017 Table 2, §4.1).
    assert f"stage2_pinion {6 * 83 / 23 * 103 / 26:.6g}" in out.stdout
    assert "sun 6" in out.stdout


def test_position_error_option_is_in_micrometres():
    from pinwind.cli.flags import parse_position_errors

    errors = parse_position_errors(["planet1=12.5,-3"])
    np.testing.assert_allclose(errors["planet1"], (12.5e-6, -3e-6), rtol=1e-15)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--mesh", "all=soft"], "the type must be one of rigid, compliant"),
        (["--mesh", "sun_planet9=compliant"], 'no mesh named "sun_planet9"'),
        (["--position-error", "planet1=10"], "must be GEAR=TANGENTIAL_UM,RADIAL_UM"),
    ],
)
def test_bad_mesh_options_exit_2_naming_the_option(args, message):
    proc = run("simulate", str(MODELS / "saleh2017_planetary.urdf"), "--no-log", *args)
    assert proc.returncode == 2
    assert message in proc.stderr


def test_simulate_runs_compliant_meshes_and_reports_load_sharing():
    proc = run(
        "simulate", str(MODELS / "saleh2017_planetary.urdf"), "--no-log",
        "--torque", "sun=1e5", "--speed", "carrier=0", "--mesh", "all=compliant",
        "--duration", "0.02", "--dt", "1e-5",
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    # A perfect stage: every planet carries a third.
    assert "load sharing at the sun: K_γ = 1.0000" in proc.stdout


def test_build_into_a_missing_folder_is_one_line_without_traceback(tmp_path):
    target = tmp_path / "missing" / "out.urdf"
    out = run(
        "build", "planetary", "--sun", "24", "--planet", "48", "--ring", "120", "-o", str(target)
    )
    assert out.returncode == 2
    assert f"cannot write the model to {target}" in out.stderr
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr


def test_build_of_planets_that_cannot_be_spaced_equally_warns_in_one_line(tmp_path):
    # (24 + 118)/4 = 35.5 is not a whole number: the builder's warning, without its source line.
    out = run("build", "planetary", "--sun", "24", "--planet", "47", "--ring", "118",
              "--planets", "4", "-o", str(tmp_path / "m.urdf"))  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "(24 + 118)/4 = 35.5 is not a whole number" in out.stderr
    assert out.stderr.count("\n") == 1 and "planetary.py" not in out.stderr


def test_help_keeps_the_units_in_brackets_and_every_option_whole():
    out = run("simulate", "--help")
    assert out.returncode == 0, out.stderr
    for text in (
        "Simulated time [s]",
        "Time step [s]",
        "[Hz]",
        "MEAN_RPM,AMPLITUDE_RPM,FREQUENCY_HZ",
    ):
        assert text in out.stdout
    assert "…" not in out.stdout
    build = run("build", "planetary", "--help")
    assert "Module [mm]" in build.stdout and "Pressure angle [deg]" in build.stdout


def test_piped_summary_fits_80_columns_in_plain_text_without_cut_numbers():
    # saleh2017_drivetrain has the longest names of the shipped models.
    out = run(
        "simulate",
        str(MODELS / "saleh2017_drivetrain.urdf"),
        "--torque",
        "carrier=1e6",
        "--duration",
        "0.01",
        "--no-log",
    )
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert max(len(line) for line in lines[1:]) <= 80  # line 0 names the model file
    assert "…" not in out.stdout and "\x1b" not in out.stdout
    assert not any(ch in out.stdout for ch in "│┃━─┏┗")  # plain ASCII rules when piped
    for header in ("speed [rpm]", "Fn [kN]", "Ft [kN]", "|M| [kN·m]", "|F| max [kN]"):
        assert header in out.stdout
    row = next(line.split() for line in lines if line.strip().startswith("stage2_pinion "))
    assert len(row) == 4 and all(cell.replace(".", "").lstrip("-").isdigit() for cell in row[1:])


def test_implausible_gear_warning_is_one_line_on_stderr():
    out = run("info", str(MODELS / "cai_spur_pair.urdf"))
    assert out.returncode == 0, out.stderr
    (line,) = out.stderr.splitlines()
    assert line.startswith("warning: ") and '<link name="gear2">: axial inertia 0.003' in line


def test_a_cause_a_command_meets_twice_is_shown_once(capsys):
    import pinwind
    from pinwind.cli.app import SHOWN_WARNINGS, warnings_as_lines

    SHOWN_WARNINGS.clear()  # as main() does for each command
    for _ in range(2):  # the model loaded for the scenario, then for the run
        with warnings_as_lines():
            pinwind.load(MODELS / "cai_spur_pair.urdf")
    assert capsys.readouterr().err.count('<link name="gear2">') == 1


def test_keep_option_is_refused_when_it_is_not_a_choice_or_a_count():
    proc = run("simulate", str(MODELS / "saleh2017_planetary.urdf"), "--no-log", "--keep", "x")
    assert proc.returncode == 2
    assert '--keep "x" must be all, last, auto or a whole number' in proc.stderr


def test_summary_counts_every_step_when_only_some_samples_are_kept():
    proc = run(
        "simulate", str(MODELS / "saleh2017_planetary.urdf"), "--no-log", "--torque",
        "carrier=1e5", "--duration", "1", "--dt", "1e-3", "--keep", "100",
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "1000 steps of 0.001 s" in proc.stdout
    assert "over every one of the 1001 samples, of which the result keeps 11 (every 100-th" in (
        " ".join(proc.stdout.split())
    )
    assert "Gear meshes over the run" in proc.stdout


def test_modes_lists_the_shaft_and_mesh_modes_of_the_cai_pair():
    out = run("modes", str(MODELS / "cai_spur_pair.urdf"), "--json")
    assert out.returncode == 0, out.stderr
    import json

    modes = [m for m in json.loads(out.stdout) if m["frequency_hz"] > 0.0]
    # Two shaft-spring modes and the mesh mode; the mesh mode's strain is all in the mesh.
    assert len(modes) == 3
    assert max(modes[-1]["strain_share"], key=modes[-1]["strain_share"].get) == "gear_pair"


def test_campbell_refuses_a_speed_range_without_a_colon_in_one_line():
    out = run("campbell", str(MODELS / "cai_spur_pair.urdf"), "--joint", "input_shaft",
              "--speed-range", "400")  # fmt: skip
    assert out.returncode == 2
    assert '--speed-range "400": give A:B in rpm' in out.stderr
    assert "Traceback" not in out.stderr


def test_build_of_a_model_pinwind_refuses_to_load_exits_2_and_keeps_no_file(tmp_path):
    # A module of 1e30 mm made a carrier of 1.7e61 kg that load then refused; build said
    # "wrote" and exited 0.
    target = tmp_path / "huge.urdf"
    out = run("build", "planetary", "--sun", "24", "--planet", "48", "--ring", "120",
              "--module", "1e30", "-o", str(target))  # fmt: skip
    assert out.returncode == 2, out.stdout
    assert out.stderr.startswith("error: the model built from --module 1e+30 mm, --face-width")
    assert (
        f"does not load, so {target} was not kept" in out.stderr and "beyond ±1e+20" in out.stderr
    )
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert not target.exists()
