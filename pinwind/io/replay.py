"""Replay a log in Rerun from the file alone: gears turning in 3D, force arrows, time series.

``replay`` streams a log (``io/log_reader.py``, ``BLOCK`` samples at a time, so a log of any
size replays in the memory of one block) and sends Rerun what a screen can show: an overview of
the whole run in which every plotted series keeps, in each of ``points / 2`` equal time spans,
its smallest and its largest sample (so no peak is lost), and poses and arrows at the first
posed sample of each span; plus, for a time window (``start``/``stop``, CLI ``--from``/``--to``),
every sample of it. Entities:

- ``gearbox/<link>``: the world pose of every link over time (``Transform3D``), and under it
  ``gearbox/<link>/<gear>``: a cylinder of pitch diameter × face width and the tooth outline of
  each face (z, m and the axis from the log's ``pinwind.model`` record); the outline shows the
  turning. Internal gears get a wireframe so that they do not hide what they enclose.
- ``gearbox/mesh_forces``: the tooth force on gear B at each pitch point;
  ``gearbox/bearing_forces``: the reaction on each bearing's child body at the bearing centre
  (the child link origin). Each
  family is scaled so that its largest force of the run is drawn half as long as the largest
  pitch radius; ``gearbox/scale`` states the scales.
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
from pinwind.io.log_reader import LogReader

#: Points per plotted series in the overview of a run: about what a plot a screen wide shows.
MAX_POINTS = 2000
#: Samples read at a time.
BLOCK = 20_000
#: Channels the replay reads.
CHANNELS = (
    "/joints",
    "/meshes/normal",
    "/meshes/force_on_b",
    "/meshes/pitch_point",
    "/bearings/force",
    "/tf",
)

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
                rrb.TimeSeriesView(origin="plots/mesh_force", name="mesh normal forces [kN]"),
                rrb.TimeSeriesView(
                    origin="plots/bearing_force", name="bearing forces |F|, world [kN]"
                ),
            ),
            column_shares=[3, 2],
        ),
        collapse_panels=True,
    )


class MinMaxDecimator:
    """The smallest and largest sample of each series in each of ``spans`` equal time spans.

    Fed block by block (``add``); memory is (spans, series). ``points`` gives, per series, the
    kept samples in time order: at most 2 per span, the min and the max (one when they are the
    same sample), so the decimated series has the extremes of the full one.
    """

    def __init__(self, start: float, stop: float, spans: int, series: int):
        self.start = start
        self.width = (stop - start) / spans if stop > start else 1.0
        self.spans = spans
        shape = (spans, series)
        self.low, self.low_at = np.full(shape, np.inf), np.full(shape, np.nan)
        self.high, self.high_at = np.full(shape, -np.inf), np.full(shape, np.nan)

    def span_of(self, time: np.ndarray) -> np.ndarray:
        """Index of the span of each time (the last span includes ``stop``)."""
        index = np.floor((time - self.start) / self.width).astype(np.int64)
        return np.clip(index, 0, self.spans - 1)

    def add(self, time: np.ndarray, values: np.ndarray) -> None:
        """Samples at ``time`` (n,), increasing, of every series: ``values`` (n, series)."""
        if not len(time):
            return
        span = self.span_of(time)
        starts = np.flatnonzero(np.r_[True, span[1:] != span[:-1]])
        spans = span[starts]
        index = np.arange(len(time))[:, None]
        for extreme, value, at, better in (
            (np.minimum, self.low, self.low_at, np.less),
            (np.maximum, self.high, self.high_at, np.greater),
        ):
            best = extreme.reduceat(values, starts, axis=0)
            # the first sample of each span that takes the extreme value
            hit = values == np.repeat(best, np.diff(np.r_[starts, len(time)]), axis=0)
            first = np.minimum.reduceat(np.where(hit, index, len(time)), starts, axis=0)
            first = np.minimum(first, len(time) - 1)
            when = time[first]
            take = better(best, value[spans]) | np.isnan(at[spans])
            value[spans] = np.where(take, best, value[spans])
            at[spans] = np.where(take, when, at[spans])

    def points(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per series: (times, values) of the kept samples, in time order."""
        out = []
        for s in range(self.low.shape[1]):
            times = np.stack([self.low_at[:, s], self.high_at[:, s]], axis=1)
            values = np.stack([self.low[:, s], self.high[:, s]], axis=1)
            keep = ~np.isnan(times)
            keep[:, 1] &= times[:, 1] != times[:, 0]  # one point when min and max coincide
            order = np.argsort(np.where(keep, times, np.inf), axis=1, kind="stable")
            times = np.take_along_axis(times, order, axis=1)[np.take_along_axis(keep, order, 1)]
            values = np.take_along_axis(values, order, axis=1)[np.take_along_axis(keep, order, 1)]
            out.append((times, values))
        return out


