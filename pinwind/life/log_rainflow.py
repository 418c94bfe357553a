"""Rainflow matrices (range × mean) of logged series, as CSV: `pinwind spectrum --rainflow`.

Each chosen series (``NAME[:ELEMENT]``, docs/series.md) of a log's time window is counted by
`cycles.rainflow_cycles` (ASTM E1049-85) and binned into equal range and mean bins
(`Cycles.matrix`); ranges and means are in the series' SI unit.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from pinwind.life.cycles import RainflowMatrix, rainflow_cycles


@dataclass(frozen=True)
class SeriesMatrix:
    """The rainflow matrix of one component of one element of a logged series."""

    series: str
    element: str
    component: str
    unit: str
    matrix: RainflowMatrix


def log_rainflow_matrices(
    path: str | os.PathLike,
    series: Sequence[str],
    *,
    start: float | None = None,
    stop: float | None = None,
    bins: int = 10,
) -> list[SeriesMatrix]:
    """Range × mean rainflow matrix of each series (each element and component) in the window.

    Raises:
        LogError: the log cannot be read.
        InputError: an unknown series, fewer than one bin.
        UnknownElement: an element the series' family does not have.
    """
    from pinwind.analysis.spectrum import parse_series, series_channel, series_values
    from pinwind.errors import InputError
    from pinwind.io.log_reader import LogReader

    if bins < 1:
        raise InputError(f"--rainflow-bins {bins}; give at least one bin per axis")
    chosen = [parse_series(text) for text in series]
    with LogReader(path) as reader:
        channels = sorted({"/joints", *(series_channel(s) for s, _ in chosen)})
        result = reader.read(start=start, stop=stop, channels=channels)
    out = []
    for s, element in chosen:
        for name, component, values in series_values(result, s, element):
            matrix = rainflow_cycles(values).matrix(range_bins=bins, mean_bins=bins)
            out.append(SeriesMatrix(s.name, name, component, s.unit, matrix))
    return out


def write_rainflow_csv(matrices: Sequence[SeriesMatrix], path: str | os.PathLike) -> Path:
    """One row per series, element, component, range bin and mean bin: its edges and cycles."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as out:
        rows = csv.writer(out)
        rows.writerow(
            ["series", "element", "component", "unit", "range_from", "range_to", "mean_from",
             "mean_to", "cycles"]
        )  # fmt: skip
        for m in matrices:
            r, c = m.matrix.range_edges, m.matrix.mean_edges
            for i in range(len(r) - 1):
                for j in range(len(c) - 1):
                    rows.writerow(
                        [m.series, m.element, m.component, m.unit, repr(float(r[i])),
                         repr(float(r[i + 1])), repr(float(c[j])), repr(float(c[j + 1])),
                         repr(float(m.matrix.counts[i, j]))]
                    )  # fmt: skip
    return path
