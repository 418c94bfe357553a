"""The overview of a run's plotted series, built block by block in bounded memory.

A log longer than memory is read in blocks (``LogReader.blocks``). ``PanelOverview`` turns each
block into the panels of ``io/panels.py`` and keeps, per series, the smallest and largest sample
in each of a fixed number of time spans (``MinMaxDecimator``): every peak survives, and memory
is (spans × series) whatever the length of the run. The replay (``io/replay.py``) sends the
result to the viewer; the figures (``io/figures.py``) draw it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from pinwind.dynamics.result import Result
from pinwind.io.panels import Panel, without_zero_series
from pinwind.io.panels import panels as run_panels


class MinMaxDecimator:
    """The smallest and largest sample of each series in each of ``spans`` equal time spans.

    Fed block by block (``add``); memory is (spans, series) whatever the number of samples.
    NaN samples are skipped. ``points`` gives, per series, the kept samples in time order: at
    most 2 per span, the min and the max (one when they are the same sample), so the decimated
    series has the extremes of the full one in every span. Of equal extremes the earliest sample
    is kept.

    Attributes:
        low, high: (spans, series) min and max of each span (+inf / -inf where no sample).
        low_at, high_at: (spans, series) their times [s] (NaN where no sample).
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
        values = np.where(np.isfinite(values), values, np.nan)
        span = self.span_of(time)
        starts = np.flatnonzero(np.r_[True, span[1:] != span[:-1]])
        spans = span[starts]
        index = np.arange(len(time))[:, None]
        counts = np.diff(np.r_[starts, len(time)])
        for extreme, value, at, better in (
            (np.fmin, self.low, self.low_at, np.less),
            (np.fmax, self.high, self.high_at, np.greater),
        ):
            best = extreme.reduceat(values, starts, axis=0)  # NaN only where a span has none
            # the first sample of each span that takes the extreme value
            hit = values == np.repeat(best, counts, axis=0)
            first = np.minimum.reduceat(np.where(hit, index, len(time)), starts, axis=0)
            when = time[np.minimum(first, len(time) - 1)]
            take = better(best, value[spans])  # False for NaN: nothing new in that span
            value[spans] = np.where(take, best, value[spans])
            at[spans] = np.where(take, when, at[spans])

    def points(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per series: (times [s], values) of the kept samples, in time order."""
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

    def all_zero(self, s: int) -> bool:
        """Series ``s`` is zero at every (finite) sample seen."""
        low, high = self.low[:, s], self.high[:, s]
        seen = np.isfinite(low)
        return bool(not np.any(low[seen]) and not np.any(high[seen]))


class Overview:
    """What the viewer gets of every plotted series of a run, fed block by block.

    A run of at most ``points`` samples is sent whole; a longer one as its ``MinMaxDecimator``
    over ``points``/2 spans from ``start`` to ``stop`` [s]. Memory: the decimator plus, while
    the run is short enough, its first ``points`` samples.
    """

    def __init__(self, start: float, stop: float, points: int, series: int):
        self.points = points
        self.decimator = MinMaxDecimator(start, stop, max(points // 2, 1), series)
        self._head: list[tuple[np.ndarray, np.ndarray]] | None = []
        self._count = 0

    def add(self, time: np.ndarray, values: np.ndarray) -> None:
        """Samples at ``time`` (n,), increasing, of every series: ``values`` (n, series)."""
        self.decimator.add(time, values)
        self._count += len(time)
        if self._head is not None and self._count <= self.points:
            self._head.append((time.copy(), values.copy()))
        else:
            self._head = None

    def series(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per series: (times [s], values) to send, in time order."""
        if self._head is None:
            return self.decimator.points()
        if not self._head:
            return [(np.zeros(0), np.zeros(0))] * self.decimator.low.shape[1]
        time = np.concatenate([t for t, _ in self._head])
        values = np.concatenate([v for _, v in self._head])
        return [(time, values[:, s]) for s in range(values.shape[1])]


def coincident_groups(low: np.ndarray, high: np.ndarray, tolerance: float) -> list[list[int]]:
    """Series that would draw as one line: groups of series indices, each in increasing order.

    Two series coincide when they have samples in the same time spans and their min and max
    (``low``, ``high``: (spans, series), ``MinMaxDecimator``) differ by at most ``tolerance``
    in every one of them; groups are closed under that relation. Every series is in one group
    (a series alone is a group of one); groups in the order of their first series.
    """
    k = low.shape[1]
    group = list(range(k))

    def root(i: int) -> int:
        while group[i] != i:
            i = group[i]
        return i

    seen = np.isfinite(low)
    for i in range(k):
        for j in range(i + 1, k):
            if not np.array_equal(seen[:, i], seen[:, j]) or not seen[:, i].any():
                continue
            both = seen[:, i]
            if (
                np.max(np.abs(low[both, i] - low[both, j])) <= tolerance
                and np.max(np.abs(high[both, i] - high[both, j])) <= tolerance
            ):
                group[root(j)] = root(i)
    members: dict[int, list[int]] = {}
    for i in range(k):
        members.setdefault(root(i), []).append(i)
    return list(members.values())


@dataclass
class DecimatedPanel:
    """A panel of the whole run as the overview keeps it.

    Attributes:
        panel: the panel, each series' ``values`` the kept samples, all-zero series of a
            ``drop_zero`` panel left out, y range as the whole run's.
        times: per series of ``panel``, the kept samples' times [s].
        low, high: per time span and series of ``panel``, its min and max (``MinMaxDecimator``),
            (spans, series).
    """

    panel: Panel
    times: list[np.ndarray]
    low: np.ndarray
    high: np.ndarray


class PanelOverview:
    """The panels of a run, fed block by block (``add``), decimated to ``points`` per series.

    The layout (panels and series) comes from the first block, with series that are zero in it
    kept (a later block may not be); the load-sharing references are the largest of the blocks';
    energies are counted from the run's first sample.

    Args:
        start, stop: time span of the run (or of the window read) [s].
        points: samples kept per series (the min and max of ``points``/2 equal time spans).
        model: the log's ``pinwind.model`` record.
        joints, gearbox: ``panels.model_of_log`` (absolute speeds, load sharing).
    """

    def __init__(
        self,
        start: float,
        stop: float,
        points: int,
        model: dict[str, Any],
        *,
        joints: dict[str, dict[str, Any]] | None = None,
        gearbox=None,
    ):
        self.start, self.stop, self.points = start, stop, points
        self.model, self.joints, self.gearbox = model, joints, gearbox
        self.layout: list[Panel] = []
        self.references: list[float | None] = []
        self.overview: Overview | None = None
        self._energy_start: dict[str, float] | None = None

    def add(self, res: Result) -> tuple[list[Panel], np.ndarray]:
        """Feed a block; returns its panels and their series as columns, (samples, series)."""
        if self._energy_start is None:
            self._energy_start = {k: float(v[0]) for k, v in res.energy.items()}
        block = run_panels(
            res,
            self.model,
            joints=self.joints,
            gearbox=self.gearbox,
            energy_start=self._energy_start,
            keep_zero=True,
        )
        if self.overview is None:
            self.layout = [
                replace(p, series=[replace(s, values=np.zeros(0)) for s in p.series]) for p in block
            ]
            self.references = [p.reference for p in block]
            count = sum(len(p.series) for p in self.layout)
            self.overview = Overview(self.start, self.stop, self.points, count)
        self.references = [
            r if p.reference is None else max(p.reference, r if r is not None else -np.inf)
            for r, p in zip(self.references, block, strict=True)
        ]
        values = np.column_stack([s.values for p in block for s in p.series])
        self.overview.add(res.time, values)
        return block, values

    def panels(self) -> list[DecimatedPanel]:
        """The panels of the run so far, each series as kept (``DecimatedPanel``)."""
        if self.overview is None:
            return []
        kept = self.overview.series()
        decimator = self.overview.decimator
        out = []
        k = 0
        for template, reference in zip(self.layout, self.references, strict=True):
            index = list(range(k, k + len(template.series)))
            k += len(template.series)
            panel = replace(
                template,
                series=[
                    replace(s, values=kept[i][1])
                    for s, i in zip(template.series, index, strict=True)
                ],
                reference=reference,
            )
            zero = [decimator.all_zero(i) for i in index]
            keep = [i for i, z in zip(index, zero, strict=True) if not (panel.drop_zero and z)]
            panel = without_zero_series(panel, zero)
            if panel.series:
                times = [kept[i][0] for i in keep]
                low, high = decimator.low[:, keep], decimator.high[:, keep]
                out.append(DecimatedPanel(panel, times, low, high))
        return out
