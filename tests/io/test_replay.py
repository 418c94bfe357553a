"""pinwind replay --save: the .rrd holds the bodies, the force arrows, the plots and a layout."""

from __future__ import annotations

import math

import numpy as np
import pytest
from rerun.chunk import RrdReader

import pinwind
from pinwind.errors import InputError
from pinwind.io import replay as replay_module
from pinwind.io.log_reader import LogReader
from pinwind.io.replay import replay, tooth_outline
from tests.io.conftest import DT, POSE_EVERY, TORQUES, rrd_columns
from tests.io.test_cli_log import run

#: Largest pitch radius of the Saleh stage: the ring, 120 teeth of module 15 mm [m].
RING_PITCH_RADIUS = 120 * 15e-3 / 2


@pytest.fixture(scope="module")
def replayed(logged_run, tmp_path_factory):
    rrd = tmp_path_factory.mktemp("replay") / "planetary.rrd"
    assert replay(logged_run.path, save=rrd) == rrd
    columns = rrd_columns(rrd)
    return rrd, columns


def test_replay_rrd_has_every_body_gear_arrow_family_and_plot(replayed, logged_run):
    _, columns = replayed
    res = logged_run.result
    for body in res.body_names:
        assert "Transform3D:quaternion" in columns[f"/gearbox/{body}"], body
    for gear, link in [("sun", "sun"), ("planet2", "planet2"), ("ring", "ring")]:
        assert "Cylinders3D:radii" in columns[f"/gearbox/{link}/{gear}/pitch_cylinder"]
        assert "LineStrips3D:strips" in columns[f"/gearbox/{link}/{gear}/teeth"]
    assert "Arrows3D:vectors" in columns["/gearbox/mesh_forces"]
    assert "Arrows3D:vectors" in columns["/gearbox/bearing_forces"]
    for joint in res.joint_names:
        assert "Scalars:scalars" in columns[f"/plots/speed/{joint}"]
    for mesh in res.mesh_names:
        assert "Scalars:scalars" in columns[f"/plots/mesh_force/{mesh}"]
    for bearing in res.bearing_names:
        assert "Scalars:scalars" in columns[f"/plots/bearing_force/{bearing}"]


def test_replay_rrd_carries_the_blueprint(replayed):
    rrd, _ = replayed
    assert RrdReader(rrd).blueprints()


def test_replay_plots_speeds_in_rpm_and_forces_in_kn(replayed, logged_run):
    _, columns = replayed
    res = logged_run.result
    sun = res.joint_names.index("sun")
    speed = np.concatenate(
        [c.flatten().to_numpy() for c in columns["/plots/speed/sun"]["Scalars:scalars"]]
    )
    np.testing.assert_allclose(speed, res.speed[:, sun] * 60 / (2 * math.pi), rtol=1e-12)
    mesh = res.mesh_names.index("planet1_ring")
    force = np.concatenate(
        [
            c.flatten().to_numpy()
            for c in columns["/plots/mesh_force/planet1_ring"]["Scalars:scalars"]
        ]
    )
    np.testing.assert_allclose(force, res.mesh_normal[:, mesh] / 1e3, rtol=1e-12)


def test_mesh_force_arrows_start_at_the_pitch_points_and_are_scaled_to_the_ring(
    replayed, logged_run
):
    _, columns = replayed
    res = logged_run.result
    nm = len(res.mesh_names)
    origins = np.concatenate(
        [
            c.flatten().flatten().to_numpy()
            for c in columns["/gearbox/mesh_forces"]["Arrows3D:origins"]
        ]
    )
    vectors = np.concatenate(
        [
            c.flatten().flatten().to_numpy()
            for c in columns["/gearbox/mesh_forces"]["Arrows3D:vectors"]
        ]
    )
    # arrows go with the link poses: every 10th sample (100 Hz)
    posed = slice(None, None, POSE_EVERY)
    np.testing.assert_allclose(origins.reshape(-1, nm, 3), res.pitch_point[posed], atol=1e-6)
    lengths = np.linalg.norm(vectors.reshape(-1, nm, 3), axis=-1)
    # The largest tooth force of the run is drawn half as long as the ring's pitch radius.
    forces = np.linalg.norm(res.mesh_force_on_b, axis=-1)
    np.testing.assert_allclose(
        lengths, forces[posed] * (0.5 * RING_PITCH_RADIUS / forces.max()), rtol=1e-5, atol=1e-7
    )


def test_tooth_outline_alternates_tip_and_root_circles():
    gear = {"teeth": 24, "module": 0.015, "pitch_radius": 0.18, "internal": False}
    outline = tooth_outline(gear, 0.19)
    radii = np.hypot(outline[:, 0], outline[:, 1])
    assert outline.shape == (4 * 24 + 1, 3)
    np.testing.assert_allclose(sorted(set(np.round(radii, 12))), [0.18 - 1.25 * 0.015, 0.195])
    np.testing.assert_allclose(outline[:, 2], 0.19)
    ring = tooth_outline({**gear, "teeth": 120, "pitch_radius": 0.9, "internal": True}, 0.0)
    ring_radii = np.hypot(ring[:, 0], ring[:, 1])
    np.testing.assert_allclose([ring_radii.min(), ring_radii.max()], [0.885, 0.9 + 1.25 * 0.015])


def test_replay_refuses_save_and_serve_together(logged_run, tmp_path):
    with pytest.raises(InputError, match="either --save FILE or --serve"):
        replay(logged_run.path, save=tmp_path / "x.rrd", serve=True)


