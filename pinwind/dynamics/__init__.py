"""Constraint rows, the proxsuite solve, integration, reactions and the Result."""

from pinwind.dynamics.result import ElementSeries, Result
from pinwind.dynamics.simulate import RunObserver, simulate
from pinwind.dynamics.solver import SolverSettings

__all__ = [
    "ElementSeries",
    "Result",
    "RunObserver",
    "SolverSettings",
    "simulate",
]
