"""Harris's roller sum: a rolling bearing's radial force from its rolling elements, SI units.

The radial load of a rolling bearing is the sum of its Z rolling elements' Hertzian contact
loads (T. A. Harris and M. N. Kotzalas, Rolling Bearing Analysis, 5th ed., 2007; the
load-deflection relation Q = K_n δⁿ of each element, n = 10/9 for line contact (rollers),
3/2 for point contact (balls)). With the body displaced by r = (x, y) [m] in the bearing's
joint frame (radial axes u, w) and a radial clearance c [m], element j at ψ_j = 2πj/Z from u
along e_j = (cos ψ_j, sin ψ_j) is compressed by δ_j = r·e_j − c when positive, and the
bearing's force on the body is

    F(r) = −Σ_j K_n max(δ_j, 0)ⁿ e_j        [N], joint frame
    K(r) = −∂F/∂r = Σ_j n K_n max(δ_j, 0)ⁿ⁻¹ e_j e_jᵀ       [N/m]

(Harris's F_r = Σ K_n (δ_r cos ψ_j − P_d/2)ⁿ cos ψ_j for a displacement δ_r along u, with the
diametral clearance P_d = 2c). The elements stay where the cage is at t = 0 (the variation of
stiffness as they roll past, the varying-compliance excitation, is not modelled).
``cpp/bearing_spring.hpp`` evaluates the same law in the step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The load-deflection exponent n of a rolling element's contact, by contact kind.
CONTACT_EXPONENTS = {"line": 10.0 / 9.0, "point": 1.5}


def element_directions(rollers: int) -> np.ndarray:
    """e_j of the Z rolling elements, (Z, 2), ψ_j = 2πj/Z from the radial axis u."""
    psi = 2.0 * np.pi * np.arange(rollers) / rollers
    return np.stack([np.cos(psi), np.sin(psi)], axis=1)


@dataclass(frozen=True)
class RollerSum:
    """Harris's roller sum of one bearing (module docstring).

    Attributes:
        rollers: Z, the rolling elements.
        contact_stiffness: K_n [N/mⁿ] of one element's contact.
        exponent: n (``CONTACT_EXPONENTS``).
        clearance: radial clearance c [m].
    """

    rollers: int
    contact_stiffness: float
    exponent: float
    clearance: float = 0.0

    def force(self, displacement: np.ndarray) -> np.ndarray:
        """F(r) [N] on the body at displacements r (..., 2) [m], joint frame."""
        e = element_directions(self.rollers)
        compression = np.maximum(np.asarray(displacement, dtype=float) @ e.T - self.clearance, 0.0)
        return -self.contact_stiffness * compression**self.exponent @ e

    def tangent(self, displacement: np.ndarray) -> np.ndarray:
        """K(r) = −∂F/∂r [N/m], (2, 2), at one displacement r (2,) [m]."""
        e = element_directions(self.rollers)
        compression = np.maximum(e @ np.asarray(displacement, dtype=float) - self.clearance, 0.0)
        slope = np.zeros_like(compression)
        loaded = compression > 0.0
        slope[loaded] = (
            self.exponent * self.contact_stiffness * compression[loaded] ** (self.exponent - 1.0)
        )
        return (e.T * slope) @ e

    def static_deflection(self, load: np.ndarray) -> np.ndarray:
        """The displacement r (2,) [m] at which the bearing carries ``load`` (2,) [N] on the body.

        Solves F(r) + load = 0 by Newton's method, from the displacement at which the element
        nearest the load's direction would carry it alone (beyond the solution: the others
        share it), halving a step that would not lower the residual.
        """
        load = np.asarray(load, dtype=float)
        magnitude = float(np.linalg.norm(load))
        if magnitude == 0.0:
            return np.zeros(2)
        direction = load / magnitude
        nearest = float(np.max(element_directions(self.rollers) @ direction))
        alone = (magnitude / self.contact_stiffness) ** (1.0 / self.exponent)
        r = direction * (self.clearance + alone) / max(nearest, 0.1)
        residual = self.force(r) + load
        for _ in range(200):
            if np.linalg.norm(residual) <= 1e-13 * magnitude:
                break
            step = np.linalg.lstsq(self.tangent(r), residual, rcond=None)[0]
            scale = 1.0
            while True:
                trial = r + scale * step
                trial_residual = self.force(trial) + load
                if np.linalg.norm(trial_residual) < np.linalg.norm(residual) or scale < 1e-6:
                    break
                scale *= 0.5
            r, residual = trial, trial_residual
        return r
