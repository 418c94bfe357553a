"""Rigid gear-mesh constraint rows, all meshes of a gearbox at once.

Each mesh A–B adds one velocity constraint along its line of action n (design.md §2):

    c = n · (v_B(P) − v_A(P)) = 0,        J = nᵀ (J_B(P) − J_A(P))

with v_X(P) the velocity of the material point of body X at the pitch point P. With fixed axes this
is the familiar r_b,A ω_A ± r_b,B ω_B = 0 of 000_3b7c4a8fe52a6eee.txt eqs. 38-40, but the row is
built from Pinocchio Jacobians and stays right when a gear centre moves. The multiplier λ of the row
is the tooth normal force (transverse, along n) on B; −λ n acts on A.

The acceleration-level bias is the exact time derivative of c at zero joint acceleration. P and n
are spatial (geometric) quantities, not material points, so

    ċ − J q̈ = ṅ·Δv + n·Δa_s(P) + n·((ω_B − ω_A) × Ṗ)

where a_s is the spatial acceleration field of a body (Pinocchio's ``data.a`` at q̈ = 0) and
Δ = B − A. For fixed axes the three terms cancel and γ = 0, as the constant row demands.

n = s cos α_w t + ε sin α_w r̂ (docs/model_format.md): the row and bias are kept as their t and r̂
parts so that switching the loaded flank s costs nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinwind.model.gearbox import Gearbox


_LEVI_CIVITA = np.zeros((3, 3, 3))
_LEVI_CIVITA[0, 1, 2] = _LEVI_CIVITA[1, 2, 0] = _LEVI_CIVITA[2, 0, 1] = 1.0
_LEVI_CIVITA[0, 2, 1] = _LEVI_CIVITA[2, 1, 0] = _LEVI_CIVITA[1, 0, 2] = -1.0


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (..., 3) arrays (np.cross is ten times slower on small arrays)."""
    return np.einsum("ijk,...j,...k->...i", _LEVI_CIVITA, a, b)


@dataclass
class MeshRows:
    """Rows of all meshes at one state, split in their tangential and radial parts.

    For flank s the row is ``cos_a * s * jac_t + sin_a * eps * jac_r`` (same for ``bias``).

    Attributes:
        jac_t, jac_r: (m, nv) row parts along t and r̂.
        bias_t, bias_r: (m,) parts of ċ − J q̈.
        tangent, radial_dir: (m, 3) unit t and r̂ in world.
        pitch_point: (m, 3) P in world [m].
        lever_a, lever_b: (m, 3) P − O_A and P − O_B (joint origins) in world [m].
    """

    jac_t: np.ndarray
    jac_r: np.ndarray
    bias_t: np.ndarray
    bias_r: np.ndarray
    tangent: np.ndarray
    radial_dir: np.ndarray
    pitch_point: np.ndarray
    lever_a: np.ndarray
    lever_b: np.ndarray


