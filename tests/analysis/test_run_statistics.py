"""Statistics over every simulated sample, folded while the run goes, checked against numpy."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.errors import InputError, TorquesUnbalanced, UnknownElement
from pinwind.loads.signals import Sine

MODEL = Path(__file__).resolve().parents[2] / "models" / "saleh2017_planetary.urdf"
DT = 1e-4
#: One sample off the every-10th grid where the carrier torque jumps (a gust, a grid fault).
SPIKE = 1234
#: Carrier torque [N·m] and the sun's reaction at the stage ratio 6.
TORQUE = 1.0e6


def spiky(t: np.ndarray | float) -> np.ndarray | float:
    """Carrier torque [N·m]: TORQUE, three times that at sample SPIKE only."""
    return TORQUE * (1.0 + 2.0 * (np.rint(np.asarray(t) / DT) == SPIKE))


@pytest.fixture(scope="module")
def gearbox() -> pinwind.Gearbox:
    return pinwind.load(MODEL)


def run(gearbox, keep, torque=None, **kwargs) -> pinwind.Result:
    torques = {
        "carrier": torque or Sine(mean=TORQUE, amplitude=0.3 * TORQUE, frequency=7.0),
        "sun": -TORQUE / 6.0,
    }
    if torque is not None:
        return pinwind.simulate(gearbox, duration=0.25, dt=DT, torques=torques, keep=keep, **kwargs)
    # 1.75 periods of 7 Hz in the run: the sine's mean is T (1 + 0.3/(3.5π)), 2.7 % above the
    # sun's balance, and the run says so
    with pytest.warns(TorquesUnbalanced, match='referred to joint "carrier"'):
        return pinwind.simulate(gearbox, duration=0.25, dt=DT, torques=torques, keep=keep, **kwargs)


def numpy_statistics(values: np.ndarray) -> tuple[float, ...]:
    """min, max, mean, RMS and final value, straight from numpy."""
    values = np.asarray(values)
    return (
        values.min(),
        values.max(),
        values.mean(),
        np.sqrt(np.mean(np.square(values))),
        values[-1],
    )


def assert_statistics(row, values: np.ndarray) -> None:
    lo, hi, mean, rms, final = numpy_statistics(values)
    assert (row.min, row.max, row.final) == (lo, hi, final)
    assert_allclose([row.mean, row.rms], [mean, rms], rtol=1e-12, atol=1e-300)


def test_keep_last_statistics_equal_numpy_over_every_sample_of_the_same_run(gearbox):
    everything = run(gearbox, "all")
    last = run(gearbox, "last")
    assert len(last) == 1 and everything.statistics is None
    stats = last.statistics
    assert stats is not None and stats.count == len(everything) == 2501
    assert (stats.first, stats.last) == (0.0, everything.time[-1])
    for i, name in enumerate(everything.mesh_names):
        assert_statistics(stats.row("mesh", name, "normal"), everything.mesh_normal[:, i])
        force = everything.mesh_force_on_b[:, i]
        for k, axis in enumerate("xyz"):
            assert_statistics(stats.row("mesh", name, "force on B (world)", axis), force[:, k])
        assert_statistics(
            stats.row("mesh", name, "force on B (world)", "|.|"), np.linalg.norm(force, axis=1)
        )
    for i, name in enumerate(everything.bearing_names):
        moment = everything.bearing_moment_local[:, i]
        assert_statistics(
            stats.row("bearing", name, "moment (joint frame)", "|.|"),
            np.linalg.norm(moment, axis=1),
        )
        assert_statistics(
            stats.row("bearing", name, "force (world)", "y"), everything.bearing_force[:, i, 1]
        )
    for i, name in enumerate(everything.joint_names):
        assert_statistics(stats.row("joint", name, "speed"), everything.speed[:, i])
    assert_statistics(stats.row("run", "", "constraint residual"), everything.constraint_residual)
    assert_statistics(stats.row("run", "kinetic", "energy"), everything.energy["kinetic"])


def test_the_sine_load_makes_the_statistics_differ_from_a_constant(gearbox):
    # Guards the test above: with a 30 % sine on the carrier (the sun's torque held, the
    # inertias take the rest), the tooth force swings by ±2.6 %: min, mean and max are apart.
    row = run(gearbox, "last").statistics.row("mesh", "sun_planet1", "normal")
    assert row.min < 0.99 * row.mean and row.max > 1.01 * row.mean


def test_a_peak_between_kept_samples_counts_in_the_run_statistics(gearbox):
    everything = run(gearbox, "all", torque=spiky)
    every_10th = run(gearbox, 10, torque=spiky)
    normal = everything.mesh_normal[:, 0]
    assert int(np.argmax(normal)) % 10 != 0  # the peak falls between kept samples
    assert every_10th.mesh_normal[:, 0].max() < 0.9 * normal.max()
    row = every_10th.statistics.row("mesh", everything.mesh_names[0], "normal")
    assert row.max == normal.max()
    assert_allclose(row.rms, np.sqrt(np.mean(normal**2)), rtol=1e-12)


def test_statistics_can_be_asked_for_or_declined(gearbox):
    assert run(gearbox, "all", statistics=True).statistics.count == 2501
    assert run(gearbox, 10, statistics=False).statistics is None


def test_folding_uneven_blocks_equals_folding_the_whole(gearbox):
    res = run(gearbox, "all")
    whole = RunningStatistics.of(res)
    folded = RunningStatistics()
    for a, b in ((0, 1), (1, 700), (700, 701), (701, 2501)):
        folded.add(res.rows(a, b))
    assert folded.count == whole.count == len(res)
    for x, y in zip(folded.rows(), whole.rows(), strict=True):
        assert (x.group, x.element, x.quantity, x.component) == (
            y.group,
            y.element,
            y.quantity,
            y.component,
        )
        assert (x.min, x.max, x.final) == (y.min, y.max, y.final)
        assert_allclose([x.mean, x.rms], [y.mean, y.rms], rtol=1e-12, atol=1e-300)


def test_a_log_read_back_folds_to_the_same_statistics_as_the_run(gearbox, tmp_path):
    # The read Result's arrays are views of one series-major array (other strides than the
    # run's sample-major blocks): the same numbers, and the same as numpy.
    res = run(gearbox, "all", log=tmp_path / "run.mcap")
    back = pinwind.read_log(tmp_path / "run.mcap")
    assert back.mesh_normal.strides != res.mesh_normal.strides
    for x, y in zip(
        RunningStatistics.of(back).rows(), RunningStatistics.of(res).rows(), strict=True
    ):
        assert x == y
    every_other = np.arange(1, len(back), 2)
    stats = RunningStatistics.of(back, every_other)
    assert stats.count == len(every_other)
    for i, name in enumerate(back.mesh_names):
        assert_statistics(stats.row("mesh", name, "normal"), back.mesh_normal[every_other, i])
    assert_statistics(
        stats.row("bearing", back.bearing_names[0], "force (world)", "|.|"),
        np.linalg.norm(back.bearing_force[every_other, 0], axis=1),
    )


def test_rows_come_element_after_element_each_vector_with_its_magnitude(gearbox):
    res = run(gearbox, "all")
    rows = RunningStatistics.of(res).rows()
    joint = res.joint_names[0]
    assert [(r.element, r.quantity) for r in rows[:4]] == [
        (joint, "angle"),
        (joint, "speed"),
        (joint, "acceleration"),
        (joint, "torque"),
    ]
    mesh = [r for r in rows if r.group == "mesh" and r.element == res.mesh_names[0]]
    assert [(r.quantity, r.component) for r in mesh][-4:] == [
        ("force on B (world)", axis) for axis in ("x", "y", "z", "|.|")
    ]
    # a mesh: normal, tangential, radial, axial, flank, the front and back flanks' normal forces,
    # TE, deflection, contact position, pairs, single-tooth force, face load factor, load centre,
    # peak and mean line load, sliding velocity, friction force, friction power, then force on
    # B's x, y, z and magnitude
    # a bearing: force and moment, world and joint frame (x, y, z, |.|); radial, axial, tilting,
    # transmitted torque; displacement and elastic force (x, y, z, |.|); friction moment, power
    per_joint, per_mesh, per_bearing = 4, 19 + 4, 4 * 4 + 4 + 2 * 4 + 2
    runs = 1 + len(res.energy)
    expected = (
        per_joint * len(res.joint_names)
        + per_mesh * len(res.mesh_names)
        + per_bearing * len(res.bearing_names)
        + runs
    )
    assert len(rows) == expected
    assert rows[-1].quantity == "energy" and not math.isnan(rows[-1].final)


def test_asking_for_a_series_that_does_not_exist_names_the_ones_that_do(gearbox):
    stats = run(gearbox, "last").statistics
    with pytest.raises(UnknownElement, match="sun_planet1"):
        stats.row("mesh", "sun_planet9", "normal")
    with pytest.raises(InputError, match="its series are: normal, tangential"):
        stats.row("mesh", "sun_planet1", "speed")


def test_the_statistics_of_one_series_are_numpy_s_and_nan_for_an_empty_one():
    from pinwind.analysis.summary import statistics

    values = np.random.default_rng(7).normal(3.0, 2.0, 1001)
    got = statistics(values)
    lo, hi, mean, rms, final = numpy_statistics(values)
    assert (got["min"], got["max"], got["final"]) == (lo, hi, final)
    assert_allclose([got["mean"], got["rms"]], [mean, rms], rtol=1e-13)
    assert all(math.isnan(v) for v in statistics(np.array([])).values())


def test_a_skipped_start_up_leaves_the_start_up_impact_out_of_the_statistics(gearbox):
    # Started undeflected, the compliant stage's first contact overshoots: the maximum of
    # the whole run is the start-up's. Skipping the start-up, the statistics are numpy's over
    # t ≥ skip of the very samples kept, and the load sharing ignores the samples before it.
    skip = 0.01
    res = pinwind.simulate(
        gearbox,
        duration=0.02,
        dt=2e-5,
        torques={"carrier": TORQUE, "sun": -TORQUE / 6.0},
        meshes={"all": "compliant"},
        keep="all",
        skip_start=skip,
        initial_deflection="none",
    )
    after = res.time >= skip
    normal = res.mesh("sun_planet1").normal
    assert normal.max() > normal[after].max()  # the start-up sets the whole run's maximum
    assert_statistics(res.statistics.row("mesh", "sun_planet1", "normal"), normal[after])
    assert res.statistics.count == np.count_nonzero(after)
    assert res.metadata["statistics_from_s"] == skip
    from pinwind.analysis import load_sharing

    for sharing in load_sharing(res, gearbox):
        assert np.isnan(sharing.factor[~after]).all()
        assert np.isfinite(sharing.factor[after]).any()


def test_a_start_up_as_long_as_the_run_is_refused(gearbox):
    with pytest.raises(InputError, match="skip_start = 0.25 s leaves nothing of a 0.25 s run"):
        run(gearbox, "all", skip_start=0.25)
