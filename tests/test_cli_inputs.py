"""Every unit conversion of ``pinwind simulate``'s options, and contradictory options refused.

The units are checked on the log the command writes, against values converted by hand here:
1 rpm = 2π/60 rad/s; torques N·m, times s, rates Hz.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from tests.conftest import MODELS
from tests.test_cli import run

RPM = 2 * math.pi / 60  # rad/s per rpm, by hand
PLANETARY = str(MODELS / "saleh2017_planetary.urdf")


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def simulate_log(*args: str) -> pinwind.Result:
    out = run("simulate", PLANETARY, "--out", "run.mcap", "--no-progress", *args)
    assert out.returncode == 0, out.stderr
    return pinwind.read_log("logs/run.mcap")


def test_speed_option_is_rpm():
    res = simulate_log("--speed", "carrier=14.2", "--duration", "0.01", "--dt", "1e-3")
    assert_allclose(res.joint("carrier").speed, 14.2 * RPM, rtol=1e-12)


def test_speed_sine_mean_and_amplitude_are_rpm_and_its_frequency_hertz():
    res = simulate_log("--speed-sine", "carrier=14.2,1.1,2.5", "--duration", "0.4", "--dt", "1e-3")
    t = res.time
    expected = (14.2 + 1.1 * np.sin(2 * math.pi * 2.5 * t)) * RPM
    assert_allclose(res.joint("carrier").speed, expected, rtol=1e-12)
    assert_allclose(res.joint("carrier").speed.max(), (14.2 + 1.1) * RPM, rtol=1e-6)


def test_initial_speed_is_rpm_and_sets_the_train_in_motion():
    res = simulate_log("--initial-speed", "carrier=14.2", "--duration", "0.01", "--dt", "1e-3")
    assert_allclose(res.joint("carrier").speed[0], 14.2 * RPM, rtol=1e-12)
    # Ring fixed, 24/120 teeth: the sun turns (1 + 120/24) = 6 times as fast.
    assert_allclose(res.joint("sun").speed[0], 6 * 14.2 * RPM, rtol=1e-12)


def test_torque_option_is_newton_metres():
    res = simulate_log(
        "--torque", "carrier=1e6", "--torque", "sun=-2.5e4", "--duration", "0.01", "--dt", "1e-3"
    )
    assert_allclose(res.joint("carrier").torque, 1e6, rtol=1e-15)
    assert_allclose(res.joint("sun").torque, -2.5e4, rtol=1e-15)


def test_duration_and_dt_are_seconds_and_log_rate_is_hertz():
    res = simulate_log("--duration", "0.02", "--dt", "5e-4", "--log-rate", "500")
    # 0.02 s of 0.5 ms steps is 41 samples; 500 Hz keeps every 4th: t = 0, 2, ..., 20 ms.
    assert_allclose(res.time, np.arange(0, 0.0201, 0.002), rtol=0, atol=1e-15)
    assert res.metadata["dt"] == 5e-4


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["--torque", "carrier=1e6", "--torque", "carrier=2e6"],
            '--torque gives joint "carrier" twice (1e6 and 2e6)',
        ),
        (
            ["--speed", "carrier=14.2", "--speed-sine", "carrier=14.2,1,1"],
            'joint "carrier" is given both in --speed and in --speed-sine',
        ),
        (
            ["--speed", "carrier=14.2", "--initial-speed", "carrier=10"],
            'joint "carrier" is given both in --speed and in --initial-speed',
        ),
        (
            ["--torque", "carrier=1e6", "--speed", "carrier=14.2"],
            'joint "carrier" is given both --torque carrier=1e6 and --speed carrier=14.2',
        ),
        (
            ["--torque", "carrier=1e6", "--speed-sine", "carrier=14.2,1,1"],
            'joint "carrier" is given both --torque carrier=1e6 and --speed-sine',
        ),
        (["--torque", "ring=1e5"], 'joint "ring" is a fixed mount'),
        (
            ["--duration", "1", "--dt", "0.3"],
            "the nearest durations are 0.9 s and 1.2 s",
        ),
        (["--dt", "1e-3", "--log-rate", "2000"], "2000 Hz is above the sample rate"),
        # Options of the dt check without it were ignored; --out with it wrote no log.
        (["--check-window", "0:0.01"], "--check-window goes with --check-dt"),
        (["--json"], "--json goes with --check-dt"),
        (["--check-dt", "--out", "x.mcap"], "--check-dt writes no log"),
        # A log's options with --no-log were ignored, even a log rate of -1 Hz.
        (["--no-log", "--log-rate", "100"], "--log-rate 100.0 sets the log, and --no-log writes"),
        (["--no-log", "--log-rate", "-1"], "--log-rate -1.0 Hz; give a positive number"),
        (["--no-log", "--pose-rate", "nan"], "--pose-rate nan Hz; give a positive number"),
        # --wind without a rotor was dropped, even NaN.
        (["--wind", "nan"], "wind: is given but there is no rotor"),
        (["--no-log", "--out", "x.mcap"], "--out x.mcap sets the log, and --no-log writes none"),
        # 1e30 rpm of amplitude: 10 rpm at t = 0, past 1e5 rad/s by step 1 (never returned).
        (
            ["--speed-sine", "carrier=10,1e30,1", "--duration", "0.01", "--dt", "1e-3", "--no-log"],
            'speeds["carrier"] is ',
        ),
        # 0.02 s / 1e-30 s = 2e28 steps: a TypeError from the compiled stepper's binding.
        (["--duration", "0.02", "--dt", "1e-30"], "dt = 1e-30 s makes 2e+28 steps"),
        # 1e30 rpm on the carrier, 6e30 rpm on the sun (ring 120 / sun 24 teeth, fixed ring:
        # 1 + 120/24 = 6): the compiled step did not return.
        (["--initial-speed", "carrier=1e30"], 'joint "sun" turns at 6.283e+29 rad/s (6e+30 rpm)'),
    ],
)
def test_contradictory_options_exit_2_with_one_line(args, message):
    out = run("simulate", PLANETARY, "--no-progress", *args)
    assert out.returncode == 2, out.stdout
    assert message in out.stderr
    assert out.stderr.count("\n") == 1, out.stderr
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize(
    "args", [["--check-window", "0:0.01"], ["--check-dt", "--out", "x.mcap"]], ids=str
)
def test_run_refuses_the_dt_checks_options_as_simulate_does(tmp_path, args):
    scenario = tmp_path / "s.toml"
    scenario.write_text(f'model = "{PLANETARY}"\nduration = 0.01\n')
    out = run("run", str(scenario), "--no-progress", *args)
    assert out.returncode == 2, out.stdout
    assert "--check-" in out.stderr and out.stderr.count("\n") == 1, out.stderr
    assert not (tmp_path / "logs").exists()


def test_latin1_torque_table_exits_2_with_one_line():
    with open("torque.csv", "wb") as f:
        f.write("time,Drehmoment in N·m\n0,1e5\n1,1e5\n".encode("latin-1"))
    out = run("simulate", PLANETARY, "--no-progress", "--torque", "carrier=csv(file='torque.csv')")
    assert out.returncode == 2, out.stdout
    # "time,Drehmoment in N" is 20 bytes: the Latin-1 middle dot (0xb7) is byte 20.
    assert "torque.csv: byte 20 (0xb7) is not UTF-8" in out.stderr
    assert out.stderr.count("\n") == 1, out.stderr
