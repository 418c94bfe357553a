"""The FMI 3.0 gearbox FMU: valid for FMPy, units declared, stepped under FMPy equal to the
session and to the pair's momentum balance."""

from __future__ import annotations

import math
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError, TorquesUnbalanced
from pinwind.runs.scenario import Scenario
from pinwind.runs.session import Session
from tests.conftest import two_gear_urdf

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("pythonfmu3")

from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from pinwind.runs.fmu_export import export_fmu  # noqa: E402

DT = 1e-3
H = 10 * DT
#: The pair's z-axis inertias [kg·m²] (two_gear_urdf) and the base-radius ratio z_a / z_b.
I_A, I_B, RATIO = 0.0015, 0.006, 20 / 40


@pytest.fixture(scope="module")
def pair_fmu(tmp_path_factory):
    """The 20/40 pair as an FMI 3.0 unit with torques on a and b open; (model, FMU file)."""
    folder = tmp_path_factory.mktemp("fmu3")
    model = folder / "pair.urdf"
    model.write_text(two_gear_urdf())
    fmu = export_fmu(model, folder / "pair3.fmu", dt=DT, duration=1.0, fmi_version=3)
    return model, fmu


def _open(fmu) -> tuple[FMU3Slave, dict[str, int]]:
    """The FMU instantiated under FMPy, logging on (FMPy prints the log to stdout)."""
    description = fmpy.read_model_description(str(fmu))
    slave = FMU3Slave(
        guid=description.guid,
        unzipDirectory=fmpy.extract(str(fmu)),
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName="gearbox",
    )
    slave.instantiate(loggingOn=True)
    return slave, {v.name: v.valueReference for v in description.modelVariables}


