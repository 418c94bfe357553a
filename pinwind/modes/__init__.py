"""Natural modes of a machine: its linearisation at speed, modal classes, whirl, Campbell diagram.

Above ``dynamics``: the modes read the machine a run steps (``dynamics/drivetrain.py``) and its
linear model (``dynamics/linear_model.py``, with the symmetric eigenproblem
``dynamics/normal_modes.py``, which the run's own checks use); nothing in ``dynamics`` imports
this package.
"""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.dynamics.normal_modes import Mode
    from pinwind.modes.campbell import CampbellDiagram, campbell
    from pinwind.modes.linearisation import Linearisation, linearise
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = ["CampbellDiagram", "Linearisation", "Mode", "campbell", "linearise"]
