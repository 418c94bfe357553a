"""Scenario files: round trip through the log, --from-log repeats bit for bit, errors with lines."""

from __future__ import annotations

import hashlib
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.cli import main
from pinwind.dynamics.result import Result
from pinwind.runs.scenario import load_scenario
from tests.conftest import MODELS

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
RPM = 2 * math.pi / 60


def pinwind_cli(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "COLUMNS": "120"}
    return subprocess.run([sys.executable, "-m", "pinwind", *args], capture_output=True,
                          text=True, cwd=cwd, env=env, check=False)  # fmt: skip


def write(tmp_path: Path, text: str) -> Path:
    shutil.copy(MODELS / "saleh2017_planetary.urdf", tmp_path / "model.urdf")
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


SHORT = """model = "model.urdf"
duration = 0.5
dt = 1e-3
initial_speed = { carrier = 14.0 }
wind = "kaimal(mean=10, turbulence_intensity=0.15, seed=3, duration=1)"
out = "case.mcap"

[torque]
carrier = "step(time=0.2, before=0, after=1e4) + sine(mean=0, amplitude=5e3, frequency=3)"

[rotor.carrier]
preset = "saleh2017"

[generator.sun]
law = "induction-dq"
preset = "cart600"
poles = 2
"""


def test_scenario_values_round_trip_through_the_log(tmp_path):
    path = write(tmp_path, SHORT)
    out = pinwind_cli("run", str(path), "--no-progress", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    res = pinwind.read_log(tmp_path / "logs" / "case.mcap")
    stored = res.metadata["scenario"]
    assert stored["values"] == load_scenario(path).values
    assert stored["source"] == str(path)
    assert res.metadata["duration"] == 0.5 and res.metadata["dt"] == 1e-3
    assert res.metadata["rotors"]["carrier"]["radius"] == 41 + 3.7 / 2
    assert res.metadata["generators"]["sun"]["law"] == "induction-dq"
    assert res.metadata["wind"]["seed"] == 3
    assert_allclose(res.joint("carrier").speed[0], 14.0 * RPM, rtol=1e-12)


def _equal(a: Result, b: Result) -> None:
    assert np.array_equal(a.pose_rows, b.pose_rows)  # the 100 Hz pose samples of a log
    for name in Result.ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    for name, values in a.energy.items():
        assert np.array_equal(values, b.energy[name]), name


def test_from_log_repeats_a_logged_run_bit_for_bit(tmp_path):
    path = write(tmp_path, SHORT)
    assert pinwind_cli("run", str(path), "--no-progress", cwd=tmp_path).returncode == 0
    # The model file changes afterwards: the repeat uses the one the log holds.
    (tmp_path / "model.urdf").write_text("not a model any more")
    out = pinwind_cli("run", "--from-log", "logs/case.mcap", "--out", "again.mcap",
                      "--no-progress", cwd=tmp_path)  # fmt: skip
    assert out.returncode == 0, out.stderr
    _equal(pinwind.read_log(tmp_path / "logs/case.mcap"),
           pinwind.read_log(tmp_path / "logs/again.mcap"))  # fmt: skip


def test_simulate_flags_are_stored_as_a_scenario_and_repeat_bit_for_bit(tmp_path):
    model = str(MODELS / "saleh2017_planetary.urdf")
    out = pinwind_cli(
        "simulate", model, "--initial-speed", "carrier=14.2", "--rotor", "carrier=saleh2017",
        "--wind", "sine(mean=10, amplitude=1, frequency=0.5)",
        "--generator", "sun=linear-slip(slope=1.26e6, sync_rpm=83.94)",
        "--torque", "carrier=ramp(start_value=0, end_value=1e4, start_time=0, end_time=0.1)",
        "--duration", "0.3", "--out", "flags.mcap", "--no-progress", cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    first = pinwind.read_log(tmp_path / "logs/flags.mcap")
    values = first.metadata["scenario"]["values"]
    assert values["generator"]["sun"] == {"law": "linear-slip", "slope": 1.26e6, "sync_rpm": 83.94}
    assert values["rotor"]["carrier"] == {"preset": "saleh2017"}
    again = pinwind_cli("run", "--from-log", "logs/flags.mcap", "--out", "b.mcap",
                        "--no-progress", cwd=tmp_path)  # fmt: skip
    assert again.returncode == 0, again.stderr
    _equal(first, pinwind.read_log(tmp_path / "logs/b.mcap"))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            'model = "model.urdf"\ndt = 1e-3\ndurtion = 2\n',
            '{p}:3: durtion: unknown key "durtion"; did you mean "duration"? keys are: model, '
            "duration, dt, torque",
        ),
        (
            'model = "model.urdf"\nduration = "2 s"\n',
            "{p}:2: duration: must be a number [s]; got '2 s'",
        ),
        ("duration = 2\n", "{p}: model: missing"),
        (
            'model = "model.urdf"\n\n[generator.sun]\nlaw = "slip"\n',
            "{p}:4: generator.sun.law: is 'slip'; laws are: constant, linear-slip, variable-speed",
        ),
        (
            'model = "model.urdf"\ntorque = { carrier = "sine(mean=1, amplitude=1)" }\n',
            "{p}:2: torque.carrier: sine() needs frequency",
        ),
        (
            'model = "model.urdf"\nwind = 10\n[rotor.carrier]\npreset = "saleh2017"\nd = 8\n',
            '{p}:5: rotor.carrier.d: unknown parameter "d"; parameters of a rotor are: preset, ',
        ),
        (
            'model = "model.urdf"\nmesh = { all = "soft" }\n',
            "{p}:2: mesh.all: is 'soft'; choose one of: rigid, compliant",
        ),
        (
            'model = "model.urdf"\ntorque = { sunn = 1e5 }\n',
            '{p}:2: torque.sunn: "sunn" is not a joint of the model; joints are: carrier, planet1',
        ),
        (
            'model = "model.urdf"\ntorque = { ring = 1e5 }\n',
            '{p}:2: torque.ring: "ring" is a fixed mount',
        ),
        ('model = "missing.urdf"\n', "{p}:1: model: "),
        ('model = "model.urdf"\nduration = 1\n[wind\n', "{p}:3: -: not valid TOML"),
        (
            'model = "model.urdf"\n[rotor.carrier]\npreset = "saleh2017"\n',
            "{p}: wind: missing: a rotor needs the wind speed",
        ),
        (
            'model = "model.urdf"\nwind = 10\n[rotor.carrier]\nradius = 40\n'
            "cp_table = { tsr = [4, 8], cp = [0.3, 0.45], pitch = [0] }\n",
            '{p}:5: rotor.carrier.cp_table.pitch: unknown key "pitch"; did you mean "pitch_deg"?',
        ),
        (
            'model = "model.urdf"\n\n[generator.sun]\nlaw = "linear-slip"\nslop = 1e6\n',
            '{p}:5: generator.sun.slop: unknown parameter "slop"; did you mean "slope"? '
            "parameters of linear-slip are: slope, sync_rpm",
        ),
    ],
    ids=[
        "unknown-key",
        "wrong-type",
        "no-model",
        "bad-law",
        "bad-signal",
        "bad-rotor-key",
        "bad-choice",
        "unknown-joint",
        "fixed-joint",
        "model-not-found",
        "bad-toml",
        "rotor-without-wind",
        "cp-table-key",
        "generator-key",
    ],
)
def test_bad_scenario_gets_one_line_naming_file_key_line_and_choices(
    tmp_path, monkeypatch, capsys, text, message
):
    path = write(tmp_path, text)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "argv", ["pinwind", "run", str(path), "--no-log"])
    with pytest.raises(SystemExit) as exit_:
        main()
    assert exit_.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert message.format(p=path) in lines[0], lines[0]


