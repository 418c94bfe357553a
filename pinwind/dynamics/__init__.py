"""Constraint rows, the proxsuite solve, integration, reactions and the Result."""

from pinwind.dynamics.result import BearingSeries, BodySeries, JointSeries, MeshSeries, Result
from pinwind.dynamics.simulate import RunObserver, simulate
from pinwind.dynamics.solver import SolverSettings

__all__ = [
    "BearingSeries",
    "BodySeries",
    "JointSeries",
    "MeshSeries",
    "Result",
    "RunObserver",
    "SolverSettings",
    "simulate",
]
