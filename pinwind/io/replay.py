"""Replay a log in Rerun from the file alone: gears turning in 3D, force arrows, time series.

``replay`` reads a log (``io/mcap_log.py``) and sends Rerun:

- ``gearbox/<link>``: the world pose of every link over time (``Transform3D``), and under it
  ``gearbox/<link>/<gear>``: a cylinder of pitch diameter × face width and the tooth outline of
  each face (z, m and the axis from the log's ``pinwind.model`` record); the outline shows the
  turning. Internal gears get a wireframe so that they do not hide what they enclose.
- ``gearbox/mesh_forces``: the tooth force on gear B at each pitch point;
  ``gearbox/bearing_forces``: the reaction on each bearing's child body at the bearing centre
  (the child link origin). Each
  family is scaled so that its largest force of the run is drawn half as long as the largest
  pitch radius; ``gearbox/scale`` states the scales.
- ``plots/single_tooth_force/<mesh>`` [kN] and, for compliant meshes,
  ``plots/mesh_deflection/<mesh>`` [µm];
- ``plots/speed/<joint>`` [rpm], ``plots/mesh_force/<mesh>`` (normal force) [kN] and
  ``plots/bearing_force/<bearing>`` (|F| in world) [kN].

Everything is on the ``time`` timeline (simulated seconds), laid out by a blueprint: the 3D view
beside the three plots.
"""

from __future__ import annotations

import math
import os
import time
import uuid
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pinwind.errors import InputError
from pinwind.io.mcap_log import LogFile, open_log

RAD_PER_S_TO_RPM = 60.0 / (2.0 * math.pi)
#: Largest arrow of a family, as a fraction of the largest pitch radius.
ARROW_FRACTION = 0.5
TIMELINE = "time"

_PALETTE = [
    (230, 159, 0),
    (86, 180, 233),
    (0, 158, 115),
    (240, 228, 66),
    (0, 114, 178),
    (213, 94, 0),
    (204, 121, 167),
    (153, 153, 153),
]


def tooth_outline(gear: dict, z: float) -> np.ndarray:
    """Closed outline of a gear face in the gear frame (axis z), straight-flanked teeth [m].

    Addendum m and dedendum 1.25 m about the pitch radius (tips inward for an internal gear);
    the tooth is 0.5 of the pitch at its root line and 0.25 at its tip.
    """
    teeth, module, radius = gear["teeth"], gear["module"], gear["pitch_radius"]
    sign = -1.0 if gear["internal"] else 1.0
    tip, root = radius + sign * module, radius - sign * 1.25 * module
    step = 2.0 * math.pi / teeth
    angles, radii = [], []
    for j in range(teeth):
        centre = j * step
        for offset, r in ((-0.3, root), (-0.125, tip), (0.125, tip), (0.3, root)):
            angles.append(centre + offset * step)
            radii.append(r)
    angles.append(angles[0])
    radii.append(radii[0])
    a, r = np.array(angles), np.array(radii)
    return np.stack([r * np.cos(a), r * np.sin(a), np.full_like(a, z)], axis=1)


def _rotation_from_z(axis: np.ndarray):
    """A rotation that turns the z axis onto ``axis`` (a rerun RotationAxisAngle)."""
    import rerun as rr

    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    z = np.array([0.0, 0.0, 1.0])
    cross = np.cross(z, axis)
    if np.linalg.norm(cross) < 1e-12:
        if axis[2] > 0:
            return rr.RotationAxisAngle(axis=[1.0, 0.0, 0.0], radians=0.0)
        return rr.RotationAxisAngle(axis=[1.0, 0.0, 0.0], radians=math.pi)
    angle = math.atan2(np.linalg.norm(cross), float(z @ axis))
    return rr.RotationAxisAngle(axis=cross / np.linalg.norm(cross), radians=angle)


def _arrow_scale(vectors: np.ndarray, length: float) -> float:
    """Metres per newton that draw the largest vector ``length`` long (1 if all are zero)."""
    largest = float(np.max(np.linalg.norm(vectors, axis=-1), initial=0.0))
    return length / largest if largest > 0.0 else 1.0


