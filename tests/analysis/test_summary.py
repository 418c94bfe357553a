"""The summary tables of ``pinwind simulate``: speed ratios, and bearing loads about the axis."""

from __future__ import annotations

import io
import warnings

import numpy as np

import pinwind
from pinwind.analysis.summary import summary_tables
from pinwind.loads.generator import LinearSlip
from pinwind.loads.rotor import Rotor
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, two_gear_urdf
from tests.dynamics.test_tilted_bearing import tilted_shaft_urdf


def test_ratio_column_of_a_rotor_and_generator_run_is_the_tooth_ratio():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the pair's inertias are not steel discs
        pair = loads(two_gear_urdf(), path="pair.urdf")
    # No speed or torque load: a rotor on a in a 10 m/s wind, a generator on b.
    res = pinwind.simulate(
        pair,
        duration=0.02,
        dt=1e-3,
        initial_speeds={"a": 1.5},
        rotors={"a": Rotor(radius=1.0)},
        wind=10.0,
        generators={"b": LinearSlip(slope=0.01, sync_speed=-3.0)},
        progress=False,
    )
    table = summary_tables(res, plain=True)[0]
    header = table.columns[2].header
    assert "ratio to a" in str(header)
    ratios = dict(zip(table.columns[0]._cells, table.columns[2]._cells, strict=True))
    # External pair of 20 and 40 teeth: b turns at −20/40 of a.
    np.testing.assert_allclose(float(ratios["b"]), -20 / 40, rtol=1e-5)
    np.testing.assert_allclose(float(ratios["a"]), 1.0, rtol=1e-12)


#: A shaft on a bearing tilted by these roll, pitch, yaw [rad], its axis its own z; its centre of
#: mass on the axis, OFFSET from the bearing centre; spun up by TORQUE about its axis.
TILT_RPY = (0.3, 0.5, 0.2)
SHAFT_MASS = 5000.0  # [kg]
OFFSET = 0.4  # [m]
TORQUE = 2500.0  # [N·m]
G = 9.81  # [m/s²], along −z of the world

TILTED_SHAFT = tilted_shaft_urdf(SHAFT_MASS, OFFSET, TILT_RPY, inertia=(200.0, 200.0, 100.0))


def _table_titled(tables, start: str) -> dict[str, list[float]]:
    """Element → the numbers of its row in the table whose title starts with ``start``."""
    (table,) = [t for t in tables if str(t.title).startswith(start)]
    cells = [column._cells for column in table.columns]
    return {row[0]: [float(c) for c in row[1:]] for row in zip(*cells, strict=True)}


def test_tilted_shafts_bearing_reads_its_weight_radially_and_axially_and_its_torque_apart():
    # Statics by hand (the centre of mass is on the axis a, so spinning up adds no force): the
    # bearing holds the weight W = m g upward, W a_z along the axis and W √(1 − a_z²) across;
    # the weight's lever c = OFFSET·a gives a tilting moment OFFSET·W √(1 − a_z²) across the
    # axis, and the moment along it is the torque that drives the shaft.
    import pinocchio as pin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # nothing holds the torque: the shaft spins up
        res = pinwind.simulate(
            loads(TILTED_SHAFT, path="tilted.urdf"),
            duration=0.01,
            dt=1e-3,
            torques={"shaft": TORQUE},
            gravity=np.array([0.0, 0.0, -G]),
            progress=False,
        )
    a_z = pin.rpy.rpyToMatrix(*TILT_RPY)[2, 2]
    weight = SHAFT_MASS * G
    across = weight * np.sqrt(1.0 - a_z**2)
    tables = summary_tables(res, plain=True)
    at_end = _table_titled(tables, "Bearing loads on the child body")
    np.testing.assert_allclose(
        np.array(at_end["shaft"]) * 1e3,  # radial [kN], axial [kN], tilting, torque [kN·m]
        [across, weight * a_z, OFFSET * across, TORQUE],
        rtol=0,
        atol=0.06,  # printed to 0.1 N, N·m
    )
    peaks = _table_titled(tables, "Bearing loads over")
    np.testing.assert_allclose(
        np.array(peaks["shaft"]) * 1e3,  # radial, |axial| [kN], tilting [kN·m], |F| [kN]
        [across, abs(weight * a_z), OFFSET * across, weight],
        rtol=0,
        atol=0.06,
    )


