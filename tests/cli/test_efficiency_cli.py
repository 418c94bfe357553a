"""``pinwind efficiency``: the map's CSV and figure, and its refusals (exit 2)."""

from __future__ import annotations

import csv
import math

from numpy.testing import assert_allclose

from tests.conftest import MODELS, two_gear_urdf
from tests.test_cli import run


def test_efficiency_map_writes_a_csv_of_every_point_and_a_figure(tmp_path):
    model = tmp_path / "pair.urdf"
    model.write_text(two_gear_urdf())
    out = run(
        "efficiency", str(model), "--input", "a", "--output", "b", "--torque", "50:100",
        "--speed", "500:1000", "--points", "2", "--duration", "0.02", "--dt", "1e-3",
        "--out", str(tmp_path),
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "efficiency_map.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4
    for row in rows:
        torque, rpm = float(row["torque_Nm"]), float(row["speed_rpm"])
        # the input power is T ω, and the losses are what the efficiency says
        assert_allclose(float(row["input_power_W"]), torque * rpm * math.pi / 30, rtol=1e-9)
        loss = float(row["bearing_loss_W"]) + float(row["mesh_loss_W"])
        assert_allclose(float(row["efficiency"]), 1 - loss / float(row["input_power_W"]))
        assert 0.98 < float(row["efficiency"]) < 1.0  # one spur mesh: 1 − μ H_V
    assert (tmp_path / "efficiency_map.png").stat().st_size > 0


def test_a_viscosity_grade_that_does_not_exist_is_one_message_and_exit_2(tmp_path):
    model = tmp_path / "pair.urdf"
    model.write_text(two_gear_urdf())
    out = run(
        "efficiency", str(model), "--input", "a", "--output", "b", "--torque", "50",
        "--speed", "500", "--lubricant-vg", "300",
    )  # fmt: skip
    assert out.returncode == 2
    assert "ISO 3448" in out.stderr and "220, 320" in out.stderr
    assert "--lubricant-vg" in out.stderr  # the option the user typed, not the model attribute
    assert "Traceback" not in out.stderr


def test_an_unknown_friction_model_is_one_message_and_exit_2(tmp_path):
    model = tmp_path / "pair.urdf"
    text = two_gear_urdf().replace(
        "  </gearbox>",
        '    <bearing joint="a" type="deep_groove_ball" friction_model="skf_2018"/>\n  </gearbox>',
    )
    model.write_text(text)
    out = run(
        "efficiency", str(model), "--input", "a", "--output", "b", "--torque", "50",
        "--speed", "500",
    )  # fmt: skip
    assert out.returncode == 2
    assert "skf_2018" in out.stderr and "none, iso_tr_14179_2" in out.stderr
    assert "Traceback" not in out.stderr


def test_a_scenario_gives_its_model(tmp_path):
    scenario = MODELS.parent / "scenarios" / "nrel5mw_rated.toml"
    out = run(
        "efficiency", str(scenario), "--input", "rotor", "--output", "generator",
        "--torque", "3.9e6", "--speed", "12.1", "--duration", "0.005", "--dt", "1e-4",
        "--out", str(tmp_path),
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "efficiency_map.csv", encoding="utf-8") as f:
        (row,) = list(csv.DictReader(f))
    # 3.9 MN·m at 12.1 rpm in, less than 3 % a stage lost over three stages
    assert_allclose(float(row["input_power_W"]), 3.9e6 * 12.1 * math.pi / 30, rtol=1e-3)
    assert 0.97**3 < float(row["efficiency"]) < 1.0
    assert "warning" not in out.stderr  # dt resolves the stiffest spring (1017 Hz)


def test_a_points_warnings_reach_the_user_once(tmp_path):
    # dt = 1 ms is coarser than half the NREL 5 MW's generator-coupling mode period (~1 ms)
    scenario = MODELS.parent / "scenarios" / "nrel5mw_rated.toml"
    out = run(
        "efficiency", str(scenario), "--input", "rotor", "--output", "generator",
        "--torque", "3e6:3.9e6", "--speed", "12.1", "--points", "2", "--duration", "0.02",
        "--dt", "1e-3", "--out", str(tmp_path),
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stderr.count("warning: dt = 0.001 s is longer than half the period") == 1
