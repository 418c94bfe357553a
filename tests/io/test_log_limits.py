"""Logs that would not fit (refused before the run) and logs whose writing fails during it."""

from __future__ import annotations

import errno
import os
import resource
import signal
import subprocess
import sys
import warnings

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.simulate import simulate
from pinwind.errors import LogRecovered, LogTooLargeToWrite, LogWriteFailed, TorquesUnbalanced
from pinwind.io import log_size
from pinwind.io.log_reader import LogReader
from pinwind.io.log_writer import McapLogger
from pinwind.runs import run
from tests.io.conftest import CHUNK, DT, DURATION, TORQUES, column_chunks
from tests.io.test_cli_log import ENV, SIMULATE
from tests.io.test_log_writer import assert_same_arrays

#: Values per sample of the planetary stage's Result (6 joints, 6 meshes, 10 links, 11 energy
#: terms): time, 4 joint series, 19 mesh scalars (3 of flank friction, 2 line loads) and 2 mesh
#: vectors, 4 bearing vectors, 4 bearing scalars about the axis, 2 bearing vectors of compliance
#: (displacement, elastic force), link positions and quaternions, the constraint residual, the
#: energy terms, 2 bearing friction scalars (moment, power).
PLANETARY_VALUES = (
    1 + 4 * 6 + 19 * 6 + 2 * 3 * 6 + 4 * 3 * 6 + 4 * 6 + 2 * 3 * 6 + 7 * 10 + 1 + 11 + 2 * 6
)


# --- refused before the run ---------------------------------------------------------------------


def test_log_above_the_limit_is_refused_before_the_run_with_its_size_and_the_memory(
    planetary, tmp_path
):
    path = tmp_path / "big.mcap"
    with pytest.raises(LogTooLargeToWrite) as refused:
        simulate(
            planetary,
            duration=DURATION,
            dt=DT,
            torques=TORQUES,
            observer=McapLogger(path, max_bytes=100_000),
        )
    err = refused.value
    samples = round(DURATION / DT) + 1
    assert err.samples == samples and err.limit_bytes == 100_000
    assert err.log_bytes > 100_000
    assert err.result_bytes == samples * 8 * PLANETARY_VALUES
    message = str(err)
    assert f"{err.log_bytes / 1e9:.3g} GB ({samples} samples)" in message
    assert "more than the limit for one log (0.0001 GB)" in message
    assert f"needs {err.result_bytes / 1e6:.3g} MB" in message
    for fix in ("--log-rate", "--no-log", "--duration", "--allow-large-log"):
        assert fix in message
    assert not path.exists()


def test_suggested_log_rate_gives_a_log_within_the_limit(planetary, tmp_path):
    with pytest.raises(LogTooLargeToWrite) as refused:
        simulate(
            planetary,
            duration=DURATION,
            dt=DT,
            torques=TORQUES,
            observer=McapLogger(tmp_path / "a.mcap", max_bytes=200_000),
        )
    rate = refused.value.fitting_rate
    assert 0 < rate < 1 / DT
    path = tmp_path / "b.mcap"
    pinwind.simulate(planetary, duration=DURATION, dt=DT, torques=TORQUES, log=path, log_rate=rate)
    assert path.stat().st_size <= 1_550_000


def test_log_larger_than_the_free_disk_space_is_refused(planetary, tmp_path, monkeypatch):
    monkeypatch.setattr(log_size, "_free_space", lambda folder: 30_000)
    with pytest.raises(
        LogTooLargeToWrite, match=r"more than the free space on its disk \(3e-05 GB"
    ):
        pinwind.simulate(planetary, duration=DURATION, dt=DT, log=tmp_path / "x.mcap")


def test_allow_large_log_writes_it_anyway(planetary, tmp_path, monkeypatch):
    monkeypatch.setattr(run, "MAX_LOG_BYTES", 1_000)
    with pytest.raises(LogTooLargeToWrite):
        pinwind.simulate(planetary, duration=0.01, dt=DT, log=tmp_path / "x.mcap")
    pinwind.simulate(planetary, duration=0.01, dt=DT, log=tmp_path / "x.mcap", allow_large_log=True)
    assert len(pinwind.read_log(tmp_path / "x.mcap")) == 11


def test_size_estimate_is_above_the_written_log_within_a_factor_of_three(logged_run):
    with LogReader(logged_run.path) as log:
        estimate = log.metadata["pinwind.run"]["log_estimate_bytes"]
    size = logged_run.path.stat().st_size
    assert size <= estimate <= 3 * size


