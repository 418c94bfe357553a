"""``pinwind modes``: mode classes and repeated frequencies, the animation, bad input."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys

import numpy as np

from pinwind.modes.mode_animation import AMPLITUDE
from tests.conftest import MODELS
from tests.io.conftest import rrd_columns
from tests.modes.test_gyroscopic_modes import ROTORS, TILT, rotor_urdf, whirl_frequencies


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


def _turn_about_z(rrd_column) -> np.ndarray:
    """Rotation angles about z [rad] of a Transform3D quaternion column (x, y, z, w)."""
    q = np.array([row[0] for row in rrd_column[0].to_pylist()], dtype=float)
    return 2.0 * np.arctan2(q[:, 2], q[:, 3])


def test_the_animated_planet_mode_swings_the_planets_against_each_other(tmp_path):
    # Mode 3 of the three-planet stage is a planet mode: sun and carrier still, the planets'
    # angles sum to zero. The animation swings them as A sin(2π t) φ, one period per second,
    # the largest angle AMPLITUDE rad (every coordinate is a rotation).
    rrd = tmp_path / "mode3.rrd"
    model = str(MODELS / "saleh2017_planetary.urdf")
    out = run("modes", model, "--animate", "3", "--save", str(rrd))
    assert out.returncode == 0, out.stderr
    assert f"wrote {rrd}" in out.stdout.replace("\n", "")
    columns = rrd_columns(rrd)
    for body in ("sun", "carrier", "planet1", "planet2", "planet3", "ring"):
        assert f"/gearbox/{body}" in columns
    time = np.array([t.total_seconds() for t in columns["/gearbox/planet1"]["time"][0].to_pylist()])
    angles = np.array(
        [_turn_about_z(columns[f"/gearbox/planet{i}"]["Transform3D:quaternion"]) for i in (1, 2, 3)]
    )
    np.testing.assert_allclose(time[-1], 3.0, rtol=1e-9)  # three periods
    np.testing.assert_allclose(angles.sum(axis=0), 0.0, atol=1e-6)
    np.testing.assert_allclose(np.abs(angles).max(), AMPLITUDE, rtol=1e-3)
    shape = angles[:, np.argmax(np.abs(angles).max(axis=0))]  # the planets at a crest
    np.testing.assert_allclose(
        angles, np.outer(shape, np.sin(2 * np.pi * time)) / np.sin(2 * np.pi * 0.25), atol=1e-5
    )
    for body in ("sun", "carrier"):
        turn = _turn_about_z(columns[f"/gearbox/{body}"]["Transform3D:quaternion"])
        np.testing.assert_allclose(turn, 0.0, atol=1e-6)


def test_animate_without_save_or_beyond_the_last_mode_is_refused_in_one_line(tmp_path):
    model = str(MODELS / "saleh2017_planetary.urdf")
    for args, message in [
        (("--animate", "2"), "--animate N and --save FILE.rrd go together"),
        (("--animate", "9", "--save", str(tmp_path / "m.rrd")), "has modes 1 to 5"),
    ]:
        out = run("modes", model, *args)
        assert out.returncode == 2
        assert message in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_modes_at_a_speed_outside_the_range_of_validity_exit_2_in_one_line():
    model = str(MODELS / "saleh2017_planetary.urdf")
    for speed, message in [
        ("carrier=-10", "give 0 or more"),
        ("carrier=1e7", "beyond the 1e+05 rad/s"),
    ]:
        out = run("modes", model, "--speed", speed)
        assert out.returncode == 2
        assert message in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_modes_of_a_spinning_rotor_list_its_forward_and_backward_whirl(tmp_path):
    # The Jeffcott closed form of tests/modes/test_gyroscopic_modes.py at 3000 rpm.
    polar, transverse = ROTORS[0]
    model = tmp_path / "rotor.urdf"
    model.write_text(rotor_urdf(polar, transverse))
    out = run("modes", str(model), "--speed", "rotor=3000", "--json")
    assert out.returncode == 0, out.stderr
    found = {m["whirl"]: m["frequency_hz"] for m in json.loads(out.stdout) if m["whirl"]}
    forward, backward = whirl_frequencies(polar, transverse, 3000 * 2 * math.pi / 60)
    np.testing.assert_allclose(found["forward"], forward / (2 * math.pi), rtol=1e-6)
    np.testing.assert_allclose(found["backward"], backward / (2 * math.pi), rtol=1e-6)
    table = run("modes", str(model), "--speed", "rotor=3000").stdout
    assert "forward" in table and "backward" in table


def test_campbell_of_a_spinning_rotor_writes_the_whirl_of_each_crossing(tmp_path):
    polar, transverse = ROTORS[0]
    model = tmp_path / "rotor.urdf"
    model.write_text(rotor_urdf(polar, transverse))
    csv_path = tmp_path / "crossings.csv"
    out = run("campbell", str(model), "--joint", "rotor", "--speed-range", "0:2500",
              "--points", "21", "--csv", str(csv_path))  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = list(csv.DictReader(csv_path.read_text(encoding="utf-8").splitlines()))
    rpm = {r["whirl"]: float(r["speed_rpm"]) for r in rows if r["whirl"]}
    per_rpm = 60 / (2 * math.pi)
    np.testing.assert_allclose(
        rpm["forward"], math.sqrt(TILT / (transverse - polar)) * per_rpm, rtol=1e-9
    )
    np.testing.assert_allclose(
        rpm["backward"], math.sqrt(TILT / (transverse + polar)) * per_rpm, rtol=1e-9
    )


def _base_radius(teeth: int, module: float) -> float:
    """r_b = m z cos α / 2 [m] of the Saleh drivetrain's gears (α = 24.5°, no profile shift)."""
    return module * teeth * math.cos(math.radians(24.5)) / 2


