"""``pinwind replay LOG`` where no viewer can open: one line naming --save/--serve, exit 2, fast."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

import pinwind.io.replay as replay_module
from pinwind.errors import NoViewer

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


def test_replay_without_a_viewer_program_is_refused_in_one_line_naming_save_and_serve(
    logged_run, monkeypatch
):
    # No such program on PATH nor beside the interpreter; a display is there.
    monkeypatch.setattr(replay_module, "VIEWER", "no-such-rerun-viewer")
    monkeypatch.setenv("DISPLAY", ":0")
    started = time.monotonic()
    with pytest.raises(NoViewer) as refused:
        replay_module.replay(logged_run.path)
    assert time.monotonic() - started < WITHIN_S
    message = str(refused.value)
    assert "\n" not in message
    assert "--save" in message and "--serve" in message and "no-such-rerun-viewer" in message


def test_the_viewer_beside_the_interpreter_is_found_when_path_lacks_it(monkeypatch, tmp_path):
    # A venv used without activating it: .venv/bin/pinwind with .venv/bin not on PATH.
    monkeypatch.setenv("PATH", str(tmp_path))
    beside = shutil.which("rerun", path=str(Path(sys.executable).parent))
    assert replay_module.viewer_program() == beside
