"""The load distribution across the face of a sliced mesh: line load over face position and time.

``pinwind plot LOG`` writes one such figure per mesh the run cut into slices (``slice_line_load``,
``dynamics/series.py``): the line load of each slice on the loaded flank as a colour map over
the face position (x: the slice's centre from the face centre along gear A's axis, mm) and time
(y, s), and beside it the face load factor K_Hβ(t) = w_max / w_mean (ISO 6336-1 §7) on the same
time axis. This is the view of the load across the face that multibody gear tools give
(SIMPACK's and Romax's line load maps): a misalignment shows as load piled at one end, a lead
crowning as a ridge in the middle, a lift-off as a band of zero.

A log is read block by block (``LogReader.blocks``): each map keeps, in each of at most
``TIME_SPANS`` spans of the window, the largest line load of each slice and the smallest and
largest K_Hβ (every peak is drawn, as in the other figures); memory does not grow with the log.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.dynamics.result import Result

#: Spans of the time window a map keeps (rows of the colour map).
TIME_SPANS = 400


@dataclass
class FaceLoadMap:
    """One sliced mesh's line load over face position and time, in spans of a time window.

    Attributes:
        mesh: the mesh.
        positions: each slice's centre from the face centre along gear A's axis [m], (N,).
        first, last: the window [s].
        spans: spans of the window kept.
        line_load: the largest line load of each slice in each span [N/m], (spans, N); NaN in
            a span without a sample.
        factor_low, factor_high: the smallest and largest K_Hβ in each span [-], (spans,).
        time_low, time_high: the first and last sample time in each span [s], (spans,).
    """

    mesh: str
    positions: np.ndarray
    first: float
    last: float
    spans: int = TIME_SPANS
    line_load: np.ndarray = field(init=False)
    factor_low: np.ndarray = field(init=False)
    factor_high: np.ndarray = field(init=False)
    time_low: np.ndarray = field(init=False)
    time_high: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.positions = np.asarray(self.positions, dtype=float)
        self.line_load = np.full((self.spans, self.positions.size), np.nan)
        self.factor_low = np.full(self.spans, np.nan)
        self.factor_high = np.full(self.spans, np.nan)
        self.time_low = np.full(self.spans, np.nan)
        self.time_high = np.full(self.spans, np.nan)

    def add(self, block: Result) -> None:
        """Folds in a block of samples (a Result of the same run)."""
        if not len(block):
            return
        _, line_load = block.slice_line_loads(self.mesh)
        factor = block.mesh(self.mesh).face_load_factor
        time = block.time
        width = max(self.last - self.first, np.finfo(float).tiny)
        span = np.clip(((time - self.first) / width * self.spans).astype(int), 0, self.spans - 1)
        starts = np.flatnonzero(np.r_[True, span[1:] != span[:-1]])
        at = span[starts]
        # a span may come back in the next block: fold with what it holds (fmax/fmin skip NaN)
        for target, values, fold in (
            (self.line_load, line_load, np.fmax),
            (self.factor_high, factor, np.fmax),
            (self.factor_low, factor, np.fmin),
            (self.time_high, time, np.fmax),
            (self.time_low, time, np.fmin),
        ):
            reduce = np.maximum if fold is np.fmax else np.minimum
            target[at] = fold(target[at], reduce.reduceat(values, starts, axis=0))

    @classmethod
    def of(cls, result: Result, mesh: str, spans: int = TIME_SPANS) -> FaceLoadMap:
        """The map of a whole Result."""
        positions, _ = result.slice_line_loads(mesh)
        out = cls(mesh, positions, float(result.time[0]), float(result.time[-1]), spans)
        out.add(result)
        return out


def sliced_meshes(result: Result) -> list[str]:
    """The meshes a run cut into slices (with a face position per slice column), in mesh order."""
    out = []
    for mesh in result.mesh_names:
        positions = (result.metadata.get("meshes") or {}).get(mesh, {}).get("slice_positions")
        if positions and any(n.startswith(f"{mesh}.") for n in result.slice_names):
            out.append(mesh)
    return out


def draw_face_load(fig: Any, face: FaceLoadMap) -> None:
    """Draws a map on an empty figure: the colour map [N/mm] and the K_Hβ strip beside it.

    The face width in the title is N times the slice pitch (the slices are equal).
    """
    kept = np.flatnonzero(np.isfinite(face.time_low))
    z_mm = face.positions * 1e3
    pitch = float(np.diff(z_mm).mean()) if z_mm.size > 1 else 1.0
    x_edges = np.r_[z_mm - 0.5 * pitch, z_mm[-1] + 0.5 * pitch]
    times = 0.5 * (face.time_low[kept] + face.time_high[kept])
    if times.size > 1:
        middle = 0.5 * (times[1:] + times[:-1])
        y_edges = np.r_[times[0] - (middle[0] - times[0]), middle]
        y_edges = np.r_[y_edges, times[-1] + (times[-1] - middle[-1])]
    else:
        y_edges = np.r_[times - 0.5, times + 0.5] if times.size else np.array([0.0, 1.0])
    grid = fig.add_gridspec(1, 3, width_ratios=(5.0, 1.4, 0.18))
    ax = fig.add_subplot(grid[0, 0])
    strip = fig.add_subplot(grid[0, 1], sharey=ax)
    bar = fig.add_subplot(grid[0, 2])
    mesh_map = ax.pcolormesh(
        x_edges, y_edges, face.line_load[kept] * 1e-3, cmap="viridis", shading="flat", vmin=0.0
    )
    b = pitch * z_mm.size
    ax.set_title(
        f"{face.mesh}: line load across the face, loaded flank "
        f"({z_mm.size} slices, b = {b:.4g} mm)",
        fontsize=9,
        loc="left",
    )
    ax.set_xlabel("face position from the face centre along gear A's axis [mm]", fontsize=8)
    ax.set_ylabel("time [s]", fontsize=8)
    ax.tick_params(labelsize=7)
    colour = fig.colorbar(mesh_map, cax=bar)
    colour.set_label("line load w [N/mm]", fontsize=8)
    colour.ax.tick_params(labelsize=7)
    strip.fill_betweenx(
        times, face.factor_low[kept], face.factor_high[kept], color="C1", alpha=0.4, linewidth=0
    )
    strip.plot(face.factor_high[kept], times, color="C1", linewidth=1.0)
    strip.set_xlabel("K_Hβ = w_max / w_mean [-]", fontsize=8)
    strip.set_title("face load factor [-]", fontsize=9, loc="left")
    strip.tick_params(labelsize=7, labelleft=False)
    strip.grid(True, linewidth=0.3)
    low = np.nanmin(face.factor_low[kept]) if kept.size else 1.0
    high = np.nanmax(face.factor_high[kept]) if kept.size else 1.0
    pad = max(0.05 * (high - low), 0.02)
    strip.set_xlim(min(low, 1.0) - pad, high + pad)
    ax.set_ylim(y_edges[0], y_edges[-1])


def plot_face_load(
    face: FaceLoadMap,
    file: Path,
    *,
    note: str,
    dpi: int = 110,
) -> Path:
    """Writes the figure of one map to ``file`` (png, svg or pdf by its extension).

    ``note``: the caption under the axes (the run's provenance, ``figures.caption``).

    Raises:
        FigureFailed: the file cannot be written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pinwind.io.figure_layout import caption_below, save_figure

    fig = plt.figure(figsize=(10, 6.0), layout="constrained")
    try:
        draw_face_load(fig, face)
        caption_below(
            fig,
            note + "\nColour: the largest line load of each slice in each time span "
            "(N F_s / b on the loaded flank; 0: the slice out of contact).\nStrip: K_Hβ, "
            "the smallest and largest in each span.",
        )
        save_figure(fig, file, dpi)
    finally:
        plt.close(fig)
    return file