def blueprint():
    """The curated layout: 3D view of the gearbox beside speeds, mesh forces, bearing forces."""
    import rerun.blueprint as rrb

    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="gearbox", name="gearbox"),
                rrb.TextDocumentView(origin="gearbox/scale", name="arrow scales"),
                row_shares=[6, 1],
            ),
            rrb.Vertical(
                rrb.TimeSeriesView(origin="plots/speed", name="joint speeds [rpm]"),
                rrb.Tabs(
                    rrb.TimeSeriesView(origin="plots/mesh_force", name="mesh normal forces [kN]"),
                    rrb.TimeSeriesView(
                        origin="plots/single_tooth_force", name="single-tooth forces [kN]"
                    ),
                    rrb.TimeSeriesView(
                        origin="plots/mesh_deflection", name="mesh deflections [µm]"
                    ),
                ),
                rrb.TimeSeriesView(
                    origin="plots/bearing_force", name="bearing forces |F|, world [kN]"
                ),
            ),
            column_shares=[3, 2],
        ),
        collapse_panels=True,
    )


def send_log(log: LogFile, recording) -> None:
    """Send a log's geometry, poses, arrows and plots to a Rerun recording stream."""
    import rerun as rr

    res = log.result
    model = log.model
    gears: dict = model.get("gears", {})
    bearings: dict = model.get("bearings", {})
    time_column = rr.TimeColumn(TIMELINE, duration=res.time)
    n = len(res)

    def send(path: str, columns) -> None:
        rr.send_columns(path, indexes=[time_column], columns=columns, recording=recording)

    rr.log("gearbox", rr.ViewCoordinates.RIGHT_HAND_Y_UP, static=True, recording=recording)
    for i, link in enumerate(res.body_names):
        send(
            f"gearbox/{link}",
            rr.Transform3D.columns(
                translation=res.body_position[:, i], quaternion=res.body_quaternion[:, i]
            ),
        )
    for k, (name, gear) in enumerate(gears.items()):
        color = _PALETTE[k % len(_PALETTE)]
        path = f"gearbox/{gear['link']}/{name}"
        rr.log(
            path,
            rr.Transform3D(
                translation=gear["centre_in_link"],
                rotation_axis_angle=_rotation_from_z(gear["axis_in_link"]),
            ),
            static=True,
            recording=recording,
        )
        half = 0.5 * gear["face_width"]
        rr.log(
            f"{path}/pitch_cylinder",
            rr.Cylinders3D(
                lengths=[gear["face_width"]],
                radii=[gear["pitch_radius"]],
                colors=[color],
                fill_mode="majorwireframe" if gear["internal"] else "solid",
                labels=[name],
            ),
            static=True,
            recording=recording,
        )
        rr.log(
            f"{path}/teeth",
            rr.LineStrips3D(
                [tooth_outline(gear, -half), tooth_outline(gear, half)],
                colors=[color],
                radii=rr.Radius.ui_points(1.0),
            ),
            static=True,
            recording=recording,
        )

    largest_radius = max((g["pitch_radius"] for g in gears.values()), default=0.1)
    length = ARROW_FRACTION * largest_radius
    notes = []
    if res.mesh_names:
        scale = _arrow_scale(res.mesh_force_on_b, length)
        nm = len(res.mesh_names)
        send(
            "gearbox/mesh_forces",
            rr.Arrows3D.columns(
                origins=res.pitch_point.reshape(-1, 3),
                vectors=(res.mesh_force_on_b * scale).reshape(-1, 3),
            ).partition([nm] * n),
        )
        rr.log(
            "gearbox/mesh_forces",
            rr.Arrows3D.from_fields(labels=res.mesh_names, colors=[(220, 40, 40)]),
            static=True,
            recording=recording,
        )
        notes.append(f"mesh forces (tooth force on gear B): {1e3 * scale:.4g} mm per N")
    centres = [
        res.body_names.index(bearings.get(name, {}).get("child", ""))
        if bearings.get(name, {}).get("child", "") in res.body_names
        else None
        for name in res.bearing_names
    ]
    shown = [i for i, c in enumerate(centres) if c is not None]
    if shown:
        origins = res.body_position[:, [centres[i] for i in shown]]
        forces = res.bearing_force[:, shown]
        scale = _arrow_scale(forces, length)
        send(
            "gearbox/bearing_forces",
            rr.Arrows3D.columns(
                origins=origins.reshape(-1, 3), vectors=(forces * scale).reshape(-1, 3)
            ).partition([len(shown)] * n),
        )
        rr.log(
            "gearbox/bearing_forces",
            rr.Arrows3D.from_fields(
                labels=[res.bearing_names[i] for i in shown], colors=[(40, 90, 220)]
            ),
            static=True,
            recording=recording,
        )
        notes.append(f"bearing forces (on the child body, world): {1e3 * scale:.4g} mm per N")
    rr.log(
        "gearbox/scale",
        rr.TextDocument(
            "Arrow scales\n\n" + "\n".join(f"- {note}" for note in notes),
            media_type="text/markdown",
        ),
        static=True,
        recording=recording,
    )

    def plot(path: str, label: str, values: np.ndarray) -> None:
        rr.log(path, rr.SeriesLines(names=[label]), static=True, recording=recording)
        send(path, rr.Scalars.columns(scalars=values))

    for i, name in enumerate(res.joint_names):
        plot(f"plots/speed/{name}", name, res.speed[:, i] * RAD_PER_S_TO_RPM)
    for i, name in enumerate(res.mesh_names):
        plot(f"plots/mesh_force/{name}", name, res.mesh_normal[:, i] / 1e3)
        plot(f"plots/single_tooth_force/{name}", name, res.mesh_single_tooth_force[:, i] / 1e3)
        if np.any(res.mesh_deflection[:, i]):  # compliant meshes only
            plot(f"plots/mesh_deflection/{name}", name, res.mesh_deflection[:, i] * 1e6)
    for i, name in enumerate(res.bearing_names):
        plot(
            f"plots/bearing_force/{name}",
            name,
            np.linalg.norm(res.bearing_force[:, i], axis=1) / 1e3,
        )


