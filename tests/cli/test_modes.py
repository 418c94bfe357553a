"""``pinwind modes``: mode classes and repeated frequencies, the animation, bad input."""

from __future__ import annotations

import json
import subprocess
import sys

from tests.conftest import MODELS


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