def test_the_rated_scenario_reaches_14_2_rpm_under_1_mnm():
    scenario = load_scenario(SCENARIOS / "saleh2017_rated.toml")
    from pinwind.runs.scenario import run

    res = run(scenario, no_log=True, progress=False)
    assert_allclose(res.joint("carrier").speed[-1], 14.2 * RPM, rtol=1e-5)
    assert_allclose(res.joint("sun").speed[-1], 85.2 * RPM, rtol=1e-5)
    assert_allclose(res.joint("carrier").torque[-1], 1e6, rtol=1e-4)
    # Each sun mesh carries the sun torque over 3 planets at r_sun = 0.18 m.
    assert_allclose(res.mesh("sun_planet1").tangential[-1], 1e6 / 6 / 3 / 0.18, rtol=1e-4)


@pytest.mark.parametrize(
    ("option", "value"),
    [
        ("--generator", 'sun=linear-slip(**{"slope": 1.26e6, "sync_rpm": 83.94})'),
        ("--rotor", 'carrier=rotor(**{"preset": "saleh2017"})'),
    ],
)
def test_double_star_parameters_in_a_flag_are_refused_in_one_line_naming_the_flag(
    monkeypatch, capsys, option, value
):
    model = str(MODELS / "saleh2017_planetary.urdf")
    argv = ["pinwind", "simulate", model, option, value, "--wind", "10", "--no-log"]
    monkeypatch.setattr(sys, "argv", argv)
    with pytest.raises(SystemExit) as exit_:
        main()
    assert exit_.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert f"{option}: in " in lines[0] and "give the parameters as key=value" in lines[0]