def replay(
    path: str | os.PathLike,
    *,
    save: str | os.PathLike | None = None,
    serve: bool = False,
    web_port: int | None = None,
    announce: Callable[[str], None] = print,
) -> Path | None:
    """Show a log in Rerun: spawn the viewer, or write an .rrd (``save``), or serve the web viewer.

    With ``serve`` the call blocks (the servers live as long as it does) until Ctrl-C.

    Returns:
        The .rrd path when saving, else None.

    Raises:
        LogError: the log cannot be read.
        InputError: both ``save`` and ``serve`` given.
    """
    import rerun as rr

    if save is not None and serve:
        raise InputError("give either --save FILE or --serve, not both")
    log = open_log(path)
    recording = rr.RecordingStream(application_id="pinwind_replay", recording_id=uuid.uuid4())
    recording.send_recording_name(Path(path).name)
    bp = blueprint()
    if save is not None:
        out = Path(save)
        out.parent.mkdir(parents=True, exist_ok=True)
        recording.save(out, default_blueprint=bp)
        send_log(log, recording)
        recording.flush()
        recording.disconnect()
        return out
    if serve:
        url = recording.serve_grpc(default_blueprint=bp)
        rr.serve_web_viewer(web_port=web_port, connect_to=url)
        send_log(log, recording)
        recording.flush()
        announce(
            f"web viewer on http://localhost:{web_port or 9090} (data at {url}); Ctrl-C to stop"
        )
        try:
            while True:
                time.sleep(3600)
        except KeyboardInterrupt:
            pass
        return None
    recording.spawn(default_blueprint=bp)
    send_log(log, recording)
    recording.flush()
    return None
