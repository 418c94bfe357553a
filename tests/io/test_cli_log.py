"""The command line with logs: --out/--force/--log-rate, SIGTERM and SIGKILL, rerun's converter."""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import pinwind
from pinwind.errors import LogBeingWritten, LogRecovered
from pinwind.io.log_reader import open_log
from tests.io.conftest import PLANETARY, VIEW_EVERY, rrd_columns

ENV = {**os.environ, "RERUN_ANALYTICS": "0"}


def run(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=cwd,
        env=ENV,
    )


def rerun_cli() -> str:
    found = Path(sys.executable).with_name("rerun")
    if found.exists():
        return str(found)
    which = shutil.which("rerun")
    if which is None:
        pytest.skip("the rerun CLI is not installed")
    return which


SIMULATE = (
    "simulate",
    str(PLANETARY),
    "-t",
    "carrier=1e6",
    "-t",
    "sun=-166666.6666666667",
    "--dt",
    "1e-3",
    "--no-progress",
)


def test_simulate_writes_the_log_and_never_overwrites_it_without_force(tmp_path):
    out = run(*SIMULATE, "--duration", "0.02", "--out", "run.mcap", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    log = tmp_path / "logs" / "run.mcap"
    assert f"log: {Path('logs') / 'run.mcap'}" in out.stdout
    assert len(pinwind.read_log(log)) == 21
    again = run(*SIMULATE, "--duration", "0.05", "--out", "run.mcap", cwd=tmp_path)
    assert again.returncode == 2
    assert "logs/run.mcap: the file already exists" in again.stderr
    assert "Traceback" not in again.stderr
    assert len(pinwind.read_log(log)) == 21
    forced = run(*SIMULATE, "--duration", "0.05", "--out", "run.mcap", "--force", cwd=tmp_path)
    assert forced.returncode == 0, forced.stderr
    assert len(pinwind.read_log(log)) == 51


def test_simulate_logs_by_default_in_logs_and_records_the_command_line(tmp_path):
    out = run(*SIMULATE, "--duration", "0.01", "--log-rate", "500", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    (log,) = (tmp_path / "logs").glob("saleh2017_planetary_*.mcap")
    data = open_log(log)
    assert data.metadata["pinwind"]["command"] == "pinwind " + " ".join(
        [*SIMULATE, "--duration", "0.01", "--log-rate", "500"]
    )
    np.testing.assert_array_equal(data.result.time, np.arange(0, 11, 2) * 1e-3)


def _start_long_run(log: Path) -> subprocess.Popen:
    proc = subprocess.Popen(
        [sys.executable, "-m", "pinwind", *SIMULATE, "--duration", "1000", "--out", str(log)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env=ENV,
        text=True,
    )
    deadline = time.monotonic() + 60
    # Wait until two chunks of 1000 samples are on disk (about 0.9 MB each).
    while not (log.exists() and log.stat().st_size > 2_000_000):
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"the run did not start logging: {proc.stderr.read()}")
        time.sleep(0.05)
    return proc


def test_sigterm_stops_the_run_with_a_complete_log_and_end_status(tmp_path):
    log = tmp_path / "term.mcap"
    proc = _start_long_run(log)
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 143, stderr
    assert "terminated (received SIGTERM)" in stderr
    data = open_log(log)
    assert data.complete
    end = data.metadata["pinwind.end"]
    assert end["status"].startswith("interrupted at step")
    assert end["cause"] == "Terminated: received SIGTERM"
    assert end["samples_logged"] == len(data.result) >= 2000
    clean = pinwind.simulate(
        pinwind.load(PLANETARY),
        duration=0.999,
        dt=1e-3,
        torques={"carrier": 1e6, "sun": -166666.6666666667},
    )
    np.testing.assert_array_equal(data.result.mesh_normal[:1000], clean.mesh_normal)
    # link poses are logged at 100 Hz: every 10th sample of 1 ms
    np.testing.assert_array_equal(data.result.pose_rows[:100], np.arange(0, 1000, 10))
    np.testing.assert_array_equal(data.result.body_quaternion[:100], clean.body_quaternion[::10])


def test_sigkill_leaves_a_log_whose_complete_chunks_are_recovered(tmp_path):
    log = tmp_path / "kill.mcap"
    proc = _start_long_run(log)
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    # The warning's wording depends on where the kill lands (between chunks, inside one, in
    # the index); what must hold is the recovery: whole blocks of 1000 samples, in order.
    with pytest.warns(LogRecovered):
        data = open_log(log)
    assert not data.complete
    assert data.result.status.startswith("log cut short")
    n = len(data.result)
    assert n >= 2000 and n % 1000 == 0  # whole chunks only
    np.testing.assert_array_equal(data.result.time, np.arange(n) * 1e-3)
    # Every recovered sample is a real one: balanced torques, F_n = T_sun / (3 r_s cos α).
    expected = (1e6 / 6) / (3 * 0.18 * math.cos(math.radians(24.5)))
    np.testing.assert_allclose(data.result.mesh_normal, expected, rtol=1e-9)


def test_report_of_a_damaged_log_warns_in_one_line_with_the_time_lost(logged_run, tmp_path):
    bad = tmp_path / "bad.mcap"
    data = bytearray(logged_run.path.read_bytes())
    data[len(data) // 2 : len(data) // 2 + 64] = bytes(64)
    bad.write_bytes(bytes(data))
    out = run("report", str(bad), "--json")
    assert out.returncode == 0, out.stderr
    assert str(bad) in out.stderr and "damaged" in out.stderr and "s lost" in out.stderr
    assert "Traceback" not in out.stderr
    assert json.loads(out.stdout)["window"]["samples"] < len(logged_run.result)


def test_report_of_a_file_that_is_not_a_log_is_one_line_without_traceback(tmp_path):
    bad = tmp_path / "notes.mcap"
    bad.write_text("not a log")
    out = run("report", str(bad))
    assert out.returncode == 2
    assert str(bad) in out.stderr and "not an MCAP file" in out.stderr
    assert "Traceback" not in out.stderr


def test_rerun_cli_converts_the_log_into_time_series(logged_run, tmp_path):
    rrd = tmp_path / "converted.rrd"
    out = subprocess.run(
        [rerun_cli(), "mcap", "convert", str(logged_run.path), "-o", str(rrd)],
        capture_output=True,
        text=True,
        timeout=300,
        env=ENV,
    )
    assert out.returncode == 0, out.stderr
    columns = rrd_columns(rrd)
    res = logged_run.result

    def scalars(entity: str) -> np.ndarray:
        parts = columns[entity]["Scalars:scalars"]
        times = np.concatenate(
            [t.to_numpy().astype(np.int64) for t in columns[entity]["message_log_time"]]
        )
        values = np.concatenate([p.flatten().to_numpy() for p in parts])
        return values.reshape(len(times), -1)[np.argsort(times, kind="stable")]

    viewed = slice(None, None, VIEW_EVERY)  # the viewers' topics are at the view rate
    np.testing.assert_array_equal(scalars("/meshes/normal"), res.mesh_normal[viewed])
    np.testing.assert_array_equal(scalars("/joints/velocity"), res.speed[viewed])
    np.testing.assert_array_equal(
        scalars("/bearings/force").reshape(-1, len(res.bearing_names), 3),
        res.bearing_force[viewed],
    )
    names = columns["/joints/velocity"]["SeriesLines:names"][0].flatten().to_pylist()
    assert names[: len(res.joint_names)] == res.joint_names
    assert "Transform3D:translation" in columns["/tf"]
    visuals = [e for e in columns if e.startswith("/saleh2017_planetary/visual_geometries/")]
    assert visuals  # the model on /robot_description, through rerun's URDF loader


def _convert(log: Path, rrd: Path, *options: str) -> dict[str, dict[str, list]]:
    out = subprocess.run(
        [rerun_cli(), "mcap", "convert", str(log), *options, "-o", str(rrd)],
        capture_output=True,
        text=True,
        timeout=300,
        env=ENV,
    )
    assert out.returncode == 0, out.stderr
    return rrd_columns(rrd)


def test_rerun_reads_log_times_as_dates_unless_converted_with_duration_timelines(
    logged_run, tmp_path
):
    """MCAP log times have no epoch field: Rerun 0.41 takes them as Unix times (1970-01-01 +
    t) when it opens the file, and as simulation time from 0 with ``--timeline-type duration``.
    """
    expected = np.rint(logged_run.result.time[::VIEW_EVERY] * 1e9).astype(np.int64)
    dates = _convert(logged_run.path, tmp_path / "dates.rrd")["/meshes/normal"]
    assert all(str(c.type) == "timestamp[ns]" for c in dates["message_log_time"])
    times = _convert(logged_run.path, tmp_path / "t.rrd", "--timeline-type", "duration")
    column = times["/meshes/normal"]["message_log_time"]
    assert all(str(c.type) == "duration[ns]" for c in column)
    stamps = np.sort(np.concatenate([c.to_numpy().astype(np.int64) for c in column]))
    np.testing.assert_array_equal(stamps, expected)


def test_rerun_names_the_joint_series_and_numbers_the_array_topics(logged_run, tmp_path):
    """JointState carries names, which Rerun puts on the plot; Float64MultiArray does not (the
    names are in the channel metadata), so Rerun shows its series by index."""
    columns = _convert(logged_run.path, tmp_path / "names.rrd")
    assert "SeriesLines:names" in columns["/joints/velocity"]
    assert "SeriesLines:names" not in columns["/meshes/normal"]
    assert "Scalars:scalars" in columns["/meshes/normal"]


def test_report_of_a_cut_log_warns_in_one_line_and_reports_the_recovered_samples(
    logged_run, tmp_path
):
    cut = tmp_path / "cut.mcap"
    data = logged_run.path.read_bytes()
    cut.write_bytes(data[: len(data) * 3 // 4])
    out = run("report", str(cut), "--json")
    assert out.returncode == 0, out.stderr
    assert out.stderr.startswith("warning: ") and "recovered" in out.stderr
    assert "Traceback" not in out.stderr
    assert json.loads(out.stdout)["status"].startswith("log cut short")


def test_log_being_written_reads_as_in_progress_and_once_killed_as_cut_with_the_time_lost(
    tmp_path,
):
    log = tmp_path / "live.mcap"
    proc = _start_long_run(log)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            live = open_log(log)
        kinds = {type(w.message) for w in caught}
        assert LogBeingWritten in kinds and LogRecovered not in kinds
        assert live.result.status.startswith("being written: the run is in progress")
        assert len(live.result) >= 2000
    finally:
        os.kill(proc.pid, signal.SIGKILL)
        proc.communicate(timeout=60)
    # The lock dies with the run: now the file is a cut log, and the warning says which span of
    # the 1000 s run it lacks, from its last sample to the run's end.
    with pytest.warns(LogRecovered) as caught:
        data = open_log(log)
    last = float(data.result.time[-1])
    message = " ".join(str(w.message) for w in caught)
    assert f"t = {last:.6g} to 1000 s, {1000 - last:.6g} s of the 1000 s run" in message
    assert data.result.status.startswith("log cut short")


@pytest.mark.parametrize(("verb", "option"), [("report", "--to"), ("export", "--from")])
def test_an_infinite_window_end_is_one_line_exit_2(logged_run, tmp_path, verb, option):
    # report --to -inf was math.ceil(-inf · 1e9): an OverflowError traceback.
    extra = ["--format", "csv", "-o", str(tmp_path / "t.csv")] if verb == "export" else []
    out = run(verb, str(logged_run.path), option, "-inf", *extra)
    assert out.returncode == 2, out.stderr
    assert f"{option} -inf s is not a time; give a finite time [s]" in out.stderr
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
