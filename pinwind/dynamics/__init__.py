"""Constraint rows, the proxsuite solve, integration, reactions and the Result."""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.dynamics.integrator import Integrator
    from pinwind.dynamics.result import ElementSeries, Result
    from pinwind.dynamics.simulate import RunObserver, simulate
    from pinwind.dynamics.solver import SolverSettings
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = [
    "ElementSeries",
    "Integrator",
    "Result",
    "RunObserver",
    "SolverSettings",
    "simulate",
]