def test_modes_of_the_saleh_drivetrain_scenario_ring_the_rotor_against_the_train():
    # scenarios/saleh2017_drivetrain.toml puts the 5e6 kg·m² rotor (loads/rotor.py) on the
    # carrier. Its first flexible mode swings rotor and carrier (J_r) against the train's
    # inertia J_t reduced to the carrier, on the train's torsional stiffness k at the carrier,
    # its meshes in series (the stiffnesses the modes list, each k r_b² reduced by the speed
    # ratio squared): a planet pin between its sun mesh k_sp and ring mesh k_rp stiffens the
    # carrier by 4 k_sp k_rp / (k_sp + k_rp) (r_b,s + r_b,p)² (the pin moves the sun mesh and
    # the ring mesh the same way; the planet turns so as to balance them), three planets; then
    # stage 1 at the sun (× 6²) and stage 2 at stage 1's pinion (× (6 · 83/23)²). The two-
    # inertia formula f = √(k (1/J_r + 1/J_t)) / 2π puts J_t at the far end of k, where it
    # moves most: the train's inertia nearer the carrier moves less, so the true frequency is
    # above it (Rayleigh), by a few per cent here. Without the rotor the mode is at 325 Hz.
    out = run("modes", str(MODELS.parent / "scenarios" / "saleh2017_drivetrain.toml"), "--json")
    assert out.returncode == 0, out.stderr
    modes = json.loads(out.stdout)
    assert "rotor inertia on carrier: 5e+06 kg·m²" in out.stderr
    first = next(m for m in modes if m["frequency_hz"] > 0)
    # The stiffnesses: those of the mesh elements (mean mesh stiffness c_γα b of each pair).
    from pinwind.modes.linearisation import linearise
    from pinwind.runs.scenario import load_scenario

    scenario = load_scenario(MODELS.parent / "scenarios" / "saleh2017_drivetrain.toml")
    gearbox = scenario.load_model()
    k = {
        e.name: e.stiffness
        for e in linearise(gearbox, meshes={"all": "compliant"}).elements
        if e.kind == "mesh"
    }
    arm = _base_radius(24, 0.015) + _base_radius(48, 0.015)
    ksp, krp = k["sun_planet1"], k["planet1_ring"]
    k_carrier = 3 * 4 * ksp * krp / (ksp + krp) * arm**2
    k_stage1 = k["stage1"] * _base_radius(83, 0.015) ** 2 * 6**2
    k_stage2 = k["stage2"] * _base_radius(103, 0.010) ** 2 * (6 * 83 / 23) ** 2
    k_train = 1 / (1 / k_carrier + 1 / k_stage1 + 1 / k_stage2)
    # Inertias from the model file and the rotor (J about each axis; planets carried at 0.54 m).
    j_rotor = 5.0e6 + 88.264 + 3 * (1.87 + 254.3 * 0.54**2) + 3 * 1113.1 * 0.54**2
    inertia = {name: gearbox.model.inertias[gearbox.model.getJointId(name)] for name in
               ("sun", "planet1", "stage1_pinion", "stage2_pinion")}  # fmt: skip
    izz = {n: float(i.inertia[2, 2] + i.mass * (i.lever[0] ** 2 + i.lever[1] ** 2))
           for n, i in inertia.items()}  # fmt: skip
    j_train = (
        izz["sun"] * 6**2
        + 3 * izz["planet1"] * 2.5**2  # planet spin relative to the carrier: −(120/48) ω_c
        + izz["stage1_pinion"] * (6 * 83 / 23) ** 2
        + izz["stage2_pinion"] * (6 * 83 / 23 * 103 / 26) ** 2
    )
    two_inertia = math.sqrt(k_train * (1 / j_rotor + 1 / j_train)) / (2 * math.pi)
    assert two_inertia <= first["frequency_hz"] <= 1.06 * two_inertia
    assert first["frequency_hz"] < 0.25 * 317.0


