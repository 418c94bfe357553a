"""Statistics of every series of a run, folded block after block: min, max, mean, RMS, final.

For each quantity of each joint, mesh and bearing (and generator, rotor, the constraint residual
and the energy ledger): min, max, mean, RMS and final value over the samples folded in (the
columns of Kelso 2011 Tables 4-1/4-2), in SI units. A vector gives one series per
axis plus one for its magnitude. Body poses are geometry, not loads, and are left out.

``RunningStatistics`` folds a Result block after block, in memory that does not grow with the
run: ``StatisticsObserver`` folds every sample of a run into it as the run goes
(``pinwind.simulate`` adds it; by default when the Result does not keep every sample, so that the
peaks between the kept samples count), and ``pinwind report`` folds a log too large for memory.
"""

from __future__ import annotations

import math
from collections import deque
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.dynamics import series
from pinwind.dynamics._native import fold_columns, fold_magnitudes
from pinwind.dynamics.result import Result
from pinwind.errors import InputError, UnknownElement

STATISTICS = ("min", "max", "mean", "rms", "final")


@dataclass(frozen=True)
class Row:
    """Statistics of one series.

    Attributes:
        group: ``joint``, ``mesh``, ``bearing``, ``load`` (generators and rotors) or ``run``.
        element: joint, mesh or bearing name, ``generator JOINT`` or ``rotor JOINT`` (the
            energy term for ``run/energy``).
        quantity: e.g. ``speed``, ``normal``, ``force (world)``.
        component: ``x``, ``y``, ``z``, ``|.|`` for vectors, else ``""``.
        unit: SI unit.
        min, max, mean, rms, final: the statistics over the samples folded in.
    """

    group: str
    element: str
    quantity: str
    component: str
    unit: str
    min: float
    max: float
    mean: float
    rms: float
    final: float


#: (group, element, quantity, component, unit): names one series.
Key = tuple[str, str, str, str, str]

_AXES = ("x", "y", "z", "|.|")
#: The report's group of each family: generators and rotors are both ``load``.
_GROUPS = {"generator": "load", "rotor": "load"}
#: Families in report order; ``run`` (constraint residual, energy) last.
_REPORT_FAMILIES = ("joint", "mesh", "bearing", "generator", "rotor")


@dataclass(frozen=True)
class _Field:
    """One Result array and the series it gives, in the order of its columns.

    ``source`` is a Result attribute or ``energy/TERM``; a vector array (samples, elements, 3)
    gives its x, y and z columns, then a magnitude per element.
    """

    source: str
    keys: list[Key]
    vector: bool


def _element_keys(
    s: series.Series, name: str, axes: tuple[str, ...], kind: str = "revolute"
) -> list[Key]:
    """The keys of one element's series (``axes`` of a vector, or the scalar).

    ``kind``: the element's joint kind, which gives a slide's joint series their unit.
    """
    group = _GROUPS.get(s.family, s.family)
    element = f"{s.family} {name}" if s.family in _GROUPS else name
    components = axes if s.components else ("",)
    return [(group, element, s.title, axis, s.unit_for(kind)) for axis in components]


def _reported(family: str) -> list[series.Series]:
    """A family's series that are reported: its scalars, then its vectors (schema order)."""
    reported = [s for s in series.of_family(family) if s.statistics]
    return sorted(reported, key=lambda s: bool(s.components))


def _fields(res: Result) -> list[_Field]:
    """The arrays of a Result that are reported (``Series.statistics``), with their keys."""
    fields = []
    for s in series.schema():
        if not s.statistics:
            continue
        if s.family == "run":
            fields.append(_Field(s.name, [("run", "", s.title, "", s.unit)], False))
            continue
        names = list(enumerate(res.names(s.family)))
        kinds = [res.kind_of(s.family, i) for i, _ in names]
        if s.components:
            keys = [k for i, n in names for k in _element_keys(s, n, _AXES[:3], kinds[i])]
            keys += [k for i, n in names for k in _element_keys(s, n, _AXES[3:], kinds[i])]
        else:
            keys = [k for i, n in names for k in _element_keys(s, n, _AXES, kinds[i])]
        fields.append(_Field(s.name, keys, bool(s.components)))
    for term in res.energy:
        fields.append(_Field(f"energy/{term}", [("run", term, "energy", "", "J")], False))
    return [f for f in fields if f.keys]


