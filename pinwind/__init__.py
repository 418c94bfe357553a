"""pinwind: loads inside wind-turbine gearboxes.

Tooth force at every gear mesh and reaction at every bearing, over time, from a URDF gearbox model
(Pinocchio) whose gear meshes are velocity-constraint rows solved with proxsuite.
"""

from pinwind.dynamics.result import Result
from pinwind.dynamics.simulate import simulate
from pinwind.errors import PinwindError
from pinwind.model.gearbox import Gearbox, load

__version__ = "0.1.0"

__all__ = ["Gearbox", "PinwindError", "Result", "__version__", "load", "simulate"]
