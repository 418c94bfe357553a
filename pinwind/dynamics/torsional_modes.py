"""The torsional-spring modes of a gear train: the frequency of the highest one.

Torsional springs (``<torsional_spring>``, shaft compliance k = GJ/L) between joints that the
meshes and drivers leave free to twist give modes of frequency ω² = eig(K, M) over the motions the
rigid rows allow, K = Σ k (e₁ − e₂)(e₁ − e₂)ᵀ. The compliant meshes' own modes are
``compliant.highest_mesh_mode_and_damping``'s.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
import pinocchio as pin
from scipy.linalg import eigh

from pinwind.dynamics.ratios import train_modes
from pinwind.model.gearbox import Gearbox


def highest_spring_mode(gearbox: Gearbox, held: Iterable[str] = ()) -> float:
    """Frequency of the highest torsional-spring mode [Hz]; 0 without springs.

    Args:
        held: joints held at their speed (speed drivers); the meshes count as rigid.
    """
    nv = gearbox.model.nv
    stiffness = np.zeros((nv, nv))
    for s in gearbox.springs:
        e = np.zeros(nv)
        e[s.v_index_1], e[s.v_index_2] = 1.0, -1.0
        stiffness += s.stiffness * np.outer(e, e)
    if not stiffness.any():
        return 0.0
    basis = train_modes(gearbox, held).T
    if basis.shape[1] == 0:
        return 0.0
    mass = pin.crba(gearbox.model, gearbox.model.createData(), gearbox.neutral())
    mass = np.triu(mass) + np.triu(mass, 1).T
    omega2 = eigh(basis.T @ stiffness @ basis, basis.T @ mass @ basis, eigvals_only=True)
    return math.sqrt(max(float(omega2[-1]), 0.0)) / (2.0 * math.pi)
