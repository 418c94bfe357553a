"""Replay a log in Rerun from the file alone: the machine turning in 3D, forces, plots.

``replay`` reads a log (``io/log_writer.py``) and sends Rerun:

- ``gearbox/<link>``: the world pose of every link over time (``Transform3D``); under it the
  gears, visuals, shafts, bearings and angle marks of ``io/replay_scene.py``, which also sends
  the body labels (``gearbox/labels``), the housing outline and the force arrows
  (``gearbox/mesh_forces``, ``gearbox/bearing_forces``; the legend is ``gearbox/scale``);
- ``plots/<panel>/<series>``: every panel of ``io/panels.py`` (speeds [rpm], torques [kN·m],
  power [kW], generator and rotor torque [kN·m] and power [kW], wind speed [m/s], tip-speed
  ratio and C_p [-], mesh forces [kN], transmission error [µm], bearing forces [kN] and moments
  [kN·m], load sharing [-], energy [kJ]), each series in its colour.

Everything is on the ``time`` timeline (simulated seconds), laid out by a blueprint: the 3D view
and its legend beside the plots, in tabs, with y ranges that do not magnify rounding. The viewer
opens on that timeline, paused at the start of the run: a live viewer gets a first layout (the
3D view from the default camera) before any data, and the machine comes before the plots, so
that the first frame stands in place while the rest loads.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import socket
import sys
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import quote

import numpy as np

from pinwind.dynamics.result import Result, concatenate
from pinwind.errors import InputError, NoViewer, PortInUse, ServeFailed
from pinwind.io.log_reader import LogFile, LogReader
from pinwind.io.overview import MinMaxDecimator, Overview, PanelOverview, coincident_groups
from pinwind.io.panels import GROUPS, Panel, legend_layout, model_of_log
from pinwind.io.replay_scene import (
    ARROW_FRACTION,
    Scene,
    first_view,
    send_scene,
    tooth_outline,
)

__all__ = [
    "ARROW_FRACTION",
    "TIMELINE",
    "FramePicker",
    "MinMaxDecimator",
    "Overview",
    "Sink",
    "blueprint",
    "first_layout",
    "line_widths",
    "replay",
    "send_frames",
    "send_log",
    "tooth_outline",
]

TIMELINE = "time"
#: Default ports of ``--serve``: Rerun's gRPC data server and its web viewer.
GRPC_PORT = 9876
WEB_PORT = 9090


def time_panel():
    """The time panel: on the ``time`` timeline (not Rerun's ``log_time``), paused, collapsed.

    Paused, the viewer stays at the first sample as data arrive (following would jump to the
    end of what has loaded).
    """
    import rerun.blueprint as rrb

    return rrb.TimePanel(state="collapsed", timeline=TIMELINE, play_state="paused")


def _eye(scene: Scene | None):
    import rerun.blueprint as rrb

    if scene is None:
        return None
    return rrb.EyeControls3D(
        position=scene.camera_position, look_target=scene.camera_target, eye_up=[0, 1, 0]
    )


def first_layout(scene: Scene | None = None):
    """The layout sent before the data: the 3D view from ``scene``'s camera, and its legend.

    The viewer shows it while the log loads (the plots come with ``blueprint`` at the end).
    """
    import rerun.blueprint as rrb

    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Spatial3DView(origin="gearbox", name="gearbox", eye_controls=_eye(scene)),
            rrb.TextDocumentView(origin="gearbox/scale", name="legend"),
            row_shares=[4, 1],
        ),
        time_panel(),
        collapse_panels=True,
    )


def blueprint(panels: list[Panel] | None = None, scene: Scene | None = None):
    """The layout: the 3D machine and its legend beside the plots, grouped in tabs.

    Each tab of ``panels.GROUPS`` holds its panels; each plot's y range follows
    ``panels.y_range`` (no magnified rounding), its legend sits in the corner where the data
    leave it the most room (``panels.legend_layout``), and hovering shows
    every series at that time. ``scene`` gives the default camera. Without arguments: the
    speed, mesh-force and bearing-force plots with automatic ranges. The time panel is on
    ``time``, paused (``time_panel``).
    """
    import rerun.blueprint as rrb

    def view(panel: Panel, legend: bool):
        corner, limits = legend_layout(panel) if legend else ("LeftTop", panel.y_range())
        return rrb.TimeSeriesView(
            origin=f"plots/{panel.key}",
            name=panel.title,
            axis_y=rrb.ScalarAxis(range=limits),
            plot_legend=rrb.PlotLegend(corner=corner, visible=legend),
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
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="gearbox", name="gearbox", eye_controls=_eye(scene)),
                rrb.TextDocumentView(origin="gearbox/scale", name="legend"),
                row_shares=[4, 1],
            ),
            plots,
            column_shares=[3, 2],
        ),
        time_panel(),
        collapse_panels=True,
    )


#: Points per plotted series in the overview of a run: about what a plot a screen wide shows.
MAX_POINTS = 2000
#: Samples read from the log at a time: the replay holds about one block of samples.
BLOCK = 5_000
#: Width of a plotted line [ui points], and the step between the nested widths of lines that lie
#: on top of each other (each shows as a stripe of its colour on each side of the next).
LINE_WIDTH = 1.5
STRIPE_WIDTH = 3.0
#: Two series of a plot coincide (would hide each other) when their min and max in every time
#: span differ by at most this fraction of the plot's y range (3 px of a 300 px plot).
COINCIDENT_FRACTION = 0.01


class FramePicker:
    """The samples drawn in 3D: a display rate over the run, full rate in a window.

    Fed block by block (``pick``): the first sample with a pose in each of ``points`` equal
    time spans from ``start`` to ``stop`` [s], every sample with a pose in ``window``
    (start, stop) [s], and (``last``) the last sample with a pose. Spans are cut on the log's
    own time stamps (whole nanoseconds), so that no rounding moves a sample across.
    """

    def __init__(self, start: float, stop: float, points: int, window: tuple[float, float] | None):
        self.start_ns = round(start * 1e9)
        self.length_ns = max(round(stop * 1e9) - self.start_ns, 1)
        self.points = max(points, 1)
        self.window = window
        self._cell = -1
        self._taken = -math.inf
        self._last: Result | None = None

    def pick(self, block: Result) -> np.ndarray:
        """Rows of ``block`` to draw."""
        posed = block.pose_rows
        if not len(posed):
            return posed
        stamps = np.rint(block.time[posed] * 1e9).astype(np.int64) - self.start_ns
        cells = np.clip(stamps * self.points // self.length_ns, 0, self.points - 1)
        new = cells != np.r_[self._cell, cells[:-1]]
        rows = posed[new & (cells > self._cell)]
        self._cell = max(self._cell, int(cells[-1]))
        if self.window is not None:
            t = block.time[posed]
            rows = np.union1d(rows, posed[(t >= self.window[0]) & (t <= self.window[1])])
        self._last = block.take(posed[-1:])
        if len(rows):
            self._taken = float(block.time[rows[-1]])
        return rows

    def last(self) -> Result | None:
        """The last sample with a pose, when it was not picked."""
        if self._last is not None and float(self._last.time[0]) > self._taken:
            return self._last
        return None


def _natural_key(name: str) -> list:
    """Sort key of names as Rerun orders entity path parts: digit runs by their value."""
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name)]


def line_widths(
    names: list[str], low: np.ndarray, high: np.ndarray, tolerance: float
) -> list[float]:
    """Widths [ui points] of a plot's lines so that lines on top of each other stay visible.

    Lines whose min and max (``low``, ``high``: (spans, series), from ``MinMaxDecimator``) differ
    by at most ``tolerance`` in every span would draw as one: each such group gets nested widths,
    widest first in Rerun's drawing order (entity names in natural order, later lines on top),
    so that every one shows as a stripe of its colour. Other lines get ``LINE_WIDTH``.
    """
    k = len(names)
    widths = [LINE_WIDTH] * k
    for together in coincident_groups(low, high, tolerance):
        together.sort(key=lambda i: _natural_key(names[i]))
        for rank, i in enumerate(together):
            widths[i] = LINE_WIDTH + STRIPE_WIDTH * (len(together) - 1 - rank)
    return widths


def _nanoseconds(times: np.ndarray) -> np.ndarray:
    """Times [s] as whole nanoseconds, the log times rint(t · 1e9)."""
    return np.rint(np.asarray(times) * 1e9).astype("timedelta64[ns]")


def _log_file(reader: LogReader, result: Result) -> LogFile:
    return LogFile(
        path=reader.path,
        result=result,
        metadata=reader.metadata,
        attachments=reader.attachments,
        channels=reader.channels,
        complete=reader.complete,
        problem=reader.problem,
        model_problem=reader.model_problem,
    )


def send_log(
    reader: LogReader,
    recording,
    *,
    points: int = MAX_POINTS,
    window: tuple[float, float] | None = None,
    block: int = BLOCK,
    progress: Callable[[float, float], None] | None = None,
) -> tuple[list[Panel], Scene]:
    """Stream a log's machine, poses, arrows and plots to a recording, a block at a time.

    The log is read in blocks of ``block`` samples (``LogReader.blocks``); each feeds a
    ``PanelOverview`` of every plotted series and a ``FramePicker`` of the samples drawn in 3D.
    Then the viewer gets: each series' min and max in ``points``/2 time spans (the whole series
    when the run has at most ``points`` samples), at most ``points`` + 1 3D frames, and every
    sample of ``window`` (start, stop) [s] besides. Memory is about one block, the frames and
    the overview, whatever the length of the log. ``progress`` gets (simulated time read, of
    the log) [s] before each block (``LogReader.blocks``).

    Returns:
        The panels (their series as sent outside the window, their y ranges those of the whole
        run) and the scene, for the blueprint.
    """
    import rerun as rr

    span = reader.span or (0.0, 0.0)
    gearbox, joints = model_of_log(reader)  # the model text, not the samples
    model = reader.metadata.get("pinwind.model", {})
    picker = FramePicker(span[0], span[1], points, window)
    overview = PanelOverview(span[0], span[1], points, model, joints=joints, gearbox=gearbox)
    frames: list[Result] = []

    def send_scalars(path: str, times: np.ndarray, values: np.ndarray) -> None:
        rr.send_columns(
            path,
            indexes=[rr.TimeColumn(TIMELINE, duration=_nanoseconds(times))],
            columns=rr.Scalars.columns(scalars=values),
            recording=recording,
        )

    for res in reader.blocks(block, progress=progress):
        if not len(res):
            continue
        block_panels, values = overview.add(res)
        if window is not None:
            inside = np.flatnonzero((res.time >= window[0]) & (res.time <= window[1]))
            if len(inside):
                k = 0
                for panel in block_panels:
                    for s in panel.series:
                        path = f"plots/{panel.key}/{s.name}"
                        send_scalars(path, res.time[inside], values[inside, k])
                        k += 1
        rows = picker.pick(res)
        if len(rows):
            frames.append(res.take(rows))
        del values, block_panels
    last = picker.last()
    if last is not None:
        frames.append(last)

    # The machine first: the viewer draws it while the plots load.
    scene = send_frames(_log_file(reader, concatenate(frames)) if frames else None, recording)
    sent: list[Panel] = []
    for kept in overview.panels():
        panel = kept.panel
        low, high = panel.y_range()
        widths = line_widths(
            [s.name for s in panel.series], kept.low, kept.high, COINCIDENT_FRACTION * (high - low)
        )
        for s, times, width in zip(panel.series, kept.times, widths, strict=True):
            path = f"plots/{panel.key}/{s.name}"
            rr.log(
                path,
                rr.SeriesLines(names=[s.name], colors=s.color, widths=[width]),
                static=True,
                recording=recording,
            )
            values = s.values
            if window is not None:
                outside = (times < window[0]) | (times > window[1])
                times, values = times[outside], values[outside]
            send_scalars(path, times, values)
        sent.append(panel)
    return sent, scene


def send_frames(view: LogFile | None, recording) -> Scene:
    """The machine, its poses at the frames of ``view.result``, labels, arrows and legend."""
    import rerun as rr

    rr.log("gearbox", rr.ViewCoordinates.RIGHT_HAND_Y_UP, static=True, recording=recording)
    if view is None:
        return Scene(camera_position=np.array([0.0, 0.0, -3.0]), camera_target=np.zeros(3))
    res = view.result.posed()
    time_column = rr.TimeColumn(TIMELINE, duration=_nanoseconds(res.time))

    def send(path: str, columns) -> None:
        rr.send_columns(path, indexes=[time_column], columns=columns, recording=recording)

    for i, link in enumerate(res.body_names):
        send(
            f"gearbox/{link}",
            rr.Transform3D.columns(
                translation=res.body_position[:, i], quaternion=res.body_quaternion[:, i]
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


#: The Rerun viewer program that rerun-sdk installs beside the Python interpreter.
VIEWER = "rerun"


def viewer_program() -> str | None:
    """The Rerun viewer to spawn: on PATH, else beside this Python (a venv not activated)."""
    found = shutil.which(VIEWER)
    if found is None:
        found = shutil.which(VIEWER, path=str(Path(sys.executable).parent))
    return found


def check_viewer_can_open() -> str:
    """The viewer program to spawn, or ``NoViewer`` when spawning it would fail or hang here.

    Without a display (Linux and the BSDs: neither DISPLAY nor WAYLAND_DISPLAY set, as on a
    headless or SSH machine) the viewer cannot open a window and never binds its port, so that
    ``spawn`` waits for ever; without the ``rerun`` program ``spawn`` fails with a long
    traceback. macOS and Windows always have a display.

    Raises:
        NoViewer: the reason, and the ``--save``/``--serve`` alternatives.
    """
    program = viewer_program()
    if program is None:
        raise NoViewer(
            f"no `{VIEWER}` program on PATH or beside {sys.executable} (install rerun-sdk)"
        )
    if sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")) and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        raise NoViewer("no display (neither DISPLAY nor WAYLAND_DISPLAY is set)")
    return program


@dataclass
class Sink:
    """Where a recording goes: an .rrd file, the web viewer, or a viewer spawned here.

    ``save``: the .rrd; ``serve``: Rerun's gRPC data server on ``grpc_port`` and its web viewer
    on ``web_port``; ``viewer``: the program spawned otherwise.
    """

    save: Path | None
    serve: bool
    web_port: int
    grpc_port: int
    viewer: str | None
    url: str = ""

    @classmethod
    def check(
        cls,
        *,
        save: str | os.PathLike | None,
        serve: bool,
        web_port: int | None,
        grpc_port: int | None,
    ) -> Sink:
        """The sink of the options, checked before any work (a headless machine fails fast).

        Raises:
            InputError: both ``save`` and ``serve``, ports without ``serve``, or equal ports.
            PortInUse: a port is taken.
            NoViewer: neither ``save`` nor ``serve``, and no display or no viewer binary here.
        """
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
        viewer = check_viewer_can_open() if save is None and not serve else None
        return cls(
            save=None if save is None else Path(save),
            serve=serve,
            web_port=web_port,
            grpc_port=grpc_port,
            viewer=viewer,
        )

    @property
    def live(self) -> bool:
        """A viewer draws the data as they arrive (not a file)."""
        return self.save is None

    def connect(self, recording) -> None:
        """Send ``recording`` to the sink: open the file, start the servers or spawn the viewer.

        Raises:
            ServeFailed: the servers do not start (a port taken meanwhile, ...).
        """
        import rerun as rr

        if self.save is not None:
            self.save.parent.mkdir(parents=True, exist_ok=True)
            recording.save(self.save)
        elif self.serve:
            try:
                self.url = recording.serve_grpc(grpc_port=self.grpc_port)
                rr.serve_web_viewer(web_port=self.web_port, open_browser=False, connect_to=self.url)
            except Exception as err:  # rerun's own error for a port taken meanwhile, ...
                raise ServeFailed(f"cannot start the Rerun servers: {err}") from err
        else:
            rr.spawn(executable_path=self.viewer, recording=recording)

    def finish(
        self, recording, *, announce: Callable[[str], None] = print, wait: bool = True
    ) -> Path | None:
        """Flush; close the file and return its path, or announce the served address and wait.

        Served, the call blocks (the servers live as long as it does) until Ctrl-C, unless
        ``wait`` is false.
        """
        recording.flush()
        if self.save is not None:
            recording.disconnect()
            return self.save
        if self.serve:
            announce(f"open {viewer_url(self.web_port, self.url)} (Ctrl-C to stop)")
            try:
                while wait:
                    time.sleep(3600)
            except KeyboardInterrupt:
                pass
        return None


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
    block: int = BLOCK,
    progress: Callable[[float, float], None] | None = None,
) -> Path | None:
    """Show a log in Rerun: spawn the viewer, or write an .rrd (``save``), or serve the web viewer.

    With ``serve`` the data are served over gRPC on ``grpc_port`` (default 9876) and the web
    viewer on ``web_port`` (default 9090); ``announce`` gets the one address that opens the
    viewer on the data, and the call blocks (the servers live as long as it does) until Ctrl-C
    (unless ``wait`` is false). The viewer gets an overview of at most ``points`` samples per
    series that keeps each series' extremes, and every sample from ``start`` to ``stop`` [s].
    The log is streamed in blocks of ``block`` samples (``send_log``, which reports to
    ``progress``): memory does not grow with the length of the log. A live viewer (spawned or
    served) gets a first layout before the data (the 3D view from the default camera, the
    ``time`` timeline paused at the start); the whole layout (blueprint) comes last, once the y
    ranges of the whole run are known.

    Returns:
        The .rrd path when saving, else None.

    Raises:
        LogError: the log cannot be read.
        InputError: both ``save`` and ``serve`` given, ports without ``serve``, or a window
            without samples.
        PortInUse: a port is taken.
        NoViewer: neither ``save`` nor ``serve``, and no display or no viewer binary here.
    """
    import rerun as rr

    sink = Sink.check(save=save, serve=serve, web_port=web_port, grpc_port=grpc_port)
    with LogReader(path) as reader:
        window = _window(reader, start, stop)
        recording = rr.RecordingStream(application_id="pinwind_replay", recording_id=uuid.uuid4())
        recording.send_recording_name(Path(path).name)
        sink.connect(recording)
        if sink.live:  # a viewer that draws as data arrive; a file gets one layout
            rr.send_blueprint(first_layout(_first_scene(reader)), recording=recording)
        sent, scene = send_log(
            reader, recording, points=points, window=window, block=block, progress=progress
        )
    rr.send_blueprint(blueprint(sent, scene), recording=recording)
    return sink.finish(recording, announce=announce, wait=wait)


def _first_scene(reader: LogReader) -> Scene | None:
    """The default camera on the log's first sample, or None for a log without samples."""
    span = reader.span
    if span is None:
        return None
    first = reader.read(start=span[0], stop=span[0])
    if not len(first.pose_rows):
        return None
    return first_view(_log_file(reader, first))


def _window(
    reader: LogReader, start: float | None, stop: float | None
) -> tuple[float, float] | None:
    """The ``--from``/``--to`` window (start, stop) [s] with open ends closed, or None.

    Raises:
        InputError: no sample of the log lies in the window.
    """
    if start is None and stop is None:
        return None
    span = reader.span
    lo = (span[0] if span else 0.0) if start is None else start
    hi = (span[1] if span else 0.0) if stop is None else stop
    if span is None or not len(reader.read(start=lo, stop=hi, channels=[]).time):
        where = f"t = {span[0]:g} to {span[1]:g} s" if span else "no sample"
        raise InputError(
            f"no sample from t = {float(lo):.1f} to {float(hi):.1f} s; the log spans {where}"
        )
    return float(lo), float(hi)