def test_cli_refuses_a_log_above_20_gb_in_one_line_with_exit_code_2(tmp_path):
    # 10^8 samples of the planetary stage: about 100 GB of log; refused before the first step
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", *SIMULATE, "--duration", "1e5", "--out", "big.mcap"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        env=ENV,
    )
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("error: logs/big.mcap: ")
    assert "more than the limit for one log (20 GB)" in out.stderr
    assert "--allow-large-log" in out.stderr and "Traceback" not in out.stderr
    assert not (tmp_path / "logs" / "big.mcap").exists()


# --- writing fails during the run ---------------------------------------------------------------


class FullDisk:
    """A file that takes ``room`` bytes, part of a write included, then fails with ENOSPC."""

    def __init__(self, path, room: int):
        self.file = open(path, "xb", buffering=0)  # noqa: SIM115
        self.room = room

    def write(self, data) -> int:
        if self.room <= 0:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        written = self.file.write(memoryview(data)[: self.room])
        self.room -= written
        return written

    def __getattr__(self, name):
        return getattr(self.file, name)


class LoggerOnFullDisk(McapLogger):
    def __init__(self, path, room: int):
        super().__init__(path)
        self.room = room

    def _open_file(self):
        return FullDisk(self.path, self.room)


def test_full_disk_stops_the_run_and_leaves_its_complete_chunks_readable(
    planetary, logged_run, tmp_path
):
    run_it = dict(duration=DURATION, dt=DT, torques=TORQUES, chunk=CHUNK)
    roomy = tmp_path / "roomy.mcap"
    simulate(planetary, **run_it, observer=LoggerOnFullDisk(roomy, 1 << 40))
    # the columns of samples 0-99, 100-199, 200-250; the disk fills inside the last ones
    first, second, third = column_chunks(roomy)
    path = tmp_path / "full.mcap"
    with pytest.raises(LogWriteFailed) as stopped:
        simulate(planetary, **run_it, observer=LoggerOnFullDisk(path, third[0] + third[1] // 2))
    err = stopped.value
    assert err.samples_logged == 2 * CHUNK and err.failed_at == 0.2
    assert str(err) == (
        f"{path}: writing the log failed at t = 0.2 s (No space left on device), so the run was "
        "stopped; the file holds the 200 samples logged before (t ≤ 0.199 s), readable with "
        "pinwind.read_log or pinwind report. Free some disk space or log less (--log-rate, "
        "--no-log)"
    )
    assert path.stat().st_size == third[0]  # cut back to the end of the second chunk
    with pytest.warns(LogRecovered, match="recovered 200 samples"):
        back = pinwind.read_log(path)
    assert_same_arrays(back, logged_run.result.truncated(2 * CHUNK))


def test_write_failure_then_room_again_gives_a_complete_log_saying_why(planetary, tmp_path):
    # The room from the same log written without a limit: its header records the same
    # command (this process's), so its chunks start where the failing log's do.
    roomy = tmp_path / "roomy.mcap"
    run_it = dict(duration=DURATION, dt=DT, torques=TORQUES, chunk=CHUNK)
    simulate(planetary, **run_it, observer=LoggerOnFullDisk(roomy, 1 << 40))
    room = column_chunks(roomy)[0][0] + 100  # inside the first block's columns
    path = tmp_path / "freed.mcap"

    class Freed(FullDisk):
        def write(self, data) -> int:
            try:
                return super().write(data)
            except OSError:
                self.room = 1 << 40  # space freed after the first failure
                raise

    logger = LoggerOnFullDisk(path, room)
    logger._open_file = lambda: Freed(path, room)
    with pytest.raises(LogWriteFailed, match="failed at t = 0 s"):
        simulate(planetary, **run_it, observer=logger)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        log = pinwind.io.open_log(path)
    assert log.complete and len(log.result) == 0
    assert "writing the log failed at t = 0 s" in log.metadata["pinwind.end"]["status"]


def test_deleted_log_stops_the_run_saying_the_samples_went_with_it(planetary, tmp_path):
    path = tmp_path / "gone.mcap"

    def torque(t: float) -> float:
        if t >= 0.15:
            path.unlink(missing_ok=True)
        return 1.0e6

    with pytest.raises(LogWriteFailed, match="deleted.*went with the file"):
        with pytest.warns(TorquesUnbalanced):
            simulate(
                planetary,
                duration=DURATION,
                dt=DT,
                torques={"carrier": torque},
                chunk=CHUNK,
                observer=McapLogger(path),
            )


def _limit_file_size(size: int):
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, resource.RLIM_INFINITY))
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # write() then fails with EFBIG

    return limit


