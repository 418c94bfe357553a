"""Time signals for torques, speed drivers and wind: constant, ramp, step, sine, sum, tables.

A ``Signal`` is a function of time t [s] whose values the run evaluates for a whole block of
samples at once (``values``), so no Python call is made per step. Every signal can be written as
text, the same in the CLI and in scenario files (``parse_signal``)::

    1e6                                                    constant
    ramp(start_value=0, end_value=1e6, start_time=0, end_time=5)
    step(time=1, before=0, after=1e6)
    sine(mean=200, amplitude=9.2, frequency=0.1, phase=0)  mean + A sin(2π f t + φ), φ [rad]
    csv(file="torque.csv", column=1)                       table, linear interpolation
    openfast(file="run.outb", channel="RotTorq", scale=1000)
    kaimal(mean=10, turbulence_intensity=0.1, seed=1)      turbulent wind (loads/wind.py)
    ramp(...) + sine(...)                                  sum

(002_bb0c67d52fe8a188.txt eq. 2-1 is the sine: Ω = A sin(ωt) + X.) Values are in the unit of
what they drive: N·m for torques, m/s for wind, rpm for speeds at the CLI and in scenario files
(``Scaled`` turns them into rad/s).

Tables refuse rows that are unsorted, duplicated or not finite, naming the file and row, and a run
longer than the table (``check_covers``).
"""

from __future__ import annotations

import ast
import csv
import hashlib
import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import InputError, NonFiniteInput


