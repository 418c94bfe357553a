"""Every ``PinwindError`` crosses a process boundary whole: a worker's error is the same line.

The classes are found by introspection (every module of pinwind imported, the subclasses walked),
so a new error class is checked without naming it here; each is made from sample values of its
arguments' annotations.
"""

from __future__ import annotations

import importlib
import inspect
import pickle
import pkgutil

import pytest

import pinwind
from pinwind.errors import PinwindError

#: A sample value for each argument annotation the error classes use.
SAMPLES: dict[str, object] = {
    "str": "sun_planet1",
    "float": 0.125,
    "int": 7,
    "bool": False,
    "object": "a value",
    "Iterable[str]": ["carrier", "sun"],
    "list[str]": ["carrier", "sun"],
    "dict[str, float]": {"sun_radial_x": 1.0},
    "tuple[str, int]": ("e99d", 19),
    "tuple[str, int] | None": ("568d", 20),
}


def _error_classes() -> list[type[PinwindError]]:
    for module in pkgutil.walk_packages(pinwind.__path__, "pinwind."):
        if not module.name.endswith("__main__"):
            importlib.import_module(module.name)
    found: dict[type[PinwindError], None] = {}
    stack = [PinwindError]
    while stack:
        cls = stack.pop()
        found[cls] = None
        stack.extend(cls.__subclasses__())
    return sorted(found, key=lambda c: f"{c.__module__}.{c.__qualname__}")


def _made(cls: type[PinwindError]) -> PinwindError:
    """An instance of ``cls`` from sample values of its arguments."""
    args, kwargs = [], {}
    for name, parameter in inspect.signature(cls.__init__).parameters.items():
        if parameter.kind is parameter.VAR_POSITIONAL:  # Exception's own (*args): the message
            args.append(f"{cls.__name__}: the message")
        if name == "self" or parameter.kind in (parameter.VAR_POSITIONAL, parameter.VAR_KEYWORD):
            continue
        if parameter.annotation in SAMPLES:
            value: object = SAMPLES[parameter.annotation]
        else:
            pytest.fail(f"{cls.__name__}({name}: {parameter.annotation}): add a sample value")
        if parameter.kind is parameter.KEYWORD_ONLY:
            kwargs[name] = value
        else:
            args.append(value)
    return cls(*args, **kwargs)


ERRORS = _error_classes()


def test_the_error_classes_are_found_in_every_module():
    names = {cls.__name__ for cls in ERRORS}
    # One from errors.py, one from runs/scenario.py, one from gears/contact.py, one from io/.
    assert {"Diverged", "ScenarioError", "ContactRatioBelowOne", "UnknownChannel"} <= names
    assert len(ERRORS) >= 45


@pytest.mark.parametrize("cls", ERRORS, ids=[cls.__name__ for cls in ERRORS])
def test_an_error_survives_a_pickle_round_trip_with_its_message_and_values(cls):
    err = _made(cls)
    again = pickle.loads(pickle.dumps(err))
    assert type(again) is cls
    assert str(again) == str(err) and str(err)
    assert again.__dict__ == err.__dict__
