"""``pinwind te``: the modifications read from the model file, torques by the base radius, errors.

The DTU stage (Jørgensen 2014) with 30 µm of long linear tip relief on the sun and the planet: the
torque on the sun T gives F_bt = T / r_b,sun, and in the double-pair zones both pairs' gaps add to
30 µm, so with ISO's stiffness (c′ b single, 0.875 c′ b per pair in double contact) the TE's
peak-to-peak is |3F/(7 c′b) − 15 µm| while every pair stays in contact (as in
tests/gears/test_transmission_error.py, here through the model file and the command line).
"""

from __future__ import annotations

import json

import numpy as np
from numpy.testing import assert_allclose
from typer.testing import CliRunner

from pinwind.cli import app
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import single_pair_stiffness
from tests.conftest import MODELS


def relieved_model(tmp_path, relief_um: float = 30.0, length_mm: float | None = None) -> str:
    text = (MODELS / "dtu500_planetary.urdf").read_text()
    pair = GearPair.from_mesh(_sun_planet())
    long = (pair.path.length - pair.path.base_pitch) * 1e3 if length_mm is None else length_mm
    for gear in ('name="sun"', 'name="planet1"'):
        text = text.replace(
            f"<gear {gear} ",
            f'<gear {gear} tip_relief_um="{relief_um}" tip_relief_length_mm="{long!r}" ',
        )
    path = tmp_path / "dtu_relieved.urdf"
    path.write_text(text)
    return str(path)


def _sun_planet():
    import pinwind

    gb = pinwind.load(MODELS / "dtu500_planetary.urdf")
    return next(m for m in gb.meshes if m.name == "sun_planet1")


def test_te_reads_the_tip_relief_from_the_model_and_the_torque_on_the_sun(tmp_path):
    model = relieved_model(tmp_path)
    out = CliRunner().invoke(
        app, ["te", model, "--mesh", "sun_planet1", "--torque", "20e3,30e3,40e3", "--json"]
    )
    assert out.exit_code == 0, out.output
    levels = json.loads(out.stdout)["levels"]
    pair = GearPair.from_mesh(_sun_planet())
    assert pair.names == ("sun", "planet1")
    k = single_pair_stiffness(pair)
    torque = np.array([r["torque_Nm"] for r in levels])
    force = torque / pair.geometry.base_radius_1
    assert_allclose([r["force_N"] for r in levels], force, rtol=1e-12)
    relief = 30e-6
    assert np.all(force / (1.75 * k) + relief / 2 >= relief)  # every pair in contact
    expected = np.abs(3 * force / (7 * k) - relief / 2) * 1e6
    assert_allclose([r["peak_to_peak_um"] for r in levels], expected, atol=1e-6)


def test_te_writes_its_three_figures(tmp_path):
    model = relieved_model(tmp_path)
    out = CliRunner().invoke(
        app,
        ["te", model, "--mesh", "sun_planet1", "--torque", "5e3:40e3:4", "--figures",
         str(tmp_path / "fig")],
    )  # fmt: skip
    assert out.exit_code == 0, out.output
    assert "[kN·m]" in out.output and "[µm]" in out.output
    for name in ("te_cycle.png", "te_map.png", "te_harmonics.png"):
        assert (tmp_path / "fig" / name).stat().st_size > 10_000


def test_bad_input_names_what_is_wrong(tmp_path):
    model = relieved_model(tmp_path)
    runner = CliRunner()
    cases = [
        (["--mesh", "sun_planet9", "--torque", "1e3"], "no mesh named 'sun_planet9'"),
        (["--mesh", "sun_planet1", "--torque", "-5"], "positive number of N·m"),
        (["--mesh", "sun_planet1", "--torque", "1:x"], "A:B:N"),
        (["--mesh", "sun_planet1", "--torque", "1e3", "--gear", "ring"], "name one"),
    ]
    for args, message in cases:
        out = runner.invoke(app, ["te", model, *args])
        assert out.exit_code != 0
        assert message in str(out.exception) or message in out.output
    bad = (
        (MODELS / "dtu500_planetary.urdf")
        .read_text()
        .replace('<gear name="sun" ', '<gear name="sun" tip_relief_um="20" ')
    )
    path = tmp_path / "bad.urdf"
    path.write_text(bad)
    out = runner.invoke(app, ["te", str(path), "--mesh", "sun_planet1", "--torque", "1e3"])
    assert "tip_relief_length" in str(out.exception)