class Signal(ABC):
    """A function of time evaluated on arrays of times.

    Subclasses give ``values(t)`` (any shape of t [s]) and ``spec()``, a plain dict that
    ``signal_from_spec`` turns back into an equal signal (scenario files and logs).
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
        """The signal as text (``parse_signal`` reads it back)."""
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
    """mean + amplitude · sin(2π frequency t + phase) (002_bb0c67d52fe8a188.txt eq. 2-1).

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


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def read_csv(path: str | Path, column: int | str = 1, *, time_column: int | str = 0) -> Table:
    """A table from a CSV file: a time column [s] and a value column.

    A first row that is not numeric is taken as the header; columns are given by index (0-based)
    or header name. Blank lines and lines starting with ``#`` are skipped.

    Raises:
        InputError: the file is missing, a row is malformed, unsorted or duplicated (naming the
            file and row), or the column does not exist.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise InputError(f"{path}: cannot read the CSV table: {err.strerror or err}") from err
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
    spec = {"type": "csv", "file": str(path), "column": column, "sha256": _sha256(path)}
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
    """Refuse a table signal that ends before the run does.

    Raises:
        InputError: naming the source, its last row and time, and the run's duration.
    """
    end = getattr(signal, "end", math.inf)
    if end < duration - 1e-9 * max(duration, 1.0):
        table = _last_table(signal)
        if table is not None:
            source = f"{table.source} ends at row {table.rows[-1]} (t = {table.end:g} s)"
        else:
            source = f"it ends at t = {end:g} s"
        raise InputError(
            f"{where}: {source} but the run lasts {duration:g} s; extend the table or shorten "
            "the run"
        )


def _last_table(signal: Any) -> Table | None:
    if isinstance(signal, Table):
        return signal
    if isinstance(signal, Scaled):
        return _last_table(signal.signal)
    if isinstance(signal, Sum):
        tables = [t for t in map(_last_table, signal.terms) if t is not None]
        return min(tables, key=lambda t: t.end, default=None)
    inner = getattr(signal, "table", None)
    return inner if isinstance(inner, Table) else None


# --- text and specs -----------------------------------------------------------------------------

#: Signal kinds and their parameters (the text form and the scenario tables use these names).
KINDS: dict[str, tuple[str, ...]] = {
    "constant": ("value",),
    "ramp": ("start_value", "end_value", "start_time", "end_time"),
    "step": ("time", "before", "after"),
    "sine": ("mean", "amplitude", "frequency", "phase"),
    "csv": ("file", "column", "time_column", "sha256"),
    "openfast": ("file", "channel", "scale", "sha256"),
    "kaimal": ("mean", "turbulence_intensity", "seed", "duration", "sample_time",
               "length_scale", "hub_height", "rotor_radius"),
}  # fmt: skip
_OPTIONAL = {"phase", "column", "time_column", "sha256", "scale", "duration", "sample_time",
             "length_scale", "hub_height", "rotor_radius"}  # fmt: skip


def signal_from_spec(spec: Any, *, base: Path | None = None, where: str = "signal") -> Signal:
    """A signal from a number, a text (``parse_signal``), a dict with ``type``, or a list (sum).

    Args:
        spec: the description.
        base: folder that relative file names are relative to (the scenario file's).
        where: the option or key, for messages.

    Raises:
        InputError: an unknown kind or parameter, naming the valid ones.
    """
    if isinstance(spec, bool):
        raise InputError(f"{where}: {spec!r} is not a signal; give a number or a signal")
    if isinstance(spec, int | float):
        return Constant(float(spec))
    if isinstance(spec, str):
        return parse_signal(spec, base=base, where=where)
    if isinstance(spec, list | tuple):
        terms = tuple(signal_from_spec(s, base=base, where=where) for s in spec)
        if not terms:
            raise InputError(f"{where}: an empty list is not a signal")
        return terms[0] if len(terms) == 1 else Sum(terms)
    if isinstance(spec, dict):
        params = dict(spec)
        kind = params.pop("type", None)
        if kind == "sum":
            return signal_from_spec(params.get("terms", []), base=base, where=where)
        if kind == "scaled":
            inner = signal_from_spec(params.get("signal"), base=base, where=where)
            return Scaled(inner, float(params.get("factor", 1.0)))
        if kind == "table":
            return Table(params["times"], params["values"], source=where)
        return make_signal(kind, params, base=base, where=where)
    raise InputError(f"{where}: {spec!r} is not a signal; give a number or a signal")


def make_signal(kind: Any, params: dict[str, Any], *, base: Path | None, where: str) -> Signal:
    """A signal of a kind from its parameters (checked against ``KINDS``)."""
    if kind not in KINDS:
        raise InputError(
            f'{where}: unknown signal "{kind}"; signals are: {", ".join(KINDS)}, or a number'
        )
    allowed = KINDS[kind]
    for key in params:
        if key not in allowed:
            raise InputError(
                f'{where}: {kind}() has no parameter "{key}"; its parameters are: '
                + ", ".join(allowed)
            )
    missing = [k for k in allowed if k not in params and k not in _OPTIONAL]
    if missing:
        raise InputError(
            f"{where}: {kind}() needs {', '.join(missing)} (parameters: {', '.join(allowed)})"
        )
    for key, value in params.items():
        if key not in ("file", "channel", "sha256", "column", "time_column"):
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise InputError(f"{where}: {kind}({key}=...) must be a number; got {value!r}")
            if not math.isfinite(value):
                raise NonFiniteInput(f"{where}: {kind}({key}={value}) is not finite")
    if kind == "constant":
        return Constant(float(params["value"]))
    if kind == "ramp":
        return Ramp(**{k: float(v) for k, v in params.items()})
    if kind == "step":
        return Step(**{k: float(v) for k, v in params.items()})
    if kind == "sine":
        return Sine(**{k: float(v) for k, v in params.items()})
    if kind == "kaimal":
        from pinwind.loads.wind import KaimalWind

        return KaimalWind(**params)
    path = Path(str(params["file"]))
    if base is not None and not path.is_absolute():
        path = base / path
    expected = params.get("sha256")
    if expected is not None and path.exists() and _sha256(path) != expected:
        raise InputError(
            f"{where}: {path} has changed since the run was logged (sha256 differs); restore "
            "the file to repeat the run"
        )
    if kind == "csv":
        return read_csv(path, params.get("column", 1), time_column=params.get("time_column", 0))
    from pinwind.loads.openfast import read_channel

    return read_channel(path, str(params["channel"]), scale=float(params.get("scale", 1.0)))


def parse_signal(text: str, *, base: Path | None = None, where: str = "signal") -> Signal:
    """A signal from its text form (module docstring): numbers, kinds with keywords, sums."""
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as err:
        raise InputError(f'{where}: cannot read "{text}" as a signal: {err.msg}') from err
    return _signal_node(tree.body, text, base, where)


def _literal(node: ast.AST, text: str, where: str) -> Any:
    try:
        return ast.literal_eval(node)
    except ValueError as err:
        raise InputError(
            f'{where}: in "{text}", {ast.unparse(node)} is not a number or a quoted text'
        ) from err


def _signal_node(node: ast.AST, text: str, base: Path | None, where: str) -> Signal:
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left = _signal_node(node.left, text, base, where)
        return left + _signal_node(node.right, text, base, where)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
        if node.args:
            raise InputError(
                f'{where}: in "{text}", give {node.func.id}() its parameters by name, e.g. '
                f"{node.func.id}({', '.join(f'{k}=...' for k in KINDS.get(node.func.id, ()))})"
            )
        params: dict[str, Any] = {}
        for kw in node.keywords:
            if kw.arg is None:  # **{...}
                raise InputError(
                    f'{where}: in "{text}", give {node.func.id}() its parameters as key=value, '
                    "not as **{...}"
                )
            params[kw.arg] = _literal(kw.value, text, where)
        return make_signal(node.func.id, params, base=base, where=where)
    value = _literal(node, text, where)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f'{where}: "{text}" is not a number or a signal')
    if not math.isfinite(value):
        raise NonFiniteInput(f"{where}: {text} is not finite")
    return Constant(float(value))
