"""Plot panels: y ranges that do not magnify rounding, absolute speeds, the energy residual."""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.io.panels import RANGE_FLOOR, RANGE_MARGIN, absolute_speeds, energy_residual, y_range

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


def test_legend_room_is_added_above_the_data_only():
    low, high = y_range(np.linspace(0.0, 10.0, 5), legend_room=0.5)
    np.testing.assert_allclose([low, high], [-0.8, 10 + 0.8 + 5.0], rtol=1e-12)


def test_absolute_planet_speed_is_its_carrier_relative_speed_plus_the_carriers(logged_run):
    res = logged_run.result
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


def test_panels_of_blocks_join_into_the_panels_of_the_whole_run(logged_run):
    from pinwind.io.log_reader import LogReader
    from pinwind.io.panels import model_of_log, panels
    from pinwind.io.replay import _log_file

    with LogReader(logged_run.path) as reader:
        gearbox, joints = model_of_log(_log_file(reader, None))
        model = reader.metadata["pinwind.model"]
        whole = panels(reader.read(), model, joints=joints, gearbox=gearbox, keep_zero=True)
        blocks = list(reader.blocks(60))  # 251 samples: 60, 60, 60, 60, 11
    start = {k: float(v[0]) for k, v in blocks[0].energy.items()}
    parts = [
        panels(b, model, joints=joints, gearbox=gearbox, energy_start=start, keep_zero=True)
        for b in blocks
    ]
    for p, panel in enumerate(whole):
        for s, series in enumerate(panel.series):
            joined = np.concatenate([part[p].series[s].values for part in parts])
            # The residual counts energy changes from the run's first sample in every block;
            # per-sample quantities are the same sample for sample.
            np.testing.assert_array_equal(
                joined, series.values, err_msg=f"{panel.key} {series.name}"
            )
    # The rigid run has no deflection: kept as zero series for streaming, dropped otherwise.
    assert any(p.key == "mesh_deflection" for p in whole)
    assert not any(p.key == "mesh_deflection" for p in panels(blocks[0], model, joints=joints))
