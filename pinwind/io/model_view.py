"""A model at rest in Rerun, before any run: ``pinwind view MODEL``.

The bodies at q = 0 (the neutral configuration), drawn as the replay draws them
(``io/replay_scene.py``: gears with their teeth interlocking, the model's own shapes, shafts,
bearings, housing outline, labels), and for every mesh its two lines of action (front and back
flank) from the tangency point on one base circle to that on the other, with the pitch point.
Nothing is simulated: the model is loaded (and checked) as ``pinwind.load`` does, and the
recording goes where the replay's would (``Sink``: an .rrd file, the web viewer, or a viewer
spawned here).
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pinwind.dynamics.result import Result
from pinwind.io.log_model import model_geometry
from pinwind.io.log_reader import LogFile
from pinwind.io.panels import MESH_ARROW_COLOR
from pinwind.io.replay import TIMELINE, Sink, first_layout
from pinwind.io.replay_scene import Scene, send_scene
from pinwind.model.gearbox import Gearbox

__all__ = ["lines_of_action", "rest_pose", "send_model", "view_model"]


def rest_pose(gearbox: Gearbox) -> Result:
    """One sample at t = 0 with every link's world pose at q = 0 and nothing else.

    No mesh or bearing series: there are no forces to draw.
    """
    import pinocchio as pin

    model = gearbox.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    frames = gearbox.body_frames()
    position = np.array([data.oMf[f].translation for f in frames])
    quaternion = np.array([pin.Quaternion(data.oMf[f].rotation).coeffs() for f in frames])
    return Result(
        joint_names=list(gearbox.joint_names),
        mesh_names=[],
        bearing_names=[],
        body_names=[model.frames[f].name for f in frames],
        time=np.zeros(1),
        body_position=position.reshape(1, -1, 3),
        body_quaternion=quaternion.reshape(1, -1, 4),
    )


def lines_of_action(gearbox: Gearbox) -> dict[str, dict[str, np.ndarray]]:
    """Each mesh's pitch point and lines of action at q = 0, in world [m].

    The line of a flank runs through the pitch point P along its unit normal n (the mesh row's,
    ``dynamics/mesh.py``); it touches each gear's base circle where the perpendicular from the
    gear's centre C meets it, at P + ((C − P)·n) n.

    Returns:
        mesh name → ``{"pitch_point": (3,), "front": (2, 3), "back": (2, 3)}``, each line from
        the tangency point on gear A's base circle to that on gear B's.
    """
    import pinocchio as pin

    from pinwind.dynamics.mesh import MeshSet

    model = gearbox.model
    data = model.createData()
    q, v = pin.neutral(model), np.zeros(model.nv)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)  # the placements too
    meshes = MeshSet(gearbox)
    rows = meshes.evaluate(model, data)
    out = {}
    for i, mesh in enumerate(gearbox.meshes):
        point = np.array(rows.pitch_point[i])
        centres = [
            data.oMi[gear.joint_id].act(gear.centre_in_joint) for gear in (mesh.gear_a, mesh.gear_b)
        ]
        lines = {}
        for flank, normals in (("front", rows.normal_front), ("back", rows.normal_back)):
            n = np.array(normals[i])
            lines[flank] = np.array([point + float((c - point) @ n) * n for c in centres])
        out[mesh.name] = {"pitch_point": point, **lines}
    return out


def view_model(
    path: str | os.PathLike,
    *,
    save: str | os.PathLike | None = None,
    serve: bool = False,
    web_port: int | None = None,
    grpc_port: int | None = None,
    announce: Callable[[str], None] = print,
    wait: bool = True,
) -> Path | None:
    """Show a model at rest in Rerun: spawn the viewer, write an .rrd (``save``), or serve it.

    The options are those of ``replay`` (``Sink``), checked before the model is loaded, so that
    a machine without a display is refused at once.

    Returns:
        The .rrd path when saving, else None.

    Raises:
        ModelError: the model cannot be read or is inconsistent.
        InputError, PortInUse, NoViewer, ServeFailed: as ``replay``.
    """
    import rerun as rr

    import pinwind

    sink = Sink.check(save=save, serve=serve, web_port=web_port, grpc_port=grpc_port)
    gearbox = pinwind.load(Path(path))
    recording = rr.RecordingStream(application_id="pinwind_view", recording_id=uuid.uuid4())
    recording.send_recording_name(Path(path).name)
    sink.connect(recording)
    scene = send_model(gearbox, recording)
    rr.send_blueprint(first_layout(scene), recording=recording)
    return sink.finish(recording, announce=announce, wait=wait)


def send_model(gearbox: Gearbox, recording) -> Scene:
    """Log the model at rest (poses at t = 0 on ``TIMELINE``) and its lines of action."""
    import rerun as rr

    rest = rest_pose(gearbox)
    source = gearbox.source
    at_rest = LogFile(
        path=Path(source.path),
        result=rest,
        metadata={"pinwind.model": model_geometry(gearbox)},
        attachments={Path(source.path).name: source.text.encode("utf-8")},
        channels={},
        complete=True,
    )
    time_column = rr.TimeColumn(TIMELINE, duration=np.zeros(1, dtype="timedelta64[ns]"))

    def send(entity: str, columns) -> None:
        rr.send_columns(entity, indexes=[time_column], columns=columns, recording=recording)

    rr.log("gearbox", rr.ViewCoordinates.RIGHT_HAND_Y_UP, static=True, recording=recording)
    for i, link in enumerate(rest.body_names):
        rr.log(
            f"gearbox/{link}",
            rr.Transform3D(
                translation=rest.body_position[0, i], quaternion=rest.body_quaternion[0, i]
            ),
            static=True,
            recording=recording,
        )
    scene = send_scene(at_rest, recording, send)
    lines = lines_of_action(gearbox)
    if lines:
        rr.log(
            "gearbox/lines_of_action",
            rr.LineStrips3D(
                [line for mesh in lines.values() for line in (mesh["front"], mesh["back"])],
                colors=[MESH_ARROW_COLOR],
                radii=rr.Radius.ui_points(1.5),
                labels=[f"{name} ({flank} flank)" for name in lines for flank in ("front", "back")],
                show_labels=False,
            ),
            rr.Points3D(
                [mesh["pitch_point"] for mesh in lines.values()],
                colors=[MESH_ARROW_COLOR],
                radii=rr.Radius.ui_points(4.0),
                labels=list(lines),
            ),
            static=True,
            recording=recording,
        )
    notes = [
        f"the model at rest (q = 0): {len(rest.body_names)} bodies, {len(gearbox.meshes)} meshes",
        "**red** (lines_of_action): each mesh's lines of action, front and back flank, between "
        "the base circles; the dot is the pitch point (hover for the mesh)",
        *scene.notes,
    ]
    rr.log(
        "gearbox/scale",
        rr.TextDocument("\n".join(f"- {note}" for note in notes), media_type="text/markdown"),
        static=True,
        recording=recording,
    )
    return scene
