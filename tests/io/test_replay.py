"""pinwind replay --save: the .rrd holds the bodies, the force arrows, the plots and a layout."""

from __future__ import annotations

import math
import re
import tracemalloc

import numpy as np
import pytest
from rerun.chunk import RrdReader

import pinwind
from pinwind.errors import InputError
from pinwind.io.replay import replay, tooth_outline
from tests.io.conftest import DT, TORQUES, rrd_columns
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
        assert "Mesh3D:vertex_positions" in columns[f"/gearbox/{link}/{gear}/body"]
        assert "LineStrips3D:strips" in columns[f"/gearbox/{link}/{gear}/teeth"]
        assert "LineStrips3D:strips" in columns[f"/gearbox/{link}/{gear}/angle_mark"]
    # The whole machine: carrier mark and cheeks, pins, bearings, housing outline.
    assert "LineStrips3D:strips" in columns["/gearbox/carrier/angle_mark"]
    cheeks = [p for p in columns if p.startswith("/gearbox/carrier/visual")]
    assert len(cheeks) == 2
    assert any(p.startswith("/gearbox/pin1/visual") for p in columns)
    for link in ("sun", "carrier", "planet1"):
        assert "LineStrips3D:strips" in columns[f"/gearbox/{link}/bearing"]
    assert "Boxes3D:half_sizes" in columns["/gearbox/housing_outline"]
    for family in ("mesh_forces", "bearing_forces"):
        for component in ("origins", "vectors", "labels", "colors", "show_labels"):
            assert f"Arrows3D:{component}" in columns[f"/gearbox/{family}"], (family, component)
    for joint in res.joint_names:
        assert "Scalars:scalars" in columns[f"/plots/speed/{joint}"]
        assert "Scalars:scalars" in columns[f"/plots/torque/{joint}"]
        assert "SeriesLines:colors" in columns[f"/plots/speed/{joint}"]
    for mesh in res.mesh_names:
        for key in ("mesh_force", "transmission_error", "mesh_radial", "load_sharing"):
            assert "Scalars:scalars" in columns[f"/plots/{key}/{mesh}"], (key, mesh)
    for bearing in res.bearing_names:
        assert "Scalars:scalars" in columns[f"/plots/bearing_force/{bearing}"]
        # the world |M| holds the shaft's torque, not a bearing load: not plotted
        assert f"/plots/bearing_moment/{bearing}" not in columns
    assert "Scalars:scalars" in columns["/plots/energy_balance/residual"]
    assert "Scalars:scalars" in columns["/plots/load_factor/sun"]


def test_one_label_per_named_body_and_none_on_pins(replayed):
    _, columns = replayed
    labels = columns["/gearbox/labels"]["Points3D:labels"][0].to_pylist()[0]
    assert sorted(labels) == ["carrier", "planet1", "planet2", "planet3", "ring", "sun"]
    # One label colour for all, not the body colours (a label vanishes on its own body).
    colors = columns["/gearbox/labels"]["Points3D:colors"][0].to_pylist()[0]
    assert len(set(colors)) == 1


def test_arrow_labels_give_the_force_in_newtons(replayed, logged_run):
    _, columns = replayed
    res = logged_run.result
    first = columns["/gearbox/mesh_forces"]["Arrows3D:labels"][0].to_pylist()[0]
    force = np.linalg.norm(res.mesh_force_on_b[0, 0])
    assert first[0] == f"sun_planet1: {force:,.0f} N".replace(",", " ")


def test_replay_plot_colours_are_distinct_within_each_panel(replayed, logged_run):
    _, columns = replayed
    res = logged_run.result
    for key, names in (("speed", res.joint_names), ("mesh_force", res.mesh_names)):
        colors = [
            tuple(columns[f"/plots/{key}/{n}"]["SeriesLines:colors"][0].to_pylist()[0])
            for n in names
        ]
        assert len(set(colors)) == len(names), key


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


