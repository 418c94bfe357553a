"""Time signals for torques, speed drivers and wind: constant, ramp, step, sine, sum, tables.

A ``Signal`` is a function of time t [s] whose values the run evaluates for a whole block of
samples at once (``values``), so no Python call is made per step. Every signal can be written as
text, the same in the CLI and in scenario files (``loads/signal_text.py``).
(Kelso 2011 eq. 2-1 is the sine: Ω = A sin(ωt) + X.) Values are in the unit of what
they drive: N·m for torques, m/s for wind, rpm for speeds at the CLI and in scenario files
(``Scaled`` turns them into rad/s).

Tables refuse rows that are unsorted, duplicated or not finite, naming the file and row, and a run
longer than the table; a table that starts after the run is warned about (``check_covers``).
"""

from __future__ import annotations

import csv
import hashlib
import math
import warnings
from abc import ABC, abstractmethod
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import InputError, NonFiniteInput, TableNotUtf8, TableStartsLate


class Signal(ABC):
    """A function of time evaluated on arrays of times.

    Subclasses give ``values(t)`` (any shape of t [s]) and ``spec()``, a plain dict that
    ``signal_text.signal_from_spec`` turns back into an equal signal (scenario files and logs).
    """

    #: Last time [s] at which the signal is defined (tables); ``inf`` for formulas.
    end: float = math.inf

    @abstractmethod
    def values(self, t: np.ndarray) -> np.ndarray:
        """Values at times t [s]."""

    @abstractmethod
    def spec(self) -> dict[str, Any]:
        """Plain description: ``{"type": name, **parameters}``."""

    def __call__(self, t: float) -> float:
        """Value at time t [s]."""
        return float(self.values(np.asarray([t], dtype=float))[0])

    def __add__(self, other: Signal) -> Sum:
        """The sum of two signals."""
        return Sum((self, other))

    @property
    def description(self) -> str:
        """The signal as text (``signal_text.parse_signal`` reads it back)."""
        spec = self.spec()
        kind = spec.pop("type")
        args = ", ".join(f"{k}={v!r}" for k, v in spec.items())
        return f"{kind}({args})"


@dataclass(frozen=True)
class Constant(Signal):
    """A constant value."""

    value: float

    def values(self, t: np.ndarray) -> np.ndarray:
        """The value at every time."""
        return np.full(np.shape(t), float(self.value))

    def spec(self) -> dict[str, Any]:
        """``{"type": "constant", "value": ...}``."""
        return {"type": "constant", "value": float(self.value)}

    @property
    def description(self) -> str:
        """The number."""
        return repr(float(self.value))


@dataclass(frozen=True)
class Ramp(Signal):
    """start_value until start_time, linear to end_value at end_time, end_value after."""

    start_value: float
    end_value: float
    start_time: float
    end_time: float

    def __post_init__(self):
        if not self.end_time > self.start_time:
            raise InputError(
                f"ramp: end_time = {self.end_time:g} s must be after start_time = "
                f"{self.start_time:g} s"
            )

    def values(self, t: np.ndarray) -> np.ndarray:
        """The ramp at times t [s]."""
        x = np.clip((np.asarray(t) - self.start_time) / (self.end_time - self.start_time), 0, 1)
        return self.start_value + (self.end_value - self.start_value) * x

    def spec(self) -> dict[str, Any]:
        """Parameters."""
        return {"type": "ramp", "start_value": self.start_value, "end_value": self.end_value,
                "start_time": self.start_time, "end_time": self.end_time}  # fmt: skip


@dataclass(frozen=True)
class Step(Signal):
    """``before`` until ``time`` [s] (exclusive), ``after`` from then on."""

    time: float
    before: float
    after: float

    def values(self, t: np.ndarray) -> np.ndarray:
        """The step at times t [s]."""
        return np.where(np.asarray(t) >= self.time, float(self.after), float(self.before))

    def spec(self) -> dict[str, Any]:
        """Parameters."""
        return {"type": "step", "time": self.time, "before": self.before, "after": self.after}


