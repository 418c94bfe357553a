"""Replay a log in Rerun from the file alone: the machine turning in 3D, forces, plots.

``replay`` reads a log (``io/mcap_log.py``) and sends Rerun:

- ``gearbox/<link>``: the world pose of every link over time (``Transform3D``); under it the
  gears, visuals, shafts, bearings and angle marks of ``io/replay_scene.py``, which also sends
  the body labels (``gearbox/labels``), the housing outline and the force arrows
  (``gearbox/mesh_forces``, ``gearbox/bearing_forces``; the legend is ``gearbox/scale``);
- ``plots/<panel>/<series>``: every panel of ``io/panels.py`` (speeds [rpm], torques [kN·m],
  power [kW], mesh forces [kN], transmission error [µm], bearing forces [kN] and moments
  [kN·m], load sharing [-], energy [kJ]), each series in its colour.

Everything is on the ``time`` timeline (simulated seconds), laid out by a blueprint: the 3D view
and its legend beside the plots, in tabs, with y ranges that do not magnify rounding.
"""

from __future__ import annotations

import copy
import math
import os
import socket
import time
import uuid
from collections.abc import Callable
from pathlib import Path
from urllib.parse import quote

import numpy as np

from pinwind.dynamics.result import Result
from pinwind.errors import InputError, PortInUse, ServeFailed
from pinwind.io.mcap_log import LogFile, open_log
from pinwind.io.panels import GROUPS, RAD_PER_S_TO_RPM, Panel, legend_room, log_panels
from pinwind.io.replay_scene import ARROW_FRACTION, Scene, scene_camera, send_scene, tooth_outline

__all__ = [
    "ARROW_FRACTION",
    "RAD_PER_S_TO_RPM",
    "TIMELINE",
    "blueprint",
    "replay",
    "send_log",
    "tooth_outline",
]

TIMELINE = "time"
#: Default ports of ``--serve``: Rerun's gRPC data server and its web viewer.
GRPC_PORT = 9876
WEB_PORT = 9090


def blueprint(panels: list[Panel] | None = None, scene: Scene | None = None):
    """The layout: the 3D machine and its legend beside the plots, grouped in tabs.

    Each tab of ``panels.GROUPS`` holds its panels; each plot's y range follows
    ``panels.y_range`` (no magnified rounding, room on top for the legend), and hovering shows
    every series at that time. ``scene`` gives the default camera. Without arguments: the
    speed, mesh-force and bearing-force plots with automatic ranges.
    """
    import rerun.blueprint as rrb

    def view(panel: Panel, legend: bool):
        room = legend_room(len(panel.series)) if legend else 0.0
        return rrb.TimeSeriesView(
            origin=f"plots/{panel.key}",
            name=panel.title,
            axis_y=rrb.ScalarAxis(range=panel.y_range(legend_room=room)),
            plot_legend=rrb.PlotLegend(corner="LeftTop", visible=legend),
            interaction=rrb.PlotInteraction(tooltip_mode="All"),
        )

    if panels is None:
        plots = rrb.Tabs(
            rrb.TimeSeriesView(origin="plots/speed", name="joint speeds, relative [rpm]"),
            rrb.TimeSeriesView(origin="plots/mesh_force", name="mesh normal forces [kN]"),
            rrb.TimeSeriesView(origin="plots/bearing_force", name="bearing forces |F| [kN]"),
        )
    else:
        tabs = []
        for group in GROUPS:
            members = [p for p in panels if p.group == group and p.series]
            views, named = [], []
            for panel in members:
                # One legend per set of series: panels of a tab that repeat the series of an
                # earlier panel (the same names, the same colours) show none.
                names = [s.name for s in panel.series]
                views.append(view(panel, legend=names not in named))
                named.append(names)
            if views:
                tabs.append(rrb.Vertical(*views, name=group))
        plots = rrb.Tabs(*tabs)
    eye = None
    if scene is not None:
        eye = rrb.EyeControls3D(
            position=scene.camera_position, look_target=scene.camera_target, eye_up=[0, 1, 0]
        )
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="gearbox", name="gearbox", eye_controls=eye),
                rrb.TextDocumentView(origin="gearbox/scale", name="legend"),
                row_shares=[4, 1],
            ),
            plots,
            column_shares=[3, 2],
        ),
        collapse_panels=True,
    )