def test_force_arrows_sit_outside_the_gears_and_share_one_scale(replayed, logged_run):
    _, columns = replayed
    res = logged_run.result
    nm = len(res.mesh_names)

    def values(family, component):
        return np.concatenate(
            [
                c.flatten().flatten().to_numpy()
                for c in columns[f"/gearbox/{family}"][f"Arrows3D:{component}"]
            ]
        )

    origins = values("mesh_forces", "origins").reshape(-1, nm, 3)
    vectors = values("mesh_forces", "vectors").reshape(-1, nm, 3)
    # The 3D frames are the samples with poses (the log keeps them at 100 Hz).
    posed = pinwind.read_log(logged_run.path).pose_rows
    np.testing.assert_array_equal(posed, np.arange(0, len(res), 10))
    # In the face plane of gear B (face width 380 mm) plus 1 % of the ring radius, toward the
    # camera (-z), straight above the pitch point.
    np.testing.assert_allclose(origins[..., :2], res.pitch_point[posed][..., :2], atol=1e-6)
    np.testing.assert_allclose(origins[..., 2], -(0.19 + 0.01 * RING_PITCH_RADIUS), atol=1e-6)
    bearing = values("bearing_forces", "vectors").reshape(len(posed), -1, 3)
    lengths = np.linalg.norm(vectors, axis=-1)
    shown_mesh, shown_bearing = res.mesh_force_on_b[posed], res.bearing_force[posed]
    largest = max(
        np.linalg.norm(shown_mesh, axis=-1).max(),
        np.linalg.norm(shown_bearing, axis=-1).max(),
    )
    # One scale for both families: the largest force drawn is half the ring radius long.
    scale = 0.5 * RING_PITCH_RADIUS / largest
    np.testing.assert_allclose(
        lengths, np.linalg.norm(shown_mesh, axis=-1) * scale, rtol=1e-5, atol=1e-7
    )
    np.testing.assert_allclose(
        max(lengths.max(), np.linalg.norm(bearing, axis=-1).max()),
        0.5 * RING_PITCH_RADIUS,
        rtol=1e-6,
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


def test_replay_plots_single_tooth_forces_and_compliant_deflections(tmp_path):
    import warnings

    import pinwind
    from pinwind.errors import PinwindWarning
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    log = tmp_path / "compliant.mcap"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gb,
            duration=0.01,
            dt=1e-4,
            torques={"sun": 1e5},
            speeds={"carrier": 0.0},
            meshes={"all": "compliant", "planet3_ring": "rigid"},
            log=log,
        )
    rrd = tmp_path / "compliant.rrd"
    replay(log, save=rrd)
    columns = rrd_columns(rrd)

    def series(path):
        return np.concatenate([c.flatten().to_numpy() for c in columns[path]["Scalars:scalars"]])

    i = res.mesh_names.index("sun_planet1")
    np.testing.assert_allclose(
        series("/plots/mesh_deflection/sun_planet1"), res.mesh_deflection[:, i] * 1e6, rtol=1e-12
    )
    np.testing.assert_allclose(
        series("/plots/single_tooth_force/sun_planet2"),
        res.mesh_single_tooth_force[:, 1] / 1e3,
        rtol=1e-12,
    )
    # Rigid meshes have no deflection to plot.
    assert "/plots/mesh_deflection/planet3_ring" not in columns


def _blueprint_views(rrd):
    """TimeSeries/3D view name → (class, y range or None), from the .rrd's blueprint."""
    reader = RrdReader(rrd)
    names, ranges, classes = {}, {}, {}
    for chunk in reader.stream(store=reader.blueprints()[0]).to_chunks():
        batch = chunk.to_record_batch()
        path = chunk.entity_path
        if "ViewBlueprint:display_name" in batch.schema.names:
            names[path] = batch.column("ViewBlueprint:display_name").to_pylist()[0][0]
            classes[path] = batch.column("ViewBlueprint:class_identifier").to_pylist()[0][0]
        if "ScalarAxis:range" in batch.schema.names:
            ranges[path.rsplit("/", 1)[0]] = batch.column("ScalarAxis:range").to_pylist()[0][0]
    return {names[p]: (classes[p], ranges.get(p)) for p in names}


