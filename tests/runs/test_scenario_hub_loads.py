"""Hub loads in scenario files: a [hub_load.BODY] table of six signals or an OpenFAST file."""

from __future__ import annotations

from pathlib import Path

import pytest
from numpy.testing import assert_allclose

from pinwind.runs.scenario import ScenarioError, load_scenario, run
from tests.dynamics.test_hub_loads import COMPONENTS, OVERHANG, _expected_reaction, shaft_urdf
from tests.test_cli import run as run_cli

NAMES = ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")


def _scenario(tmp_path, table: str) -> str:
    (tmp_path / "shaft.urdf").write_text(shaft_urdf())
    path = tmp_path / "hub.toml"
    path.write_text(
        f'model = "shaft.urdf"\nduration = 0.01\ndt = 1e-3\nno_log = true\n\n'
        f"[hub_load.shaft]\n{table}"
    )
    return str(path)


def test_a_hub_load_table_loads_the_body_as_simulate_s_hub_loads_do(tmp_path):
    lines = [f"{n} = {float(v)!r}" for n, v in zip(NAMES, COMPONENTS, strict=True)]
    table = "\n".join([*lines, f"point = [0.0, 0.0, {OVERHANG!r}]", "up = [0.0, 1.0, 0.0]"])
    res = run(load_scenario(_scenario(tmp_path, table)), progress=False)
    force, moment = _expected_reaction(COMPONENTS)
    assert_allclose(res.bearing("shaft").force[-1], force, rtol=1e-12)
    assert_allclose(res.bearing("shaft").moment[-1], moment, rtol=1e-12)


def test_components_left_out_of_a_hub_load_table_are_zero(tmp_path):
    table = 'force_x = 1000.0\nup = [0.0, 1.0, 0.0]\nframe = "rotating"\n'
    res = run(load_scenario(_scenario(tmp_path, table)), progress=False)
    # the thrust along the hub's x, the shaft axis (world z), on a shaft that does not turn
    assert_allclose(res.bearing("shaft").force[-1], [0.0, 0.0, -1000.0], atol=1e-9)


def test_an_openfast_file_beside_components_is_refused_naming_the_key(tmp_path):
    table = 'openfast = "loads.out"\nforce_x = 1.0\n'
    with pytest.raises(ScenarioError, match=r"hub_load\.shaft\.openfast.*remove force_x"):
        load_scenario(_scenario(tmp_path, table))


def test_a_misspelt_component_is_refused_naming_the_key_and_the_known_ones(tmp_path):
    with pytest.raises(ScenarioError, match=r"moment_yy.*moment_y"):
        load_scenario(_scenario(tmp_path, "moment_yy = 1.0\n"))


def test_a_hub_load_on_an_unknown_body_exits_2_in_one_line(tmp_path):
    path = Path(_scenario(tmp_path, "force_x = 1.0\nup = [0.0, 1.0, 0.0]\n"))
    path.write_text(path.read_text().replace("[hub_load.shaft]", "[hub_load.rotor]"))
    out = run_cli("run", str(path))
    assert out.returncode == 2
    assert 'hub load on "rotor": no such body; bodies are: ground, shaft' in out.stderr
    assert "Traceback" not in out.stderr


def test_the_hub_load_option_loads_the_body_and_the_table_shows_the_reaction(tmp_path):
    model = tmp_path / "shaft.urdf"
    model.write_text(shaft_urdf())
    load = "shaft=hub_load(force_x=1000.0, moment_y=50.0, point=(0, 0, 1.5), up=(0, 1, 0))"
    out = run_cli("simulate", str(model), "--duration", "0.01", "--dt", "1e-3", "--no-log",
                  "--hub-load", load)  # fmt: skip
    assert out.returncode == 0, out.stderr
    # the thrust's reaction −1 kN along the axis; the bending moment 0.05 kN·m (the thrust
    # acts on the axis, so it adds none)
    row = next(line for line in out.stdout.splitlines() if line.startswith(" shaft ") and
               "-1.0000" in line)  # fmt: skip
    assert row.split()[1:4] == ["0.0000", "-1.0000", "0.0500"]


def test_a_hub_load_option_that_is_not_a_load_exits_2_saying_the_form(tmp_path):
    model = tmp_path / "shaft.urdf"
    model.write_text(shaft_urdf())
    out = run_cli("simulate", str(model), "--duration", "0.01", "--dt", "1e-3", "--no-log",
                  "--hub-load", "shaft=thrust(value=1e3)")  # fmt: skip
    assert out.returncode == 2
    assert "give BODY=hub_load(force_x=" in out.stderr
