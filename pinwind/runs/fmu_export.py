"""``pinwind fmu``: a gearbox (or a scenario) as an FMI 2.0 or FMI 3.0 co-simulation unit (FMU).

FMI 2.0 units are built with PythonFMU (``pythonfmu``), FMI 3.0 units with PythonFMU3
(``pythonfmu3``): Python-side slaves (``fmu_slave``, ``fmu_slave3``) around one implementation
of the variables and the session (``fmu_unit.GearboxUnit``). The unit's binary embeds the
Python interpreter of the process that loads it, which must have pinwind installed (FMPy in
the same environment, or a tool whose Python is that environment: docs/coupling.md).

The FMU packs the model file (and the scenario file), and ``pinwind_fmu.json``: the inputs and
outputs with their units and descriptions. Each communication step is one ``Session.advance``
(``runs/session.py``): the step must be a whole number of the scenario's dt. The model
description gets the SI unit of every variable (``UnitDefinitions``: FMI 2.0 §2.2.2, written
here since PythonFMU does not; FMI 3.0 §2.4.3, written by PythonFMU3 from the slave's units).
"""

from __future__ import annotations

import importlib
import json
import shutil
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pinwind.errors import FmuExportFailed, InputError
from pinwind.runs.fmu_unit import CONFIG, FMI_UNITS, load_model
from pinwind.runs.session import Session

#: The FMI versions written: the exporter's module (and pip name), the slave's source, and its
#: module name in the FMU (one per version: the FMU's binary imports it by name into the
#: master's process, where an FMI 2.0 and an FMI 3.0 unit may both be loaded).
EXPORTERS: dict[int, tuple[str, str, str]] = {
    2: ("pythonfmu", "fmu_slave.py", "pinwind_gearbox"),
    3: ("pythonfmu3", "fmu_slave3.py", "pinwind_gearbox3"),
}

#: The slave's class (the FMU's model identifier).
SLAVE_CLASS = "PinwindGearbox"


def describe(
    model: str | Path,
    *,
    dt: float,
    duration: float,
    scenario: str | Path | None,
    inputs: Sequence[str] | None,
    outputs: Sequence[str] | None,
) -> dict[str, Any]:
    """The FMU's configuration: files, dt, duration, inputs and outputs with units (SI).

    Opens a session (prepared, one sample) to check the names against the model: an unknown
    input or output raises ``UnknownSessionName`` here, before anything is written.
    """
    gearbox, scen = load_model(model, scenario, dt=dt, duration=duration)
    if inputs is None:  # every free joint the scenario leaves without a torque or speed
        loaded = set(scen.torques) | set(scen.speeds) | set(scen.generators) | set(scen.rotors)
        inputs = [f"torque.{j}" for j in gearbox.joint_names
                  if j not in gearbox.locked_joints and j not in loaded]  # fmt: skip
    session = Session(gearbox, scen, inputs=inputs, outputs=outputs)
    available = session.available_outputs
    start = dict(session.state().start)
    session.close()
    return {
        "model": Path(model).name,
        "scenario": Path(scenario).name if scenario is not None else None,
        "dt": scen.dt,
        "duration": scen.duration,
        "inputs": {
            n: {"unit": session.input_unit(n), "start": start[n], "description": _what(n)}
            for n in session.input_names
        },  # fmt: skip
        "outputs": {
            n: {"unit": available[n], "description": _what(n)} for n in session.output_names
        },  # fmt: skip
    }


def _what(name: str) -> str:
    series, _, element = name.partition(".")
    return f"{series} of {element}" if element else series


