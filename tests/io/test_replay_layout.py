"""How the replay opens: on the ``time`` timeline at the start, the machine seen from its camera.

The viewer cannot be watched headless; what it is told can: the blueprints in the .rrd and the
order in which the layout and the data leave the SDK.
"""

from __future__ import annotations

import numpy as np
import pytest
import rerun as rr
from rerun.chunk import RrdReader

import pinwind
from pinwind.io.replay import replay
from pinwind.model.gearbox import Gearbox
from tests.conftest import MODELS

#: Rerun's PlayState.Paused: the time cursor stays where it is as data arrive.
PAUSED = 1


def blueprint_fields(rrd, path: str, component: str) -> list:
    """Every value of a blueprint component at ``path``, over the blueprints of an .rrd."""
    reader = RrdReader(rrd)
    values = []
    for store in reader.blueprints():
        for chunk in reader.stream(store=store).to_chunks():
            if str(chunk.entity_path) != path:
                continue
            batch = chunk.to_record_batch()
            if component in batch.schema.names:
                values += [v for v in batch.column(component).to_pylist() if v is not None]
    return values


def blueprint_paths(rrd, suffix: str) -> set[str]:
    """Entity paths of the blueprints of an .rrd that end with ``suffix``."""
    reader = RrdReader(rrd)
    return {
        str(chunk.entity_path)
        for store in reader.blueprints()
        for chunk in reader.stream(store=store).to_chunks()
        if str(chunk.entity_path).endswith(suffix)
    }


@pytest.fixture(scope="module")
def replayed(logged_run, tmp_path_factory):
    rrd = tmp_path_factory.mktemp("layout") / "planetary.rrd"
    replay(logged_run.path, save=rrd)
    return rrd


def test_replay_opens_on_the_simulated_time_timeline_not_log_time(replayed):
    timelines = blueprint_fields(replayed, "/time_panel", "TimePanelBlueprint:timeline")
    assert timelines and all(t == ["time"] for t in timelines)


def test_replay_stays_paused_at_the_first_sample_while_loading(replayed):
    states = blueprint_fields(replayed, "/time_panel", "TimePanelBlueprint:play_state")
    assert states and all(s == [PAUSED] for s in states)


def test_a_live_viewer_gets_the_layout_and_camera_before_any_sample(logged_run, monkeypatch):
    import pinwind.io.replay as replay_module

    sent: list[object] = []
    real = rr.send_blueprint
    blueprints_before_data: list[int] = []

    def send_blueprint(blueprint, **kwargs):
        sent.append(blueprint)
        return real(blueprint, **kwargs)

    def progress(done: float, total: float) -> None:
        if not blueprints_before_data:
            blueprints_before_data.append(len(sent))

    # A viewer that would open here, not spawned: the data stay in the SDK's buffer.
    monkeypatch.setattr(replay_module, "check_viewer_can_open", lambda: "rerun")
    monkeypatch.setattr(rr, "spawn", lambda **kwargs: None)
    monkeypatch.setattr(rr, "send_blueprint", send_blueprint)
    replay(logged_run.path, progress=progress)
    assert blueprints_before_data == [1]
    assert len(sent) == 2  # the first layout, then the whole one
    first = sent[0]
    assert first.time_panel.timeline is not None
    assert str(first.time_panel.timeline) == "time"


@pytest.fixture(scope="module")
def drivetrain_replay(drivetrain_run, tmp_path_factory) -> tuple[Gearbox, object]:
    rrd = replay(drivetrain_run.path, save=tmp_path_factory.mktemp("drivetrain") / "d.rrd")
    return pinwind.load(MODELS / "saleh2017_drivetrain.urdf"), rrd


def _gear_solids(gearbox: Gearbox) -> dict[str, tuple[np.ndarray, np.ndarray, float, float]]:
    """(centre, unit axis, outer radius, half face width) of every gear at rest, in world [m]."""
    import pinocchio as pin

    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    solids = {}
    for name, gear in gearbox.gears.items():
        spec = gear.spec
        placement = data.oMi[gear.joint_id]
        radius = spec.teeth * spec.module / (2.0 * np.cos(spec.helix_angle)) + spec.module
        solids[name] = (
            placement.act(gear.centre_in_joint),
            placement.rotation @ gear.axis_in_joint,
            radius,
            0.5 * spec.face_width,
        )
    return solids


def test_the_default_camera_sees_the_planets_past_the_parallel_wheels(drivetrain_replay):
    gearbox, rrd = drivetrain_replay
    eyes = [
        value
        for path in blueprint_paths(rrd, "/EyeControls3D")
        for value in blueprint_fields(rrd, path, "EyeControls3D:position")
    ]
    assert eyes
    solids = _gear_solids(gearbox)
    parallel = [n for n in solids if n.startswith("stage")]
    planets = [n for n in solids if n.startswith("planet")]
    assert parallel and planets
    for eye in eyes:
        eye = np.asarray(eye[0], dtype=float)
        for planet in planets:
            target = solids[planet][0]
            # Points along the sight line from the eye to the planet's centre (the last 2 %
            # lies inside the planet itself and the ring around it).
            for s in np.linspace(0.0, 0.98, 2000):
                point = eye + s * (target - eye)
                for wheel in parallel:
                    centre, axis, radius, half = solids[wheel]
                    along = float((point - centre) @ axis)
                    across = float(np.linalg.norm(point - centre - along * axis))
                    assert not (abs(along) <= half and across <= radius), (planet, wheel, s)