@dataclass(frozen=True)
class Sine(Signal):
    """mean + amplitude · sin(2π frequency t + phase) (Kelso 2011 eq. 2-1).

    frequency [Hz], phase [rad].
    """

    mean: float
    amplitude: float
    frequency: float
    phase: float = 0.0

    def values(self, t: np.ndarray) -> np.ndarray:
        """The sine at times t [s]."""
        arg = 2.0 * math.pi * self.frequency * np.asarray(t) + self.phase
        return self.mean + self.amplitude * np.sin(arg)

    def spec(self) -> dict[str, Any]:
        """Parameters."""
        return {"type": "sine", "mean": self.mean, "amplitude": self.amplitude,
                "frequency": self.frequency, "phase": self.phase}  # fmt: skip


@dataclass(frozen=True)
class Sum(Signal):
    """The sum of signals."""

    terms: tuple[Signal, ...]

    @property
    def end(self) -> float:  # type: ignore[override]
        """The earliest end of the terms."""
        return min((s.end for s in self.terms), default=math.inf)

    def values(self, t: np.ndarray) -> np.ndarray:
        """Sum of the terms at times t [s]."""
        total = np.zeros(np.shape(t))
        for term in self.terms:
            total = total + term.values(t)
        return total

    def spec(self) -> dict[str, Any]:
        """``{"type": "sum", "terms": [...]}``."""
        return {"type": "sum", "terms": [s.spec() for s in self.terms]}

    @property
    def description(self) -> str:
        """Terms joined by +."""
        return " + ".join(s.description for s in self.terms)

    def __add__(self, other: Signal) -> Sum:
        """Flattened sum."""
        return Sum((*self.terms, other))


@dataclass(frozen=True)
class Scaled(Signal):
    """factor · signal: unit conversion at the edges (rpm → rad/s, kN·m → N·m)."""

    signal: Signal
    factor: float

    @property
    def end(self) -> float:  # type: ignore[override]
        """The signal's end."""
        return self.signal.end

    def values(self, t: np.ndarray) -> np.ndarray:
        """The signal times the factor."""
        return self.factor * self.signal.values(t)

    def spec(self) -> dict[str, Any]:
        """The inner signal's spec with the factor."""
        return {"type": "scaled", "factor": self.factor, "signal": self.signal.spec()}

    @property
    def description(self) -> str:
        """``factor·(signal)``."""
        return f"{self.factor!r}*({self.signal.description})"


