"""Where a warning points: the user's line, not pinwind's.

A warning raised deep in a run (``simulate`` → ``prepare`` → a check) would name a line of
pinwind with a fixed ``stacklevel``, and one reached by two routes (``pinwind.simulate`` and
``pinwind.dynamics.simulate``) could name the right line on one route only. ``user_stacklevel``
counts the frames up to the first outside the package instead.
"""

from __future__ import annotations

import sys


def user_stacklevel() -> int:
    """The ``stacklevel`` of the first frame outside the ``pinwind`` package.

    For ``warnings.warn`` in the calling function; the outermost frame if every one is
    pinwind's (as under the command line).
    """
    frame = sys._getframe(1)  # the function that warns: stacklevel 1
    level = 1
    while frame.f_back is not None and frame.f_globals.get("__name__", "").split(".")[0] == (
        "pinwind"
    ):
        frame = frame.f_back
        level += 1
    return level
