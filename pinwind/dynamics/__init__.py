"""Constraint rows, the step's solve (direct Schur by default), integration, reactions, Result."""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.dynamics.drivetrain import Drivetrain, drivetrain
    from pinwind.dynamics.integrator import Integrator
    from pinwind.dynamics.result import ElementSeries, Result
    from pinwind.dynamics.run_settings import RunSettings
    from pinwind.dynamics.simulate import PreparedRun, RunObserver, prepare, simulate
    from pinwind.dynamics.solver import SolverSettings
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = [
    "Drivetrain",
    "ElementSeries",
    "Integrator",
    "PreparedRun",
    "Result",
    "RunObserver",
    "RunSettings",
    "SolverSettings",
    "drivetrain",
    "prepare",
    "simulate",
]