class _PoseSampler:
    """The first sample with poses of each time span: poses and arrows for the overview."""

    def __init__(self, decimator: MinMaxDecimator):
        self.decimator = decimator
        self.samples: dict[int, tuple] = {}

    def add(self, res) -> None:
        posed = np.flatnonzero(np.isfinite(res.body_position).all(axis=(1, 2)))
        if not len(posed):
            return
        spans = self.decimator.span_of(res.time[posed])
        new, first = np.unique(spans, return_index=True)
        for span, row in zip(new, posed[first], strict=True):
            if int(span) not in self.samples:
                self.samples[int(span)] = _frame(res, row)

    def frames(self) -> list[tuple]:
        return [self.samples[k] for k in sorted(self.samples)]


def _frame(res, row: int) -> tuple:
    return (
        res.time[row],
        res.body_position[row],
        res.body_quaternion[row],
        res.pitch_point[row],
        res.mesh_force_on_b[row],
        res.bearing_force[row],
    )


def _plotted(res) -> np.ndarray:
    """Every plotted series of a block as columns: speeds [rpm], mesh forces [kN], |F| [kN]."""
    return np.concatenate(
        [
            res.speed * RAD_PER_S_TO_RPM,
            res.mesh_normal / 1e3,
            np.linalg.norm(res.bearing_force, axis=2) / 1e3,
        ],
        axis=1,
    )


def _plot_paths(names: dict) -> list[tuple[str, str]]:
    """(entity path, legend label) of each plotted series, in ``_plotted`` column order."""
    return (
        [(f"plots/speed/{n}", n) for n in names["joint_names"]]
        + [(f"plots/mesh_force/{n}", n) for n in names["mesh_names"]]
        + [(f"plots/bearing_force/{n}", n) for n in names["bearing_names"]]
    )


