"""The application with every verb registered: what ``pinwind --help`` and ``pinwind.cli.app`` show.

Each verb module registers its commands on ``app`` as it is imported: ``simulate`` and ``run``
first, then the others, the order of ``pinwind --help``. A command that names its verb imports
only that verb's module (``pinwind.cli.main``).
"""

from __future__ import annotations

from pinwind.cli import simulate  # noqa: F401

# isort: split
from pinwind.cli import (  # noqa: F401
    efficiency,
    fatigue,
    fmu,
    life,
    logs,
    model,
    modes,
    rating,
    spectrum,
    sweep,
    transmission_error,
)
from pinwind.cli.app import app

__all__ = ["app"]
