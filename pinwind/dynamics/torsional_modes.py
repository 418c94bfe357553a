"""The torsional-spring modes of a gear train: the frequency of the highest one.

Torsional springs (``<torsional_spring>``, shaft compliance k = GJ/L) between joints that the
meshes and drivers leave free to twist give modes of frequency ω² = eig(K, M) over the motions the
rigid rows allow, K = Σ k (e₁ − e₂)(e₁ − e₂)ᵀ: the train's linearisation
(``dynamics/linearisation.py``) with every mesh rigid. The compliant meshes' own modes are
``compliant.highest_mesh_mode_and_damping``'s.
"""

from __future__ import annotations

from collections.abc import Iterable

from pinwind.dynamics.linearisation import linearise
from pinwind.model.gearbox import Gearbox


def highest_spring_mode(gearbox: Gearbox, held: Iterable[str] = ()) -> float:
    """Frequency of the highest torsional-spring mode [Hz]; 0 without springs.

    Args:
        held: joints held at their speed (speed drivers); the meshes count as rigid.
    """
    if not gearbox.springs:
        return 0.0
    modes = linearise(gearbox, meshes={"all": "rigid"}, held=held).modes()
    return max((m.frequency for m in modes), default=0.0)
