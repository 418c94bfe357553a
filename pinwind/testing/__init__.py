"""Checks that make a gearbox model trustworthy, for users' own models and pytest suites.

Each check is one function that returns its figure (``CheckFigure``: what was compared, the
measured value, the tolerance) and raises ``pinwind.errors.CheckFailed`` with those values
beyond the tolerance (docs/testing.md):

- ``ledger_closure``: the energy ledger of a run closes;
- ``free_body_balance``: the bearings on the ground balance the weights and loads;
- ``speed_ratios``: every joint turns at its tooth ratio times the input's speed;
- ``element_tangents`` and ``conservative_forces``: the elements' tangents equal finite
  differences of their force, and their force is the gradient of their stored energy;
- ``modes_in_spectrum``: the natural modes ring in a free vibration's spectrum.

The names are imported on first use (``lazy_exports.py``).
"""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.testing.figure import CheckFigure
    from pinwind.testing.free_body import free_body_balance
    from pinwind.testing.free_vibration import modes_in_spectrum
    from pinwind.testing.kinematic_ratios import speed_ratios
    from pinwind.testing.ledger import ledger_closure
    from pinwind.testing.tangents import conservative_forces, element_tangents
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = [
    "CheckFigure",
    "conservative_forces",
    "element_tangents",
    "free_body_balance",
    "ledger_closure",
    "modes_in_spectrum",
    "speed_ratios",
]