class _Sender:
    """Sends geometry, poses, arrows and plots of a log to a Rerun recording stream."""

    def __init__(self, model: dict, names: dict, recording):
        import rerun as rr

        self.rr = rr
        self.recording = recording
        self.names = names
        self.gears: dict = model.get("gears", {})
        bearings: dict = model.get("bearings", {})
        bodies = names["body_names"]
        children = [bearings.get(name, {}).get("child", "") for name in names["bearing_names"]]
        #: bearings drawn as arrows (those whose child link is a logged body) and their links
        self.shown = [i for i, child in enumerate(children) if child in bodies]
        self.centres = [bodies.index(children[i]) for i in self.shown]
        largest_radius = max((g["pitch_radius"] for g in self.gears.values()), default=0.1)
        self.length = ARROW_FRACTION * largest_radius
        self.mesh_scale = self.bearing_scale = 1.0

    def send(self, path: str, times: np.ndarray, columns) -> None:
        rr = self.rr
        # whole nanoseconds, as the log times: a float time would be truncated by Rerun
        ns = np.rint(np.asarray(times) * 1e9).astype("timedelta64[ns]")
        rr.send_columns(
            path,
            indexes=[rr.TimeColumn(TIMELINE, duration=ns)],
            columns=columns,
            recording=self.recording,
        )

    def static(self, notes: list[str]) -> None:
        """The gears, arrow labels and the text beside the 3D view."""
        rr, recording = self.rr, self.recording
        rr.log("gearbox", rr.ViewCoordinates.RIGHT_HAND_Y_UP, static=True, recording=recording)
        for k, (name, gear) in enumerate(self.gears.items()):
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
        if self.names["mesh_names"]:
            rr.log(
                "gearbox/mesh_forces",
                rr.Arrows3D.from_fields(labels=self.names["mesh_names"], colors=[(220, 40, 40)]),
                static=True,
                recording=recording,
            )
            notes.append(
                f"mesh forces (tooth force on gear B): {1e3 * self.mesh_scale:.4g} mm per N"
            )
        if self.shown:
            rr.log(
                "gearbox/bearing_forces",
                rr.Arrows3D.from_fields(
                    labels=[self.names["bearing_names"][i] for i in self.shown],
                    colors=[(40, 90, 220)],
                ),
                static=True,
                recording=recording,
            )
            scale = 1e3 * self.bearing_scale
            notes.append(f"bearing forces (on the child body, world): {scale:.4g} mm per N")
        rr.log(
            "gearbox/scale",
            rr.TextDocument(
                "Arrow scales\n\n" + "\n".join(f"- {note}" for note in notes),
                media_type="text/markdown",
            ),
            static=True,
            recording=recording,
        )
        for path, label in _plot_paths(self.names):
            rr.log(path, rr.SeriesLines(names=[label]), static=True, recording=recording)

    def poses(self, time, position, quaternion, pitch_point, mesh_force, bearing_force) -> None:
        """Link poses and force arrows at the samples ``time`` (n,)."""
        rr = self.rr
        n = len(time)
        if not n:
            return
        for i, link in enumerate(self.names["body_names"]):
            self.send(
                f"gearbox/{link}",
                time,
                rr.Transform3D.columns(translation=position[:, i], quaternion=quaternion[:, i]),
            )
        nm = len(self.names["mesh_names"])
        if nm:
            self.send(
                "gearbox/mesh_forces",
                time,
                rr.Arrows3D.columns(
                    origins=pitch_point.reshape(-1, 3),
                    vectors=(mesh_force * self.mesh_scale).reshape(-1, 3),
                ).partition([nm] * n),
            )
        if self.shown:
            origins = position[:, self.centres]
            vectors = bearing_force[:, self.shown] * self.bearing_scale
            self.send(
                "gearbox/bearing_forces",
                time,
                rr.Arrows3D.columns(
                    origins=origins.reshape(-1, 3), vectors=vectors.reshape(-1, 3)
                ).partition([len(self.shown)] * n),
            )

    def plots(self, series: list[tuple[np.ndarray, np.ndarray]]) -> None:
        """Each plotted series: (times, values)."""
        for (path, _), (times, values) in zip(_plot_paths(self.names), series, strict=True):
            if len(times):
                self.send(path, times, self.rr.Scalars.columns(scalars=values))

    def block(self, res) -> None:
        """Every sample of a block (the full-rate window)."""
        posed = np.flatnonzero(np.isfinite(res.body_position).all(axis=(1, 2)))
        self.poses(*_frame(res, posed))
        values = _plotted(res)
        self.plots([(res.time, values[:, s]) for s in range(values.shape[1])])