def test_carrier_bearing_holds_the_weight_of_carrier_and_planets_and_the_carrier_torque():
    # Saleh 2017's stage at constant speed under balanced torques: the three planets' mesh
    # forces are equal and 120° apart, so they cancel on the carrier's subtree, and its bearing
    # holds the weight of the carrier with its planets. Torque balance of the stage about its
    # axis: the ring's mount reacts −(T_carrier + T_sun); each bearing transmits its shaft's
    # torque (none for a planet's).
    gearbox = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    carrier_torque, sun_torque = 1e6, -1e6 / 6
    res = pinwind.simulate(
        gearbox,
        duration=0.02,
        dt=1e-3,
        initial_speeds={"carrier": 14.2 * np.pi / 30},
        torques={"carrier": carrier_torque, "sun": sun_torque},
        progress=False,
    )
    model = gearbox.model

    def weight(joint: str) -> float:
        """The weight of a joint's subtree [N]: the bodies its bearing carries."""
        subtree = model.subtrees[model.getJointId(joint)]
        return sum(model.inertias[j].mass for j in subtree) * np.linalg.norm(model.gravity.linear)

    at_end = _table_titled(summary_tables(res, plain=True), "Bearing loads on the child body")
    expected = {
        "carrier": [weight("carrier"), 0.0, 0.0, carrier_torque],
        "sun": [weight("sun"), 0.0, 0.0, sun_torque],
        "ring": [weight("ring"), 0.0, 0.0, -(carrier_torque + sun_torque)],
    }
    for name, values in expected.items():
        np.testing.assert_allclose(
            np.array(at_end[name]) * 1e3, values, rtol=0, atol=0.06, err_msg=name
        )


def test_bearing_tables_fit_80_columns_with_the_longest_shipped_names():
    # saleh2017_drivetrain has the longest bearing names (stage1_pinion, stage2_pinion).
    from rich.console import Console

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # nothing holds the torque: the train spins up
        res = pinwind.simulate(
            pinwind.load(MODELS / "saleh2017_drivetrain.urdf"),
            duration=0.01,
            dt=1e-3,
            torques={"carrier": 1e6},
            progress=False,
        )
    wide = Console(width=200, record=True, file=io.StringIO())
    for table in summary_tables(res, plain=True):
        if str(table.title).startswith("Bearing loads"):
            wide.print(table)
    lines = wide.export_text().splitlines()
    assert len(lines) >= 2 * (3 + len(res.bearing_names))  # title, header, rule, rows
    # Their natural width, unfolded: an 80-column terminal shows every cell whole.
    assert max(len(line.rstrip()) for line in lines) <= 80


def test_a_planetary_at_rest_under_balanced_torques_prints_no_signed_zero():
    # The carrier's 1 MN·m against the sun's 1/6 of it (ratio 1 + 120/24 = 6) hold the stage
    # at rest: every speed is the solver's rounding (|ω| ~ 1e-13 rad/s), and the planets'
    # bearings pass no torque. Printed to 4 decimals that is 0.0000, never "-0.0000".
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = pinwind.simulate(
        gb, duration=0.05, dt=1e-3, torques={"carrier": 1e6, "sun": -1e6 / 6}, progress=False
    )
    assert np.abs(res.speed[-1]).max() < 1e-9  # at rest, but for rounding
    assert np.any(np.signbit(res.speed[-1]))  # and some of that rounding is negative
    cells = [
        cell
        for table in summary_tables(res, plain=True)
        for column in table.columns
        for cell in column._cells
    ]
    assert "0.0000" in cells and not any(str(cell).startswith("-0.0000") for cell in cells)


def _printed(table, width: int = 80) -> list[str]:
    """The lines of a table printed to a pipe of ``width`` columns (no colours)."""
    from rich.console import Console

    out = io.StringIO()
    Console(width=width, file=out, color_system=None).print(table)
    return out.getvalue().splitlines()


def test_no_name_or_number_of_the_shipped_drivetrains_tables_is_cut_at_80_columns():
    # The tables fit a pipe's 80 columns: a cell folded across two lines reads as two values
    # ("stage1_planet" over "1", a thrust "170.106" over "0"). The Saleh 2017 drivetrain has a
    # rotor and a generator on the long-named stage2_pinion; the NREL 5 MW gearbox has bearing
    # rows on stage1_planet1, ...
    from pinwind.analysis.summary import row_table
    from pinwind.runs.scenario import load_scenario, run

    scenario = load_scenario(
        MODELS.parent / "scenarios" / "saleh2017_drivetrain.toml",
        changes={"duration": 0.02, "no_log": True},
    )
    tables = summary_tables(run(scenario, progress=False), plain=True)
    assert [t for t in tables if str(t.title).startswith("Rotors")]
    nrel = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    rows = row_table(pinwind.simulate(nrel, duration=2e-3, dt=1e-4, progress=False), nrel)
    assert rows is not None
    for table in [*tables, rows]:
        lines = _printed(table)
        assert max(len(line) for line in lines) <= 80, table.title
        words = {word for line in lines for word in line.split()}
        cells = [str(cell) for column in table.columns for cell in column._cells]
        cut = [cell for cell in cells if cell not in words and cell != "0 (fixed)"]
        assert not cut, f"{table.title}: {cut[:5]}"
