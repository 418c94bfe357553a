"""A figure's page: a caption under the axes, legends beside them, nothing cut at the edge.

Every figure pinwind writes (``pinwind plot``, ``spectrum``, ``campbell``, the fatigue and sweep
figures) is laid out by matplotlib's constrained layout, which shrinks the axes until their
titles, tick and axis labels and legends (also those placed beside the axes) fit the figure.
It does not know a caption written with ``Figure.text``: ``caption_below`` measures the caption
and keeps the axes above it, widening the figure when a caption line is wider than the page.
``save_figure`` writes a figure whole or not at all. ``outside_figure`` is the check of the
figures' tests: every artist drawn wholly inside the figure's bounding box, which is what the
saved file holds (matplotlib cuts the rest).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from pinwind.errors import FigureFailed

#: Gap between the caption and the lowest axis labels, and the caption's margin [inch].
CAPTION_PAD = 0.08


def caption_below(fig: Any, text: str, *, fontsize: float = 6.5, color: str = "0.25") -> Any:
    """Writes ``text`` at the bottom left of ``fig`` and keeps the laid-out axes above it.

    The figure must use the constrained layout (``plt.subplots(layout="constrained")``); its
    area for axes is set to start above the caption. A figure narrower than the caption's
    widest line is widened to it. Returns the caption's ``Text``.
    """
    renderer = fig.canvas.get_renderer()  # a text's extent needs no drawing
    note = fig.text(0.0, 0.0, text, fontsize=fontsize, va="bottom", ha="left", color=color)
    extent = note.get_window_extent(renderer)
    width, height = fig.get_size_inches()
    needed = extent.width / fig.dpi + 2 * CAPTION_PAD
    if needed > width:
        fig.set_size_inches(needed, height)
        width = needed
    note.set_position((CAPTION_PAD / width, CAPTION_PAD / height))
    bottom = (extent.height / fig.dpi + 2 * CAPTION_PAD) / height
    fig.get_layout_engine().set(rect=(0.0, bottom, 1.0, 1.0 - bottom))
    return note


def _named(artist: Any) -> str:
    """An artist as a reader finds it on the page: its kind and the start of its text."""
    kind = type(artist).__name__
    text = artist.get_text() if hasattr(artist, "get_text") else ""
    if kind == "Legend":
        text = ", ".join(t.get_text() for t in artist.get_texts())
    return f"{kind} {text[:60]!r}" if text else kind


def _drawn(fig: Any) -> list[Any]:
    """The artists that carry words: texts, legends, titles, axis labels, and each axes whole.

    Tick labels are counted in their axes' extent (``get_tightbbox`` counts the ticks drawn;
    an axis keeps labels of ticks beyond its limits that are never drawn).
    """
    out: list[Any] = [t for t in fig.texts if t.get_text()]
    for legend in fig.legends:
        out.append(legend)
    suptitle = getattr(fig, "_suptitle", None)
    if suptitle is not None and suptitle.get_text():
        out.append(suptitle)
    for ax in fig.axes:
        out.append(ax)
        legend = ax.get_legend()
        if legend is not None:
            out.append(legend)
        for text in (ax.title, ax._left_title, ax._right_title, *ax.texts):
            if text.get_text():
                out.append(text)
        for axis in (ax.xaxis, ax.yaxis):
            if axis.label.get_text():
                out.append(axis.label)
    return out


def outside_figure(fig: Any, *, tolerance: float = 0.5) -> list[str]:
    """The artists whose drawn extent leaves the figure's bounding box (cut from the file).

    Draws the figure first. An axes counts with everything it draws (``get_tightbbox``: tick
    labels, axis labels, title, legend); texts, legends and labels are also checked one by one
    so that the message names them. ``tolerance`` [pixel] absorbs the rounding of extents.
    """
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    out = []
    for artist in _drawn(fig):
        if hasattr(artist, "get_tightbbox") and type(artist).__name__.endswith("Axes"):
            box = artist.get_tightbbox(renderer)
        else:
            box = artist.get_window_extent(renderer)
        if box is None:
            continue
        if (
            box.x0 < page.x0 - tolerance
            or box.y0 < page.y0 - tolerance
            or box.x1 > page.x1 + tolerance
            or box.y1 > page.y1 + tolerance
        ):
            out.append(
                f"{_named(artist)} spans x {box.x0:.0f}-{box.x1:.0f}, y {box.y0:.0f}-"
                f"{box.y1:.0f} px; the figure {page.x1:.0f} × {page.y1:.0f} px"
            )
    return out


def save_with_caption(fig: Any, path: Any, *, caption: str, mark: str = "") -> Any:
    """Writes a figure at 120 dpi with its caption under the axes, making its folder; closes it.

    ``mark`` is the figure's title (above the axes' own), e.g. that it is a quick set's. The
    figure must use the constrained layout: legends beside the axes are kept on the page, and
    the caption under them (`caption_below`). Both are also the PNG's Description and Title.
    Returns the path.
    """
    from pathlib import Path

    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if mark:
        fig.suptitle(mark, fontsize=11, x=0.02, ha="left")
    caption_below(fig, caption)
    metadata = {"Description": caption} | ({"Title": mark} if mark else {})
    fig.savefig(path, dpi=120, metadata=metadata)
    plt.close(fig)
    return path


def save_figure(fig: Any, file: Path, dpi: int) -> None:
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
