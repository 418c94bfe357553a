"""pinwind report: statistics of every quantity from the file alone, checked against numpy."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError
from pinwind.io.report import report_dict, report_rows
from tests.io.test_cli_log import run


def numpy_statistics(values: np.ndarray) -> dict[str, float]:
    return {
        "min": values.min(),
        "max": values.max(),
        "mean": values.mean(),
        "rms": np.sqrt(np.mean(np.square(values))),
        "final": values[-1],
    }


def expected_series(res: pinwind.Result, t0: float, t1: float) -> dict[tuple, np.ndarray]:
    """A few series cut to t0 ≤ t ≤ t1, straight from the read-back arrays."""
    rows = (res.time >= t0) & (res.time <= t1)
    sun = res.joint_names.index("sun")
    mesh = res.mesh_names.index("sun_planet1")
    carrier = res.bearing_names.index("carrier")
    return {
        ("joint", "sun", "speed", ""): res.speed[rows, sun],
        ("mesh", "sun_planet1", "normal", ""): res.mesh_normal[rows, mesh],
        ("bearing", "carrier", "force (world)", "|.|"): np.linalg.norm(
            res.bearing_force[rows, carrier], axis=1
        ),
        ("bearing", "carrier", "moment (joint frame)", "z"): res.bearing_moment_local[
            rows, carrier, 2
        ],
        ("run", "kinetic", "energy", ""): res.energy["kinetic"][rows],
    }


def test_report_statistics_equal_numpy_on_the_read_back_arrays(logged_run):
    res = pinwind.read_log(logged_run.path)
    rows = {(r.group, r.element, r.quantity, r.component): r for r in report_rows(res, 0.05, 0.2)}
    for key, values in expected_series(res, 0.05, 0.2).items():
        assert len(values) == 151
        for stat, value in numpy_statistics(values).items():
            np.testing.assert_allclose(
                getattr(rows[key], stat), value, rtol=1e-13, err_msg=str(key)
            )


def test_report_covers_every_joint_mesh_and_bearing(logged_run):
    res = pinwind.read_log(logged_run.path)
    rows = report_rows(res)
    assert {r.element for r in rows if r.group == "joint"} == set(res.joint_names)
    assert {r.element for r in rows if r.group == "mesh"} == set(res.mesh_names)
    assert {r.element for r in rows if r.group == "bearing"} == set(res.bearing_names)
    per_bearing = {
        (r.quantity, r.component) for r in rows if r.element == "carrier" and r.group == "bearing"
    }
    # force and moment, world and joint frame, x y z |.|; radial, axial, tilting, torque;
    # displacement in the bearing and elastic force, x y z |.|; friction moment and power
    assert len(per_bearing) == 16 + 4 + 8 + 2


def test_report_window_without_samples_names_the_log_span(logged_run):
    res = pinwind.read_log(logged_run.path)
    with pytest.raises(InputError, match=r"the log covers t = 0 to 0\.25 s"):
        report_dict(res, 1.0, 2.0)


def test_report_cli_json_equals_numpy_from_the_file_alone(logged_run):
    out = run("report", str(logged_run.path), "--json", "--from", "0.05", "--to", "0.2")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["window"] == {"from": 0.05, "to": 0.2, "samples": 151}
    assert data["status"] == "completed"
    rows = {
        (q["group"], q["element"], q["quantity"], q["component"]): q for q in data["quantities"]
    }
    res = pinwind.read_log(logged_run.path)
    for key, values in expected_series(res, 0.05, 0.2).items():
        for stat, value in numpy_statistics(values).items():
            np.testing.assert_allclose(rows[key][stat], value, rtol=1e-13, err_msg=str(key))


def test_report_cli_prints_tables_of_every_group(logged_run):
    out = run("report", str(logged_run.path))
    assert out.returncode == 0, out.stderr
    for title in ("Bearings (joints)", "Gear meshes", "Bearing reactions", "energy ledger"):
        assert title in out.stdout


# --- streamed reports ---------------------------------------------------------------------------


def test_streamed_report_equals_the_report_of_the_whole_read(logged_run):
    from pinwind.io.report import report, report_log

    whole = report(pinwind.read_log(logged_run.path), 0.05, 0.2)
    streamed = report_log(logged_run.path, 0.05, 0.2, block=37)
    assert (streamed.first, streamed.last, streamed.samples) == (0.05, 0.2, 151)
    assert len(streamed.rows) == len(whole.rows)
    for a, b in zip(streamed.rows, whole.rows, strict=True):
        assert (a.group, a.element, a.quantity, a.component) == (
            b.group,
            b.element,
            b.quantity,
            b.component,
        )
        assert (a.min, a.max, a.final) == (b.min, b.max, b.final)
        np.testing.assert_allclose([a.mean, a.rms], [b.mean, b.rms], rtol=1e-13, atol=1e-300)


def test_streamed_report_reads_only_its_window_one_block_at_a_time(logged_run, monkeypatch):
    from pinwind.io import log_reader, mcap_file
    from pinwind.io.report import report_log

    chunks, capacities = [], []
    read_chunk, sink = mcap_file.read_chunk, log_reader.ColumnSink

    def spy_read(fd, chunk, into=None):
        chunks.append(chunk.start_ns)
        return read_chunk(fd, chunk, into)

    def spy_sink(layout, shapes, keys, capacity):
        capacities.append(capacity)
        return sink(layout, shapes, keys, capacity)

    monkeypatch.setattr(mcap_file, "read_chunk", spy_read)
    monkeypatch.setattr(log_reader, "ColumnSink", spy_sink)
    report_log(logged_run.path, 0.12, 0.15, block=10)
    assert chunks == [100_000_000]  # the chunk of samples 100-199 only
    assert set(capacities) == {10}


def test_streamed_report_of_an_empty_window_names_the_log_span(logged_run):
    from pinwind.io.report import report_log

    with pytest.raises(InputError, match=r"the log covers t = 0 to 0\.25 s"):
        report_log(logged_run.path, 1.0, 2.0)


def test_report_cli_prints_the_units_of_simulate_in_each_row(logged_run):
    # rpm, kN and kN·m like pinwind simulate's summary; converted by hand from the SI arrays.
    out = run("report", str(logged_run.path))
    assert out.returncode == 0, out.stderr
    res = pinwind.read_log(logged_run.path)
    lines = out.stdout.splitlines()

    def row(element: str, quantity: str) -> list[str]:
        """The cells of ``quantity`` in the block headed by ``element``."""
        start = next(i for i, line in enumerate(lines) if line.split() == [element])
        return next(
            line.split() for line in lines[start + 1 :] if line.strip().startswith(quantity)
        )

    sun_speed = row("sun", "speed [rpm]")
    final_rpm = res.joint("sun").speed[-1] * 60 / (2 * np.pi)
    np.testing.assert_allclose(float(sun_speed[-1]), final_rpm, rtol=1e-5)
    normal = row("sun_planet1", "normal [kN]")
    np.testing.assert_allclose(
        float(normal[-1]), res.mesh("sun_planet1").normal[-1] / 1e3, rtol=1e-5
    )
    torque = row("carrier", "torque [kN·m]")
    np.testing.assert_allclose(float(torque[-1]), res.joint("carrier").torque[-1] / 1e3, rtol=1e-5)
    assert "[rad/s]" not in out.stdout and "[N]" not in out.stdout
    assert max(len(line) for line in lines[1:]) <= 80 and "…" not in out.stdout
