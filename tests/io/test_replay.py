"""pinwind replay --save: the .rrd holds the bodies, the force arrows, the plots and a layout."""

from __future__ import annotations

import math

import numpy as np
import pytest
from rerun.chunk import RrdReader

from pinwind.errors import InputError
from pinwind.io.replay import replay, tooth_outline
from tests.io.conftest import rrd_columns
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
    np.testing.assert_allclose(origins.reshape(-1, nm, 3), res.pitch_point, atol=1e-6)
    lengths = np.linalg.norm(vectors.reshape(-1, nm, 3), axis=-1)
    # The largest tooth force of the run is drawn half as long as the ring's pitch radius.
    np.testing.assert_allclose(lengths.max(), 0.5 * RING_PITCH_RADIUS, rtol=1e-6)
    forces = np.linalg.norm(res.mesh_force_on_b, axis=-1)
    np.testing.assert_allclose(
        lengths, forces * (0.5 * RING_PITCH_RADIUS / forces.max()), rtol=1e-5, atol=1e-7
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