def test_modes_of_a_scenario_do_not_depend_on_how_its_model_writes_the_meshes(tmp_path):
    # Lin & Parker's planar stage (tests/dynamics/test_loaded_flanks.py) under a scenario: the
    # sun driven by 2 kN·m against the carrier and the ring held by speed drivers at rest. The
    # same machine written with every mesh's gears swapped and the mesh lines reversed.
    from tests.dynamics.test_loaded_flanks import WRITINGS, lin_parker_text

    found = []
    for name, text in [
        ("built", lin_parker_text()),
        ("rewritten", WRITINGS["mesh lines reversed"](WRITINGS["all swapped"](lin_parker_text()))),
    ]:
        (tmp_path / f"{name}.urdf").write_text(text)
        (tmp_path / f"{name}.toml").write_text(
            f'model = "{name}.urdf"\ntorque = {{ sun = 2000.0 }}\n'
            "speed = { carrier = 0.0, ring = 0.0 }\n"
        )
        out = run("modes", str(tmp_path / f"{name}.toml"), "--json")
        assert out.returncode == 0, out.stderr
        assert "no static load" not in out.stderr
        found.append([m["frequency_hz"] for m in json.loads(out.stdout)])
    np.testing.assert_allclose(found[1], found[0], rtol=1e-9)


def test_campbell_of_a_scenario_draws_the_modes_with_its_rotor(tmp_path):
    # On torsional coordinates the modes do not move with speed: the diagram's frequencies are
    # those of ``pinwind modes SCENARIO`` (the rotor in), each once, a repeated one as "f ×2".
    scenario = str(MODELS.parent / "scenarios" / "saleh2017_drivetrain.toml")
    listed = [m["frequency_hz"] for m in json.loads(run("modes", scenario, "--json").stdout)]
    out = run("campbell", scenario, "--joint", "carrier", "--speed-range", "0:20")
    assert out.returncode == 0, out.stderr
    drawn = out.stdout.replace("\n", "").split("natural frequencies [Hz]: ")[1].split(";")[0]
    groups: list[list[float]] = []  # a repeated frequency (the planet modes) once, "×2"
    for f in (f for f in listed if f > 0):
        if groups and math.isclose(groups[-1][0], f, rel_tol=1e-6):
            groups[-1].append(f)
        else:
            groups.append([f])
    expected = [f"{g[0]:.5g}" + (f" ×{len(g)}" if len(g) > 1 else "") for g in groups]
    assert drawn.split(", ") == expected and any(len(g) > 1 for g in groups)


def test_campbell_lists_a_repeated_planet_mode_once_with_the_speed_unit_in_its_header(tmp_path):
    # The double planet mode of three planets met each line twice (two identical rows), and
    # rich took the header's "[rpm]" for markup: the column read "speed".
    model = str(MODELS / "saleh2017_planetary.urdf")
    planet = [m for m in json.loads(run("modes", model, "--json").stdout) if m["kind"] == "planet"]
    f_planet = planet[0]["frequency_hz"]
    # Mesh frequency z_ring Ω / 2π on the carrier with the ring fixed (120 teeth): the line
    # meets the planet mode at Ω* = 60 f / z_ring rpm; a range reaching past it.
    crossing_rpm = 60 * f_planet / 120
    csv_path = tmp_path / "crossings.csv"
    top = f"0:{1.2 * crossing_rpm:.6g}"
    out = run("campbell", model, "--joint", "carrier", "--speed-range", top,
              "--harmonics", "1", "--csv", str(csv_path))  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "speed [rpm]" in out.stdout and f"{f_planet:.5g} ×2" in out.stdout
    rows = list(csv.DictReader(csv_path.read_text(encoding="utf-8").splitlines()))
    at_planet = [r for r in rows if math.isclose(float(r["mode_hz"]), f_planet, rel_tol=1e-6)]
    assert len(at_planet) == 1 and at_planet[0]["multiplicity"] == "2", rows
    np.testing.assert_allclose(float(at_planet[0]["speed_rpm"]), crossing_rpm, rtol=1e-9)
