"""``pinwind replay LOG --web``: the log's recording in Rerun's web viewer, in headless Chromium.

Engineers run long cases on machines without a display; the web viewer shows the same recording
in a browser. The test serves a log, opens the viewer in headless Chromium (tests/io/
headless_chromium.py) and reads its screenshot: the page is drawn (not the dark loading screen)
and holds the gearbox's coloured bodies and plot lines, which the same viewer without a recording
(its welcome page, the control) does not.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import pinwind
from pinwind.model.gearbox import load
from tests.conftest import MODELS
from tests.io.headless_chromium import browser, chromium, free_port

pytestmark = pytest.mark.skipif(
    browser() is None, reason="needs Chromium on PATH: apt-get install chromium (.ci/run does)"
)

#: A pixel is coloured when its channels spread by more than this (grey UI: 0; gears: 0.5-0.9).
SPREAD = 0.35
#: Seconds to wait for the viewer (its WebAssembly, 30 MB, and the data) on a busy machine.
PATIENCE = 180.0


def coloured(image: np.ndarray) -> float:
    """The fraction of the image's pixels that are coloured (not grey)."""
    return float(np.mean(image.max(axis=-1) - image.min(axis=-1) > SPREAD))


def drawn(image: np.ndarray) -> bool:
    """The viewer has drawn its light user interface (the loading screen is dark)."""
    return float(image.mean()) > 0.5


def wait_for(page, test, what: str) -> np.ndarray:
    """Screenshots every second until ``test`` holds; the last one."""
    deadline = time.monotonic() + PATIENCE
    while True:
        shot = page.screenshot()
        if test(shot):
            return shot
        if time.monotonic() > deadline:
            raise AssertionError(
                f"after {PATIENCE:g} s the page shows no {what}: mean {shot.mean():.3f}, "
                f"coloured {coloured(shot):.4f}"
            )
        time.sleep(1.0)


def test_the_web_viewer_draws_the_recording_a_log_holds(tmp_path):
    log = tmp_path / "saleh.mcap"
    pinwind.simulate(load(MODELS / "saleh2017_planetary.urdf"), duration=0.05, dt=1e-3,
                     initial_speeds={"carrier": 1.487}, torques={"carrier": 1e6, "sun": -1e6 / 6},
                     log=log)  # fmt: skip
    web, grpc = free_port(), free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "pinwind", "replay", str(log), "--web", "--web-port", str(web),
         "--grpc-port", str(grpc)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    try:
        line = server.stdout.readline()  # "open http://localhost:WEB/?url=... (Ctrl-C to stop)"
        assert line.startswith(f"open http://localhost:{web}/?url="), line + server.stderr.read()
        with chromium() as page:
            page.navigate(f"http://localhost:{web}/")  # the viewer alone: the control
            control = wait_for(page, drawn, "viewer")
            page.navigate(line.split()[1])
            shot = wait_for(page, lambda s: drawn(s) and coloured(s) > 4 * coloured(control),
                            "gearbox beyond the control's colours")  # fmt: skip
    finally:
        server.send_signal(signal.SIGINT)  # Ctrl-C stops the servers, exit 0
        server.wait(timeout=60)
        server.stdout.close()
        server.stderr.close()
    assert server.returncode == 0
    assert float(shot.std()) > 0.1  # not a blank page
