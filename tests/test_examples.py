"""Every example runs briefly and gives the closed-form numbers it prints."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

from numpy.testing import assert_allclose

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_saleh_rated_load_reaches_the_rated_sun_mesh_force():
    res = _load("saleh_rated_load").main(["--duration", "0.2"])
    # Rated rotor torque at constant speed: 1e6/6 N·m on the sun, shared by 3 planets at
    # r_b = 0.18 m · cos 24.5°.
    expected = 1e6 / 6 / (3 * 0.18 * math.cos(math.radians(24.5)))
    assert_allclose(res.mesh("sun_planet1").normal[-1], expected, rtol=1e-9)


def test_cai_quasi_steady_contact_force_is_the_brake_torque_over_the_base_radius(capsys):
    rows = _load("cai_quasi_steady").main(["--duration", "1", "--runs", "1", "--dt", "2e-4"])
    printed = capsys.readouterr().out
    assert "A [rpm]" in printed and "f [Hz]" in printed  # units not eaten as rich markup
    static = 49.0 / (0.120 * math.cos(math.radians(20.0)))
    assert_allclose(rows[0]["force"]["mean"], static, rtol=1e-3)
    assert_allclose(rows[0]["t_in"]["mean"], 49.0 * 40 / 80, rtol=1e-3)