@pytest.mark.skipif(not hasattr(signal, "SIGXFSZ"), reason="needs RLIMIT_FSIZE (POSIX)")
def _simulate_ten_seconds(log, preexec_fn=None) -> subprocess.CompletedProcess[str]:
    """``pinwind simulate`` of the planetary case for 10 s into ``log``, in a child process."""
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *SIMULATE, "--duration", "10", "--out", str(log)],
        capture_output=True,
        text=True,
        timeout=120,
        env=ENV,
        preexec_fn=preexec_fn,
    )


def _limit_inside_a_chunk(tmp_path, near: int) -> int:
    """A file-size limit [bytes] near ``near`` that falls inside a chunk of the run's log and
    leaves room, after where that chunk starts, for the log's closing records.

    Taken from the same run logged without a limit: its chunks' spans (the summary's chunk
    index, read by the ``mcap`` package) and the bytes after its last chunk (data end, summary,
    footer). The writer reserves no room for them, so a limit a few kB after a chunk's start would
    leave a cut file (recovered with a warning) instead: the limit must not depend on how well
    one run's chunks happen to compress.
    """
    from mcap.reader import make_reader

    full = tmp_path / "unlimited.mcap"
    done = _simulate_ten_seconds(full)
    assert done.returncode == 0, done.stderr
    with open(full, "rb") as f:
        chunks = make_reader(f).get_summary().chunk_indexes
    spans = sorted((c.chunk_start_offset, c.chunk_start_offset + c.chunk_length) for c in chunks)
    closing = full.stat().st_size - spans[-1][1]
    # A write failing inside a chunk cuts the file back to where that chunk starts: the limit
    # lies inside the chunk, at least `closing` bytes after its start.
    limits = [(start + closing + end) // 2 for start, end in spans if end - start > closing]
    assert limits, (spans, closing)
    return min(limits, key=lambda limit: abs(limit - near))


def test_cli_run_hitting_a_file_size_limit_stops_in_one_line_and_keeps_its_chunks(tmp_path):
    log = tmp_path / "limited.mcap"
    limit = _limit_inside_a_chunk(tmp_path, near=1_550_000)
    out = _simulate_ten_seconds(log, preexec_fn=_limit_file_size(limit))
    assert out.returncode == 2, out.stderr
    assert out.stderr.count("\n") == 1, out.stderr
    assert out.stderr.startswith(f"error: {log}: writing the log failed at t = ")
    assert "(File too large), so the run was stopped; the file holds the " in out.stderr
    assert log.stat().st_size <= limit
    # cut back to its last complete chunk, the file had room for the end record and summary
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        data = pinwind.io.open_log(log)
    assert data.complete
    assert "writing the log failed" in data.metadata["pinwind.end"]["status"]
    back = data.result
    assert len(back) > 0 and len(back) % 1000 == 0  # whole chunks of 1000 samples
    clean = pinwind.simulate(
        pinwind.load(SIMULATE[1]),
        duration=(len(back) - 1) * 1e-3,
        dt=1e-3,
        torques={"carrier": 1e6, "sun": -166666.6666666667},
    )
    np.testing.assert_array_equal(back.time, clean.time)
    np.testing.assert_array_equal(back.mesh_normal, clean.mesh_normal)
    np.testing.assert_array_equal(back.bearing_force_local, clean.bearing_force_local)


@pytest.mark.parametrize("room", [0, 300], ids=["no-room", "mid-header"])
def test_cli_run_on_a_full_disk_with_allow_large_log_is_one_line_and_no_file(
    tmp_path, monkeypatch, capsys, room
):
    """--allow-large-log skips the free-space check, so a full disk met the log's first
    records: a traceback (OSError) instead of one line. The disk is this test's: the writer's
    file refuses its writes with ENOSPC after ``room`` bytes (a small tmpfs needs root)."""
    from pinwind.cli import main

    log = tmp_path / "full.mcap"
    monkeypatch.setattr(McapLogger, "_open_file", lambda self: FullDisk(self.path, room))
    monkeypatch.setattr(sys, "argv", ["pinwind", *SIMULATE, "--duration", "0.01",
                                      "--out", str(log), "--allow-large-log"])  # fmt: skip
    with pytest.raises(SystemExit) as exit_:
        main()
    err = capsys.readouterr().err
    assert exit_.value.code == 2
    assert err.startswith(f"error: {log}: cannot write the log's first records")
    assert "(No space left on device), so the run was not started" in err
    assert err.count("\n") == 1
    assert not log.exists()
