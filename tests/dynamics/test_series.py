"""The schema of series: a series declared once is in every consumer; the list is one list."""

from __future__ import annotations

import csv
import io
import pickle

import numpy as np
import pytest
from rich.console import Console

import pinwind
from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.dynamics import _native, series
from pinwind.dynamics.series import Plot, Series
from pinwind.io.export import export_log
from pinwind.io.log_channels import CHANNELS
from pinwind.io.log_reader import open_log
from pinwind.io.panels import log_panels
from pinwind.io.report import report_log, report_tables
from tests.conftest import MODELS

#: Saleh 2017's planetary stage at its rated point: carrier 1 MN·m, 3 planets, r_sun 0.18 m
#: (module 15 mm × 24 teeth / 2), face width 0.38 m.
CARRIER_TORQUE = 1e6
SUN_TORQUE = -CARRIER_TORQUE / 6.0
PLANETS, SUN_RADIUS, FACE_WIDTH = 3, 0.015 * 24 / 2, 0.38


def line_load(block, gearbox) -> np.ndarray:
    """ISO 6336's line load w = F_t / b of every mesh [N/m]."""
    widths = np.array([m.face_width for m in gearbox.meshes])
    return block.mesh_tangential / widths


@pytest.fixture
def with_line_load():
    """The line load declared as a mesh series for the test, withdrawn after."""
    declared = series.declare(
        Series(
            "mesh_line_load",
            "mesh",
            "line_load",
            "N/m",
            "line load w = F_t / b",
            plot=Plot(
                "line_load", "force components", "line load w = F_t / b [kN/m]", "kN/m"
            ),  # fmt: skip
            derive=line_load,
        )
    )
    yield declared
    series.withdraw(declared.name)


@pytest.fixture
def rated_run(with_line_load, tmp_path):
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    path = tmp_path / "rated.mcap"
    res = pinwind.simulate(
        gb,
        duration=0.05,
        dt=1e-3,
        torques={"carrier": CARRIER_TORQUE, "sun": SUN_TORQUE},
        initial_speeds={"carrier": 14.2 * 2 * np.pi / 60},
        log=path,
    )
    return gb, res, path


def test_a_declared_series_is_in_the_result_with_its_closed_form_value(rated_run):
    gb, res, _ = rated_run
    # each sun mesh carries F_t = T_sun / (N r_sun) at the rated, steady point
    expected = -SUN_TORQUE / (PLANETS * SUN_RADIUS) / FACE_WIDTH
    for name in ("sun_planet1", "sun_planet2", "sun_planet3"):
        np.testing.assert_allclose(res.mesh(name).line_load, expected, rtol=1e-9)
    assert res.mesh_line_load.shape == (len(res), len(gb.meshes))


def test_a_declared_series_is_logged_on_its_own_channel_and_read_back_bit_for_bit(rated_run):
    _, res, path = rated_run
    assert CHANNELS["/meshes/line_load"] == ("mesh_line_load",)
    back = pinwind.read_log(path)
    np.testing.assert_array_equal(back.mesh_line_load, res.mesh_line_load)
    just = pinwind.read_log(path, channels="/meshes/line_load")
    np.testing.assert_array_equal(just.mesh("sun_planet2").line_load, res.mesh_line_load[:, 1])


def test_a_declared_series_is_in_the_report_and_the_run_statistics(rated_run):
    _, res, path = rated_run
    row = RunningStatistics.of(res).row("mesh", "sun_planet1", "line load")
    values = res.mesh("sun_planet1").line_load
    assert row.unit == "N/m"
    np.testing.assert_allclose([row.min, row.max], [values.min(), values.max()], rtol=0)
    rows = [r for r in report_log(path).rows if r.quantity == "line load"]
    assert len(rows) == len(res.mesh_names)
    console = Console(file=io.StringIO(), width=80)
    for table in report_tables(report_log(path), plain=True):
        console.print(table)
    assert "line load" in console.file.getvalue()


def test_a_declared_series_is_in_the_export_and_a_plot_panel(rated_run, tmp_path):
    _, res, path = rated_run
    out = tmp_path / "run.csv"
    export_log(path, out)
    with open(out, newline="") as f:
        table = list(csv.DictReader(f))
    column = [float(r["mesh/sun_planet3/line_load_N_m"]) for r in table]
    np.testing.assert_array_equal(column, res.mesh("sun_planet3").line_load)
    panel = {p.key: p for p in log_panels(open_log(path))}["line_load"]
    assert panel.unit == "kN/m" and [s.name for s in panel.series] == res.mesh_names
    np.testing.assert_allclose(panel.series[0].values, res.mesh_line_load[:, 0] / 1e3, rtol=1e-15)


def test_the_compiled_step_writes_exactly_the_series_declared_without_derive():
    compiled = {m.name for m in _native.Series}
    ledger = {t.name for t in series.ENERGY_TERMS} - {"numerical"}  # numerical: Python's
    assert {s.name for s in series.compiled()} == compiled - ledger
    for s in series.compiled():
        family, components = _native.series_layout(getattr(_native.Series, s.name))
        assert (family.name, components) == (s.family, s.width), s.name
    for term in ledger:
        assert _native.series_layout(getattr(_native.Series, term)) == (_native.Family.run, 1)