BUILT_ONCE = """model = "model.urdf"
duration = 0.01
initial_speed = { carrier = 14.0 }
wind = "kaimal(mean=10, turbulence_intensity=0.1, seed=1, duration=1)"
torque = { carrier = "sine(mean=0, amplitude=1e3, frequency=2)" }

[rotor.carrier]
preset = "saleh2017"

[generator.sun]
law = "linear-slip"
slope = 1.26e6
sync_rpm = 83.94
"""
SINE = "carrier=sine(mean=0, amplitude=1e3, frequency=2)"
ONCE_EACH = {"Sine": 1, "KaimalWind": 1, "Rotor": 1, "LinearSlip": 1}


@pytest.mark.parametrize(
    ("argv", "built"),
    [
        (
            ["simulate", "model.urdf", "--initial-speed", "carrier=14", "--duration", "0.01",
             "--torque", SINE, "--rotor", "carrier=saleh2017",
             "--wind", "kaimal(mean=10, turbulence_intensity=0.1, seed=1, duration=1)",
             "--generator", "sun=linear-slip(slope=1.26e6, sync_rpm=83.94)", "--no-log"],
            ONCE_EACH,
        ),
        (["run", "case.toml", "--no-log"], ONCE_EACH),
        (["rate", "model.urdf", "--torque", SINE, "--duration", "0.01"], {"Sine": 1}),
    ],
    ids=["simulate", "run", "rate"],
)  # fmt: skip
def test_each_signal_and_law_of_a_run_is_built_once(tmp_path, monkeypatch, argv, built):
    from pinwind.loads.generator import LinearSlip
    from pinwind.loads.rotor import Rotor
    from pinwind.loads.signals import Sine
    from pinwind.loads.wind import KaimalWind

    write(tmp_path, BUILT_ONCE)
    monkeypatch.chdir(tmp_path)
    counted: dict[str, int] = {}
    for cls in (Sine, KaimalWind, Rotor, LinearSlip):

        def init(self, *args, _name=cls.__name__, _init=cls.__init__, **kwargs):
            counted[_name] = counted.get(_name, 0) + 1
            _init(self, *args, **kwargs)

        monkeypatch.setattr(cls, "__init__", init)
    monkeypatch.setattr(sys, "argv", ["pinwind", *argv])
    with pytest.raises(SystemExit) as exit_:
        main()
    assert exit_.value.code == 0
    assert counted == built


@pytest.mark.parametrize(
    ("law", "params"),
    [
        ("constant", {"torque": 1e3}),
        ("linear-slip", {"slope": 1e4, "sync_rpm": 60.0}),
        ("variable-speed", {"gain": 2.0, "rated_power": 1e6}),
        ("induction", {"preset": "cart600"}),
        ("induction-dq", {"preset": "cart600", "poles": 6}),
    ],
)
def test_every_generator_law_is_logged_under_the_name_it_was_given(law, params):
    from pinwind.loads.generator import describe
    from pinwind.runs.scenario import build

    values = {"model": "m.urdf", "generator": {"sun": {"law": law, **params}}}
    logged = describe(build(values, source="case.toml").generators["sun"])
    assert logged["law"] == law
    if law == "linear-slip":  # 60 rpm is one turn per second: 2π rad/s
        assert_allclose(logged["sync_speed"], 2 * math.pi, rtol=1e-15)
    if law == "induction-dq":
        assert logged["dynamic"] is True and logged["poles"] == 6


TABLE_SCENARIO = """model = "model.urdf"
duration = 0.2
dt = 1e-3
initial_speed = { carrier = 14.0 }
out = "table.mcap"

[torque]
carrier = "csv(file='torque.csv', column=1)"
"""


