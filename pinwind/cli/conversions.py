"""Command-line values converted without pydantic, as typer would convert them.

Typer (from 0.2x) converts every value of a command through a pydantic ``TypeAdapter``: importing
pydantic and building the adapters of one command costs about 0.15 s of CPU, more than
``pinwind modes`` spends on the modes themselves (issue 24: the command in < 1 s). The flags of
pinwind take text, flags, integers, decimals, paths and lists of them, which convert as
pydantic converts them: ``int("12")``, ``float("-1.5e3")``, ``Path("model.urdf")``. Those
conversions are done here; every other value (``3.0`` for an integer, ``inf``, ``yes`` for a
flag, a malformed number, an unreadable path, a type pinwind does not use) goes to typer's own
conversion, so errors and their messages stay typer's.

``use_plain_conversions`` installs this in typer's parameter class; with a typer whose internals
differ (older ones convert through click and never import pydantic) it changes nothing, and
``tests/test_lazy_exports.py`` says so by finding pydantic imported.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, get_args, get_origin

#: Integers and decimals in the forms pydantic reads as a typer value (ASCII digits; pydantic
#: rejects other scripts' digits, which ``int`` and ``float`` read).
_INTEGER = re.compile(r"\s*[+-]?[0-9]+\s*", re.ASCII)
_DECIMAL = re.compile(r"\s*[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?\s*", re.ASCII)
#: A path option's checks at typer's defaults (``typer.Option(exists=False, ...)``): then only
#: an existing file that cannot be read fails.
_PATH_DEFAULTS = {
    "exists": False,
    "file_okay": True,
    "dir_okay": True,
    "writable": False,
    "readable": True,
    "resolve_path": False,
    "allow_dash": False,
    "path_type": None,
}


def _text(value: Any) -> str | None:
    return value if isinstance(value, str) else None


def _flag(value: Any) -> bool | None:
    return value if isinstance(value, bool) else None


def _integer(value: Any) -> int | None:
    if type(value) is int:
        return value
    if isinstance(value, str) and _INTEGER.fullmatch(value):
        return int(value)
    return None


def _decimal(value: Any) -> float | None:
    if type(value) in (int, float):
        return float(value)
    if isinstance(value, str) and _DECIMAL.fullmatch(value):
        return float(value)
    return None


def _path(value: Any) -> Path | None:
    if not isinstance(value, str | Path) or value == "":
        return None
    if os.path.exists(value) and not os.access(value, os.R_OK):
        return None  # typer's message: "path '...' is not readable."
    return Path(value)


#: Each plain type and its conversion: the value, or None for typer to convert (or reject).
CONVERSIONS: dict[type, Callable[[Any], Any]] = {
    str: _text,
    bool: _flag,
    int: _integer,
    float: _decimal,
    Path: _path,
}


def plain_conversion(annotation: Any, parameter_info: Any) -> Callable[[Any], Any] | None:
    """The conversion of one value of a parameter, None if typer must convert it.

    Args:
        annotation: the parameter's type as typer resolved it (``int``, ``list[Path]``, ...).
        parameter_info: its ``typer.Option`` or ``typer.Argument``.
    """
    if get_origin(annotation) is list:
        (annotation,) = get_args(annotation)
    convert = CONVERSIONS.get(annotation)
    if convert is None or getattr(parameter_info, "parser", None) is not None:
        return None
    if annotation in (int, float) and (parameter_info.min, parameter_info.max) != (None, None):
        return None
    if annotation is Path and any(
        getattr(parameter_info, flag) != default for flag, default in _PATH_DEFAULTS.items()
    ):
        return None
    return convert


def use_plain_conversions() -> None:
    """Convert the plain values of every typer command here, the others with typer's pydantic."""
    try:
        import typer.core
        from typer._coercion import RuntimeParam, TypeDescriptor

        typer_conversion = typer.core.build_runtime_param
    except (ImportError, AttributeError):  # a typer that converts through click: nothing to do
        return
    if typer_conversion.__module__ == __name__:
        return  # installed already

    @dataclass(frozen=True)
    class PlainValue(RuntimeParam):
        """A parameter whose values convert here; the others go to typer's conversion."""

        descriptor: TypeDescriptor
        convert: Callable[[Any], Any]

        def _coerce_value(self, value: Any, param: Any, ctx: Any) -> Any:
            if get_origin(self.annotation) is list:
                items = value if isinstance(value, list | tuple) else [value]
                converted = [self.convert(item) for item in items]
                if None not in converted:
                    return converted
            elif (single := self.convert(value)) is not None:
                return single
            return typer_conversion(self.descriptor)._coerce_value(value, param=param, ctx=ctx)

    def build_runtime_param(descriptor: TypeDescriptor) -> RuntimeParam:
        convert = None
        if descriptor.file_annotation is None:
            convert = plain_conversion(descriptor.annotation, descriptor.parameter_info)
        if convert is None:
            return typer_conversion(descriptor)
        return PlainValue(
            parameter_info=descriptor.parameter_info,
            annotation=descriptor.annotation,
            descriptor=descriptor,
            convert=convert,
        )

    typer.core.build_runtime_param = build_runtime_param
