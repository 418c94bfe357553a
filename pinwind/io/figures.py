"""Static figures of a log for reports: ``pinwind plot LOG -o DIR`` (matplotlib, Agg backend).

One figure per group of ``io/panels.py`` (speeds, torques and power, rotor, mesh forces, force
components, mesh deflection, bearings, load sharing, energy; a group without panels in the run,
such as the rotor of a run without one, gets no figure), one subplot per panel, the time in
seconds on a shared axis. Files are numbered by the group's place in ``GROUPS``; after them, one
figure per mesh the run cut into slices (``FACE_LOAD``: the line load across the face over
time and K_Hβ(t), ``io/face_load_figures.py``). Every figure
says in its caption which model and log it comes from and how the run was made (dt, loads,
status, pinwind version, model hash), so that a figure pasted in a report keeps its provenance.
The y ranges follow ``panels.y_range`` (no magnified rounding); colours are distinct within a
subplot and equal to the replay's; legends sit to the right, outside the data, and the
constrained layout keeps them, the titles and the caption on the page (``io/figure_layout.py``).
The caption gives the loads in the units of the axes (kN·m, rpm). Series that lie on top of each
other (identical planets) are drawn with nested widths and dashes, and the legend says which
coincide. Shafts whose speeds differ by more than ``SPEED_BAND`` get subplots of their
own, so that a fast shaft does not flatten the slow ones. The transmission error of a rigid mesh
is zero by construction: it is drawn at zero with a note, not its numerical drift.
"""

from __future__ import annotations

import os
import re
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import FigureFailed, InputError
from pinwind.io.face_load_figures import FaceLoadMap, plot_face_load, sliced_meshes
from pinwind.io.figure_layout import caption_below, save_figure
from pinwind.io.log_reader import LogReader
from pinwind.io.overview import DecimatedPanel, PanelOverview, coincident_groups
from pinwind.io.panels import GROUPS, model_of_log

#: Figure formats, by file extension.
FORMATS = ("png", "svg", "pdf")
#: Above twice this many samples a series is drawn as its min and max in this many time spans.
MAX_POINTS = 4000
#: Samples read from the log at a time.
BLOCK = 20_000
#: (dash pattern, line width) of the lines of a group that coincide, the first drawn first
#: (underneath): identical lines stay visible. A line alone is ``_ALONE``.
_STYLES = (("-", 2.6), ((0, (5, 2)), 1.9), ((0, (1, 1.5)), 1.5), ((0, (6, 2, 1, 2)), 1.2))
_ALONE = ("-", 1.6)
#: Two series of a subplot coincide when their min and max in every time span differ by at most
#: this fraction of the subplot's y range (as in the replay).
COINCIDENT_FRACTION = 0.01
#: Largest ratio of the fastest to the slowest (non-zero) speed of one subplot.
SPEED_BAND = 10.0
#: A speed below this fraction of the fastest is a standstill (a locked joint's rounding noise).
STANDSTILL = 1e-9
#: The group name of the face load figures (one per sliced mesh, after ``GROUPS``' figures).
FACE_LOAD = "face load"
#: Speed panels, split in bands of ``SPEED_BAND``.
SPEED_PANELS = ("speed", "body_speed")
#: A number in a caption: digits with a decimal point, not part of a word or a version.
_NUMBER = re.compile(r"(?<![\w.])-?\d+\.\d+(?:e[-+]?\d+)?(?![\w.])")


def rounded(text: str) -> str:
    """``text`` with every decimal number to 4 significant digits (15.750374768772428 → 15.75)."""
    return _NUMBER.sub(lambda m: f"{float(m.group()):.4g}", text)