def test_a_series_declared_twice_or_without_derive_is_refused():
    with pytest.raises(ValueError, match="already declared"):
        series.declare(Series("mesh_normal", "mesh", "normal", "N", "again", derive=line_load))
    with pytest.raises(ValueError, match="give derive="):
        series.declare(Series("mesh_extra", "mesh", "extra", "N", "no derive"))


def test_a_compliant_runs_mesh_series_are_in_the_export_and_the_report(tmp_path):
    # The compliant mesh's own series (deflection, contact position, pairs, single-tooth
    # force) reach the export and the report like every other one; they used to be dropped.
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    path = tmp_path / "compliant.mcap"
    res = pinwind.simulate(
        gb,
        duration=0.004,
        dt=2e-5,
        torques={"carrier": CARRIER_TORQUE, "sun": SUN_TORQUE},
        meshes={"all": "compliant"},
        log=path,
    )
    mesh = res.mesh("sun_planet1")
    assert np.ptp(mesh.deflection) > 0 and set(np.unique(mesh.pairs)) <= {1.0, 2.0}
    out = tmp_path / "compliant.csv"
    export_log(path, out)
    with open(out, newline="") as f:
        table = list(csv.DictReader(f))
    for quantity, unit, values in (
        ("deflection", "_m", mesh.deflection),
        ("contact_position", "_m", mesh.contact_position),
        ("pairs", "", mesh.pairs),
        ("single_tooth_force", "_N", mesh.single_tooth_force),
    ):
        column = [float(r[f"mesh/sun_planet1/{quantity}{unit}"]) for r in table]
        np.testing.assert_array_equal(column, values, err_msg=quantity)
    rows = {r.quantity: r for r in report_log(path).rows if r.element == "sun_planet1"}
    for quantity, values in (
        ("deflection", mesh.deflection),
        ("contact position", mesh.contact_position),
        ("pairs", mesh.pairs),
        ("single tooth force", mesh.single_tooth_force),
    ):
        np.testing.assert_allclose(
            [rows[quantity].min, rows[quantity].max], [values.min(), values.max()], rtol=0
        )


def test_the_compiled_series_are_the_compiled_tables_in_its_order_with_its_layout():
    # The names, order, families and components come from _native.Series alone (cpp/series.hpp):
    # series.py repeats none of them.
    ledger = {t.name for t in series.ENERGY_TERMS}
    table = [m for m in _native.Series if m.name not in ledger]
    assert [s.name for s in series.compiled()] == [m.name for m in table]
    widths = {"": 1, "xyz": 3, "xyzw": 4}
    for s, member in zip(series.compiled(), table, strict=True):
        family, components = _native.series_layout(member)
        assert (s.family, widths[s.components]) == (family.name, components), s.name


def test_every_compiled_series_has_one_meaning_and_every_meaning_a_compiled_series():
    ledger = {t.name for t in series.ENERGY_TERMS}
    assert set(series._MEANINGS) == {m.name for m in _native.Series} - ledger


def test_a_schema_cannot_be_changed_in_place():
    schema = series.current()
    names = schema.names
    with pytest.raises(AttributeError, match="immutable"):
        schema._series = ()  # type: ignore[misc]
    with pytest.raises(TypeError):
        schema["mesh_extra"] = schema["mesh_normal"]  # type: ignore[index]
    extra = Series(
        "mesh_twice", "mesh", "twice", "N", "2 F_n", derive=lambda b, g: 2 * b.mesh_normal
    )
    grown = schema.with_series(extra)
    assert schema.names == names and "mesh_twice" not in schema
    assert grown.names == (*names, "mesh_twice")
    assert grown.without("mesh_twice").names == names


def test_a_schema_survives_a_pickle_round_trip_with_its_series_in_order():
    # A Result sent back by a sweep's worker process holds its schema.
    again = pickle.loads(pickle.dumps(series.BUILT_IN))
    assert again.series == series.BUILT_IN.series and again.names == series.BUILT_IN.names


def test_a_run_keeps_the_schema_of_its_start_whatever_is_declared_while_it_runs():
    class DeclaresOnBegin:
        """An observer that declares a series when the run begins (after the run's start)."""

        def begin(self, gearbox, result):
            series.declare(
                Series("mesh_late", "mesh", "late", "N", "declared mid-run", derive=line_load)
            )

        def samples(self, block, start):
            assert "mesh_late" not in block.ARRAYS  # every block has the start's series

        def end(self, result, status):
            pass

    before = series.current()
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    try:
        res = pinwind.simulate(
            gb, duration=0.01, dt=1e-3, torques={"carrier": CARRIER_TORQUE, "sun": SUN_TORQUE},
            observer=DeclaresOnBegin(),
        )  # fmt: skip
        assert "mesh_late" in series.current()
    finally:
        if "mesh_late" in series.current():  # not declared if the run failed before its begin
            series.withdraw("mesh_late")
    assert res.schema is before
    assert list(res.ARRAYS) == list(before.names) and not hasattr(res, "mesh_late")
    assert series.current().names == before.names