def test_blueprint_has_a_panel_per_quantity_with_floored_ranges(replayed, logged_run):
    rrd, _ = replayed
    views = _blueprint_views(rrd)
    assert views["gearbox"][0] == "3D"
    for title in (
        "joint speeds, relative to the parent body [rpm]",
        "body speeds, absolute (about the own axis, in the world) [rpm]",
        "joint torques, applied + driver/lock [kN·m]",
        "joint power T·ω, ω relative to the parent [kW]",
        "mesh normal forces F_n [kN]",
        "mesh force components: axial F_a [kN]",
        "transmission error along the line of action [µm]",
        "torques the shafts transmit about the bearing axes (not a bearing load) [kN·m]",
        "planet load share F_n / mean F_n of the meshes of one gear [-]",
        "energy balance residual Δ(kinetic + spring) − net work [kJ]",
    ):
        assert views[title][0] == "TimeSeries", title
    # no world |M| at a bearing: it would show the shaft's torque as a bearing moment
    assert "bearing moments |M| about the bearing centre, world [kN·m]" not in views
    # The mesh force axis holds every value and spans at least 5 % of the largest force.
    low, high = views["mesh normal forces F_n [kN]"][1]
    force = logged_run.result.mesh_normal / 1e3
    assert low < force.min() and force.max() < high
    assert high - low >= 0.05 * force.max()
    # Equal planets share exactly: the load-share axis is not zoomed onto rounding.
    low, high = views["planet load share F_n / mean F_n of the meshes of one gear [-]"][1]
    assert high - low >= 0.05


def test_meshing_teeth_interlock_at_the_pitch_point_in_the_first_frame(logged_run):
    from pinwind.io.log_reader import open_log
    from pinwind.io.replay_scene import gear_pose, pitch_fraction, tooth_phases

    log = open_log(logged_run.path, stop=0.0)
    res, model = log.result, log.model
    gears = model["gears"]
    phases = tooth_phases(model, res)
    bodies = {name: i for i, name in enumerate(res.body_names)}
    for m, name in enumerate(res.mesh_names):
        mesh = model["meshes"][name]
        point = res.pitch_point[0, m]
        fractions = []
        for gear in (mesh["gear_a"], mesh["gear_b"]):
            centre, rotation = gear_pose(gears[gear], res, 0, bodies)
            fractions.append(pitch_fraction(gears[gear], centre, rotation, point, phases[gear]))
        # Fraction 0: a tooth centred at the pitch point; 0.5: a gap centred there. A tooth of
        # one gear sits centred in a gap of the other: the fractions differ by half a pitch.
        offset = (fractions[0] - fractions[1]) % 1.0
        np.testing.assert_allclose(offset, 0.5, atol=1e-9, err_msg=name)
        # ... and the tooth is centred, not anywhere along the pitch.
        assert min(min(f, 1.0 - f) for f in fractions) < 1e-9, (name, fractions)
        if m == 0:  # sun_planet1: the sun's tooth in the planet's gap
            assert min(fractions[0], 1.0 - fractions[0]) < 1e-9, fractions


def test_viewer_url_opens_the_served_data():
    from pinwind.io.replay import viewer_url

    assert viewer_url(9191, "rerun+http://127.0.0.1:9877/proxy") == (
        "http://localhost:9191/?url=rerun%2Bhttp%3A%2F%2F127.0.0.1%3A9877%2Fproxy"
    )


@pytest.fixture
def taken_port():
    import socket

    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        sock.listen(1)
        yield sock.getsockname()[1]


def test_a_taken_data_port_is_refused_before_anything_starts(logged_run, taken_port):
    from pinwind.errors import PortInUse

    with pytest.raises(PortInUse, match=f"port {taken_port} \\(--grpc-port\\) is taken"):
        replay(logged_run.path, serve=True, grpc_port=taken_port, web_port=taken_port + 1)


def test_replay_cli_names_the_taken_web_port_in_one_line(logged_run, taken_port):
    out = run(
        "replay", str(logged_run.path), "--serve", "--web-port", str(taken_port),
        "--grpc-port", str(taken_port + 1 if taken_port < 65535 else taken_port - 1),
    )  # fmt: skip
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1, out.stderr
    assert f"port {taken_port} (--web-port) is taken" in out.stderr
    assert f"--web-port {taken_port + 1}" in out.stderr
    assert "Traceback" not in out.stderr


def test_ports_without_serve_are_refused(logged_run, tmp_path):
    with pytest.raises(InputError, match="go with --serve"):
        replay(logged_run.path, save=tmp_path / "x.rrd", web_port=9999)


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


@pytest.mark.parametrize("block", [777, 10_000])
def test_overview_has_the_min_and_max_of_every_time_span(long_log, tmp_path, block):
    path, res = long_log
    rrd = tmp_path / "coarse.rrd"
    # 10 spans of 0.5 s; blocks of 777 samples (0.777 s) end inside spans, or one block
    replay(path, save=rrd, points=20, block=block)
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