#: Keyword arguments of a signal's text that are values of the signal (converted to the
#: caption's unit); the others are times [s] or frequencies [Hz] and stay as they are.
_VALUE_KEYWORDS = {"value", "start_value", "end_value", "before", "after", "mean", "amplitude"}
#: Signals of ``loads/signal_text.py`` whose values are keyword arguments (``_VALUE_KEYWORDS``).
_SHAPED = {"ramp", "step", "sine"}
#: SI unit → the unit captions and axes use (``units.to_display``).
_CAPTION_UNITS = {"N·m": "kN·m", "rad/s": "rpm", "W": "kW", "N": "kN"}
#: Settings of a rotor, generator or wind in the log (SI) → their SI unit.
_SETTING_UNITS = {
    "torque": "N·m",
    "slope": "N·m·s/rad",
    "sync_speed": "rad/s",
    "gain": "N·m·s²",
    "rated_power": "W",
    "radius": "m",
    "inertia": "kg·m²",
    "air_density": "kg/m³",
    "pitch": "rad",
    "mean": "m/s",
    "amplitude": "m/s",
    "frequency": "Hz",
    "voltage": "V",
    "stator_resistance": "Ω",
    "rotor_resistance": "Ω",
    "stator_leakage": "H",
    "rotor_leakage": "H",
    "magnetizing": "H",
    "height": "m",
    "hub_height": "m",
    "mass": "kg",
    "shaft_tilt": "rad",
    "speed_set": "rad/s",
    "kp": "s",
    "gain_angle": "rad",
    "pitch_min": "rad",
    "pitch_max": "rad",
}
#: Settings in rad/s that are not shaft speeds (a filter's corner, the pitch rate): kept in SI.
_SETTINGS_IN_SI = {"corner": "rad/s", "rate": "rad/s"}


def _number(value: float, unit: str) -> str:
    """An SI value in the caption's unit for ``unit``, 4 significant digits."""
    from pinwind.units import to_display

    shown = _CAPTION_UNITS.get(unit, unit)
    return f"{float(to_display(np.asarray(value, dtype=float), shown)):.4g}"


def signal_in_units(text: str, unit: str) -> str:
    """A signal's text (``loads/signal_text.py``) with its values in the caption's unit.

    ``unit`` is the signal's SI unit (N·m, rad/s); torques are given in kN·m and speeds in rpm,
    as on the axes: a number, and the value arguments of ``ramp``, ``step``, ``sine``
    (``start_value``, ``mean``, ...), are converted, times and frequencies kept. A text that is
    not a signal's (a callable's description) is given as it is, with its SI unit unless it
    names it.
    """
    import ast

    shown = _CAPTION_UNITS.get(unit, unit)
    try:
        body = ast.parse(text, mode="eval").body
    except SyntaxError:
        body = None
    terms: list[ast.expr] = []
    while isinstance(body, ast.BinOp) and isinstance(body.op, ast.Add):
        terms.insert(0, body.right)
        body = body.left
    terms.insert(0, body)  # type: ignore[arg-type]

    def number(node: ast.expr) -> float | None:
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            value = number(node.operand)
            return None if value is None else -value
        constant = node.value if isinstance(node, ast.Constant) else None
        if isinstance(constant, int | float) and not isinstance(constant, bool):
            return float(constant)
        return None

    def converted(node: ast.expr) -> ast.expr | None:
        """The term in the caption's unit; None when it is not a number or a shaped signal."""
        value = number(node)
        if value is not None:
            return ast.Name(_number(value, unit))  # unparsed as written: 4 significant digits
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
            return None
        if node.func.id not in _SHAPED or node.args:
            return None  # a table or a file's channel: values as its file holds them
        for keyword in node.keywords:
            value = number(keyword.value)
            if keyword.arg in _VALUE_KEYWORDS and value is not None:
                keyword.value = ast.Name(_number(value, unit))
        return node

    parts = [converted(term) for term in terms]
    if any(part is None for part in parts):
        return text if unit in text else f"{text} [{unit}]"
    return f"{' + '.join(ast.unparse(part) for part in parts if part is not None)} {shown}"


def _is_table(value: dict[str, Any] | list[Any]) -> bool:
    """Whether a setting holds more than a few numbers (a C_p table, a list of breakpoints)."""
    if isinstance(value, list):
        return len(value) > 3
    return any(isinstance(item, dict | list) and len(item) > 3 for item in value.values())


