"""``pinwind replay LOG`` where no viewer can open: one line naming --save/--serve, exit 2, fast."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

#: The issue's bound: a headless replay ends within this time [s], not at a kill.
WITHIN_S = 15.0


def replay_with_env(log: Path, env: dict[str, str]) -> tuple[subprocess.CompletedProcess, float]:
    started = time.monotonic()
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "replay", str(log)],
        capture_output=True,
        text=True,
        timeout=60,
        env={**env, "RERUN_ANALYTICS": "0"},
    )
    return out, time.monotonic() - started


def _without_display() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="displays are X11/Wayland here")
def test_replay_without_a_display_ends_at_once_with_one_line_naming_save_and_serve(logged_run):
    env = _without_display()
    # The viewer binary is there: only the display is missing.
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    out, seconds = replay_with_env(logged_run.path, env)
    assert out.returncode == 2
    assert seconds < WITHIN_S
    assert "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert "--save" in out.stderr and "--serve" in out.stderr
    assert "display" in out.stderr


def test_replay_without_the_viewer_on_path_ends_with_one_line_naming_save_and_serve(
    logged_run, tmp_path
):
    env = {**os.environ, "DISPLAY": ":0", "PATH": str(tmp_path)}  # an empty folder
    assert shutil.which("rerun", path=env["PATH"]) is None
    out, seconds = replay_with_env(logged_run.path, env)
    assert out.returncode == 2
    assert seconds < WITHIN_S
    assert "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert "--save" in out.stderr and "--serve" in out.stderr
    assert "rerun" in out.stderr
