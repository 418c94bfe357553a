"""The ``pinwind`` Typer application and how its output reaches the terminal.

The apps (``app`` and its ``build`` and ``sweep`` groups) that the verb modules register their
commands on; the consoles (tables fit 80 columns, messages are one line each); pinwind warnings as
one line on stderr; SIGTERM raised like Ctrl-C so that a run stops cleanly and finishes its log.
"""

from __future__ import annotations

import signal
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

import typer
from rich.console import Console
from rich.markup import escape

from pinwind.cli.conversions import use_plain_conversions
from pinwind.errors import PinwindWarning

# Plain values (text, numbers, paths) convert without importing pydantic: 0.15 s per command.
use_plain_conversions()

app = typer.Typer(
    name="pinwind",
    help="Loads inside wind-turbine gearboxes: gear-mesh forces and bearing reactions.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Help texts are plain: "[s]" and "[rpm]" are units, not rich markup.
    rich_markup_mode=None,
)
build_app = typer.Typer(
    help="Write parametric gearbox models.", no_args_is_help=True, rich_markup_mode=None
)


def _print_version(value: bool) -> None:
    """``--version``: print the installed version of pinwind and stop."""
    if not value:
        return
    from importlib.metadata import PackageNotFoundError, version

    try:
        installed = version("pinwind")
    except PackageNotFoundError:  # run from a checkout on PYTHONPATH, never pip-installed
        installed = "not installed (run from a source tree)"
    print(f"pinwind {installed}")
    raise typer.Exit()


@app.callback()
def _options(
    version: bool = typer.Option(
        False,
        "--version",
        callback=_print_version,
        is_eager=True,
        help="Print the installed version of pinwind and exit.",
    ),
) -> None:
    """Loads inside wind-turbine gearboxes: gear-mesh forces and bearing reactions."""


app.add_typer(build_app, name="build")
sweep_app = typer.Typer(
    help="Design sweeps: enumerate, simulate, rate, query.", no_args_is_help=True
)
app.add_typer(sweep_app, name="sweep")

# Tables fit 80 columns (a terminal's width; 80 in pipes); pipes get plain ASCII tables.
console = Console()
# Errors and warnings are one line each, never hard-wrapped, so they can be copied whole.
err_console = Console(stderr=True, soft_wrap=True)


def say(text: str) -> None:
    """Print a line of text whole (never hard-wrapped, so it can be copied)."""
    console.print(text, soft_wrap=True, highlight=False)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that the run stops cleanly and its log is finished."""


def raise_terminated(signum, frame) -> None:
    """A SIGTERM handler: raise ``Terminated``."""
    raise Terminated(f"received {signal.Signals(signum).name}")


#: (category, message) of every pinwind warning a command has shown: one cause is shown once,
#: whichever of the command's steps meets it again (``main`` empties it for each command).
SHOWN_WARNINGS: set[tuple[type, str]] = set()


@contextmanager
def warnings_as_lines() -> Iterator[None]:
    """Show pinwind warnings (a recovered log, ...) as one line on stderr, each cause once.

    A command may meet one cause several times (the model loaded for the scenario, the run
    and the log): the same message is shown once (``SHOWN_WARNINGS``).
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PinwindWarning)
        try:
            yield
        finally:
            shown = list(caught)
    for warning in shown:
        if issubclass(warning.category, PinwindWarning):
            cause = (warning.category, str(warning.message))
            if cause in SHOWN_WARNINGS:
                continue
            SHOWN_WARNINGS.add(cause)
            err_console.print(
                f"[yellow]warning:[/yellow] {escape(str(warning.message))}", highlight=False
            )
        else:
            warnings.warn_explicit(
                warning.message, warning.category, warning.filename, warning.lineno
            )