@pytest.fixture(scope="module")
def logs_ten_times_apart(planetary, tmp_path_factory):
    """The planetary stage for 10 s and 100 s at 1 ms (10 001 and 100 001 samples).

    In chunks of 1000 samples, so that the reader's read-ahead (4 chunks) is full in both.
    """
    folder = tmp_path_factory.mktemp("lengths")
    paths = []
    for duration in (10.0, 100.0):
        path = folder / f"planetary_{duration:g}s.mcap"
        pinwind.simulate(
            planetary,
            duration=duration,
            dt=DT,
            torques=TORQUES,
            log=path,
            keep="last",
            chunk=1000,
        )
        paths.append(path)
    return paths


def _replay_peak_bytes(path, rrd) -> int:
    tracemalloc.start()
    try:
        replay(path, save=rrd, points=200, block=1000)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_replay_memory_does_not_grow_with_the_log_length(logs_ten_times_apart, tmp_path):
    short_log, long_log = logs_ten_times_apart
    replay(short_log, save=tmp_path / "warm.rrd", points=200)  # imports, caches
    short = _replay_peak_bytes(short_log, tmp_path / "short.rrd")
    long = _replay_peak_bytes(long_log, tmp_path / "long.rrd")
    # Read whole, the long log's 100 001 samples take ~160 MB (~1.6 KB each) and the short
    # one's 16 MB. Streamed, both take one block of 1000 samples, the reader's read-ahead
    # (4 chunks), the overview of 200 points per series and 201 frames: ~25 MB either way.
    assert long < 1.15 * short + 2e6, (short, long)
    assert long < 60e6, long
    columns = rrd_columns(tmp_path / "long.rrd")
    times, _ = scalars(columns, "/plots/mesh_force/sun_planet1")
    assert len(times) <= 200
    frames = sum(len(c) for c in columns["/gearbox/sun"]["Transform3D:quaternion"])
    assert frames == 201  # one pose in each of 200 spans of 0.5 s, and the last one


