"""Ctrl-C during a logged run: every simulated sample reaches the log, or the log says so."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import pinwind
from pinwind.errors import SamplesNotLogged, TorquesUnbalanced
from pinwind.io.log_reader import LogReader
from pinwind.io.log_writer import McapLogger
from tests.io.conftest import PLANETARY

ROOT = Path(__file__).resolve().parent.parent.parent

#: A logged run whose disk is slow (50 ms per chunk of 500 samples, 2 s for the run's 40): the
#: run waits for the log's writer thread most of the time, where a Ctrl-C used to drop the block
#: just simulated.
SLOW_DISK_RUN = textwrap.dedent(
    """
    import sys, time
    import pinwind
    from pinwind.io import log_writer

    columns = log_writer.McapLogger._assemble_columns

    def slow_disk(self, *args):
        time.sleep(0.05)
        return columns(self, *args)

    log_writer.McapLogger._assemble_columns = slow_disk
    gearbox = pinwind.load(sys.argv[1])
    print("started", flush=True)
    pinwind.simulate(gearbox, duration=2.0, dt=1e-4, torques={"carrier": 1e5},
                     initial_speeds={"carrier": 1.47}, log="logs/run.mcap", chunk=500)
    """
)


def _interrupted_run(folder: Path, after: float) -> tuple[int, dict, int]:
    """(exit code, end record, samples read back) of the run interrupted ``after`` s in."""
    script = folder / "run.py"
    script.write_text(SLOW_DISK_RUN)
    child = subprocess.Popen(
        [sys.executable, str(script), str(PLANETARY)],
        cwd=folder,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *sys.path])},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # Ctrl-C raises
    )
    assert child.stdout is not None
    assert child.stdout.readline() == "started\n", child.communicate()[1]
    log = folder / "logs" / "run.mcap"
    while not log.exists() and child.poll() is None:  # the run has begun: its log is open
        time.sleep(0.005)
    time.sleep(after)
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=120)
    with LogReader(log) as reader:
        end = reader.metadata["pinwind.end"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", SamplesNotLogged)
        res = pinwind.read_log(log)
    assert "interrupted" in res.status, err
    return child.returncode, end, len(res)


@pytest.mark.parametrize("after", [0.2, 0.5, 0.9, 1.3])
def test_ctrl_c_keeps_every_simulated_sample_in_the_log(tmp_path, after):
    code, end, read = _interrupted_run(tmp_path, after)
    assert code != 0  # the run was interrupted, not completed
    assert end["samples_simulated"] < 20_001
    assert end["samples_logged"] == end["samples_simulated"]
    assert read == end["samples_simulated"]


def test_read_log_states_samples_the_run_simulated_but_did_not_log(planetary, tmp_path):
    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(planetary, duration=0.01, dt=1e-3, torques={"carrier": 1e5})
    assert res.metadata["samples_simulated"] == 11
    logger = McapLogger(tmp_path / "lost.mcap", pose_rate=None, view_rate=None)
    logger.begin(planetary, res)
    logger.samples(res.truncated(5), 0)  # the last 6 samples never reach the log
    logger.end(res, "interrupted at step 11 (t = 0.011 s)")
    with pytest.warns(SamplesNotLogged, match="simulated 11 samples but logged 5 of the 11"):
        back = pinwind.read_log(tmp_path / "lost.mcap")
    assert len(back) == 5
    assert "6 logged samples are missing" in back.metadata["log"]["not_logged"]
    assert back.metadata["samples_simulated"] == 11
    np.testing.assert_allclose(back.time, res.time[:5], rtol=0, atol=0)