#: Points per plotted series in the overview of a run: about what a plot a screen wide shows.
MAX_POINTS = 2000


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


def overview_rows(res: Result, points: int, window: tuple[float, float] | None) -> np.ndarray:
    """Rows of the 3D frames.

    At most ``points`` posed samples spread over the run, plus every posed sample of ``window``
    (start, stop) [s].
    """
    posed = np.arange(len(res))
    if res.body_position.shape[1]:
        posed = posed[np.isfinite(res.body_position[:, 0, 0])]
    rows = posed[:: max(1, math.ceil(len(posed) / max(points, 1)))]
    if len(posed) and rows[-1] != posed[-1]:
        rows = np.append(rows, posed[-1])
    if window is not None:
        inside = posed[(res.time[posed] >= window[0]) & (res.time[posed] <= window[1])]
        rows = np.union1d(rows, inside)
    return rows


def overview_series(
    time: np.ndarray, values: np.ndarray, points: int, window: tuple[float, float] | None
) -> tuple[np.ndarray, np.ndarray]:
    """(rows, values) of a plotted series.

    Its min and max in each of ``points``/2 time spans (``MinMaxDecimator``), plus every sample of
    ``window`` (start, stop) [s].
    """
    if len(time) <= points and window is None:
        return np.arange(len(time)), values
    decimator = MinMaxDecimator(float(time[0]), float(time[-1]), max(points // 2, 1), 1)
    finite = np.isfinite(values)
    decimator.add(time[finite], values[finite][:, None])
    kept_times, _ = decimator.points()[0]
    rows = np.flatnonzero(finite)[np.searchsorted(time[finite], kept_times)]
    if window is not None:
        rows = np.union1d(rows, np.flatnonzero((time >= window[0]) & (time <= window[1])))
    return rows, values[rows]


def _nanoseconds(times: np.ndarray) -> np.ndarray:
    """Times [s] as whole nanoseconds, the log's own time stamps rint(t · 1e9)."""
    return np.rint(np.asarray(times) * 1e9).astype("timedelta64[ns]")


def send_log(
    log: LogFile,
    recording,
    panels: list[Panel] | None = None,
    *,
    points: int = MAX_POINTS,
    window: tuple[float, float] | None = None,
) -> Scene:
    """Send a log's machine, poses, arrows and plots (``panels``, default all) to a recording.

    The viewer gets an overview a screen can show: at most ``points`` 3D frames, and each plotted
    series' min and max in ``points``/2 time spans, so no peak is lost; every sample of ``window``
    (start, stop) [s] is sent besides.
    """
    import rerun as rr

    res = log.result
    frames = overview_rows(res, points, window)
    view = copy.copy(log)
    view.result = res.take(frames)
    time_column = rr.TimeColumn(TIMELINE, duration=_nanoseconds(res.time[frames]))

    def send(path: str, columns) -> None:
        rr.send_columns(path, indexes=[time_column], columns=columns, recording=recording)

    rr.log("gearbox", rr.ViewCoordinates.RIGHT_HAND_Y_UP, static=True, recording=recording)
    for i, link in enumerate(view.result.body_names):
        send(
            f"gearbox/{link}",
            rr.Transform3D.columns(
                translation=view.result.body_position[:, i],
                quaternion=view.result.body_quaternion[:, i],
            ),
        )
    scene = send_scene(view, recording, send)
    rr.log(
        "gearbox/scale",
        rr.TextDocument(
            "**Arrows**\n\n" + "\n".join(f"- {note}" for note in scene.notes),
            media_type="text/markdown",
        ),
        static=True,
        recording=recording,
    )

    def plot(path: str, label: str, values: np.ndarray, color=None) -> None:
        rr.log(path, rr.SeriesLines(names=[label], colors=color), static=True, recording=recording)
        rows, kept = overview_series(res.time, values, points, window)
        rr.send_columns(
            path,
            indexes=[rr.TimeColumn(TIMELINE, duration=_nanoseconds(res.time[rows]))],
            columns=rr.Scalars.columns(scalars=kept),
            recording=recording,
        )

    for panel in panels if panels is not None else log_panels(log):
        for series in panel.series:
            plot(f"plots/{panel.key}/{series.name}", series.name, series.values, series.color)
    return scene


def viewer_url(web_port: int, grpc_url: str) -> str:
    """The web viewer's address that opens the data of ``grpc_url`` (``?url=`` parameter)."""
    return f"http://localhost:{web_port}/?url={quote(grpc_url, safe='')}"


def check_port_free(port: int, option: str) -> None:
    """Raise ``PortInUse`` when ``port`` cannot be bound on this machine.

    Raises:
        PortInUse: another process listens there (another viewer, server or replay).
    """
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        try:
            probe.bind(("", port))
        except OSError as err:
            raise PortInUse(port, option) from err


def replay(
    path: str | os.PathLike,
    *,
    save: str | os.PathLike | None = None,
    serve: bool = False,
    web_port: int | None = None,
    grpc_port: int | None = None,
    announce: Callable[[str], None] = print,
    wait: bool = True,
    start: float | None = None,
    stop: float | None = None,
    points: int = MAX_POINTS,
) -> Path | None:
    """Show a log in Rerun: spawn the viewer, or write an .rrd (``save``), or serve the web viewer.

    With ``serve`` the data are served over gRPC on ``grpc_port`` (default 9876) and the web
    viewer on ``web_port`` (default 9090); ``announce`` gets the one address that opens the
    viewer on the data, and the call blocks (the servers live as long as it does) until Ctrl-C
    (unless ``wait`` is false). The viewer gets an overview of at most ``points`` samples per
    series that keeps each series' extremes, and every sample from ``start`` to ``stop`` [s].

    Returns:
        The .rrd path when saving, else None.

    Raises:
        LogError: the log cannot be read.
        InputError: both ``save`` and ``serve`` given, or ports without ``serve``.
        PortInUse: a port is taken.
    """
    import rerun as rr

    if save is not None and serve:
        raise InputError("give either --save FILE or --serve, not both")
    if not serve and (web_port is not None or grpc_port is not None):
        raise InputError("--web-port and --grpc-port go with --serve")
    web_port = WEB_PORT if web_port is None else web_port
    grpc_port = GRPC_PORT if grpc_port is None else grpc_port
    if serve:
        if web_port == grpc_port:
            raise InputError(
                f"--web-port and --grpc-port are both {web_port}; give two different ports"
            )
        check_port_free(grpc_port, "--grpc-port")
        check_port_free(web_port, "--web-port")
    log = open_log(path)
    window = None
    if start is not None or stop is not None:
        t = log.result.time
        lo = t[0] if start is None else start
        hi = t[-1] if stop is None else stop
        if not len(t) or not np.any((t >= lo) & (t <= hi)):
            span = f"t = {t[0]:g} to {t[-1]:g} s" if len(t) else "no sample"
            raise InputError(
                f"no sample from t = {float(lo):.1f} to {float(hi):.1f} s; the log spans {span}"
            )
        window = (float(lo), float(hi))
    recording = rr.RecordingStream(application_id="pinwind_replay", recording_id=uuid.uuid4())
    recording.send_recording_name(Path(path).name)
    panels = log_panels(log)
    bp = blueprint(panels, scene_camera(log))
    if save is not None:
        out = Path(save)
        out.parent.mkdir(parents=True, exist_ok=True)
        recording.save(out, default_blueprint=bp)
        send_log(log, recording, panels, points=points, window=window)
        recording.flush()
        recording.disconnect()
        return out
    if serve:
        try:
            url = recording.serve_grpc(grpc_port=grpc_port, default_blueprint=bp)
            rr.serve_web_viewer(web_port=web_port, open_browser=False, connect_to=url)
        except Exception as err:  # rerun's own error for a port taken meanwhile, ...
            raise ServeFailed(f"cannot start the Rerun servers: {err}") from err
        send_log(log, recording, panels, points=points, window=window)
        recording.flush()
        announce(f"open {viewer_url(web_port, url)} (Ctrl-C to stop)")
        try:
            while wait:
                time.sleep(3600)
        except KeyboardInterrupt:
            pass
        return None
    recording.spawn(default_blueprint=bp)
    send_log(log, recording, panels, points=points, window=window)
    recording.flush()
    return None
