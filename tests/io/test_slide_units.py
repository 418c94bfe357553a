"""A compliant bearing's slides in the log, export, report and plots: metres and newtons.

The disc of ``tests/dynamics/test_compliant_bearing.py`` (10 kg, radial stiffness 1e6 N/m,
gravity −y) starts at its static sag: its bearing's axis is z, so that its radial slides run
along the joint frame's x and y (``model/gearbox._radial_axes``), and the y slide sits at
−m g / k for the whole run.
"""

from __future__ import annotations

import csv
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from rich.console import Console

import pinwind
from pinwind.analysis.summary import summary_tables
from pinwind.errors import PinwindWarning
from pinwind.io import log_writer
from pinwind.io.export import columns, export_log
from pinwind.io.log_model import model_names
from pinwind.io.log_reader import open_log
from pinwind.io.panels import log_panels
from pinwind.io.report import report_dict, report_tables
from pinwind.model.gearbox import loads
from tests.dynamics.test_compliant_bearing import MASS, STIFFNESS, G, disc_urdf
from tests.io.test_cli_log import run

SAG = MASS * G / STIFFNESS  # static sag of the disc on its radial springs [m]
JOINT_SUFFIXES = {
    "revolute": ("angle_rad", "speed_rad_s", "acceleration_rad_s2", "torque_N_m"),
    "prismatic": ("angle_m", "speed_m_s", "acceleration_m_s2", "torque_N"),
}


@dataclass
class DiscRun:
    result: pinwind.Result
    path: Path
    model: Path


def _simulate(gearbox, path: Path) -> pinwind.Result:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gearbox, duration=0.01, dt=1e-3, log=path)


@pytest.fixture(scope="module")
def disc_run(tmp_path_factory) -> DiscRun:
    folder = tmp_path_factory.mktemp("disc")
    model = folder / "disc.urdf"
    model.write_text(disc_urdf(f'radial_stiffness="{STIFFNESS!r}"'))
    path = folder / "disc.mcap"
    return DiscRun(_simulate(loads(model.read_text(), str(model)), path), path, model)


def _header(path: Path) -> list[str]:
    with open(path, newline="", encoding="utf-8") as f:
        return next(csv.reader(f))


def _csv(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    values = np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(rows[0])}


def test_a_slides_exported_columns_are_in_metres_and_newtons_the_bearings_in_radians(
    disc_run, tmp_path
):
    out = tmp_path / "disc.csv"
    export_log(disc_run.path, out)
    header = _header(out)
    for joint, kind in (
        ("disc_radial_x", "prismatic"),
        ("disc_radial_y", "prismatic"),
        ("disc", "revolute"),
    ):
        got = [c.removeprefix(f"joint/{joint}/") for c in header if c.startswith(f"joint/{joint}/")]
        assert got == list(JOINT_SUFFIXES[kind]), joint


def test_a_slides_exported_displacement_is_the_static_sag_m_g_over_k_in_metres(disc_run, tmp_path):
    out = tmp_path / "disc.csv"
    export_log(disc_run.path, out)
    table = _csv(out)
    np.testing.assert_allclose(table["joint/disc_radial_y/angle_m"], -SAG, rtol=1e-9)
    np.testing.assert_allclose(table["joint/disc_radial_x/angle_m"], 0.0, atol=1e-12 * SAG)
    # the spring force m g is the bearing's, not a force from outside the train on the slide
    np.testing.assert_allclose(table["joint/disc_radial_y/torque_N"], 0.0, atol=1e-9 * MASS * G)


def test_the_log_and_the_run_it_wrote_export_the_same_column_names(disc_run, tmp_path):
    out = tmp_path / "disc.csv"
    result = run("export", str(disc_run.path), "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert _header(out) == [name for name, _ in columns(disc_run.result)]
    assert pinwind.read_log(disc_run.path).joint_kinds == disc_run.result.joint_kinds


def test_a_log_that_records_no_joint_kinds_reads_as_all_revolute(disc_run, tmp_path, monkeypatch):
    def without_kinds(result):
        names = model_names(result)
        del names["joint_kinds"]
        return names

    monkeypatch.setattr(log_writer, "model_names", without_kinds)
    path = tmp_path / "old.mcap"
    _simulate(loads(disc_run.model.read_text(), str(disc_run.model)), path)
    res = pinwind.read_log(path)
    assert res.joint_kinds == ["revolute"] * len(res.joint_names)
    names = [name for name, _ in columns(res)]
    assert "joint/disc_radial_y/angle_rad" in names


def test_the_report_gives_a_slides_displacement_in_metres_and_prints_it_in_micrometres(disc_run):
    res = pinwind.read_log(disc_run.path)
    rows = {
        (r["element"], r["quantity"]): r
        for r in report_dict(res)["quantities"]
        if r["group"] == "joint"
    }
    assert rows["disc_radial_y", "angle"]["unit"] == "m"
    assert rows["disc_radial_y", "speed"]["unit"] == "m/s"
    assert rows["disc_radial_y", "torque"]["unit"] == "N"
    assert rows["disc", "torque"]["unit"] == "N*m"
    np.testing.assert_allclose(rows["disc_radial_y", "angle"]["mean"], -SAG, rtol=1e-9)
    console = Console(width=80, record=True)
    for table in report_tables(res, plain=True, all_rows=True):
        console.print(table)
    rows_of: dict[str, list[str]] = {}  # element → its rows in the joints' table
    element = ""
    for line in console.export_text().split(" Bearing reactions")[0].splitlines():
        if line.startswith("disc"):
            element = line.split()[0]
        elif element and line.startswith("  "):
            rows_of.setdefault(element, []).append(line)
    slide = "\n".join(rows_of["disc_radial_y"])
    assert "angle [µm]" in slide and "torque [kN]" in slide and "[rpm]" not in slide
    assert "torque [kN·m]" in "\n".join(rows_of["disc"])
    row = next(line for line in rows_of["disc_radial_y"] if "angle [µm]" in line)
    np.testing.assert_allclose(float(row.split()[2]), -SAG * 1e6, rtol=1e-5)


def test_the_speed_and_torque_panels_in_rpm_and_kn_m_have_no_slide(disc_run):
    found = {p.key: [s.name for s in p.series] for p in log_panels(open_log(disc_run.path))}
    assert found["speed"] == ["disc"]
    assert found["torque"] == ["disc"]
    assert found.get("body_speed", ["disc"]) == ["disc"]


def test_a_slides_accessor_names_its_units_metres_and_newtons(disc_run):
    slide, bearing = disc_run.result.joint("disc_radial_y"), disc_run.result.joint("disc")
    assert slide.units == {"angle": "m", "speed": "m/s", "acceleration": "m/s^2", "torque": "N"}
    assert bearing.units["speed"] == "rad/s" and bearing.units["torque"] == "N*m"


def test_the_run_summary_lists_the_slides_apart_with_the_sag_in_micrometres(disc_run):
    joints, slides = summary_tables(disc_run.result, plain=True)[:2]
    assert joints.columns[0]._cells == ["disc"]
    assert str(slides.columns[1].header) == "displacement [µm]"
    sag = dict(zip(slides.columns[0]._cells, slides.columns[1]._cells, strict=True))
    np.testing.assert_allclose(float(sag["disc_radial_y"]), -SAG * 1e6, rtol=1e-6)
    np.testing.assert_allclose(float(sag["disc_radial_x"]), 0.0, atol=1e-4)