def _settings(values: dict[str, Any]) -> str:
    """A load's settings as ``key value unit`` (a rotor's radius, a generator's law, ...).

    Powers in kW, torques in kN·m and speeds in rpm, as on the axes; other settings in SI.
    """
    out = []
    for key, value in values.items():
        if value is None:
            continue  # a setting left unset (a rotor without a hub height): nothing to show
        if isinstance(value, dict | list) and _is_table(value):
            # a C_p or C_t table: its numbers would fill the figure, its name says it was given
            name = key.replace("_", " ")
            out.append(name if name.endswith("table") else f"{name} table")
            continue
        if isinstance(value, dict):
            out.append(f"{key.replace('_', ' ')} ({_settings(value)})")
            continue
        unit = _SETTING_UNITS.get(key)
        if key in _SETTINGS_IN_SI and isinstance(value, int | float):
            out.append(f"{key.replace('_', ' ')} {value:.4g} {_SETTINGS_IN_SI[key]}")
            continue
        if unit is None or isinstance(value, bool) or not isinstance(value, int | float):
            out.append(f"{key.replace('_', ' ')} {value}")
            continue
        shown = _CAPTION_UNITS.get(unit, unit)
        out.append(f"{key.replace('_', ' ')} {_number(value, unit)} {shown}")
    return ", ".join(out)


def loads_text(meta: dict[str, Any]) -> list[str]:
    """Every load of a run as its metadata records them, in the units of the axes.

    Torques [kN·m], speeds (driven and initial) [rpm], rotors, generators and the wind.
    """
    loads = [
        f"{k}: torque {signal_in_units(v, 'N·m')}" for k, v in (meta.get("torques") or {}).items()
    ]
    loads += [
        f"{k}: speed {signal_in_units(v, 'rad/s')}" for k, v in (meta.get("speeds") or {}).items()
    ]
    loads += [
        f"{k}: initial speed {signal_in_units(v, 'rad/s')}"
        for k, v in (meta.get("initial_speeds") or {}).items()
    ]
    loads += [f"{k}: rotor ({_settings(v)})" for k, v in (meta.get("rotors") or {}).items()]
    loads += [f"{k}: generator ({_settings(v)})" for k, v in (meta.get("generators") or {}).items()]
    wind = meta.get("wind")
    if wind:
        loads.append(f"wind: {_settings(wind) if isinstance(wind, dict) else wind}")
    return loads


def caption(
    meta: dict[str, Any],
    status: str,
    path: str | os.PathLike,
    shown: tuple[float, float] | None,
    start: float | None,
    stop: float | None,
) -> str:
    """Provenance of a figure: model, log file, run settings, loads, status and versions.

    Args:
        meta: the run's metadata as read back (``Result.metadata``).
        status: how the run ended.
        path: the log.
        shown: times of the first and last sample drawn [s].
        start, stop: the window asked for [s].
    """
    loads = loads_text(meta)
    window = ""
    if shown is not None:
        window = f"; shown t = {shown[0]:.6g} to {shown[1]:.6g} s"
    if start is not None or stop is not None:
        window += f" (asked --from {start} --to {stop})"
    text = (
        f"model {meta.get('model_name', '?')} (sha256 {str(meta.get('model_sha256', ''))[:12]}), "
        f"log {Path(path).name}: {status}; dt = {meta.get('dt', float('nan')):g} s, "
        f"logged every {meta.get('log', {}).get('stride', 1)} sample(s){window}; "
        f"loads: {'; '.join(loads) or 'none'}; pinwind {meta.get('pinwind_version', '?')}"
    )
    return "\n".join(textwrap.wrap(rounded(text), 150))


def together(names: Sequence[str]) -> str:
    """Names of coinciding series, compact: sun_planet1, sun_planet2, sun_planet3 → sun_planet1–3.

    Names that differ only in consecutive numbers are contracted; others are listed.
    """
    parts = [re.fullmatch(r"(\D*)(\d+)(.*)", name) for name in names]
    if all(parts):
        found = [(m.group(1), int(m.group(2)), m.group(3)) for m in parts if m]
        numbers = [n for _, n, _ in found]
        if len({(a, c) for a, _, c in found}) == 1 and numbers == list(
            range(numbers[0], numbers[0] + len(numbers))
        ):
            prefix, _, suffix = found[0]
            return f"{prefix}{numbers[0]}–{numbers[-1]}{suffix}"
    return ", ".join(names)


