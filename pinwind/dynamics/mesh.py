"""Rigid gear-mesh constraint rows, all meshes of a gearbox at once.

Each mesh A–B adds one velocity constraint along its line of action n (the gear-mesh
velocity constraint of Saleh 2017, eqs. 38-40, written for moving centres):

    c = n · (v_B(P) − v_A(P)) = 0,        J = nᵀ (J_B(P) − J_A(P))

with v_X(P) the velocity of the material point of body X at the pitch point P. With fixed axes this
is the familiar r_b,A ω_A ± r_b,B ω_B = 0 of Saleh 2017 eqs. 38-40, but the row is
built from Pinocchio Jacobians and stays right when a gear centre moves. The multiplier λ of the row
is the tooth normal force (transverse, along n) on B; −λ n acts on A.

A helical mesh's row is along the direction of its whole tooth force on B, f = n − s tan β_b k
(k gear A's axis, β_b A's base helix angle, signed by its hand): c = f · (v_B(P) − v_A(P)), so its
multiplier's generalized force Jᵀλ carries the axial thrust −s λ tan β_b k at P to the gears'
axial slides and, by P's lever from each centre, its tilting moment.

The acceleration-level bias is the exact time derivative of c at zero joint acceleration. P and n
are spatial (geometric) quantities, not material points, so

    ċ − J q̈ = ṅ·Δv + n·Δa_s(P) + n·((ω_B − ω_A) × Ṗ)

where a_s is the spatial acceleration field of a body (Pinocchio's ``data.a`` at q̈ = 0) and
Δ = B − A. For fixed axes the three terms cancel and γ = 0, as the constant row demands.

n = s cos α_w t + ε sin α_w r̂ (docs/model_format.md): the row and bias are kept as their t, r̂
and k parts so that switching the loaded flank s costs nothing (f's bias has ḟ for ṅ).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pinwind.dynamics import _native
from pinwind.model.gearbox import Gearbox, Mesh


def joint_placements(model: pin.Model, data: pin.Data) -> np.ndarray:
    """World placements of all joints (njoints, 4, 4) from ``data.oMi``."""
    out = np.empty((model.njoints, 4, 4))
    for j in range(model.njoints):
        out[j] = data.oMi[j].homogeneous
    return out


#: Rows of all meshes at one state (``MeshSet.evaluate``), split in their tangential, radial and
#: axial parts and formed for both flanks by the compiled code (``cpp/mesh_rows.hpp``): for flank
#: s the row is ``cos_a * s * jac_t + sin_a * eps * jac_r - s * tan_beta_b * jac_k`` (same for the
#: bias), the direction f = n − s tan β_b k of the tooth force on B. Fields: ``_native.pyi``.
MeshRows = _native.MeshRows


class MeshSet:
    """Geometry constants of every mesh, and the evaluation of their rows at a state.

    Args:
        gearbox: the model.
        meshes: the meshes, if not the gearbox's own (a run's rigid/compliant choice).
    """

    def __init__(self, gearbox: Gearbox, meshes: list[Mesh] | None = None):
        meshes = gearbox.meshes if meshes is None else meshes
        self.names = [m.name for m in meshes]
        self.count = len(meshes)
        joints = sorted({m.gear_a.joint_id for m in meshes} | {m.gear_b.joint_id for m in meshes})
        #: Pinocchio joint ids that carry a meshing gear.
        self.joint_ids = joints
        slot = {j: i for i, j in enumerate(joints)}
        self.slot_a = np.array([slot[m.gear_a.joint_id] for m in meshes], dtype=int)
        self.slot_b = np.array([slot[m.gear_b.joint_id] for m in meshes], dtype=int)
        self.joint_a = np.array([m.gear_a.joint_id for m in meshes], dtype=int)
        self.joint_b = np.array([m.gear_b.joint_id for m in meshes], dtype=int)
        self.centre_a = np.array([m.gear_a.centre_in_joint for m in meshes]).reshape(-1, 3)
        self.centre_b = np.array([m.gear_b.centre_in_joint for m in meshes]).reshape(-1, 3)
        self.axis_a = np.array([m.gear_a.axis_in_joint for m in meshes]).reshape(-1, 3)
        self.axis_b = np.array([m.gear_b.axis_in_joint for m in meshes]).reshape(-1, 3)
        alpha = np.array([m.working_pressure_angle for m in meshes])
        self.cos_a = np.cos(alpha)
        self.sin_a = np.sin(alpha)
        self.tan_beta_b = np.tan(np.array([m.base_helix_angle for m in meshes]))
        self.mu = np.array([m.pitch_fraction for m in meshes])
        self.sigma = np.array([m.line_sign for m in meshes])
        self.eps = np.array([m.radial_sign for m in meshes])
        model = gearbox.model
        #: support[i, k] = 1 when velocity k moves the body of joint_ids[i].
        self.support = np.zeros((len(joints), model.nv))
        for i, j in enumerate(joints):
            for s in model.supports[j]:
                if s > 0:
                    self.support[i, model.joints[s].idx_v] = 1.0
        self._v = np.zeros(model.nv)
        #: The constants as the compiled code takes them (cpp/mesh_rows.hpp MeshConstants).
        self.constants = constants = _native.MeshConstants()
        constants.joint_ids = joints
        constants.slot_a = self.slot_a.tolist()
        constants.slot_b = self.slot_b.tolist()
        constants.centre_a = self.centre_a
        constants.centre_b = self.centre_b
        constants.axis_a = self.axis_a
        constants.axis_b = self.axis_b
        constants.mu = self.mu
        constants.sigma = self.sigma
        constants.support = self.support
        constants.cos_a = self.cos_a
        constants.sin_a = self.sin_a
        constants.eps = self.eps
        constants.tan_beta_b = self.tan_beta_b
        constants.joint_a = self.joint_a.tolist()
        constants.joint_b = self.joint_b.tolist()

    def evaluate(
        self, model: pin.Model, data: pin.Data, placements: np.ndarray | None = None
    ) -> MeshRows:
        """Rows at the state of ``data``.

        Needs ``computeJointJacobiansTimeVariation(q, v)`` to have run on ``data``: it gives the
        placements, the world-frame Jacobian J and its time variation J̇ (whose product with v is
        the spatial acceleration at q̈ = 0). Velocities here are spatial, taken at the world origin
        and in world axes, so a point x of body X moves with v_o + ω × x. The arithmetic is
        compiled, ``cpp/mesh_rows.hpp``, the same code the step loop uses.

        Args:
            placements: (njoints, 4, 4) world placements of all joints, if already read from
                ``data.oMi``.
        """
        if placements is None:
            placements = joint_placements(model, data)
        ids = self.joint_ids
        nv = model.nv
        # Pinocchio hands a one-column matrix to numpy as a vector: keep it (6, nv).
        return _native.mesh_rows(
            self.constants,
            np.reshape(data.J, (6, nv)),
            np.reshape(data.dJ, (6, nv)),
            self._v,
            np.ascontiguousarray(placements[ids, :3, 3]).reshape(-1, 3),
            np.ascontiguousarray(placements[ids, :3, :3]).reshape(-1, 9),
        )

    def set_velocity(self, v: np.ndarray) -> None:
        """Joint velocity the next ``evaluate`` uses."""
        self._v = v

    def combine(self, rows: MeshRows, flank: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Row matrix J (m, nv) and bias (m,) of the loaded flanks ``flank`` (±1 each)."""
        front = np.asarray(flank) > 0
        jac = np.where(front[:, None], rows.row_front, rows.row_back)
        bias = np.where(front, rows.bias_front, rows.bias_back)
        return jac, bias

    def line_of_action(self, rows: MeshRows, flank: np.ndarray) -> np.ndarray:
        """Unit line of action n (m, 3) in world for the given flanks."""
        front = np.asarray(flank) > 0
        return np.where(front[:, None], rows.normal_front, rows.normal_back)