class MeshSet:
    """Geometry constants of every mesh, and the evaluation of their rows at a state."""

    def __init__(self, gearbox: Gearbox):
        meshes = gearbox.meshes
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
        alpha = np.array([m.working_pressure_angle for m in meshes])
        self.cos_a = np.cos(alpha)
        self.sin_a = np.sin(alpha)
        self.tan_beta = np.tan(np.array([m.helix_angle for m in meshes]))
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

    def evaluate(self, model: pin.Model, data: pin.Data) -> MeshRows:
        """Rows at the state of ``data``.

        Needs ``computeJointJacobiansTimeVariation(q, v)`` to have run on ``data``: it gives the
        placements, the world-frame Jacobian J and its time variation J̇ (whose product with v is
        the spatial acceleration at q̈ = 0). Velocities here are spatial, taken at the world origin
        and in world axes, so a point x of body X moves with v_o + ω × x.
        """
        origin = np.empty((len(self.joint_ids), 3))
        rot = np.empty((len(self.joint_ids), 3, 3))
        for i, j in enumerate(self.joint_ids):
            placement = data.oMi[j]
            origin[i] = placement.translation
            rot[i] = placement.rotation
        # (joints, 6, nv) world Jacobians of each gear-carrying body, and their spatial
        # velocities and accelerations (at q̈ = 0) at the world origin.
        jac = data.J[None, :, :] * self.support[:, None, :]
        twist = jac @ self._v
        accel = (data.dJ[None, :, :] * self.support[:, None, :]) @ self._v
        sa, sb = self.slot_a, self.slot_b
        c_a = origin[sa] + np.einsum("mij,mj->mi", rot[sa], self.centre_a)
        c_b = origin[sb] + np.einsum("mij,mj->mi", rot[sb], self.centre_b)
        k = np.einsum("mij,mj->mi", rot[sa], self.axis_a)
        v_a, w_a = twist[sa, :3], twist[sa, 3:]
        v_b, w_b = twist[sb, :3], twist[sb, 3:]

        d = c_b - c_a
        dk = np.einsum("mi,mi->m", d, k)[:, None]
        d_perp = d - dk * k
        rho = np.linalg.norm(d_perp, axis=1)[:, None]
        u = d_perp / rho
        r_hat = self.sigma[:, None] * u
        t = cross(k, r_hat)
        p = c_a + self.mu[:, None] * d_perp

        # n·v(P) = n·v_o + (P × n)·ω for each body, in joint space.
        both = np.stack([t, r_hat])  # (2, m, 3)
        moment = cross(np.broadcast_to(p, both.shape), both)
        jl_b, ja_b = jac[sb, :3], jac[sb, 3:]
        jl_a, ja_a = jac[sa, :3], jac[sa, 3:]
        rows = (
            np.einsum("dmi,min->dmn", both, jl_b - jl_a)
            + np.einsum("dmi,min->dmn", moment, ja_b)
            - np.einsum("dmi,min->dmn", moment, ja_a)
        )

        w_all = np.concatenate([w_a, w_b, w_a, w_b, w_a])
        x_all = np.concatenate([p, p, c_a, c_b, k])
        crossed = cross(w_all, x_all)
        m = self.count
        dv = (v_b + crossed[m : 2 * m]) - (v_a + crossed[:m])
        v_ca = v_a + crossed[2 * m : 3 * m]
        v_cb = v_b + crossed[3 * m : 4 * m]
        k_dot = crossed[4 * m :]
        d_dot = v_cb - v_ca
        d_perp_dot = (
            d_dot
            - np.einsum("mi,mi->m", d_dot, k)[:, None] * k
            - np.einsum("mi,mi->m", d, k_dot)[:, None] * k
            - dk * k_dot
        )
        u_dot = (d_perp_dot - np.einsum("mi,mi->m", u, d_perp_dot)[:, None] * u) / rho
        r_hat_dot = self.sigma[:, None] * u_dot
        p_dot = v_ca + self.mu[:, None] * d_perp_dot
        more = cross(
            np.concatenate([k_dot, k, accel[sb, 3:], accel[sa, 3:], w_b - w_a]),
            np.concatenate([r_hat, r_hat_dot, p, p, p_dot]),
        )
        t_dot = more[:m] + more[m : 2 * m]
        da = (accel[sb, :3] + more[2 * m : 3 * m]) - (accel[sa, :3] + more[3 * m : 4 * m])
        spin = more[4 * m :]
        dirs_dot = np.stack([t_dot, r_hat_dot])
        bias = (
            np.einsum("dmi,mi->dm", dirs_dot, dv)
            + np.einsum("dmi,mi->dm", both, da + spin)
        )
        return MeshRows(
            jac_t=rows[0],
            jac_r=rows[1],
            bias_t=bias[0],
            bias_r=bias[1],
            tangent=t,
            radial_dir=r_hat,
            pitch_point=p,
            lever_a=p - origin[sa],
            lever_b=p - origin[sb],
        )

    def set_velocity(self, v: np.ndarray) -> None:
        """Joint velocity the next ``evaluate`` uses."""
        self._v = v

    def combine(self, rows: MeshRows, flank: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Row matrix J (m, nv) and bias (m,) of the loaded flanks ``flank`` (±1 each)."""
        ct = (self.cos_a * flank)[:, None]
        cr = (self.sin_a * self.eps)[:, None]
        jac = ct * rows.jac_t + cr * rows.jac_r
        bias = ct[:, 0] * rows.bias_t + cr[:, 0] * rows.bias_r
        return jac, bias

    def line_of_action(self, rows: MeshRows, flank: np.ndarray) -> np.ndarray:
        """Unit line of action n (m, 3) in world for the given flanks."""
        return (self.cos_a * flank)[:, None] * rows.tangent + (self.sin_a * self.eps)[:, None] * (
            rows.radial_dir
        )

    def flank_flip_is_free(self, rows: MeshRows) -> np.ndarray:
        """Meshes whose other flank has the opposite row (fixed axes): λ just changes sign."""
        # When the radial part of the row vanishes in joint space it vanishes at every state
        # (the axes cannot move apart), so its bias, the time derivative, vanishes too.
        scale = np.abs(rows.jac_t).max(axis=1) + 1e-300
        return np.abs(rows.jac_r).max(axis=1) <= 1e-12 * scale
