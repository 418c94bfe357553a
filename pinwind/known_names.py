"""The one check of the names a file may use: TOML keys, the model file's elements and attributes.

A misspelt name must not be ignored: ``<bearing joint="sun" radial_stifness="1e9"/>`` would
leave the bearing rigid, ``[fatigue] duraton = 600`` would run the default 30 s, and nothing would
say so. Every reader of a file (``model/urdf.py``, ``scenario.py``,
``life/fatigue_set_file.py``) names what it takes and hands the names it found to
`unknown_name`; the first one it does not take is refused in the reader's own error, with the
nearest known name (difflib's ratio, as Python's own "did you mean" does) and the whole list.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

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
