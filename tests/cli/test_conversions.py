"""Plain command-line values convert as typer's own (pydantic) conversion converts them.

``pinwind/cli/conversions.py`` converts text, flags, integers, decimals, paths and lists of them
without importing pydantic; every value it declines goes to typer's conversion. Each check here
compares with typer's conversion itself (``typer._coercion.build_runtime_param``, which the
plain conversions replace only in ``typer.core``).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import pytest
from typer import _coercion
from typer._click.exceptions import BadParameter
from typer.models import ArgumentInfo, OptionInfo

from pinwind.cli import main
from pinwind.cli.conversions import plain_conversion
from tests.conftest import MODELS

MODEL = str(MODELS / "cart600_gearbox.urdf")


def typer_converts(annotation: Any, value: Any) -> Any:
    """The value as typer's own conversion (pydantic) gives it for an option of ``annotation``."""
    descriptor = _coercion.resolve_type_descriptor(annotation, OptionInfo())
    return _coercion.build_runtime_param(descriptor)._coerce_value(value, param=None, ctx=None)


def plain_converts(annotation: Any, value: Any) -> Any:
    """The value as ``conversions.py`` gives it, None where it leaves the value to typer."""
    convert = plain_conversion(annotation, OptionInfo())
    assert convert is not None
    return convert(value)


@pytest.mark.parametrize(
    ("annotation", "value"),
    [
        (int, "12"),
        (int, "-3"),
        (int, "+7"),
        (int, "007"),
        (int, " 5 "),
        (int, 101),  # a default value
        (float, "1.5"),
        (float, "-1.5e3"),
        (float, ".5"),
        (float, "5."),
        (float, "2"),
        (float, "1E-3"),
        (float, "+0.25"),
        (float, 3),  # a default value
        (str, "sun=-166666.6666666667"),
        (str, ""),
        (bool, True),
        (Path, MODEL),
        (Path, "no/such/model.urdf"),
        (Path, "."),
    ],
)
def test_a_plain_value_converts_to_what_typer_gives(annotation: Any, value: Any):
    converted = plain_converts(annotation, value)
    expected = typer_converts(annotation, value)
    assert converted == expected
    assert type(converted) is type(expected)


@pytest.mark.parametrize(
    ("annotation", "value"),
    [
        (int, "3.0"),  # pydantic reads it as 3
        (int, "1_000"),
        (int, "x"),
        (int, "٣"),  # Arabic-Indic three: int() reads it, pydantic does not
        (int, True),
        (float, "inf"),
        (float, "nan"),
        (float, "1_0.5"),
        (float, "1.5.2"),
        (bool, "yes"),
        (Path, ""),
    ],
)
def test_any_other_value_is_left_to_typer(annotation: Any, value: Any):
    assert plain_converts(annotation, value) is None


def test_a_list_option_converts_each_value():
    # ``--speed carrier=10 --speed sun=5``: click hands the values over as a tuple.
    convert = plain_conversion(list[float], OptionInfo())
    assert convert is not None
    assert [convert(v) for v in ("10", "-2.5e1")] == typer_converts(list[float], ("10", "-2.5e1"))


@pytest.mark.parametrize(
    "info",
    [
        OptionInfo(min=0),
        OptionInfo(parser=float),
        OptionInfo(exists=True),
        OptionInfo(resolve_path=True),
        ArgumentInfo(dir_okay=False),
    ],
)
def test_a_constrained_or_parsed_parameter_is_left_to_typer(info):
    annotation = Path if info.parser is None and info.min is None else int
    assert plain_conversion(annotation, info) is None


def test_a_malformed_number_gets_typers_message_and_exit_2(monkeypatch, capsys):
    with pytest.raises(BadParameter) as typers:
        typer_converts(int, "second")
    monkeypatch.setattr(sys, "argv", ["pinwind", "modes", MODEL, "--animate", "second"])
    with pytest.raises(SystemExit) as caught:
        main()
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert f"Invalid value for '--animate': {typers.value.message}" in err
