"""Plot panels: y ranges, legends off the data, absolute speeds, the energy residual, the
generator and rotor series."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.io.log_reader import open_log
from pinwind.io.panels import (
    LEGEND_CORNERS,
    LEGEND_ENTRY_PX,
    LEGEND_ROOM_CAP,
    PLOT_HEIGHT_PX,
    RANGE_FLOOR,
    RANGE_MARGIN,
    Panel,
    Series,
    absolute_speeds,
    energy_residual,
    legend_layout,
    log_panels,
    y_range,
)
from tests.io.conftest import ROTOR_RADIUS, TORQUES, WIND

#: A planet mesh force of the Saleh stage at rated torque [kN], with float rounding on top.
RATED_KN = 339.512


def test_constant_force_with_rounding_noise_is_drawn_flat():
    rng = np.random.default_rng(11)
    planets = [RATED_KN + rng.uniform(-2e-5, 2e-5, 2000) for _ in range(3)]
    low, high = y_range(planets)
    # The span is at least 5 % of the value: 4e-5 kN of noise is < 1e-5 of the height.
    assert high - low >= RANGE_FLOOR * RATED_KN
    assert (np.ptp(np.concatenate(planets))) / (high - low) < 1e-5
    assert low < RATED_KN < high


def test_all_zero_data_get_a_unit_range_around_zero():
    assert y_range(np.zeros(50)) == pytest.approx((-0.5 - 0.08, 0.5 + 0.08), abs=1e-12)


def test_varying_data_fill_the_axis_up_to_the_margins():
    low, high = y_range(np.linspace(-20.0, 100.0, 7))
    np.testing.assert_allclose([low, high], [-20 - 9.6, 100 + 9.6], rtol=1e-12)
    assert RANGE_MARGIN == 0.08


def test_a_residual_gets_its_floor_from_the_reference_not_from_itself():
    residual = 1e-9 * np.sin(np.linspace(0, 6, 100))  # kJ of rounding in a 1e4 kJ ledger
    low, high = y_range(residual, reference=1e4)
    assert high - low >= RANGE_FLOOR * 1e4


def panel_of(*values: np.ndarray) -> Panel:
    """A panel with one series per array, named s0, s1, …"""
    return Panel("p", "speeds", "p [-]", "-", [Series(f"s{i}", v, (0, 0, 0)) for i, v in
                                               enumerate(values)])  # fmt: skip


def legend_clearance(panel: Panel, corner: str, limits: tuple[float, float]) -> float:
    """How far [panel unit] the data under the legend's width stay off its box (< 0: overlap).

    The box: (entries + ½) entries of 23 px in a 300 px plot, from the top or bottom of the axis;
    it spans the first or last samples, here a quarter of the run (wider than any legend of the
    short names used, which the layout estimates at ≤ 12 %).
    """
    low, high = limits
    box = (len(panel.series) + 0.5) * 23.0 / 300.0 * (high - low)
    quarter = [s.values[: len(s.values) // 4] if corner.startswith("Left")
               else s.values[-(len(s.values) // 4):] for s in panel.series]  # fmt: skip
    under = np.concatenate(quarter)
    if corner.endswith("Top"):
        return (high - box) - under.max()
    return under.min() - (low + box)


def test_legend_goes_above_rising_data_without_widening_the_range():
    panel = panel_of(np.linspace(0.0, 10.0, 200), np.linspace(-1.0, 4.0, 200))
    corner, limits = legend_layout(panel)
    assert corner == "LeftTop"
    assert limits == panel.y_range()
    assert legend_clearance(panel, corner, limits) > 0.0


def test_legend_moves_right_of_falling_data():
    panel = panel_of(np.linspace(10.0, 0.0, 200), np.linspace(4.0, -1.0, 200))
    corner, limits = legend_layout(panel)
    assert corner == "RightTop"
    assert limits == panel.y_range()
    assert legend_clearance(panel, corner, limits) > 0.0


def test_legend_over_flat_data_gets_room_that_keeps_it_off_them():
    panel = panel_of(np.full(100, 10.0), np.full(100, 2.0))
    corner, limits = legend_layout(panel)
    assert corner in LEGEND_CORNERS
    low, high = panel.y_range()
    assert limits[0] <= low and high <= limits[1]
    # Clear of the data by the range margin (8 % of the data span, 10 − 2) or more.
    assert legend_clearance(panel, corner, limits) >= RANGE_MARGIN * 8.0 * (1 - 1e-9)


def test_eight_flat_series_keep_most_of_the_height():
    # The drivetrain speeds: 8 series, none leaving a corner free. The old rule gave the legend
    # (8 + ½) · 23 / 300 = 65 % of the height and squeezed the data into the lower third.
    panel = panel_of(*(np.full(100, 10.0 * k) for k in range(8)))
    assert (8 + 0.5) * LEGEND_ENTRY_PX / PLOT_HEIGHT_PX > 0.6
    corner, limits = legend_layout(panel)
    low, high = panel.y_range()
    assert (high - low) / (limits[1] - limits[0]) >= 1.0 - LEGEND_ROOM_CAP - 1e-12
    assert (high - low) / (limits[1] - limits[0]) < 1.0  # still some room


def test_legend_room_is_taken_in_the_corner_the_data_leave_free():
    # Seven flat series near zero and one rising from 0 to 70: the top left is free.
    panel = panel_of(np.linspace(0.0, 70.0, 400), *(np.full(400, 0.5 * k) for k in range(7)))
    corner, limits = legend_layout(panel)
    assert corner == "LeftTop"
    assert legend_clearance(panel, corner, limits) > 0.0
    assert limits == panel.y_range()


@pytest.mark.parametrize("source", ["simulated", "read back (poses at 100 Hz)"])
def test_absolute_planet_speed_is_its_carrier_relative_speed_plus_the_carriers(logged_run, source):
    # at every sample, also those between the logged poses (every 10th sample)
    res = logged_run.result if source == "simulated" else pinwind.read_log(logged_run.path)
    assert len(res.pose_rows) == (len(res) if source == "simulated" else 26)
    joints = {
        "carrier": {"parent": "housing", "child": "carrier", "axis": [0, 0, 1]},
        "planet1": {"parent": "carrier", "child": "planet1", "axis": [0, 0, 1]},
        "sun": {"parent": "housing", "child": "sun", "axis": [0, 0, 1]},
    }
    absolute = absolute_speeds(res, joints)
    carrier, planet = res.joint("carrier").speed, res.joint("planet1").speed
    np.testing.assert_allclose(absolute["planet1"], planet + carrier, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(absolute["sun"], res.joint("sun").speed, rtol=1e-9, atol=1e-12)


def test_energy_residual_of_a_rigid_run_is_rounding_of_the_ledger(logged_run):
    energy = logged_run.result.energy
    scale = np.max(np.abs(energy["work_applied"]))
    assert np.max(np.abs(energy_residual(energy))) < 1e-6 * scale


def whole_and_blocks(path, size: int):
    """The panels of a log read whole, and those of its blocks of ``size`` samples."""
    from pinwind.io.log_reader import LogReader
    from pinwind.io.panels import model_of_log, panels

    with LogReader(path) as reader:
        gearbox, joints = model_of_log(reader)
        model = reader.metadata["pinwind.model"]
        whole = panels(reader.read(), model, joints=joints, gearbox=gearbox, keep_zero=True)
        blocks = list(reader.blocks(size))
    start = {k: float(v[0]) for k, v in blocks[0].energy.items()}
    parts = [
        panels(b, model, joints=joints, gearbox=gearbox, energy_start=start, keep_zero=True)
        for b in blocks
    ]
    return whole, parts, blocks, (model, joints)


def assert_blocks_join(whole, parts):
    for p, panel in enumerate(whole):
        assert [part[p].key for part in parts] == [panel.key] * len(parts)
        for s, series in enumerate(panel.series):
            joined = np.concatenate([part[p].series[s].values for part in parts])
            # The residual counts energy changes from the run's first sample in every block;
            # per-sample quantities are the same sample for sample.
            np.testing.assert_array_equal(
                joined, series.values, err_msg=f"{panel.key} {series.name}"
            )


def test_panels_of_blocks_join_into_the_panels_of_the_whole_run(logged_run):
    from pinwind.io.panels import panels

    whole, parts, blocks, (model, joints) = whole_and_blocks(logged_run.path, 60)
    assert len(blocks) == 5  # 251 samples: 60, 60, 60, 60, 11
    assert_blocks_join(whole, parts)
    # The rigid run has no deflection: kept as zero series for streaming, dropped otherwise.
    assert any(p.key == "mesh_deflection" for p in whole)
    assert not any(p.key == "mesh_deflection" for p in panels(blocks[0], model, joints=joints))


def test_generator_and_rotor_panels_of_blocks_join_into_the_whole_run(rotor_run):
    whole, parts, blocks, _ = whole_and_blocks(rotor_run.path, 70)
    assert len(blocks) == 3  # 201 samples: 70, 70, 61
    assert {"generator_torque", "rotor_power", "rotor_power_coefficient"} <= {p.key for p in whole}
    assert_blocks_join(whole, parts)


def test_generator_and_rotor_panels_carry_the_runs_series_in_plot_units(rotor_run):
    res = rotor_run.result
    shown = {p.key: p for p in log_panels(open_log(rotor_run.path))}
    expected = {  # key → (group, unit, values in the plotted unit)
        "generator_torque": ("torques and power", "kN·m", res.generator("b").torque / 1000.0),
        "rotor_torque": ("torques and power", "kN·m", res.rotor("a").torque / 1000.0),
        "rotor_power": ("torques and power", "kW", res.rotor("a").power / 1000.0),
        "rotor_wind_speed": ("rotor", "m/s", res.rotor("a").wind_speed),
        "rotor_tip_speed_ratio": ("rotor", "-", res.rotor("a").tip_speed_ratio),
        "rotor_power_coefficient": ("rotor", "-", res.rotor("a").power_coefficient),
    }
    for key, (group, unit, values) in expected.items():
        panel = shown[key]
        assert (panel.group, panel.unit) == (group, unit), key
        assert panel.title.endswith(f"[{unit}]"), panel.title
        assert [s.name for s in panel.series] == (["b"] if key.startswith("generator") else ["a"])
        np.testing.assert_allclose(panel.series[0].values, values, rtol=1e-15, atol=0, err_msg=key)
    # The series are the run's physics: the wind is the sine asked for, λ = ω R / v on shaft a.
    wind = WIND.mean + WIND.amplitude * np.sin(2 * math.pi * WIND.frequency * res.time)
    np.testing.assert_allclose(shown["rotor_wind_speed"].series[0].values, wind, rtol=1e-12)
    tsr = res.joint("a").speed * ROTOR_RADIUS / wind
    np.testing.assert_allclose(shown["rotor_tip_speed_ratio"].series[0].values, tsr, rtol=1e-9)
    # Colours: the body each element turns, as in the speed panel.
    speed = {s.name: s.color for s in shown["speed"].series}
    assert shown["generator_torque"].series[0].color == speed["b"]
    assert shown["rotor_power"].series[0].color == speed["a"]


def test_a_run_without_generator_or_rotor_has_no_such_panels(logged_run):
    keys = {p.key for p in log_panels(open_log(logged_run.path))}
    assert not {k for k in keys if k.startswith(("generator", "rotor"))}
    assert "speed" in keys and "torque" in keys


def test_bearing_panels_show_radial_force_and_the_shaft_torque_apart(logged_run, planetary):
    # Equal planets 120° apart: their mesh forces cancel on the carrier's subtree, whose bearing
    # holds the weight of carrier and planets across its axis; along the axis it passes the
    # torque applied to the carrier (1 MN·m with its ripple), the shaft's, not a bearing load.
    # Spur teeth: no axial force, no tilting moment, so those panels are left out.
    found = {p.key: p for p in log_panels(open_log(logged_run.path)) if p.group == "bearings"}
    assert {"bearing_radial", "bearing_torque"} <= set(found)
    assert "bearing_axial" not in found and "bearing_tilting" not in found
    # The loads about the axis first, the world-axis |F| after; no world-axis |M|, which would
    # show the shaft's torque (1 MN·m on the carrier) as a moment the bearing carries.
    assert list(found) == ["bearing_radial", "bearing_torque", "bearing_force"]
    model = planetary.model
    subtree = model.subtrees[model.getJointId("carrier")]
    weight = sum(model.inertias[j].mass for j in subtree) * np.linalg.norm(model.gravity.linear)
    radial = {s.name: s.values for s in found["bearing_radial"].series}
    torque = {s.name: s.values for s in found["bearing_torque"].series}
    np.testing.assert_allclose(radial["carrier"], weight / 1e3, rtol=1e-9)
    applied = [TORQUES["carrier"](t) for t in logged_run.result.time]
    np.testing.assert_allclose(torque["carrier"], np.array(applied) / 1e3, rtol=1e-9)
    np.testing.assert_allclose(torque["planet1"], 0.0, atol=1e-9)