def send_log(
    path: str | os.PathLike,
    recording,
    *,
    start: float | None = None,
    stop: float | None = None,
    points: int = MAX_POINTS,
    block: int | None = None,
) -> dict:
    """Send a log to a Rerun recording stream: the overview, and every sample of a window.

    Args:
        path: the log.
        recording: a ``rerun.RecordingStream``.
        start, stop: the window sent at full rate [s]; with neither, the overview only.
        points: the overview's samples per plotted series, at most (≥ 2).
        block: samples read at a time (default ``BLOCK``).

    Returns:
        What was sent: ``{"overview_points": ..., "window_samples": ..., "span": (t0, t1)}``.

    Raises:
        LogError: the log cannot be read.
        InputError: ``points`` below 2, or a window without samples.
    """
    if points < 2:
        raise InputError(f"--points is {points}; give at least 2 (a min and a max)")
    block = block or BLOCK
    with LogReader(path) as log:
        names = log.names
        sender = _Sender(log.metadata.get("pinwind.model", {}), names, recording)
        span = log.span or (0.0, 0.0)
        paths = _plot_paths(names)
        decimator = MinMaxDecimator(span[0], span[1], points // 2, len(paths))
        sampler = _PoseSampler(decimator)
        largest_mesh = largest_bearing = 0.0
        for res in log.blocks(block, channels=CHANNELS):
            decimator.add(res.time, _plotted(res))
            sampler.add(res)
            largest_mesh = max(largest_mesh, _largest(res.mesh_force_on_b))
            largest_bearing = max(largest_bearing, _largest(res.bearing_force[:, sender.shown]))
        sender.mesh_scale = sender.length / largest_mesh if largest_mesh > 0 else 1.0
        sender.bearing_scale = sender.length / largest_bearing if largest_bearing > 0 else 1.0
        notes = []
        if start is not None or stop is not None:
            notes.append(
                f"every sample from t = {start if start is not None else span[0]:g} to "
                f"{stop if stop is not None else span[1]:g} s; elsewhere the smallest and largest "
                f"of each series in {points // 2} equal time spans"
            )
        sender.static(notes)
        frames = sampler.frames()
        if frames:
            sender.poses(*(np.stack(column) for column in zip(*frames, strict=True)))
        overview = decimator.points()
        sender.plots(overview)
        window = 0
        if start is not None or stop is not None:
            for res in log.blocks(block, start=start, stop=stop, channels=CHANNELS):
                sender.block(res)
                window += len(res)
            if not window:
                raise InputError(
                    f"no sample from t = {start} to {stop} s; the log spans t = {span[0]:g} to "
                    f"{span[1]:g} s"
                )
    return {
        "overview_points": max((len(t) for t, _ in overview), default=0),
        "window_samples": window,
        "span": span,
    }


def _largest(vectors: np.ndarray) -> float:
    """Largest norm of a (..., 3) array, 0 when it is empty."""
    return float(np.max(np.linalg.norm(vectors, axis=-1), initial=0.0))


def replay(
    path: str | os.PathLike,
    *,
    save: str | os.PathLike | None = None,
    serve: bool = False,
    web_port: int | None = None,
    start: float | None = None,
    stop: float | None = None,
    points: int = MAX_POINTS,
    announce: Callable[[str], None] = print,
) -> Path | None:
    """Show a log in Rerun: spawn the viewer, or write an .rrd (``save``), or serve the web viewer.

    The whole run is sent as an overview of at most ``points`` samples per plotted series (the
    smallest and largest of each time span), the window start ≤ t ≤ stop [s] at full rate.
    With ``serve`` the call blocks (the servers live as long as it does) until Ctrl-C.

    Returns:
        The .rrd path when saving, else None.

    Raises:
        LogError: the log cannot be read.
        InputError: both ``save`` and ``serve`` given, ``points`` below 2, an empty window.
    """
    import rerun as rr

    if save is not None and serve:
        raise InputError("give either --save FILE or --serve, not both")
    LogReader(path).close()  # a missing or foreign file is refused before a viewer starts
    recording = rr.RecordingStream(application_id="pinwind_replay", recording_id=uuid.uuid4())
    recording.send_recording_name(Path(path).name)
    bp = blueprint()
    window = dict(start=start, stop=stop, points=points)
    if save is not None:
        out = Path(save)
        out.parent.mkdir(parents=True, exist_ok=True)
        recording.save(out, default_blueprint=bp)
        send_log(path, recording, **window)
        recording.flush()
        recording.disconnect()
        return out
    if serve:
        url = recording.serve_grpc(default_blueprint=bp)
        rr.serve_web_viewer(web_port=web_port, connect_to=url)
        send_log(path, recording, **window)
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
    send_log(path, recording, **window)
    recording.flush()
    return None