def _draw(ax, kept: DecimatedPanel) -> None:
    from matplotlib.lines import Line2D

    panel = kept.panel
    low, high = panel.y_range()
    groups = coincident_groups(kept.low, kept.high, COINCIDENT_FRACTION * (high - low))
    style = {}
    for group in groups:
        for rank, i in enumerate(group):
            style[i] = _STYLES[rank % len(_STYLES)] if len(group) > 1 else _ALONE
    for k, (series, times) in enumerate(zip(panel.series, kept.times, strict=True)):
        dash, width = style[k]
        ax.plot(
            times,
            series.values,
            color=np.array(series.color) / 255.0,
            linestyle=dash,
            linewidth=width,
            label=series.name,
        )
    handles, labels = ax.get_legend_handles_labels()
    for group in groups:
        # A legend entry without a line (not drawn in the axes) says why some lines seem
        # missing; zeros get a note instead.
        if len(group) > 1 and any(np.any(panel.series[i].values) for i in group):
            names = [panel.series[i].name for i in group]
            handles.append(Line2D([], [], linestyle="none"))
            # wrapped: one long line would narrow the axes by its whole width
            labels.append(textwrap.fill(f"{together(names)} coincide", 36))
    for note in panel.notes:
        ax.text(0.01, 0.97, note, transform=ax.transAxes, fontsize=7, va="top", color="0.2")
    ax.set_ylim(low, high)
    ax.set_title(panel.title, fontsize=9, loc="left")
    ax.set_ylabel(f"[{panel.unit}]", fontsize=8)
    ax.grid(True, linewidth=0.3)
    ax.tick_params(labelsize=7)
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.legend(
        handles,
        labels,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize=7,
        frameon=False,
        borderaxespad=0,
    )


def speed_bands(kept: DecimatedPanel) -> list[DecimatedPanel]:
    """A speed panel split so that no subplot's speeds differ by more than ``SPEED_BAND``.

    Series in increasing order of their largest |speed|; a band takes series while the largest
    stays within ``SPEED_BAND`` times the band's smallest non-zero one (a locked joint, zero
    but for rounding, below ``STANDSTILL`` of the fastest, joins the slowest band). Each band
    keeps the panel's order of series; a panel that needs one band is returned as it is.
    """
    panel = kept.panel
    peak = [float(np.max(np.abs(s.values), initial=0.0)) for s in panel.series]
    negligible = STANDSTILL * max(peak, default=0.0)
    bands: list[list[int]] = []
    floor = 0.0
    for i in sorted(range(len(peak)), key=lambda i: peak[i]):
        if bands and (floor == 0.0 or peak[i] <= SPEED_BAND * floor):
            bands[-1].append(i)
        else:
            bands.append([i])
            floor = 0.0
        if floor == 0.0 and peak[i] > negligible:
            floor = peak[i]
    if len(bands) <= 1:
        return [kept]
    out = []
    for number, band in enumerate(bands, start=1):
        band.sort()
        top = max(peak[i] for i in band)
        out.append(
            DecimatedPanel(
                replace(
                    panel,
                    series=[panel.series[i] for i in band],
                    title=f"{panel.title}, {number} of {len(bands)}: up to {top:.4g} {panel.unit}",
                ),
                [kept.times[i] for i in band],
                kept.low[:, band],
                kept.high[:, band],
            )
        )
    return out


def rigid_meshes_at_zero(kept: DecimatedPanel, rigid: set[str]) -> DecimatedPanel:
    """The transmission-error panel with the rigid meshes' series at zero, and a note.

    A rigid mesh keeps its teeth in contact by construction (a constraint row): its
    transmission error is zero, and what the log holds is the solver's numerical drift.
    """
    panel = kept.panel
    drawn = [s for s in panel.series if s.name in rigid]
    if not drawn:
        return kept
    drift = max(float(np.max(np.abs(s.values), initial=0.0)) for s in drawn)
    series = [
        replace(s, values=np.zeros_like(s.values)) if s.name in rigid else s for s in panel.series
    ]
    which = (
        "rigid meshes"
        if len(drawn) == len(panel.series)
        else f"rigid meshes {together([s.name for s in drawn])}"
    )
    note = (
        f"{which}: no transmission error (drawn at 0; the log's numerical drift, "
        f"≤ {drift:.1g} {panel.unit}, is not a result)"
    )
    index = [i for i, s in enumerate(panel.series) if s.name in rigid]
    low, high = kept.low.copy(), kept.high.copy()
    low[:, index] = np.where(np.isfinite(low[:, index]), 0.0, low[:, index])
    high[:, index] = np.where(np.isfinite(high[:, index]), 0.0, high[:, index])
    return DecimatedPanel(
        replace(panel, series=series, notes=[*panel.notes, note]), kept.times, low, high
    )