def _report_order(res: Result) -> list[Key]:
    """Every series' key, element after element (each joint's, mesh's, bearing's together)."""
    keys: list[Key] = []
    for family in _REPORT_FAMILIES:
        for i, name in enumerate(res.names(family)):
            for s in _reported(family):
                keys += _element_keys(s, name, _AXES, res.kind_of(family, i))
    keys += [("run", "", s.title, "", s.unit) for s in _reported("run")]
    keys += [("run", term, "energy", "", "J") for term in res.energy]
    return keys


class RunningStatistics:
    """min, max, sum, sum of squares and final value of every series, block after block.

    Memory is a few numbers per series whatever the number of samples. Each array of a block
    is folded in one pass of the compiled module, where it lies (``fold_columns``,
    ``fold_magnitudes`` in ``dynamics/cpp/column_statistics.hpp``); the blocks' sums add up
    here.

    Attributes:
        count: samples folded in.
        first, last: times of the first and last of them [s] (NaN before any).
    """

    def __init__(self) -> None:
        self.count = 0
        self.first = math.nan
        self.last = math.nan
        self._fields: list[_Field] = []
        self._width = 0
        self._values: np.ndarray | None = None  # (5, series): min, max, sum, sum sq, final
        self._order: np.ndarray | None = None  # report order → column of _values
        self._keys: list[Key] = []

    @classmethod
    def of(cls, res: Result, rows: np.ndarray | slice = slice(None)) -> RunningStatistics:
        """The statistics of the samples ``rows`` of a Result."""
        stats = cls()
        stats.add(res, rows)
        return stats

    def _layout(self, res: Result) -> None:
        self._fields = _fields(res)
        keys = [key for f in self._fields for key in f.keys]
        self._width = len(keys)
        at = {key: i for i, key in enumerate(keys)}
        self._keys = _report_order(res)
        self._order = np.array([at[key] for key in self._keys], dtype=np.intp)

    def add(self, res: Result, rows: np.ndarray | slice = slice(None)) -> None:
        """Fold in the samples ``rows`` of a Result (a block of a run or of a log)."""
        time = res.time[rows]
        m = len(time)
        if not m:
            return
        if self._values is None:
            self._layout(res)
        block = np.empty((5, self._width))  # min, max, sum, sum of squares, last
        row = 0
        for f in self._fields:
            if f.source.startswith("energy/"):
                values = res.energy[f.source[7:]][rows]
            else:
                values = getattr(res, f.source)[rows]
            width = len(f.keys)
            if f.vector:  # (m, elements, 3): the axes, then the magnitudes
                axes = values.reshape(m, width // 4 * 3)
                fold_columns(axes, block[:, row : row + axes.shape[1]])
                fold_magnitudes(axes, block[:, row + axes.shape[1] : row + width])
            else:
                fold_columns(values.reshape(m, width), block[:, row : row + width])
            row += width
        if self._values is None:
            self._values, self.first = block, float(time[0])
        else:
            old = self._values
            np.minimum(old[0], block[0], out=old[0])
            np.maximum(old[1], block[1], out=old[1])
            old[2:4] += block[2:4]
            old[4] = block[4]
        self.count += m
        self.last = float(time[-1])

    def rows(self) -> list[Row]:
        """One Row per series, element after element (empty before any sample)."""
        if self._values is None:
            return []
        return [self._row(position) for position in range(len(self._keys))]

    def _row(self, position: int) -> Row:
        """The Row of the series at ``position`` in element order."""
        assert self._values is not None and self._order is not None  # after a fold
        lo, hi, total, squares, final = self._values[:, self._order[position]].tolist()
        n = self.count
        return Row(*self._keys[position], lo, hi, total / n, math.sqrt(squares / n), final)

    def row(self, group: str, element: str, quantity: str, component: str = "") -> Row:
        """The statistics of one series, e.g. ``row("mesh", "sun_planet1", "normal")``.

        Raises:
            UnknownElement: no such element in the group.
            InputError: the element has no such series (the message lists its series).
        """
        wanted = (group, element, quantity, component)
        for position, key in enumerate(self._keys):
            if key[:4] == wanted and self._values is not None:
                return self._row(position)
        mine = [f"{k[2]} {k[3]}".strip() for k in self._keys if k[:2] == (group, element)]
        if not mine:
            known = list(dict.fromkeys(k[1] for k in self._keys if k[0] == group))
            raise UnknownElement(group, element, known)
        raise InputError(
            f'{group} "{element}" has no series "{f"{quantity} {component}".strip()}"; its '
            f"series are: {', '.join(mine)}"
        )


class StatisticsObserver:
    """Folds a run's blocks into ``RunningStatistics`` as they are computed: a run observer.

    The folding runs on a thread of its own, at most ``holds`` blocks behind the step loop; the
    compiled folding and the compiled loop both run without the GIL, so on two cores the
    folding costs the loop 4–6 % of its wall time (``benchmarks/run_statistics.py``). At the
    end the statistics go to ``result.statistics``.

    Args:
        fold: fold every sample (True), none (False), or (None, the default) only when the
            Result does not keep every sample (``keep``) or ``skip_start`` is given, so that
            the peaks between the kept samples count.
        skip_start: the samples before this time [s] are left out: the start-up of a run that
            starts away from its operating state (compliant meshes undeflected), whose impact
            would otherwise set the maxima.
    """

    #: Blocks added and not yet folded, at most; the run keeps their arrays unchanged.
    holds: int | None = 2

    def __init__(self, fold: bool | None = None, *, skip_start: float = 0.0):
        if not (math.isfinite(skip_start) and skip_start >= 0.0):
            raise InputError(
                f"skip_start = {skip_start} s: give the start-up span to leave out of the "
                "statistics, a finite time ≥ 0 [s]"
            )
        self.fold = fold
        self.skip_start = float(skip_start)
        self.statistics: RunningStatistics | None = None
        self._pool: ThreadPoolExecutor | None = None
        self._pending: deque[Future] = deque()

    def begin(self, gearbox: Any, result: Result) -> None:
        """Starts folding when asked, or when the run keeps every N-th sample only."""
        stride = int(result.metadata.get("keep_stride", 1))
        duration = float(result.metadata.get("duration", math.inf))
        if self.skip_start >= duration:
            raise InputError(
                f"skip_start = {self.skip_start:g} s leaves nothing of a {duration:g} s run; "
                "give a start-up span shorter than the duration"
            )
        if self.skip_start > 0.0:
            result.metadata["statistics_from_s"] = self.skip_start
        default = stride > 1 or self.skip_start > 0.0
        if self.fold if self.fold is not None else default:
            self.statistics = RunningStatistics()
            self._pool = ThreadPoolExecutor(1, thread_name_prefix="pinwind-statistics")

    @property
    def reads(self) -> bool:
        """Whether ``samples`` reads the blocks: when folding (after ``begin``)."""
        return self._pool is not None

    def samples(self, block: Result, start: int) -> None:
        """Folds a block, its samples from ``skip_start`` on.

        Waits for the oldest block when ``holds`` are pending.
        """
        if self._pool is None or self.statistics is None or not len(block):
            return
        if block.time[-1] < self.skip_start:
            return
        rows: slice | np.ndarray = slice(None)
        if block.time[0] < self.skip_start:
            rows = np.flatnonzero(block.time >= self.skip_start)
        while self.holds is not None and len(self._pending) >= self.holds:
            self._pending.popleft().result()
        self._pending.append(self._pool.submit(self.statistics.add, block, rows))

    def end(self, result: Result, status: str) -> None:
        """Waits for the last blocks and gives ``result`` the statistics of every one."""
        if self._pool is None:
            return
        try:
            while self._pending:
                self._pending.popleft().result()
        finally:
            self._pool.shutdown()
        result.statistics = self.statistics