def export_fmu(
    source: str | Path,
    out: str | Path,
    *,
    inputs: Sequence[str] | None = None,
    outputs: Sequence[str] | None = None,
    dt: float = 1e-3,
    duration: float = 3600.0,
    fmi_version: int = 2,
) -> Path:
    """Writes ``out``, an FMI 2.0 or 3.0 co-simulation FMU of a model file or a scenario file.

    Args:
        source: a model file (``.urdf``) or a scenario (``.toml``, naming its model).
        out: the FMU file to write.
        inputs: the open inputs (``Session``'s names); default a torque on every free joint the
            scenario leaves unloaded.
        outputs: the outputs; default ``Session``'s.
        dt: internal step [s] for a model file (a scenario gives its own).
        duration: the longest run [s] for a model file (a scenario gives its own; the FMI 2.0
            master's stop time, when it gives one, replaces it; FMI 3.0 units keep it, as
            PythonFMU3 does not pass the stop time on).
        fmi_version: 2 (PythonFMU) or 3 (PythonFMU3).

    Raises:
        InputError, UnknownSessionName: a bad source, input, output or FMI version.
        FmuExportFailed: the exporter is not installed or could not write the unit.
    """
    if fmi_version not in EXPORTERS:
        raise InputError(f"FMI version {fmi_version} is not written; give --fmi-version 2 or 3")
    exporter, slave, module = EXPORTERS[fmi_version]
    try:
        FmuBuilder = importlib.import_module(exporter).FmuBuilder  # noqa: N806
    except ImportError as err:
        raise FmuExportFailed(
            str(out), f"{exporter} is not installed; pip install 'pinwind[fmi]'"
        ) from err
    source = Path(source)
    if not source.is_file():
        raise InputError(f"{source} does not exist; give a model (.urdf) or scenario (.toml) file")
    scenario = source if source.suffix == ".toml" else None
    if scenario is not None:
        from pinwind.runs.scenario import load_scenario

        model = load_scenario(scenario).model_path()
    else:
        model = source
    config = describe(model, dt=dt, duration=duration, scenario=scenario, inputs=inputs,
                      outputs=outputs)  # fmt: skip
    out = Path(out)
    with tempfile.TemporaryDirectory(prefix="pinwind_fmu_") as folder:
        work = Path(folder)
        script = work / f"{module}.py"
        shutil.copy(Path(__file__).with_name(slave), script)
        files = [work / model.name]
        shutil.copy(model, files[0])
        if scenario is not None:
            files.append(work / scenario.name)
            shutil.copy(scenario, files[-1])
        files.append(work / CONFIG)
        files[-1].write_text(json.dumps(config, indent=1))
        # fmi2GetFMUstate/SetFMUstate (fmi3GetFMUState/SetFMUState): the session's compiled
        # state (fmu_unit); not serializable (a copy in memory of the compiled run's). Any
        # communication step of whole dt's (PythonFMU3 0.3.4 writes the FMI 3 flag as
        # canSerializeFMUState's value unless given).
        options: dict[str, bool] = (
            {"canGetAndSetFMUstate": True}
            if fmi_version == 2
            else {"canGetAndSetFMUState": True, "canHandleVariableCommunicationStepSize": True}
        )
        try:  # PythonFMU3 names the file after the model identifier: built in a folder, moved
            built = FmuBuilder.build_FMU(script, dest=work / "built", project_files=files,
                                         **options)  # fmt: skip
            out.parent.mkdir(parents=True, exist_ok=True)
            shutil.move(built, out)
        except Exception as err:
            raise FmuExportFailed(str(out), f"{exporter}: {type(err).__name__}: {err}") from err
    if fmi_version == 2:
        _add_units(out, config)
    return out


def _add_units(fmu: Path, config: Mapping[str, Any]) -> None:
    """Writes the variables' units into the FMU's modelDescription.xml (and UnitDefinitions)."""
    with zipfile.ZipFile(fmu) as z:
        entries = {i.filename: z.read(i.filename) for i in z.infolist()}
    root = ET.fromstring(entries["modelDescription.xml"])
    units = {**config["inputs"], **config["outputs"]}
    used: dict[str, dict[str, int]] = {}
    for var in root.iter("ScalarVariable"):
        spec = units.get(var.get("name"))
        real = var.find("Real")
        if spec is None or real is None or spec["unit"] not in FMI_UNITS:
            continue
        name, base = FMI_UNITS[spec["unit"]]
        real.set("unit", name)
        used[name] = base
    definitions = ET.Element("UnitDefinitions")
    for name, base in used.items():
        unit = ET.SubElement(definitions, "Unit", {"name": name})
        ET.SubElement(unit, "BaseUnit", {k: str(v) for k, v in base.items()})
    children = list(root)
    at = next(i for i, c in enumerate(children) if c.tag == "CoSimulation") + 1
    root.insert(at, definitions)
    # FMI 2.0 §2.2.8: every output with initial "calculated" is an initial unknown
    structure = root.find("ModelStructure")
    outputs = structure.find("Outputs") if structure is not None else None
    if structure is not None and outputs is not None:
        initial = ET.SubElement(structure, "InitialUnknowns")
        for unknown in outputs:
            ET.SubElement(initial, "Unknown", {"index": unknown.get("index", "")})
    entries["modelDescription.xml"] = ET.tostring(root, encoding="UTF-8", xml_declaration=True)
    with zipfile.ZipFile(fmu, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in entries.items():
            z.writestr(name, data)