def test_fmpy_finds_no_problem_and_reads_fmi3_inputs_and_outputs_with_si_units(pair_fmu):
    _, fmu = pair_fmu
    assert validate_fmu(str(fmu)) == []
    description = fmpy.read_model_description(str(fmu))
    assert description.fmiVersion == "3.0"
    assert description.coSimulation.canGetAndSetFMUstate  # FMPy's name for FMI 3.0's flag too
    variables = {v.name: v for v in description.modelVariables}
    assert {n: (v.causality, v.unit) for n, v in variables.items() if v.causality == "input"} == {
        "torque.a": ("input", "N.m"),
        "torque.b": ("input", "N.m"),
    }
    assert (variables["speed.a"].causality, variables["speed.a"].unit) == ("output", "rad/s")
    assert (variables["mesh_normal.m"].causality, variables["mesh_normal.m"].unit) == (
        "output",
        "N",
    )
    assert (variables["time"].causality, variables["time"].unit) == ("independent", "s")
    # SI base units: N·m = kg·m²/s², N = kg·m/s², rad/s = rad/s (FMI 3.0 §2.4.3)
    with zipfile.ZipFile(fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    base = {u.get("name"): dict(u.find("BaseUnit").attrib) for u in root.iter("Unit")}
    assert base["N.m"] == {"kg": "1", "m": "2", "s": "-2"}
    assert base["N"] == {"kg": "1", "m": "1", "s": "-2"}
    assert base["rad/s"] == {"rad": "1", "s": "-1"}


def test_the_fmu3_under_fmpy_equals_the_session_and_the_momentum_balance(pair_fmu):
    """Held torques over 8 points of 10 steps: the outputs equal the session's to 1e-9, and
    the pair's momentum balance holds: the mesh force's moments on the two shafts (lever arms
    the base radii, in the ratio z_a / z_b) cancel in I_a ω_a − (z_a/z_b) I_b ω_b, whose
    change over a step dt is (T_a − (z_a/z_b) T_b) dt with the torques of the step's first
    sample (sample 0: the start values; the samples of a communication step after its first
    point: the inputs set for it)."""
    model, fmu = pair_fmu
    rng = np.random.default_rng(5)
    u = np.column_stack([rng.uniform(0.5, 2.0, 8), rng.uniform(1.0, 4.0, 8)])
    slave, refs = _open(fmu)
    slave.enterInitializationMode(startTime=0.0, stopTime=1.0)
    slave.setFloat64([refs["torque.a"], refs["torque.b"]], [1.0, 2.0])
    slave.exitInitializationMode()
    names = ["speed.a", "speed.b", "angle.b", "mesh_normal.m", "bearing_force.a.y", "time"]
    got = []
    for i in range(8):
        slave.setFloat64([refs["torque.a"], refs["torque.b"]], list(u[i]))
        *_, last = slave.doStep(currentCommunicationPoint=i * H, communicationStepSize=H)
        assert last == pytest.approx((i + 1) * H, abs=1e-12)
        got.append(slave.getFloat64([refs[n] for n in names]))
    slave.terminate()
    slave.freeInstance()
    start = {"torque.a": 1.0, "torque.b": 2.0}
    session = Session(pinwind.load(model), Scenario(dt=DT, duration=1.0), inputs=list(start),
                      start=start)  # fmt: skip
    steps = round(H / DT)
    net = [1.0 - RATIO * 2.0] + [a - RATIO * b for a, b in u for _ in range(steps)]
    for i in range(8):
        out = session.advance((i + 1) * H, {"torque.a": u[i, 0], "torque.b": u[i, 1]})
        want = [out[n] for n in names[:-1]] + [(i + 1) * H]
        np.testing.assert_allclose(got[i], want, rtol=1e-9, atol=1e-12)
        impulse = math.fsum(net[: (i + 1) * steps]) * DT  # samples 0 .. (i+1)·steps − 1
        momentum = I_A * got[i][0] - RATIO * I_B * got[i][1]
        assert momentum == pytest.approx(impulse, rel=1e-9, abs=1e-15)
    session.close()


def test_fmpy_simulate_fmu_accelerates_the_pair_through_its_reflected_inertia(pair_fmu):
    """FMPy's own master, 1 N·m on a from t = 0 (its start value): ω_a = T t / J with
    J = I_a + (z_a/z_b)² I_b (the rigid mesh; the TorquesUnbalanced warning says nothing holds
    the train), and ω_b = −(z_a/z_b) ω_a (an external pair turns the other way)."""
    _, fmu = pair_fmu
    signal = np.array([(0.0, 1.0, 0.0)], dtype=[("time", float), ("torque.a", float),
                                                ("torque.b", float)])  # fmt: skip
    with pytest.warns(TorquesUnbalanced):
        got = fmpy.simulate_fmu(str(fmu), stop_time=0.1, output_interval=H, input=signal,
                                output=["speed.a", "speed.b"])  # fmt: skip
    assert len(got) == 11
    inertia = I_A + RATIO**2 * I_B
    np.testing.assert_allclose(got["speed.a"], 1.0 * got["time"] / inertia, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(got["speed.b"], -RATIO * got["speed.a"], rtol=1e-9, atol=1e-12)


def test_get_and_set_fmu_state_repeat_a_step_bit_for_bit(pair_fmu):
    _, fmu = pair_fmu
    slave, refs = _open(fmu)
    slave.enterInitializationMode(startTime=0.0, stopTime=1.0)
    slave.exitInitializationMode()
    inputs, names = [refs["torque.a"], refs["torque.b"]], [refs["speed.a"], refs["mesh_normal.m"]]
    slave.setFloat64(inputs, [1.5, 2.5])
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    saved = slave.getFMUState()
    slave.setFloat64(inputs, [0.7, 3.0])
    slave.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    first = slave.getFloat64(names)
    slave.setFMUState(saved)
    slave.setFloat64(inputs, [5.0, 1.0])
    slave.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    other = slave.getFloat64(names)
    slave.setFMUState(saved)
    slave.setFloat64(inputs, [0.7, 3.0])
    slave.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    assert slave.getFloat64(names) == first != other
    slave.freeFMUState(saved)
    slave.terminate()
    slave.freeInstance()


def test_a_refused_step_is_fmi3_discard_with_the_message_logged_and_the_unit_goes_on(
    pair_fmu, capfd
):
    _, fmu = pair_fmu
    slave, refs = _open(fmu)
    slave.enterInitializationMode(startTime=0.0, stopTime=1.0)
    slave.exitInitializationMode()
    slave.setFloat64([refs["torque.a"]], [math.nan])
    with pytest.raises(FMICallException, match=r"status 2 \(discard\)"):
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    assert 'NonFiniteInput: input "torque.a" is nan' in capfd.readouterr().out
    slave.setFloat64([refs["torque.a"]], [1.0])
    with pytest.raises(FMICallException, match=r"status 2 \(discard\)"):  # 4.5 internal steps
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=4.5 * DT)
    log = capfd.readouterr().out
    assert "StepNotOnGrid" in log and "4.5 steps" in log, log
    assert slave.getFloat64([refs["time"]]) == [0.0]  # the session where it was
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)  # goes on
    assert slave.getFloat64([refs["speed.a"]])[0] > 0.0  # 1 N·m on a alone accelerates it
    slave.terminate()
    slave.freeInstance()


def test_an_fmi_version_other_than_2_or_3_is_refused_naming_both(tmp_path):
    model = tmp_path / "pair.urdf"
    model.write_text(two_gear_urdf())
    with pytest.raises(InputError, match=r"FMI version 4 .*--fmi-version 2 or 3"):
        export_fmu(model, tmp_path / "p.fmu", fmi_version=4)
    assert not (tmp_path / "p.fmu").exists()


def test_pinwind_fmu_fmi_version_3_writes_the_unit_and_refuses_an_unknown_input(tmp_path):
    model = tmp_path / "pair.urdf"
    model.write_text(two_gear_urdf())
    out = tmp_path / "sub" / "p3.fmu"
    command = [sys.executable, "-m", "pinwind", "fmu", str(model), "-o", str(out),
               "--fmi-version", "3", "--duration", "2"]  # fmt: skip
    done = subprocess.run([*command, "--inputs", "torque.c"], capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.count('unknown input "torque.c"') == 1 and "torque.a" in done.stderr
    done = subprocess.run([*command, "--inputs", "torque.a", "--outputs", "speed.b"],
                          capture_output=True, text=True)  # fmt: skip
    assert done.returncode == 0, done.stderr
    description = fmpy.read_model_description(str(out))
    assert description.fmiVersion == "3.0"
    assert description.defaultExperiment.stopTime == "2.0"
    assert {v.name for v in description.modelVariables} == {"time", "torque.a", "speed.b"}
