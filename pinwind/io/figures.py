"""Static figures of a log for reports: ``pinwind plot LOG -o DIR`` (matplotlib, Agg backend).

One figure per group of ``io/panels.py`` (speeds, torques and power, rotor, mesh forces, force
components, mesh deflection, bearings, load sharing, energy; a group without panels in the run,
such as the rotor of a run without one, gets no figure), one subplot per panel, the time in
seconds on a shared axis. Files are numbered by the group's place in ``GROUPS``. Every figure
says in its caption which model and log it comes from and how the run was made (dt, loads,
status, pinwind version, model hash), so that a figure pasted in a report keeps its provenance.
The y ranges follow ``panels.y_range`` (no magnified rounding); colours are distinct within a
subplot and equal to the replay's; legends sit to the right, outside the data; identical series
are drawn with different dashes and widths so that none hides another.
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import FigureFailed, InputError
from pinwind.io.log_reader import LogReader
from pinwind.io.overview import DecimatedPanel, PanelOverview
from pinwind.io.panels import GROUPS, model_of_log

#: Figure formats, by file extension.
FORMATS = ("png", "svg", "pdf")
#: Above twice this many samples a series is drawn as its min and max in this many time spans.
MAX_POINTS = 4000
#: Samples read from the log at a time.
BLOCK = 20_000
#: (dash pattern, line width) per series in a subplot: identical lines stay visible.
_STYLES = (("-", 2.6), ((0, (5, 2)), 1.9), ((0, (1, 1.5)), 1.5), ((0, (6, 2, 1, 2)), 1.2))


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
    loads = [f"{k}: {v}" for k, v in (meta.get("torques") or {}).items()]
    loads += [f"{k}: speed {v}" for k, v in (meta.get("speeds") or {}).items()]
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
    return "\n".join(textwrap.wrap(text, 150))


def _draw(ax, kept: DecimatedPanel) -> None:
    panel = kept.panel
    for k, (series, times) in enumerate(zip(panel.series, kept.times, strict=True)):
        dash, width = _STYLES[k % len(_STYLES)] if len(panel.series) > 1 else _STYLES[0]
        ax.plot(
            times,
            series.values,
            color=np.array(series.color) / 255.0,
            linestyle=dash,
            linewidth=width,
            label=series.name,
        )
    ax.set_ylim(*panel.y_range())
    ax.set_title(panel.title, fontsize=9, loc="left")
    ax.set_ylabel(f"[{panel.unit}]", fontsize=8)
    ax.grid(True, linewidth=0.3)
    ax.tick_params(labelsize=7)
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.legend(
        loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False, borderaxespad=0
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
        groups: the figures to write (``panels.GROUPS`` names); default all.
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
        for res in reader.blocks(block, start=start, stop=stop, progress=progress):
            meta, status = res.metadata, res.status
            if len(res):
                overview.add(res)
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
    all_panels = overview.panels()
    note = caption(meta, status, path, shown, start, stop)
    written = []
    for number, group in enumerate(GROUPS, start=1):
        shown_panels = [p for p in all_panels if p.panel.group == group]
        if not shown_panels or (groups is not None and group not in groups):
            continue
        rows = len(shown_panels)
        fig, axes = plt.subplots(
            rows, 1, figsize=(10, 1.0 + 2.3 * rows), sharex=True, squeeze=False
        )
        for ax, kept in zip(axes[:, 0], shown_panels, strict=True):
            _draw(ax, kept)
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(f"{meta.get('model_name', '')}: {group}", fontsize=11, x=0.02, ha="left")
        fig.tight_layout(rect=(0, 0.45 / (1.0 + 2.3 * rows), 1, 1))
        fig.text(0.01, 0.005, note, fontsize=6.5, va="bottom", ha="left", color="0.25")
        file = out / f"{number:02d}_{group.replace(' ', '_')}.{format}"
        _save(fig, file, dpi)
        plt.close(fig)
        written.append(file)
    return written


def _save(fig: Any, file: Path, dpi: int) -> None:
    """Writes a figure under a hidden name, renamed at the end.

    A full disk or a failed write then leaves no partial figure; raises ``FigureFailed`` naming
    the file.
    """
    part = file.with_name(f".{file.name}.{os.getpid()}.part")
    try:
        fig.savefig(part, dpi=dpi, format=file.suffix.lstrip("."))
        os.replace(part, file)
    except OSError as err:
        part.unlink(missing_ok=True)
        raise FigureFailed(str(file), err.strerror or str(err)) from err