class Table(Signal):
    """Linear interpolation in a table of (time, value) rows.

    Args:
        times: sample times [s], strictly increasing and finite.
        values: values at those times, finite.
        source: where the table comes from, for messages (a file name).
        rows: the row number of each sample in the source (1-based, header counted), for
            messages; default 1, 2, ...
        spec: the spec that rebuilds the table (``csv(...)``, ``openfast(...)``).

    Raises:
        InputError: unsorted or duplicated times, naming the source and row.
        NonFiniteInput: a time or value that is NaN or infinite.
    """

    def __init__(
        self,
        times,
        values,
        *,
        source: str = "table",
        rows=None,
        spec: dict[str, Any] | None = None,
    ):
        t = np.asarray(times, dtype=float)
        v = np.asarray(values, dtype=float)
        rows = np.arange(1, len(t) + 1) if rows is None else np.asarray(rows)
        if t.ndim != 1 or t.shape != v.shape or len(t) < 2:
            raise InputError(f"{source}: a table needs at least two rows of (time, value)")
        bad = np.flatnonzero(~(np.isfinite(t) & np.isfinite(v)))
        if bad.size:
            i = int(bad[0])
            raise NonFiniteInput(
                f"{source}: row {rows[i]} has time {t[i]} s, value {v[i]}; every row must be finite"
            )
        steps = np.diff(t)
        bad = np.flatnonzero(steps <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            what = "repeats" if steps[i - 1] == 0 else "goes back from"
            raise InputError(
                f"{source}: row {rows[i]} {what} the time of row {rows[i - 1]} "
                f"({t[i]:g} s after {t[i - 1]:g} s); the times must increase strictly"
            )
        self.times = t
        self.samples = v
        self.source = source
        self.rows = rows
        self._spec = spec or {"type": "table", "times": t.tolist(), "values": v.tolist()}
        self.start = float(t[0])
        self.end = float(t[-1])

    def values(self, t: np.ndarray) -> np.ndarray:
        """Linear interpolation at t [s] (held at the ends; ``check_covers`` refuses them)."""
        return np.interp(np.asarray(t, dtype=float), self.times, self.samples)

    def spec(self) -> dict[str, Any]:
        """The spec that rebuilds the table."""
        return dict(self._spec)

    @property
    def description(self) -> str:
        """The source and its span."""
        if self._spec.get("type") == "table":
            return f"table of {len(self.times)} rows, {self.start:g} … {self.end:g} s"
        return super().description


def file_sha256(path: Path) -> str:
    """SHA-256 of a file's bytes, as hex: a logged run names the exact input file."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def read_csv(path: str | Path, column: int | str = 1, *, time_column: int | str = 0) -> Table:
    """A table from a CSV file: a time column [s] and a value column.

    A first row that is not numeric is taken as the header; columns are given by index (0-based)
    or header name. Blank lines and lines starting with ``#`` are skipped. The file is UTF-8,
    with or without the byte-order mark Excel's "CSV UTF-8" writes.

    Raises:
        InputError: the file is missing, a row is malformed, unsorted or duplicated (naming the
            file and row), or the column does not exist.
        TableNotUtf8: the file is not UTF-8 (a Latin-1 export).
    """
    path = Path(path)
    try:
        # utf-8-sig: a BOM left in the first cell would make the first data row a header.
        text = path.read_text(encoding="utf-8-sig")
    except OSError as err:
        raise InputError(f"{path}: cannot read the CSV table: {err.strerror or err}") from err
    except UnicodeDecodeError as err:
        raise TableNotUtf8(str(path), err.start, err.object[err.start]) from err
    header: list[str] | None = None
    times: list[float] = []
    values: list[float] = []
    rows: list[int] = []
    for number, row in enumerate(csv.reader(text.splitlines()), start=1):
        if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
            continue
        if header is None and not times:
            try:
                float(row[0])
            except ValueError:
                header = [c.strip() for c in row]
                continue
        if not times:
            t_col = _column(time_column, header, path)
            v_col = _column(column, header, path)
        try:
            times.append(float(row[t_col]))
            values.append(float(row[v_col]))
        except (ValueError, IndexError) as err:
            raise InputError(
                f"{path}: row {number} ({','.join(row)!r}) does not have numbers in columns "
                f"{t_col} and {v_col}"
            ) from err
        rows.append(number)
    spec = {"type": "csv", "file": str(path), "column": column, "sha256": file_sha256(path)}
    if time_column != 0:
        spec["time_column"] = time_column
    return Table(times, values, source=str(path), rows=rows, spec=spec)


def _column(column: int | str, header: list[str] | None, path: Path) -> int:
    if isinstance(column, int):
        return column
    if header is None or column not in header:
        raise InputError(
            f'{path}: no column named "{column}"; columns are: '
            + (", ".join(header) if header else "(no header row: give a column number)")
        )
    return header.index(column)


def check_covers(signal: Any, duration: float, where: str) -> None:
    """Refuse a table signal that ends before the run does; warn if one starts after t = 0.

    Raises:
        InputError: naming the source, its last row and time, and the run's duration.

    Warns:
        TableStartsLate: naming the source, its first time and the run's start (0 s).
    """
    tables = _tables(signal)
    for table in tables:
        if table.start > 0.0:
            warnings.warn(
                TableStartsLate(where, table.source, table.start, 0.0, float(table.samples[0])),
                stacklevel=2,
            )
    end = getattr(signal, "end", math.inf)
    if end < duration - 1e-9 * max(duration, 1.0):
        last = min(tables, key=lambda t: t.end, default=None)
        if last is not None:
            source = f"{last.source} ends at row {last.rows[-1]} (t = {last.end:g} s)"
        else:
            source = f"it ends at t = {end:g} s"
        raise InputError(
            f"{where}: {source} but the run lasts {duration:g} s; extend the table or shorten "
            "the run"
        )


def _tables(signal: Any) -> list[Table]:
    """The tables a signal reads, through its sums and scalings."""
    if isinstance(signal, Table):
        return [signal]
    if isinstance(signal, Scaled):
        return _tables(signal.signal)
    if isinstance(signal, Sum):
        return [t for term in signal.terms for t in _tables(term)]
    inner = getattr(signal, "table", None)
    return [inner] if isinstance(inner, Table) else []
