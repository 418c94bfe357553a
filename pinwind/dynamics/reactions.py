"""Bearing reactions from Pinocchio's RNEA with the mesh forces applied at the pitch points.

With a and λ known, RNEA run with the tooth forces as external forces gives in ``data.f[j]`` the
spatial force that joint j transmits from its parent to its child, in the joint frame, about the
joint origin: the bearing force and moment (the reduced-coordinate form of
000_3b7c4a8fe52a6eee.txt eqs. 16, 18, 23 and 26).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pinwind.dynamics.mesh import cross


class BearingReactions:
    """Evaluates every bearing's reaction for one state."""

    def __init__(self, model: pin.Model, joint_a: np.ndarray, joint_b: np.ndarray):
        self.model = model
        self.joint_a = joint_a
        self.joint_b = joint_b
        self.njoints = model.njoints
        self._touched = sorted({int(j) for j in joint_a} | {int(j) for j in joint_b})
        self._fext = pin.StdVec_Force()
        for _ in range(model.njoints):
            self._fext.append(pin.Force.Zero())

    def external_forces(
        self,
        data: pin.Data,
        force_on_b: np.ndarray,
        lever_a: np.ndarray,
        lever_b: np.ndarray,
    ) -> pin.StdVec_Force:
        """Tooth forces as Pinocchio external forces, in each joint's frame about its origin.

        Args:
            force_on_b: (m, 3) tooth force on gear B in world [N]; gear A gets the opposite.
            lever_a, lever_b: (m, 3) pitch point minus the joint origin of A and of B, world [m].
        """
        wrench = np.zeros((self.njoints, 6))
        moments = cross(np.stack([lever_b, lever_a]), np.broadcast_to(force_on_b, (2,) + force_on_b.shape))
        np.add.at(wrench[:, :3], self.joint_b, force_on_b)
        np.add.at(wrench[:, 3:], self.joint_b, moments[0])
        np.add.at(wrench[:, :3], self.joint_a, -force_on_b)
        np.add.at(wrench[:, 3:], self.joint_a, -moments[1])
        for j in self._touched:
            rot_t = data.oMi[j].rotation.T
            self._fext[j] = pin.Force(rot_t @ wrench[j, :3], rot_t @ wrench[j, 3:])
        return self._fext

    def evaluate(
        self,
        data: pin.Data,
        q: np.ndarray,
        v: np.ndarray,
        a: np.ndarray,
        fext: pin.StdVec_Force,
        out_local: np.ndarray,
        out_world: np.ndarray,
    ) -> None:
        """Fill ``out_local`` and ``out_world`` (joints, 6) = [force, moment] per bearing.

        The world version keeps the moment about the bearing centre and only rotates the axes.
        """
        pin.rnea(self.model, data, q, v, a, fext)
        for j in range(1, self.njoints):
            f = data.f[j].vector
            rot = data.oMi[j].rotation
            out_local[j - 1] = f
            out_world[j - 1, :3] = rot @ f[:3]
            out_world[j - 1, 3:] = rot @ f[3:]
