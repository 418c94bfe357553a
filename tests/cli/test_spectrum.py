"""``pinwind spectrum LOG``: the mesh frequency of a shipped model, the figure, bad input."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

import pinwind
from pinwind.errors import InputError, UnknownElement
from pinwind.io.log_spectrum import spectrum_of_log
from tests.conftest import MODELS

CARRIER_RPM = 14.2


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *args], capture_output=True, text=True, timeout=300
    )


@pytest.fixture(scope="module")
def planetary_log(tmp_path_factory) -> Path:
    """Half a second of the Saleh stage at 14.2 rpm on the carrier, logged at 1 kHz."""
    path = tmp_path_factory.mktemp("logs") / "planetary.mcap"
    gearbox = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    pinwind.simulate(
        gearbox, duration=0.5, dt=1e-3, speeds={"carrier": CARRIER_RPM * 2 * math.pi / 60},
        torques={"sun": -1.0e6 / 6.0}, log=path,
    )  # fmt: skip
    return path


def test_spectrum_lists_the_mesh_frequency_of_the_ring_teeth_and_carrier_speed(planetary_log):
    # The ring (120 teeth) is fixed: its teeth pass each planet 120 times per carrier turn.
    mesh_hz = 120 * CARRIER_RPM / 60.0
    out = run("spectrum", str(planetary_log), "--json", "--series", "mesh_normal:sun_planet1")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    (mesh,) = report["mesh_frequencies"]
    assert len(mesh["meshes"]) == 6
    assert mesh["frequency_Hz"] == pytest.approx(mesh_hz, rel=1e-9)
    shafts = {s["joint"]: s["frequency_Hz"] for s in report["shaft_frequencies"]}
    assert shafts["sun"] == pytest.approx(6 * CARRIER_RPM / 60.0, rel=1e-9)
    assert report["sample_rate_Hz"] == pytest.approx(1000.0, rel=1e-9)
    assert [s["element"] for s in report["spectra"]] == ["sun_planet1"]

    table = run("spectrum", str(planetary_log))
    assert table.returncode == 0, table.stderr
    assert f"{mesh_hz:.6g}" in table.stdout and "planet3_ring" in table.stdout


def test_spectrum_writes_the_figure(planetary_log, tmp_path):
    png = tmp_path / "psd.png"
    out = run("spectrum", str(planetary_log), "--series", "bearing_force:carrier",
              "--series", "speed:sun", "--png", str(png))  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {png}" in out.stdout.replace("\n", "")


@pytest.mark.parametrize(
    "args, message",
    [
        (["--series", "mesh_nromal"], 'unknown series "mesh_nromal"'),
        (["--segment", "2"], "a segment of 2 s is 2000 samples"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(planetary_log, args, message):
    out = run("spectrum", str(planetary_log), *args)
    assert out.returncode == 2, out.stdout
    assert message in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize(
    "options, error, message",
    [
        ({"series": ["mesh_normal:sun_planet9"]}, UnknownElement, 'no mesh named "sun_planet9"'),
        ({"segment": 0.005}, InputError, "a segment of 0.005 s is 5 samples"),
        ({"segment": -1.0}, InputError, "give a positive segment length"),
        # inf overflowed int(round(inf · rate)): an OverflowError traceback.
        ({"segment": math.inf}, InputError, "--segment inf s; give a positive segment length"),
        ({"start": 0.49}, InputError, "a segment needs 16 to 11"),
        ({"series": ["constraint_residual:sun"]}, InputError, "one value per run"),
    ],
)
def test_bad_elements_and_segments_are_refused_naming_the_fix(planetary_log, options, error,
                                                              message):  # fmt: skip
    with pytest.raises(error, match=message):
        spectrum_of_log(planetary_log, **options)


def test_rainflow_csv_holds_every_cycle_the_rainflow_package_counts_in_each_series(tmp_path):
    # The matrix only bins the cycles: per element, its cycles add up to the ASTM E1049 count of
    # the `rainflow` package on the same logged samples, and its ranges reach the largest one.
    # Compliant meshes started undeflected ring down: every mesh force has cycles.
    import csv

    import numpy as np
    import rainflow

    log = tmp_path / "compliant.mcap"
    pinwind.simulate(
        pinwind.load(MODELS / "saleh2017_planetary.urdf"), duration=0.05, dt=2e-5,
        speeds={"carrier": CARRIER_RPM * 2 * math.pi / 60}, torques={"sun": -1.0e6 / 6.0},
        meshes={"all": "compliant"}, log=log,
    )  # fmt: skip
    out_csv = tmp_path / "rf.csv"
    out = run("spectrum", str(log), "--series", "mesh_normal", "--rainflow", str(out_csv),
              "--rainflow-bins", "4")  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = list(csv.DictReader(out_csv.read_text(encoding="utf-8").splitlines()))
    res = pinwind.read_log(log)
    assert {r["element"] for r in rows} == set(res.mesh_names)
    for i, mesh in enumerate(res.mesh_names):
        mine = [r for r in rows if r["element"] == mesh]
        assert len(mine) == 4 * 4 and {r["unit"] for r in mine} == {"N"}
        cycles = list(rainflow.extract_cycles(res.mesh_normal[:, i]))
        expected = sum(count for _, _, count, _, _ in cycles)
        assert np.isclose(sum(float(r["cycles"]) for r in mine), expected, rtol=1e-12, atol=0)
        largest = max(rng for rng, _, _, _, _ in cycles)
        assert largest > 0.0
        assert np.isclose(max(float(r["range_to"]) for r in mine), largest, rtol=1e-12, atol=0)


@pytest.mark.parametrize("png", [False, True], ids=["table", "png"])
def test_a_series_of_an_element_the_run_has_none_of_is_one_line_and_no_figure(
    planetary_log, tmp_path, png
):
    """The Saleh stage runs without a generator: ``generator_torque`` printed an empty table
    (and drew an empty figure) and exited 0."""
    figure = tmp_path / "psd.png"
    out = run("spectrum", str(planetary_log), "--series", "generator_torque",
              *(["--png", str(figure)] if png else []))  # fmt: skip
    assert out.returncode == 2, out.stdout
    assert out.stderr.count("\n") == 1
    assert "--series generator_torque: the run has no generator" in out.stderr
    assert "element the run has: joint, mesh, bearing, body (docs/series.md)" in out.stderr
    assert not figure.exists()
