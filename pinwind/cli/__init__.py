"""Command-line interface: ``simulate``, ``run``, ``replay``, ``plot``, ``report``, ``build``, ...

Units at this edge are the ones drivetrain engineers type: rpm, mm, degrees; everything is turned
into SI before it reaches the library. One module per family of verbs, each registering its
commands on ``app`` (``cli/app.py``): ``simulate`` (simulate, run), ``logs`` (replay, plot,
report, export), ``model`` (info, view, build), ``rating`` (rate), ``spectrum`` (spectrum),
``modes`` (modes, campbell), ``sweep`` (sweep ...), ``fatigue`` (fatigue); ``flags`` turns
the flags of a run into scenario values. ``simulate`` logs every run to an MCAP file
(``logs/`` by default) that ``replay`` and ``report`` read back on their own.
"""

from __future__ import annotations

import sys

from rich.markup import escape

# The verb modules register their commands on ``app`` as they are imported: ``simulate`` and
# ``run`` first, then the others, the order of ``pinwind --help``.
from pinwind.cli import simulate  # noqa: F401

# isort: split
from pinwind.cli import fatigue, logs, model, modes, rating, spectrum, sweep  # noqa: F401
from pinwind.cli.app import app, err_console
from pinwind.errors import PinwindError

__all__ = ["app", "main"]


def main() -> None:
    """Entry point: run the CLI and turn pinwind errors into one clear line and exit code 2."""
    try:
        app()
    except PinwindError as err:
        # soft_wrap: one line whatever its length (a long path must not be broken in two).
        err_console.print(
            f"[bold red]error:[/bold red] {escape(str(err))}", highlight=False, soft_wrap=True
        )
        sys.exit(2)
    except KeyboardInterrupt:
        err_console.print("interrupted")
        sys.exit(130)
