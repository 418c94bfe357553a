"""Bearing reactions from Pinocchio's RNEA with the mesh forces applied at the pitch points.

With a and λ known, RNEA run with the tooth forces as external forces gives in ``data.f[j]`` the
spatial force that joint j transmits from its parent to its child, in the joint frame, about the
joint origin: the bearing force and moment (the reduced-coordinate form of
000_3b7c4a8fe52a6eee.txt eqs. 16, 18, 23 and 26).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pinwind.dynamics import kernels


class BearingReactions:
    """Evaluates every bearing's reaction for one state."""

    def __init__(self, model: pin.Model, joint_a: np.ndarray, joint_b: np.ndarray):
        self.model = model
        self.joint_a = joint_a
        self.joint_b = joint_b
        self.njoints = model.njoints
        self._wrench = np.zeros((model.njoints, 6))

        self._touched = sorted({int(j) for j in joint_a} | {int(j) for j in joint_b})
        self._fext = pin.StdVec_Force()
        for _ in range(model.njoints):
            self._fext.append(pin.Force.Zero())

    def external_forces(
        self, placements: np.ndarray, force_on_b: np.ndarray, pitch_point: np.ndarray
    ) -> pin.StdVec_Force:
        """Tooth forces as Pinocchio external forces, in each joint's frame about its origin.

        Args:
            placements: (njoints, 4, 4) world placements of the joints.
            force_on_b: (m, 3) tooth force on gear B in world [N]; gear A gets the opposite.
            pitch_point: (m, 3) where the tooth forces act, world [m].
        """
        kernels.tooth_wrenches(
            self.joint_a,
            self.joint_b,
            force_on_b,
            pitch_point,
            np.ascontiguousarray(placements[:, :3, 3]),
            np.ascontiguousarray(placements[:, :3, :3]),
            self._wrench,
        )
        for j in self._touched:
            self._fext[j] = pin.Force(self._wrench[j])
        return self._fext

    def evaluate(
        self,
        data: pin.Data,
        q: np.ndarray,
        v: np.ndarray,
        a: np.ndarray,
        fext: pin.StdVec_Force,
        placements: np.ndarray,
        out_local: np.ndarray,
        out_world: np.ndarray,
    ) -> None:
        """Fill ``out_local`` and ``out_world`` (joints, 6) = [force, moment] per bearing.

        The world version keeps the moment about the bearing centre and only rotates the axes.
        """
        pin.rnea(self.model, data, q, v, a, fext)
        for j in range(1, self.njoints):
            out_local[j - 1] = data.f[j].vector
        rot = placements[1:, :3, :3]
        out_world[:, :3] = np.einsum("jab,jb->ja", rot, out_local[:, :3])
        out_world[:, 3:] = np.einsum("jab,jb->ja", rot, out_local[:, 3:])
