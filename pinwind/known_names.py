"""The one check of the names a file may use: TOML keys, the model file's elements and attributes.

A misspelt name must not be ignored: ``<bearing joint="sun" radial_stifness="1e9"/>`` would
leave the bearing rigid, ``[fatigue] skip_strat = 5`` would count from 0 s, and nothing would
say so. Every reader of a file (``model/urdf.py``, ``runs/scenario.py``,
``runs/fatigue_set_file.py``) names what it takes and hands the names it found to
`unknown_name`; the first one it does not take is refused in the reader's own error, with the
nearest known name (difflib's ratio, as Python's own "did you mean" does) and the whole list.
The TOML files (scenarios and fatigue sets) share one check of a table's keys, `check_keys`,
with the keys written with ``-`` or ``_`` alike (`toml_keys`).
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable, Mapping
from typing import Any

#: difflib's similarity ratio from which a known name is offered as the one meant [-].
CUTOFF = 0.6


def nearest(name: str, known: Iterable[str]) -> str | None:
    """The known name most like ``name`` (case aside), or None when none is alike.

    Args:
        name: the name as written.
        known: the names the reader takes.
    """
    by_lower = {k.lower(): k for k in known}
    matches = difflib.get_close_matches(name.lower(), list(by_lower), n=1, cutoff=CUTOFF)
    return by_lower[matches[0]] if matches else None


def unknown_message(name: str, known: Iterable[str], kind: str = "key", of: str = "") -> str:
    """What to say of an unknown ``name``: the nearest known name and the list of them all.

    ``unknown key "durtion"; did you mean "duration"? keys are: model, duration, ...``

    Args:
        name: the unknown name.
        known: the names the reader takes, in the order to list them.
        kind: what a name is (``key``, ``attribute``, ``element``, ``parameter``).
        of: whose names they are, after "keys" in the list's words (``" of [fatigue]"``).
    """
    names = list(known)
    guess = nearest(name, names)
    hint = f' did you mean "{guess}"?' if guess is not None else ""
    listed = ", ".join(names) or "none"
    return f'unknown {kind} "{name}";{hint} {kind}s{of} are: {listed}'


def unknown_name(given: Iterable[str], known: Iterable[str]) -> str | None:
    """The first of ``given`` that is not one of ``known``, or None when all are."""
    allowed = set(known)
    return next((name for name in given if name not in allowed), None)


#: A reader's error for a key's path (the table's path, then the key) and a message.
Refusal = Callable[[tuple[str, ...], str], Exception]


def toml_keys(table: Mapping[str, Any]) -> dict[str, Any]:
    """A TOML table with its keys written with ``_`` (``skip-start`` is ``skip_start``)."""
    return {key.replace("-", "_"): value for key, value in table.items()}


def check_keys(
    table: tuple[str, ...],
    given: Iterable[str],
    known: Iterable[str],
    fail: Refusal,
    *,
    kind: str = "key",
    of: str = "",
) -> None:
    """Refuse the first key of a TOML table that the reader does not take.

    Args:
        table: the table's path (``("fatigue", "site")``; ``()`` for the top level).
        given: its keys as written (after `toml_keys`).
        known: the keys the reader takes, in the order to list them.
        fail: the reader's error for a key path and a message (it names the file and line).
        kind, of: as in `unknown_message`.

    Raises:
        Exception: ``fail((*table, name), message)`` for the first unknown ``name``, the message
            naming the nearest known key and listing them all.
    """
    names = tuple(known)
    name = unknown_name(given, names)
    if name is not None:
        raise fail((*table, name), unknown_message(name, names, kind, of))
