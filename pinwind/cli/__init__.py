"""Command-line interface: ``simulate``, ``run``, ``replay``, ``plot``, ``report``, ``build``, ...

Units at this edge are the ones drivetrain engineers type: rpm, mm, degrees; everything is turned
into SI before it reaches the library. One module per family of verbs, each registering its
commands on ``app`` (``cli/app.py``): ``simulate`` (simulate, run), ``logs`` (replay, plot,
report, export), ``model`` (info, view, build), ``rating`` (rate), ``spectrum`` (spectrum),
``modes`` (modes, campbell), ``sweep`` (sweep ...), ``fatigue`` (fatigue), ``life`` (life),
``transmission_error`` (te), ``fmu`` (fmu), ``efficiency`` (efficiency);
``flags`` turns
the flags of a run into scenario values. ``simulate`` logs every run to an MCAP file
(``logs/`` by default) that ``replay`` and ``report`` read back on their own.

A command imports only its verb's module (``VERB_MODULES``): ``pinwind modes`` neither imports
nor builds the other verbs, ``pinwind --version`` none. ``app`` (``pinwind.cli.app``),
``pinwind --help`` and a command that names no known verb register every verb (``cli/verbs.py``).
"""

from __future__ import annotations

import importlib
import sys
from typing import TYPE_CHECKING

from pinwind.errors import PinwindError
from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.cli.verbs import app

__all__ = ["app", "main"]
__getattr__, __dir__ = lazy_exports(__name__)

#: The module (in ``pinwind/cli/``) that registers each verb and group of verbs on ``app``.
VERB_MODULES = {
    "simulate": "simulate",
    "run": "simulate",
    "fatigue": "fatigue",
    "replay": "logs",
    "plot": "logs",
    "report": "logs",
    "export": "logs",
    "info": "model",
    "build": "model",
    "view": "model",
    "modes": "modes",
    "campbell": "modes",
    "rate": "rating",
    "spectrum": "spectrum",
    "sweep": "sweep",
    "life": "life",
    "te": "transmission_error",
    "fmu": "fmu",
    "efficiency": "efficiency",
}


def main() -> None:
    """Entry point: run the CLI and turn pinwind errors into one clear line and exit code 2."""
    verb = sys.argv[1] if len(sys.argv) > 1 else ""
    # ``--version`` needs no verb; ``--help``, no verb or an unknown one (its message lists the
    # verbs) need every verb.
    module = "app" if verb == "--version" else VERB_MODULES.get(verb, "verbs")
    try:
        importlib.import_module(f"pinwind.cli.{module}")
        from pinwind.cli.app import SHOWN_WARNINGS, err_console
        from pinwind.cli.app import app as application
    except KeyboardInterrupt:  # Ctrl-C while the command starts: a line, not an import traceback
        sys.stderr.write("interrupted while starting, before the command did anything\n")
        sys.exit(130)

    SHOWN_WARNINGS.clear()

    try:
        application()
    except PinwindError as err:
        from rich.markup import escape

        # soft_wrap: one line whatever its length (a long path must not be broken in two).
        err_console.print(
            f"[bold red]error:[/bold red] {escape(str(err))}", highlight=False, soft_wrap=True
        )
        sys.exit(2)
    except KeyboardInterrupt:
        err_console.print("interrupted")
        sys.exit(130)
