"""pinwind: loads inside wind-turbine gearboxes.

Tooth force at every gear mesh and reaction at every bearing, over time, from a URDF gearbox model
(Pinocchio) whose gear meshes are velocity-constraint rows, solved each step by default through the
Schur complement of the KKT system (proxsuite's proximal method is the reference alternative,
``SolverSettings(method="proxsuite")``). Every run can be logged to one self-contained MCAP
file (``simulate(..., log="run.mcap")``, ``read_log``).

The names below are imported on first use (``lazy_exports.py``): ``import pinwind`` stays cheap
for the command line and for worker processes.
"""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.errors import PinwindError
    from pinwind.io.log_reader import read_log
    from pinwind.model.gearbox import Gearbox, load
    from pinwind.runs.run import simulate
    from pinwind.runs.session import Session
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__version__ = "0.1.0"

__all__ = [
    "Gearbox",
    "PinwindError",
    "Result",
    "Session",
    "__version__",
    "load",
    "read_log",
    "simulate",
]
