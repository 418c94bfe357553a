"""Force elements between bodies: torsional spring-dampers and viscous bearing damping.

Torsional spring between coaxial joints 1 and 2 (002_bb0c67d52fe8a188.txt "RSDA", k = GJ/L):

    τ₁ = −k (θ₁ − θ₂ − θ₀) − c (ω₁ − ω₂),   τ₂ = −τ₁

Viscous bearing damping (URDF ``<dynamics damping="c"/>``): τ = −c ω on the joint.
"""

from __future__ import annotations

import numpy as np

from pinwind.model.gearbox import Gearbox


class ForceElements:
    """Joint-space forces of all springs and bearing dampers of a gearbox."""

    def __init__(self, gearbox: Gearbox):
        springs = gearbox.springs
        self.index_1 = np.array([s.v_index_1 for s in springs], dtype=int)
        self.index_2 = np.array([s.v_index_2 for s in springs], dtype=int)
        self.stiffness = np.array([s.stiffness for s in springs])
        self.spring_damping = np.array([s.damping for s in springs])
        self.preload = np.array([s.preload_angle for s in springs])
        self.bearing_damping = np.array(gearbox.model.damping, dtype=float).copy()
        self.nv = gearbox.model.nv
        self._damped = bool(np.any(self.bearing_damping)) or bool(np.any(self.spring_damping))

    def elastic_torque(self, q: np.ndarray) -> np.ndarray:
        """Generalised force of the springs' stiffness, −k(θ₁ − θ₂ − θ₀) on joint 1 [N·m], (nv,).

        Assumes one coordinate per joint (all bearings revolute), so q and v share indices.
        """
        tau = np.zeros(self.nv)
        if len(self.stiffness):
            torque = -self.stiffness * (q[self.index_1] - q[self.index_2] - self.preload)
            np.add.at(tau, self.index_1, torque)
            np.add.at(tau, self.index_2, -torque)
        return tau

    def damping_torque(self, v: np.ndarray) -> np.ndarray:
        """Viscous forces of bearing dampers and spring dampers [N·m], (nv,)."""
        if not self._damped:
            return np.zeros(self.nv)
        tau = -self.bearing_damping * v
        if len(self.stiffness):
            torque = -self.spring_damping * (v[self.index_1] - v[self.index_2])
            np.add.at(tau, self.index_1, torque)
            np.add.at(tau, self.index_2, -torque)
        return tau

    def spring_energy(self, q: np.ndarray) -> float:
        """Elastic energy ½ k (θ₁ − θ₂ − θ₀)² stored in the springs [J]."""
        if not len(self.stiffness):
            return 0.0
        twist = q[self.index_1] - q[self.index_2] - self.preload
        return float(0.5 * np.sum(self.stiffness * twist**2))