def plot_log(
    path: str | os.PathLike,
    out_dir: str | os.PathLike,
    *,
    start: float | None = None,
    stop: float | None = None,
    format: str = "png",
    dpi: int = 110,
    groups: Sequence[str] | None = None,
    block: int = BLOCK,
    progress: Callable[[float, float], None] | None = None,
) -> list[Path]:
    """Write one figure per panel group of a log; return the files written.

    The log is read ``block`` samples at a time (``LogReader.blocks``) into a ``PanelOverview``
    of ``MAX_POINTS`` min/max spans per series: memory does not grow with the length of the log,
    and every peak is drawn.

    Args:
        path: the log (MCAP file written by pinwind).
        out_dir: folder for the figures (created).
        start, stop: time window [s] (inclusive; open ends when None).
        format: ``png``, ``svg`` or ``pdf`` (the file extension).
        dpi: resolution of PNG figures.
        groups: the figures to write (``panels.GROUPS`` names, and ``FACE_LOAD`` for the
            sliced meshes' face load figures); default all.
        block: samples read at a time.
        progress: gets (simulated time read, of the window) [s] before each block.

    Raises:
        LogError: the log cannot be read.
        InputError: an unknown format, or no sample in the window.
        FigureFailed: a figure or the folder cannot be written (a full disk, no permission).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    format = format.lower().lstrip(".")
    if format not in FORMATS:
        raise InputError(f'unknown figure format "{format}"; give one of {", ".join(FORMATS)}')
    with LogReader(path) as reader:
        span = reader.span or (0.0, 0.0)
        first = span[0] if start is None else max(start, span[0])
        last = span[1] if stop is None else min(stop, span[1])
        gearbox, joints = model_of_log(reader)
        model = reader.metadata.get("pinwind.model", {})
        overview = PanelOverview(
            first, max(last, first), 2 * MAX_POINTS, model, joints=joints, gearbox=gearbox
        )
        meta: dict[str, Any] = {}
        status = ""
        shown: tuple[float, float] | None = None
        faces: list[FaceLoadMap] | None = None
        for res in reader.blocks(block, start=start, stop=stop, progress=progress):
            meta, status = res.metadata, res.status
            if faces is None and (groups is None or FACE_LOAD in groups):
                faces = [
                    FaceLoadMap(m, res.slice_line_loads(m)[0], first, max(last, first))
                    for m in sliced_meshes(res)
                ]
            if len(res):
                overview.add(res)
                for face in faces or []:
                    face.add(res)
                shown = (shown[0] if shown else float(res.time[0]), float(res.time[-1]))
        if shown is None:
            duration = reader.metadata.get("pinwind.run", {}).get("duration", "?")
            raise InputError(
                f"{path}: no samples between --from {start} and --to {stop}; the log spans "
                f"the run's duration {duration} s"
            )
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise FigureFailed(str(out), err.strerror or str(err)) from err
    rigid = {n for n, spec in (meta.get("meshes") or {}).items() if spec.get("type") == "rigid"}
    all_panels = []
    for kept in overview.panels():
        if kept.panel.key == "transmission_error":
            kept = rigid_meshes_at_zero(kept, rigid)
        all_panels += speed_bands(kept) if kept.panel.key in SPEED_PANELS else [kept]
    note = caption(meta, status, path, shown, start, stop)
    written = []
    for number, group in enumerate(GROUPS, start=1):
        shown_panels = [p for p in all_panels if p.panel.group == group]
        if not shown_panels or (groups is not None and group not in groups):
            continue
        rows = len(shown_panels)
        fig, axes = plt.subplots(
            rows,
            1,
            figsize=(10, 1.0 + 2.3 * rows),
            sharex=True,
            squeeze=False,
            layout="constrained",
        )
        for ax, kept in zip(axes[:, 0], shown_panels, strict=True):
            _draw(ax, kept)
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(f"{meta.get('model_name', '')}: {group}", fontsize=11, x=0.02, ha="left")
        caption_below(fig, note)
        file = out / f"{number:02d}_{group.replace(' ', '_')}.{format}"
        save_figure(fig, file, dpi)
        plt.close(fig)
        written.append(file)
    for face in faces or []:
        file = out / f"{len(GROUPS) + 1:02d}_face_load_{face.mesh}.{format}"
        written.append(plot_face_load(face, file, note=note, dpi=dpi))
    return written
