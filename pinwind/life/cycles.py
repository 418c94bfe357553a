"""Rainflow cycles of a load or stress history (ASTM E1049-85 §5.4.4; Jørgensen 2014 §1.3).

The counting is ASTM E1049-85's rainflow method as the maintained ``rainflow`` package implements
it, compiled (``pinwind.life._rainflow``, a line-for-line port of the package's
``extract_cycles``): the package's Python loop took half of each fatigue case (1.9 million
cycles of 642 tooth histories, 32 of 70 s). The port gives the package's cycles bit for bit, in
its order (tests/life/test_cycles.py checks it against the package). This module turns them into
arrays and bins them into the range × mean matrix that Jørgensen 2014 §1.3 feeds to
Palmgren-Miner (eq. 2). Ranges and means have the unit of the history (Pa for a stress history, N
for a force).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import rainflow

from pinwind.errors import InputError, NonFiniteInput
from pinwind.life._rainflow import closed_cycles, extract_cycles


@dataclass(frozen=True)
class RainflowMatrix:
    """Counted cycles binned by range and mean.

    Attributes:
        range_edges: bin edges of the cycle range [unit of the history], (r + 1,).
        mean_edges: bin edges of the cycle mean [unit of the history], (c + 1,).
        counts: cycles in each (range, mean) bin, half cycles counting 0.5, (r, c). The last bin
            of each axis includes its upper edge; cycles outside the edges are not counted.
    """

    range_edges: np.ndarray
    mean_edges: np.ndarray
    counts: np.ndarray

    @property
    def range_centres(self) -> np.ndarray:
        """Centre of each range bin [unit of the history], (r,)."""
        return 0.5 * (self.range_edges[:-1] + self.range_edges[1:])

    @property
    def mean_centres(self) -> np.ndarray:
        """Centre of each mean bin [unit of the history], (c,)."""
        return 0.5 * (self.mean_edges[:-1] + self.mean_edges[1:])


@dataclass(frozen=True)
class Cycles:
    """Rainflow cycles of one history: one entry per counted full or half cycle.

    Attributes:
        ranges: cycle range, peak minus valley [unit of the history], (n,).
        means: cycle mean, (peak + valley) / 2 [unit of the history], (n,).
        counts: 1.0 for a full cycle, 0.5 for a half cycle (ASTM E1049-85 §5.4.4), times any
            factor applied with `scaled`, (n,).
    """

    ranges: np.ndarray
    means: np.ndarray
    counts: np.ndarray

    @property
    def total(self) -> float:
        """Number of cycles, half cycles counting 0.5."""
        return float(np.sum(self.counts))

    @property
    def amplitudes(self) -> np.ndarray:
        """Cycle amplitude, half the range [unit of the history], (n,)."""
        return 0.5 * self.ranges

    def scaled(self, factor: float) -> Cycles:
        """The same cycles with every count multiplied by ``factor``.

        A time factor (`pinwind.life.site`) turns the cycles of a simulated history into the
        cycles of the hours it stands for (Jørgensen 2014 §3.1).
        """
        if not np.isfinite(factor) or factor < 0.0:
            raise InputError(
                f"a cycle count factor must be finite and non-negative, got {factor!r}; pass the "
                "time factor of the wind bin (hours x 3600 / simulated seconds)"
            )
        return Cycles(self.ranges, self.means, self.counts * factor)

    def matrix(
        self,
        *,
        range_bins: int | Sequence[float] | np.ndarray = 10,
        mean_bins: int | Sequence[float] | np.ndarray = 10,
    ) -> RainflowMatrix:
        """Bin the cycles into a range × mean matrix.

        Args:
            range_bins: number of equal bins from zero to the largest range, or the bin edges.
            mean_bins: number of equal bins from the smallest to the largest mean, or the edges.
        """
        range_edges = _edges(range_bins, 0.0, float(np.max(self.ranges, initial=0.0)), "range")
        low = float(np.min(self.means, initial=0.0))
        high = float(np.max(self.means, initial=0.0))
        mean_edges = _edges(mean_bins, low, high, "mean")
        counts, _, _ = np.histogram2d(
            self.ranges, self.means, bins=(range_edges, mean_edges), weights=self.counts
        )
        return RainflowMatrix(range_edges, mean_edges, counts)


def rainflow_cycles(history: npt.ArrayLike) -> Cycles:
    """Count the rainflow cycles of a history (ASTM E1049-85 §5.4.4, as the ``rainflow`` package).

    Args:
        history: samples of a load or stress in time order, (n,). Only its turning points matter;
            fewer than three samples hold no cycle.

    Raises:
        NonFiniteInput: a sample is NaN or infinite.
        InputError: the history is not one-dimensional.
    """
    values = np.asarray(history, dtype=float)
    if values.ndim != 1:
        raise InputError(
            f"a rainflow history must be one series of samples, got an array of shape "
            f"{values.shape}; count each series (one mesh, one tooth) on its own"
        )
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise NonFiniteInput(
            f"the history to count has {bad.size} NaN or infinite samples (first at index "
            f"{bad[0]}); count a finite series, e.g. the part of the run before it diverged"
        )
    # Only the reversals matter, found here at once: the package counts a series of reversals
    # exactly as the whole history (a strictly alternating series is its own reversals), except
    # a history of fewer than three samples, which it counts in its own way (two samples: no
    # cycle), left to it.
    if values.size < 3:
        found = [(r, m, c) for r, m, c, _, _ in rainflow.extract_cycles(values)]
        table = np.array(found, dtype=float).reshape(-1, 3)
        return Cycles(ranges=table[:, 0], means=table[:, 1], counts=table[:, 2])
    ranges, means, counts = extract_cycles(turning_points(values))
    return Cycles(ranges=ranges, means=means, counts=counts)


class CycleStream:
    """The rainflow cycles of a history given in parts, counted as they close.

    Each part is reduced at once to its turning points (`turning_points`) with the two last
    points of the parts before: the first (a reversal, or the history's first sample) and the
    last sample, which the next part may turn into a reversal or drop; a reversal with a later
    sample on each side stays one whatever follows. The reversals it confirms continue the
    count of the reversals before: the three-point rule (ASTM E1049-85 §5.4.4) keeps only a
    stack of points not yet closed (the residue, its ranges decreasing, the history's start
    first), so counting the residue followed by the next reversals is counting the history
    joined (``pinwind.life._rainflow.closed_cycles``). `add` gives the cycles each part closes
    and `end` the rest, the residue's half cycles: all of them, in order, are
    `rainflow_cycles` of the whole history, while only the residue and two points are held.
    """

    def __init__(self) -> None:
        self._tail = np.zeros(0)
        self._residue = np.zeros(0)
        self._samples = 0
        self._largest = -math.inf

    @property
    def samples(self) -> int:
        """Samples given so far."""
        return self._samples

    @property
    def largest(self) -> float:
        """The largest sample given so far (−inf before any)."""
        return self._largest

    @property
    def held(self) -> int:
        """Points held: the residue and the last two reversals (bounded, not the history)."""
        return self._residue.size + self._tail.size

    def add(self, values: npt.ArrayLike) -> Cycles:
        """The next samples of the history, in time order, (n,): the cycles they close.

        Raises:
            NonFiniteInput: a sample is NaN or infinite.
        """
        part = np.asarray(values, dtype=float).reshape(-1)
        if not part.size:
            return _NO_CYCLES
        bad = np.flatnonzero(~np.isfinite(part))
        if bad.size:
            raise NonFiniteInput(
                f"the history to count has {bad.size} NaN or infinite samples (first at index "
                f"{self._samples + bad[0]}); count a finite series, e.g. the part of the run "
                "before it diverged"
            )
        self._samples += part.size
        self._largest = max(self._largest, float(np.max(part)))
        found = turning_points(np.concatenate((self._tail, part)))
        self._tail = found[-2:]
        if found.size <= 2:
            return _NO_CYCLES
        ranges, means, counts, self._residue = closed_cycles(
            np.concatenate((self._residue, found[:-2]))
        )
        return Cycles(ranges=ranges, means=means, counts=counts)

    def end(self) -> Cycles:
        """The history ends: the cycles not given yet (the residue's half cycles, mostly).

        No part may follow.
        """
        if self._samples < 3:  # then the reversals are the samples (`rainflow_cycles`)
            return rainflow_cycles(self._tail)
        ranges, means, counts = extract_cycles(np.concatenate((self._residue, self._tail)))
        self._residue, self._tail = np.zeros(0), np.zeros(0)
        return Cycles(ranges=ranges, means=means, counts=counts)


_NO_CYCLES = Cycles(ranges=np.zeros(0), means=np.zeros(0), counts=np.zeros(0))


def turning_points(history: np.ndarray) -> np.ndarray:
    """The reversals of a history as ``rainflow.reversals`` finds them, their values only.

    The first and the last sample, and each sample where the slope changes sign: repeated
    values are one point, and the sign test is the package's own product of the slopes before
    and after (so that a product that underflows to zero is no reversal there either).

    Args:
        history: samples in time order, (n,).

    Returns:
        The values of its reversals in time order, (k,); fewer than three: no cycle within.
    """
    if history.size < 2:
        return history[:1].copy()
    distinct = history[np.concatenate(([True], history[1:] != history[:-1]))]
    slope = np.diff(distinct)
    turn = np.flatnonzero(slope[:-1] * slope[1:] < 0.0) + 1
    return np.concatenate((distinct[:1], distinct[turn], history[-1:]))


def _edges(
    bins: int | Sequence[float] | np.ndarray, low: float, high: float, what: str
) -> np.ndarray:
    """Bin edges: ``bins`` equal bins over [low, high], or the given increasing edges."""
    if isinstance(bins, int | np.integer):
        if bins < 1:
            raise InputError(f"the number of {what} bins must be at least 1, got {bins}")
        if high <= low:  # one value (or none): a bin of unit width around it
            low, high = low - 0.5, high + 0.5
        return np.linspace(low, high, int(bins) + 1)
    edges = np.asarray(bins, dtype=float)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0.0):
        raise InputError(
            f"{what} bin edges must be at least two increasing values, got {edges.tolist()}"
        )
    return edges