def test_replay_cli_save_writes_an_rrd(logged_run, tmp_path):
    rrd = tmp_path / "cli.rrd"
    out = run("replay", str(logged_run.path), "--save", str(rrd))
    assert out.returncode == 0, out.stderr
    assert f"wrote {rrd}" in out.stdout.replace("\n", "")
    assert RrdReader(rrd).recordings()


# --- long logs: overview and window ---------------------------------------------------------------


@pytest.fixture(scope="module")
def long_log(planetary, tmp_path_factory):
    """5001 samples (5 s at 1 ms) of the planetary stage under the rippled rotor torque."""
    path = tmp_path_factory.mktemp("long") / "long.mcap"
    pinwind.simulate(planetary, duration=5.0, dt=DT, torques=TORQUES, log=path)
    return path, pinwind.read_log(path)


def scalars(columns, entity: str) -> tuple[np.ndarray, np.ndarray]:
    """(times [ns], values) of a plotted series in an .rrd, in time order.

    Times are whole nanoseconds, the log times rint(t · 1e9) of the samples.
    """
    times = np.concatenate(
        [t.to_numpy().astype("timedelta64[ns]").astype(np.int64) for t in columns[entity]["time"]]
    )
    values = np.concatenate([c.flatten().to_numpy() for c in columns[entity]["Scalars:scalars"]])
    order = np.argsort(times, kind="stable")
    return times[order], values[order]


def test_overview_keeps_at_most_2000_points_per_series_and_its_min_and_max(long_log, tmp_path):
    path, res = long_log
    rrd = tmp_path / "overview.rrd"
    replay(path, save=rrd)
    columns = rrd_columns(rrd)
    series = {
        "/plots/mesh_force/planet1_ring": res.mesh("planet1_ring").normal / 1e3,
        "/plots/speed/sun": res.joint("sun").speed * (60 / (2 * math.pi)),
        "/plots/bearing_force/carrier": np.linalg.norm(res.bearing("carrier").force, axis=1) / 1e3,
    }
    for entity, full in series.items():
        times, values = scalars(columns, entity)
        assert len(values) <= 2000 < len(full), entity
        assert values.max() == full.max() and values.min() == full.min(), entity
        # every point is a sample of the run, at its own time
        rows = times // 1_000_000  # samples of 1 ms
        np.testing.assert_array_equal(values, full[rows], err_msg=entity)
    assert len(columns["/gearbox/sun"]["Transform3D:quaternion"]) >= 1


def test_overview_has_the_min_and_max_of_every_time_span(long_log, tmp_path):
    path, res = long_log
    rrd = tmp_path / "coarse.rrd"
    replay(path, save=rrd, points=20)  # 10 spans of 0.5 s
    times, values = scalars(rrd_columns(rrd), "/plots/mesh_force/sun_planet1")
    full = res.mesh("sun_planet1").normal / 1e3
    assert len(values) <= 20
    sample_ns = np.rint(res.time * 1e9)
    edges = np.linspace(0.0, 5e9, 11)
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        inside = (sample_ns >= lo) & ((sample_ns < hi) | (hi == 5e9))
        sent = (times >= lo) & ((times < hi) | (hi == 5e9))
        assert values[sent].min() == full[inside].min()
        assert values[sent].max() == full[inside].max()


def test_window_is_sent_at_full_rate_beside_the_overview(long_log, tmp_path):
    path, res = long_log
    rrd = tmp_path / "window.rrd"
    replay(path, save=rrd, start=1.0, stop=1.5, points=100)
    times, values = scalars(rrd_columns(rrd), "/plots/mesh_force/sun_planet1")
    inside = (res.time >= 1.0) & (res.time <= 1.5)
    sent = (times >= 1_000_000_000) & (times <= 1_500_000_000)
    # every sample of the window (overview points inside it are samples too)
    np.testing.assert_array_equal(np.unique(times[sent]), np.rint(res.time[inside] * 1e9))
    assert len(values[~sent]) <= 100


def test_replay_reads_the_log_in_blocks_never_the_whole_of_it(long_log, tmp_path, monkeypatch):
    path, res = long_log
    sizes = []
    blocks = LogReader.blocks

    def counted(self, samples, **kwargs):
        for part in blocks(self, samples, **kwargs):
            sizes.append(len(part))
            yield part

    def whole(self, **kwargs):
        raise AssertionError("replay read the whole log at once")

    monkeypatch.setattr(LogReader, "blocks", counted)
    monkeypatch.setattr(LogReader, "read", whole)
    monkeypatch.setattr(replay_module, "BLOCK", 1000)
    replay(path, save=tmp_path / "blocks.rrd", start=4.0)
    assert max(sizes) == 1000 < len(res)
    assert sum(sizes) == len(res) + np.count_nonzero(res.time >= 4.0)  # overview, then window


def test_replay_cli_sends_a_window_and_refuses_an_empty_one(long_log, tmp_path):
    path, _ = long_log
    rrd = tmp_path / "cli.rrd"
    out = run("replay", str(path), "--save", str(rrd), "--from", "2", "--to", "2.1")
    assert out.returncode == 0, out.stderr
    times, _ = scalars(rrd_columns(rrd), "/plots/speed/sun")
    assert np.count_nonzero((times >= 2_000_000_000) & (times <= 2_100_000_000)) >= 101
    empty = run("replay", str(path), "--save", str(rrd), "--from", "7", "--to", "8")
    assert empty.returncode == 2
    assert "no sample from t = 7.0 to 8.0 s; the log spans t = 0 to 5 s" in empty.stderr
