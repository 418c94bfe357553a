"""The gearbox FMU: valid for FMPy, units declared, stepped under FMPy equal to the session."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.runs.scenario import Scenario
from pinwind.runs.session import Session
from tests.conftest import two_gear_urdf

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("pythonfmu")

from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from pinwind.runs.fmu_export import export_fmu  # noqa: E402

DT = 1e-3
H = 10 * DT


@pytest.fixture(scope="module")
def pair_fmu(tmp_path_factory):
    """The 20/40 pair exported with torques on a and b open; (model file, FMU file)."""
    folder = tmp_path_factory.mktemp("fmu")
    model = folder / "pair.urdf"
    model.write_text(two_gear_urdf())
    return model, export_fmu(model, folder / "pair.fmu", dt=DT, duration=1.0)


def _open(fmu) -> tuple[FMU2Slave, dict[str, int]]:
    """The FMU instantiated under FMPy, logging on (FMPy prints the log to stdout)."""
    description = fmpy.read_model_description(str(fmu))
    folder = fmpy.extract(str(fmu))
    slave = FMU2Slave(
        guid=description.guid,
        unzipDirectory=folder,
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName="gearbox",
    )
    slave.instantiate(loggingOn=True)
    refs = {v.name: v.valueReference for v in description.modelVariables}
    return slave, refs


def test_fmpy_finds_no_problem_and_reads_the_declared_inputs_and_outputs_with_units(pair_fmu):
    _, fmu = pair_fmu
    assert validate_fmu(str(fmu)) == []
    variables = {v.name: v for v in fmpy.read_model_description(str(fmu)).modelVariables}
    assert {n: (v.causality, v.unit) for n, v in variables.items() if v.causality == "input"} == {
        "torque.a": ("input", "N.m"),
        "torque.b": ("input", "N.m"),
    }
    assert (variables["speed.a"].causality, variables["speed.a"].unit) == ("output", "rad/s")
    assert (variables["mesh_normal.m"].causality, variables["mesh_normal.m"].unit) == (
        "output",
        "N",
    )
    assert variables["angle.b"].unit == "rad"


def test_the_fmu_under_fmpy_equals_the_session_at_every_communication_point(pair_fmu):
    model, fmu = pair_fmu
    rng = np.random.default_rng(4)
    u = np.column_stack([rng.uniform(0.5, 2.0, 8), rng.uniform(1.0, 4.0, 8)])
    slave, refs = _open(fmu)
    slave.setupExperiment(startTime=0.0, stopTime=1.0)
    slave.enterInitializationMode()
    slave.setReal([refs["torque.a"], refs["torque.b"]], [1.0, 2.0])
    slave.exitInitializationMode()
    names = ["speed.a", "angle.b", "mesh_normal.m", "bearing_force.a.y"]
    got = []
    for i in range(8):
        slave.setReal([refs["torque.a"], refs["torque.b"]], list(u[i]))
        slave.doStep(currentCommunicationPoint=i * H, communicationStepSize=H)
        got.append(slave.getReal([refs[n] for n in names]))
    slave.terminate()
    slave.freeInstance()
    start = {"torque.a": 1.0, "torque.b": 2.0}
    scenario = Scenario(dt=DT, duration=1.0)
    session = Session(pinwind.load(model), scenario, inputs=list(start), start=start)
    for i in range(8):
        out = session.advance((i + 1) * H, {"torque.a": u[i, 0], "torque.b": u[i, 1]})
        np.testing.assert_allclose(got[i], [out[n] for n in names], rtol=1e-9, atol=1e-12)


def test_get_and_set_fmu_state_repeat_a_step_bit_for_bit(pair_fmu):
    """fmi2GetFMUstate before a step, fmi2SetFMUstate after it: the step again gives the same
    outputs exactly (the session's compiled state restored), another input other ones."""
    _, fmu = pair_fmu
    slave, refs = _open(fmu)
    slave.setupExperiment(startTime=0.0, stopTime=1.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    inputs, names = [refs["torque.a"], refs["torque.b"]], ["speed.a", "mesh_normal.m"]
    slave.setReal(inputs, [1.5, 2.5])
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    saved = slave.getFMUstate()
    slave.setReal(inputs, [0.7, 3.0])
    slave.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    first = slave.getReal([refs[n] for n in names])
    slave.setFMUstate(saved)
    slave.setReal(inputs, [5.0, 1.0])
    slave.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    other = slave.getReal([refs[n] for n in names])
    slave.setFMUstate(saved)
    slave.setReal(inputs, [0.7, 3.0])
    slave.doStep(currentCommunicationPoint=H, communicationStepSize=H)
    assert slave.getReal([refs[n] for n in names]) == first != other
    slave.freeFMUstate(saved)
    slave.terminate()
    slave.freeInstance()


def test_a_bad_input_refuses_the_step_with_the_message_in_the_log_and_the_unit_goes_on(
    pair_fmu, capfd
):
    _, fmu = pair_fmu
    slave, refs = _open(fmu)
    slave.setupExperiment(startTime=0.0, stopTime=1.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.setReal([refs["torque.a"]], [math.nan])
    with pytest.raises(FMICallException, match=r"status 2 \(discard\)"):
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    assert 'NonFiniteInput: input "torque.a" is nan' in capfd.readouterr().out
    slave.setReal([refs["torque.a"]], [1.0])
    with pytest.raises(FMICallException):  # 4.5 internal steps
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=4.5 * DT)
    log = capfd.readouterr().out
    assert "StepNotOnGrid" in log and "4.5 steps" in log, log
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)  # goes on
    assert slave.getReal([refs["speed.a"]])[0] > 0.0  # 1 N·m on a alone accelerates it
    slave.terminate()
    slave.freeInstance()


def test_pinwind_fmu_writes_the_unit_and_refuses_an_unknown_input_with_exit_code_2(tmp_path):
    import subprocess
    import sys

    model = tmp_path / "pair.urdf"
    model.write_text(two_gear_urdf())
    command = [sys.executable, "-m", "pinwind", "fmu", str(model), "-o", str(tmp_path / "p.fmu")]
    done = subprocess.run([*command, "--inputs", "torque.c"], capture_output=True, text=True)
    assert done.returncode == 2
    assert 'unknown input "torque.c"' in done.stderr and "torque.a" in done.stderr
    done = subprocess.run([*command, "--inputs", "torque.a", "--outputs", "speed.b"],
                          capture_output=True, text=True)  # fmt: skip
    assert done.returncode == 0, done.stderr
    names = {v.name for v in fmpy.read_model_description(str(tmp_path / "p.fmu")).modelVariables}
    assert names == {"torque.a", "speed.b"}