def test_frames_come_at_a_display_rate_and_at_the_pose_rate_in_a_window(long_log, tmp_path):
    path, res = long_log
    rrd = tmp_path / "frames.rrd"
    replay(path, save=rrd, points=50, start=2.0, stop=2.5, block=777)
    columns = rrd_columns(rrd)
    frames = np.concatenate(
        [
            t.to_numpy().astype("timedelta64[ns]").astype(np.int64)
            for t in columns["/gearbox/sun"]["time"]
        ]
    )
    posed = np.rint(res.pose_time * 1e9).astype(np.int64)
    assert set(frames) <= set(posed)
    in_window = posed[(posed >= 2_000_000_000) & (posed <= 2_500_000_000)]
    np.testing.assert_array_equal(frames[np.isin(frames, in_window)], in_window)
    # outside the window: the first pose of each of 50 spans of 0.1 s, and the last pose
    outside = np.sort(frames[~np.isin(frames, in_window)])
    first = [posed[np.minimum(posed // 100_000_000, 49) == k].min() for k in range(50)]
    expected = [f for f in first if not 2_000_000_000 <= f <= 2_500_000_000] + [posed[-1]]
    np.testing.assert_array_equal(outside, expected)


def test_lines_on_top_of_each_other_get_nested_widths(replayed, logged_run):
    from pinwind.io.replay import LINE_WIDTH

    _, columns = replayed
    res = logged_run.result

    def width(key: str, name: str) -> float:
        return columns[f"/plots/{key}/{name}"]["SeriesLines:widths"][0].to_pylist()[0][0]

    # In the symmetric stage the three sun meshes carry equal forces (to rounding), and so do
    # the three ring meshes (the planets' inertia makes the two sets differ while the torque
    # varies), so each set would draw as one line: each line of a set gets its own width,
    # widest first in Rerun's drawing order (names in natural order, later lines on top), so
    # that each shows as a stripe of its own colour.
    force = res.mesh_normal
    for first in ("sun_planet1", "planet1_ring"):
        i = res.mesh_names.index(first)
        same = [
            name
            for j, name in enumerate(res.mesh_names)
            if np.max(np.abs(force[:, j] - force[:, i])) < 1e-6 * np.max(np.abs(force))
        ]
        assert len(same) == 3, same
        widths = [width("mesh_force", name) for name in sorted(same)]  # no digit runs to compare
        assert len(set(widths)) == 3, widths
        assert widths == sorted(widths, reverse=True), widths
        assert widths[-1] == LINE_WIDTH
    # The sun turns 6 times as fast as the carrier: lines apart keep the one width.
    assert width("speed", "sun") == width("speed", "carrier") == LINE_WIDTH


def test_line_widths_nest_only_lines_that_coincide():
    from pinwind.io.replay import LINE_WIDTH, STRIPE_WIDTH, line_widths

    low = np.array([[0.0, 0.0, 5.0, 0.0], [1.0, 1.0, 6.0, 1.0]])
    high = low + 0.5
    low[1, 3] += 0.02  # within the tolerance of 0.05
    names = ["planet10", "planet2", "ring", "planet1"]
    widths = line_widths(names, low, high, tolerance=0.05)
    # planet1, planet2, planet10 coincide: in natural order the widest first; ring stands apart
    assert widths == [
        LINE_WIDTH,
        LINE_WIDTH + STRIPE_WIDTH,
        LINE_WIDTH,
        LINE_WIDTH + 2 * STRIPE_WIDTH,
    ]
    low[1, 3] += 0.1  # now planet1 is apart too
    assert line_widths(names, low, high, tolerance=0.05) == [
        LINE_WIDTH,
        LINE_WIDTH + STRIPE_WIDTH,
        LINE_WIDTH,
        LINE_WIDTH,
    ]


def test_replay_plots_generator_torque_and_rotor_series_of_a_rotor_run(rotor_run, tmp_path):
    rrd = replay(rotor_run.path, save=tmp_path / "rotor.rrd")
    columns = rrd_columns(rrd)
    res = rotor_run.result

    def sent(path):
        return np.concatenate([c.flatten().to_numpy() for c in columns[path]["Scalars:scalars"]])

    np.testing.assert_allclose(
        sent("/plots/generator_torque/b"), res.generator("b").torque / 1000.0, rtol=1e-15
    )
    np.testing.assert_allclose(sent("/plots/rotor_power/a"), res.rotor("a").power / 1000.0,
                               rtol=1e-15)  # fmt: skip
    np.testing.assert_allclose(
        sent("/plots/rotor_tip_speed_ratio/a"), res.rotor("a").tip_speed_ratio, rtol=1e-15
    )
    titles = _blueprint_views(rrd)
    for title in (
        "generator torque T_gen on the shaft, > 0 generating [kN·m]",
        "rotor aerodynamic power P = ½ ρ π R² v³ C_p [kW]",
        "wind speed at the rotor v [m/s]",
        "power coefficient C_p(λ, β) [-]",
    ):
        assert titles[title][0] == "TimeSeries", title


def test_replay_of_a_run_without_rotor_has_no_rotor_plots(replayed):
    _, columns = replayed
    assert not [p for p in columns if p.startswith(("/plots/rotor", "/plots/generator"))]


def test_bearing_arrow_labels_give_the_loads_about_the_axis_and_the_shaft_torque_apart(
    replayed, logged_run, planetary
):
    # The planets' mesh forces are equal and 120° apart: on the carrier's subtree they cancel,
    # and its bearing holds the weight of carrier and planets, across its axis (gravity −y, axes
    # z). Along the axis it passes the torque applied to the carrier, the shaft's, not a load.
    _, columns = replayed
    first = columns["/gearbox/bearing_forces"]["Arrows3D:labels"][0].to_pylist()[0]
    (label,) = [text for text in first if text.startswith("carrier: ")]
    numbers = re.findall(r"(-?[0-9][0-9 ]*) N", label)
    radial, axial, tilting, torque = (float(n.replace(" ", "")) for n in numbers)
    model = planetary.model
    subtree = model.subtrees[model.getJointId("carrier")]
    weight = sum(model.inertias[j].mass for j in subtree) * np.linalg.norm(model.gravity.linear)
    np.testing.assert_allclose(radial, weight, atol=0.5)  # printed to the newton
    np.testing.assert_allclose([axial, tilting], 0.0, atol=0.5)
    np.testing.assert_allclose(torque, TORQUES["carrier"](0.0), atol=0.5)
    assert "shaft torque" in label
