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
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pinwind.errors import InputError
from pinwind.io.panels import GROUPS, Panel, log_panels

#: Figure formats, by file extension.
FORMATS = ("png", "svg", "pdf")
#: Above this many samples a series is drawn as its min/max envelope over this many columns.
MAX_POINTS = 4000
#: (dash pattern, line width) per series in a subplot: identical lines stay visible.
_STYLES = (("-", 2.6), ((0, (5, 2)), 1.9), ((0, (1, 1.5)), 1.5), ((0, (6, 2, 1, 2)), 1.2))


def envelope(time: np.ndarray, values: np.ndarray, columns: int = MAX_POINTS):
    """(time, values) reduced to the min and max of ``columns`` equal slices, in time order.

    Series with at most 2 × ``columns`` samples are returned as they are; peaks are never lost.
    """
    n = len(values)
    if n <= 2 * columns:
        return time, values
    edges = np.linspace(0, n, columns + 1).astype(int)
    t_out = np.empty(2 * columns)
    v_out = np.empty(2 * columns)
    for k in range(columns):
        a, b = edges[k], edges[k + 1]
        chunk = values[a:b]
        finite = bool(np.any(np.isfinite(chunk)))
        lo = int(np.nanargmin(chunk)) if finite else 0
        hi = int(np.nanargmax(chunk)) if finite else 0
        first, second = sorted((lo, hi))
        t_out[2 * k], v_out[2 * k] = time[a + first], chunk[first]
        t_out[2 * k + 1], v_out[2 * k + 1] = time[a + second], chunk[second]
    return t_out, v_out


def caption(log, start: float | None, stop: float | None) -> str:
    """Provenance of a figure: model, log file, run settings, loads, status and versions."""
    res = log.result
    meta = res.metadata
    info = log.metadata.get("pinwind", {})
    loads = [f"{k}: {v}" for k, v in (meta.get("torques") or {}).items()]
    loads += [f"{k}: speed {v}" for k, v in (meta.get("speeds") or {}).items()]
    window = ""
    if len(res):
        window = f"; shown t = {res.time[0]:.6g} to {res.time[-1]:.6g} s"
    if start is not None or stop is not None:
        window += f" (asked --from {start} --to {stop})"
    text = (
        f"model {meta.get('model_name', '?')} (sha256 {str(meta.get('model_sha256', ''))[:12]}), "
        f"log {Path(log.path).name}: {res.status}; dt = {meta.get('dt', float('nan')):g} s, "
        f"logged every {meta.get('log', {}).get('stride', 1)} sample(s){window}; "
        f"loads: {'; '.join(loads) or 'none'}; pinwind {info.get('pinwind_version', '?')}"
    )
    return "\n".join(textwrap.wrap(text, 150))


def _draw(ax, time: np.ndarray, panel: Panel) -> None:
    for k, series in enumerate(panel.series):
        dash, width = _STYLES[k % len(_STYLES)] if len(panel.series) > 1 else _STYLES[0]
        t, v = envelope(time, series.values)
        ax.plot(
            t,
            v,
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
) -> list[Path]:
    """Write one figure per panel group of a log; return the files written.

    Args:
        path: the log (MCAP file written by pinwind).
        out_dir: folder for the figures (created).
        start, stop: time window [s] (inclusive; open ends when None).
        format: ``png``, ``svg`` or ``pdf`` (the file extension).
        dpi: resolution of PNG figures.
        groups: the figures to write (``panels.GROUPS`` names); default all.

    Raises:
        LogError: the log cannot be read.
        InputError: an unknown format.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pinwind.io.mcap_log import open_log

    format = format.lower().lstrip(".")
    if format not in FORMATS:
        raise InputError(f'unknown figure format "{format}"; give one of {", ".join(FORMATS)}')
    log = open_log(path, start=start, stop=stop)
    res = log.result
    if len(res) == 0:
        raise InputError(
            f"{path}: no samples between --from {start} and --to {stop}; the log spans "
            f"the run's duration {res.metadata.get('duration', '?')} s"
        )
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    all_panels = log_panels(log)
    note = caption(log, start, stop)
    written = []
    for number, group in enumerate(GROUPS, start=1):
        shown = [p for p in all_panels if p.group == group and p.series]
        if not shown or (groups is not None and group not in groups):
            continue
        fig, axes = plt.subplots(
            len(shown), 1, figsize=(10, 1.0 + 2.3 * len(shown)), sharex=True, squeeze=False
        )
        for ax, panel in zip(axes[:, 0], shown, strict=True):
            _draw(ax, res.time, panel)
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(f"{res.metadata.get('model_name', '')}: {group}", fontsize=11, x=0.02,
                     ha="left")  # fmt: skip
        fig.tight_layout(rect=(0, 0.45 / (1.0 + 2.3 * len(shown)), 1, 1))
        fig.text(0.01, 0.005, note, fontsize=6.5, va="bottom", ha="left", color="0.25")
        file = out / f"{number:02d}_{group.replace(' ', '_')}.{format}"
        fig.savefig(file, dpi=dpi)
        plt.close(fig)
        written.append(file)
    return written
