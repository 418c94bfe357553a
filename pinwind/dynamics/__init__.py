"""Constraint rows, the proxsuite solve, integration, reactions and the Result."""

from pinwind.dynamics.integrator import Integrator
from pinwind.dynamics.result import ElementSeries, Result
from pinwind.dynamics.simulate import RunObserver, simulate
from pinwind.dynamics.solver import SolverSettings

__all__ = [
    "ElementSeries",
    "Integrator",
    "Result",
    "RunObserver",
    "SolverSettings",
    "simulate",
]
