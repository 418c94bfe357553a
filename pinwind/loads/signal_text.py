"""Signals written as text or as plain specs, the same in the CLI, scenario files and logs.

The text form (``parse_signal``)::

    1e6                                                    constant
    ramp(start_value=0, end_value=1e6, start_time=0, end_time=5)
    step(time=1, before=0, after=1e6)
    sine(mean=200, amplitude=9.2, frequency=0.1, phase=0)  mean + A sin(2π f t + φ), φ [rad]
    csv(file="torque.csv", column=1)                       table, linear interpolation
    openfast(file="run.outb", channel="RotTorq", scale=1000)
    kaimal(mean=10, turbulence_intensity=0.1, seed=1)      turbulent wind (loads/wind.py)
    ramp(...) + sine(...)                                  sum

A spec (``signal_from_spec``) is a number, such a text, a dict with ``type`` (``Signal.spec()``)
or a list (a sum).
"""

from __future__ import annotations

import ast
import math
from pathlib import Path
from typing import Any

from pinwind.errors import InputError, NonFiniteInput
from pinwind.loads.input_files import InputFile
from pinwind.loads.openfast import read_channel
from pinwind.loads.signals import (
    Constant,
    Ramp,
    Scaled,
    Signal,
    Sine,
    Step,
    Sum,
    Table,
    file_sha256,
    read_csv,
)
from pinwind.loads.wind import KaimalWind

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


def signal_from_spec(
    spec: Any,
    *,
    base: Path | None = None,
    where: str = "signal",
    files: list[InputFile] | None = None,
) -> Signal:
    """A signal from a number, a text (``parse_signal``), a dict with ``type``, or a list (sum).

    Args:
        spec: the description.
        base: folder that relative file names are relative to (the scenario file's).
        where: the option or key, for messages.
        files: the fingerprint of every file the signal reads is appended to it (the log
            records them).

    Raises:
        InputError: an unknown kind or parameter, naming the valid ones.
    """
    if isinstance(spec, bool):
        raise InputError(f"{where}: {spec!r} is not a signal; give a number or a signal")
    if isinstance(spec, int | float):
        return Constant(float(spec))
    if isinstance(spec, str):
        return parse_signal(spec, base=base, where=where, files=files)
    if isinstance(spec, list | tuple):
        terms = tuple(signal_from_spec(s, base=base, where=where, files=files) for s in spec)
        if not terms:
            raise InputError(f"{where}: an empty list is not a signal")
        return terms[0] if len(terms) == 1 else Sum(terms)
    if isinstance(spec, dict):
        params = dict(spec)
        kind = params.pop("type", None)
        if kind == "sum":
            return signal_from_spec(params.get("terms", []), base=base, where=where, files=files)
        if kind == "scaled":
            inner = signal_from_spec(params.get("signal"), base=base, where=where, files=files)
            return Scaled(inner, float(params.get("factor", 1.0)))
        if kind == "table":
            return Table(params["times"], params["values"], source=where)
        return make_signal(kind, params, base=base, where=where, files=files)
    raise InputError(f"{where}: {spec!r} is not a signal; give a number or a signal")


def make_signal(
    kind: Any,
    params: dict[str, Any],
    *,
    base: Path | None,
    where: str,
    files: list[InputFile] | None = None,
) -> Signal:
    """A signal of a kind from its parameters (checked against ``KINDS``).

    ``files``: a file the signal reads is fingerprinted into it.
    """
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
        return KaimalWind(**params)
    path = Path(str(params["file"]))
    if base is not None and not path.is_absolute():
        path = base / path
    expected = params.get("sha256")
    if expected is not None and path.exists() and file_sha256(path) != expected:
        raise InputError(
            f"{where}: {path} has changed since the run was logged (sha256 differs); restore "
            "the file to repeat the run"
        )
    signal: Signal
    if kind == "csv":
        signal = read_csv(path, params.get("column", 1), time_column=params.get("time_column", 0))
    else:
        signal = read_channel(path, str(params["channel"]), scale=float(params.get("scale", 1.0)))
    if files is not None:
        files.append(InputFile.of(path, given=str(params["file"]), where=where))
    return signal


def parse_signal(
    text: str,
    *,
    base: Path | None = None,
    where: str = "signal",
    files: list[InputFile] | None = None,
) -> Signal:
    """A signal from its text form (module docstring): numbers, kinds with keywords, sums.

    ``files``: the fingerprint of every file the signal reads is appended to it.
    """
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as err:
        raise InputError(f'{where}: cannot read "{text}" as a signal: {err.msg}') from err
    return _signal_node(tree.body, text, base, where, files)


def _literal(node: ast.AST, text: str, where: str) -> Any:
    try:
        return ast.literal_eval(node)
    except ValueError as err:
        raise InputError(
            f'{where}: in "{text}", {ast.unparse(node)} is not a number or a quoted text'
        ) from err


def _signal_node(
    node: ast.AST, text: str, base: Path | None, where: str, files: list[InputFile] | None
) -> Signal:
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left = _signal_node(node.left, text, base, where, files)
        return left + _signal_node(node.right, text, base, where, files)
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
        return make_signal(node.func.id, params, base=base, where=where, files=files)
    value = _literal(node, text, where)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f'{where}: "{text}" is not a number or a signal')
    if not math.isfinite(value):
        raise NonFiniteInput(f"{where}: {text} is not finite")
    return Constant(float(value))