def test_input_files_are_fingerprinted_in_the_log(tmp_path):
    path = write(tmp_path, TABLE_SCENARIO)
    table = b"t,torque\n0,0\n1,1e5\n"
    (tmp_path / "torque.csv").write_bytes(table)
    out = pinwind_cli("run", str(path), "--no-progress", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    files = pinwind.read_log(tmp_path / "logs/table.mcap").metadata["input_files"]
    by_input = {f["where"]: f for f in files}
    assert set(by_input) == {"scenario", "torque.carrier"}
    assert by_input["torque.carrier"]["path"] == "torque.csv"  # as the scenario gave it
    assert by_input["torque.carrier"]["sha256"] == hashlib.sha256(table).hexdigest()
    assert by_input["torque.carrier"]["bytes"] == len(table)
    assert by_input["scenario"]["sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()


def test_from_log_refuses_a_table_changed_since_the_run(tmp_path):
    path = write(tmp_path, TABLE_SCENARIO)
    table = tmp_path / "torque.csv"
    table.write_text("t,torque\n0,0\n1,1e5\n")
    assert pinwind_cli("run", str(path), "--no-progress", cwd=tmp_path).returncode == 0
    recorded = hashlib.sha256(table.read_bytes()).hexdigest()
    # unchanged: repeated
    same = pinwind_cli("run", "--from-log", "logs/table.mcap", "--out", "same.mcap",
                       "--no-progress", cwd=tmp_path)  # fmt: skip
    assert same.returncode == 0, same.stderr
    # one digit edited: refused before the run, naming the file and both fingerprints
    table.write_text("t,torque\n0,0\n1,2e5\n")
    edited = hashlib.sha256(table.read_bytes()).hexdigest()
    out = pinwind_cli("run", "--from-log", "logs/table.mcap", "--out", "edited.mcap",
                      "--no-progress", cwd=tmp_path)  # fmt: skip
    assert out.returncode == 2, out.stderr
    message = " ".join(out.stderr.split())
    assert "InputFileChanged" in message or "torque.csv has changed" in message
    assert "torque.carrier: torque.csv has changed" in message
    assert recorded in message and edited in message
    assert "Traceback" not in out.stderr
    assert not (tmp_path / "logs/edited.mcap").exists()
    # gone: refused too
    table.rename(tmp_path / "moved.csv")
    gone = pinwind_cli("run", "--from-log", "logs/table.mcap", "--out", "gone.mcap",
                       "--no-progress", cwd=tmp_path)  # fmt: skip
    assert gone.returncode == 2 and "is missing now" in " ".join(gone.stderr.split())
    # accepted on purpose: runs with the file as it is and records its new fingerprint
    (tmp_path / "moved.csv").rename(table)
    accepted = pinwind_cli("run", "--from-log", "logs/table.mcap", "--out", "accepted.mcap",
                           "--accept-changed-inputs", "--no-progress", cwd=tmp_path)  # fmt: skip
    assert accepted.returncode == 0, accepted.stderr
    files = pinwind.read_log(tmp_path / "logs/accepted.mcap").metadata["input_files"]
    assert [f["sha256"] for f in files if f["where"] == "torque.carrier"] == [edited]


def test_a_rotors_pitch_control_is_a_preset_or_a_table_in_scenario_units():
    from pinwind.loads.pitch_control import PitchControl
    from pinwind.runs.scenario import build

    def rotor(control):
        values = {"model": "m.urdf", "wind": 12.0,
                  "rotor": {"rotor": {"preset": "nrel5mw", "pitch_control": control}}}  # fmt: skip
        return build(values, source="case.toml").rotors["rotor"]

    assert rotor("nrel5mw").pitch_control == PitchControl.nrel5mw()
    # A table in rpm, degrees and hertz: 12.1 rpm is 1.2671 rad/s, 0.25 Hz is π/2 rad/s.
    table = rotor({"preset": "nrel5mw", "speed_rpm": 12.1, "rate_deg_s": 4.0, "corner_hz": 0.25})
    assert_allclose(table.pitch_control.speed_set, 12.1 * 2 * math.pi / 60, rtol=1e-15)
    assert_allclose(table.pitch_control.rate, math.radians(4.0), rtol=1e-15)
    assert_allclose(table.pitch_control.corner, math.pi / 2, rtol=1e-15)
    full = {"speed_rpm": 20.0, "kp": 1.0, "ki": 0.5, "gain_angle_deg": 5.0, "corner_hz": 1.0}
    assert rotor(full).pitch_control.gain_angle == math.radians(5.0)
    assert rotor(full).describe()["pitch_control"]["kp"] == 1.0  # logged with the rotor
    # The flag's form: a preset with changes.
    from pinwind.cli.flags import rotor_values

    flag = rotor_values(["rotor=nrel5mw(pitch_control='nrel5mw', pitch_deg=5)"])["rotor"]
    assert rotor(flag["pitch_control"]).pitch_control == PitchControl.nrel5mw()
    assert flag == {"preset": "nrel5mw", "pitch_control": "nrel5mw", "pitch_deg": 5}


@pytest.mark.parametrize(
    ("control", "message"),
    [
        ("jonkman", "rotor.rotor.pitch_control.preset: is 'jonkman'; presets are: nrel5mw"),
        ({"preset": "nrel5mw", "kp_gain": 1.0}, 'unknown parameter "kp_gain"'),
        ({"speed_rpm": 12.1}, "give a preset (nrel5mw) or every value"),
        ({"preset": "nrel5mw", "corner_hz": 0.0}, "corner is 0.0; it must be a positive"),
    ],
)
def test_a_bad_pitch_control_names_the_key_and_the_fix(control, message):
    from pinwind.runs.scenario import ScenarioError, build

    values = {"model": "m.urdf", "wind": 12.0,
              "rotor": {"rotor": {"preset": "nrel5mw", "pitch_control": control}}}  # fmt: skip
    with pytest.raises(ScenarioError) as err:
        build(values, source="case.toml")
    assert message in str(err.value)
