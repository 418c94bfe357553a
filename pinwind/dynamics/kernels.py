"""Compiled inner loops of a step (numba).

A gearbox has a handful of meshes and bearings: numpy spends more time dispatching its calls on
such tiny arrays than computing. These kernels do the same arithmetic as plain loops compiled by
numba; ``dynamics/mesh.py`` and ``dynamics/reactions.py`` document the formulas. They are cached
on disk after the first compilation.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(cache=True)
def body_motion(jac, djac, support, v, twist, accel):
    """Spatial velocity (twist) and acceleration at q̈ = 0 of each body, at the world origin.

    Args:
        jac, djac: Pinocchio's world-frame J and J̇ (6, nv) from computeJointJacobiansTimeVariation.
        support: (bodies, nv) 1 where velocity k moves the body.
        v: joint velocity (nv,).
        twist, accel: (bodies, 6) outputs, [linear, angular].
    """
    nb, nv = support.shape
    for b in range(nb):
        for i in range(6):
            s1 = 0.0
            s2 = 0.0
            for k in range(nv):
                if support[b, k] != 0.0:
                    s1 += jac[i, k] * v[k]
                    s2 += djac[i, k] * v[k]
            twist[b, i] = s1
            accel[b, i] = s2


@njit(cache=True)
def mesh_rows(
    jac,
    support,
    origin,
    rot,
    twist,
    accel,
    slot_a,
    slot_b,
    centre_a,
    centre_b,
    axis_a,
    mu,
    sigma,
    jac_t,
    jac_r,
    bias_t,
    bias_r,
    tangent,
    radial,
    pitch,
    axis,
):
    """Rows of every mesh split along t and r̂, their biases, and the geometry (mesh.py)."""
    nm = slot_a.shape[0]
    nv = jac.shape[1]
    for m in range(nm):
        a = slot_a[m]
        b = slot_b[m]
        ca = np.empty(3)
        cb = np.empty(3)
        k = np.empty(3)
        for i in range(3):
            ca[i] = origin[a, i]
            cb[i] = origin[b, i]
            k[i] = 0.0
            for j in range(3):
                ca[i] += rot[a, i, j] * centre_a[m, j]
                cb[i] += rot[b, i, j] * centre_b[m, j]
                k[i] += rot[a, i, j] * axis_a[m, j]
        d0, d1, d2 = cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]
        dk = d0 * k[0] + d1 * k[1] + d2 * k[2]
        p0, p1, p2 = d0 - dk * k[0], d1 - dk * k[1], d2 - dk * k[2]
        rho = np.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
        u0, u1, u2 = p0 / rho, p1 / rho, p2 / rho
        r0, r1, r2 = sigma[m] * u0, sigma[m] * u1, sigma[m] * u2
        t0, t1, t2 = _cross(k[0], k[1], k[2], r0, r1, r2)
        x0, x1, x2 = ca[0] + mu[m] * p0, ca[1] + mu[m] * p1, ca[2] + mu[m] * p2
        tangent[m, 0], tangent[m, 1], tangent[m, 2] = t0, t1, t2
        radial[m, 0], radial[m, 1], radial[m, 2] = r0, r1, r2
        pitch[m, 0], pitch[m, 1], pitch[m, 2] = x0, x1, x2
        axis[m, 0], axis[m, 1], axis[m, 2] = k[0], k[1], k[2]

        # Rows: n·v_o + (P × n)·ω of B minus that of A.
        mt0, mt1, mt2 = _cross(x0, x1, x2, t0, t1, t2)
        mr0, mr1, mr2 = _cross(x0, x1, x2, r0, r1, r2)
        for c in range(nv):
            w = support[b, c] - support[a, c]
            if w == 0.0:
                jac_t[m, c] = 0.0
                jac_r[m, c] = 0.0
                continue
            lin0, lin1, lin2 = jac[0, c] * w, jac[1, c] * w, jac[2, c] * w
            ang0, ang1, ang2 = jac[3, c] * w, jac[4, c] * w, jac[5, c] * w
            jac_t[m, c] = t0 * lin0 + t1 * lin1 + t2 * lin2 + mt0 * ang0 + mt1 * ang1 + mt2 * ang2
            jac_r[m, c] = r0 * lin0 + r1 * lin1 + r2 * lin2 + mr0 * ang0 + mr1 * ang1 + mr2 * ang2

        # Bias ċ − J q̈ = ṅ·Δv + n·Δa_s(P) + n·((ω_B − ω_A) × Ṗ).
        va0, va1, va2 = twist[a, 0], twist[a, 1], twist[a, 2]
        wa0, wa1, wa2 = twist[a, 3], twist[a, 4], twist[a, 5]
        vb0, vb1, vb2 = twist[b, 0], twist[b, 1], twist[b, 2]
        wb0, wb1, wb2 = twist[b, 3], twist[b, 4], twist[b, 5]
        c0, c1, c2 = _cross(wa0, wa1, wa2, x0, x1, x2)
        e0, e1, e2 = _cross(wb0, wb1, wb2, x0, x1, x2)
        dv0, dv1, dv2 = vb0 + e0 - va0 - c0, vb1 + e1 - va1 - c1, vb2 + e2 - va2 - c2
        c0, c1, c2 = _cross(wa0, wa1, wa2, ca[0], ca[1], ca[2])
        vca0, vca1, vca2 = va0 + c0, va1 + c1, va2 + c2
        c0, c1, c2 = _cross(wb0, wb1, wb2, cb[0], cb[1], cb[2])
        vcb0, vcb1, vcb2 = vb0 + c0, vb1 + c1, vb2 + c2
        kd0, kd1, kd2 = _cross(wa0, wa1, wa2, k[0], k[1], k[2])
        dd0, dd1, dd2 = vcb0 - vca0, vcb1 - vca1, vcb2 - vca2
        ddk = dd0 * k[0] + dd1 * k[1] + dd2 * k[2]
        dkd = d0 * kd0 + d1 * kd1 + d2 * kd2
        pd0 = dd0 - ddk * k[0] - dkd * k[0] - dk * kd0
        pd1 = dd1 - ddk * k[1] - dkd * k[1] - dk * kd1
        pd2 = dd2 - ddk * k[2] - dkd * k[2] - dk * kd2
        up = u0 * pd0 + u1 * pd1 + u2 * pd2
        rd0 = sigma[m] * (pd0 - up * u0) / rho
        rd1 = sigma[m] * (pd1 - up * u1) / rho
        rd2 = sigma[m] * (pd2 - up * u2) / rho
        xd0, xd1, xd2 = vca0 + mu[m] * pd0, vca1 + mu[m] * pd1, vca2 + mu[m] * pd2
        f0, f1, f2 = _cross(kd0, kd1, kd2, r0, r1, r2)
        g0, g1, g2 = _cross(k[0], k[1], k[2], rd0, rd1, rd2)
        td0, td1, td2 = f0 + g0, f1 + g1, f2 + g2
        f0, f1, f2 = _cross(accel[b, 3], accel[b, 4], accel[b, 5], x0, x1, x2)
        g0, g1, g2 = _cross(accel[a, 3], accel[a, 4], accel[a, 5], x0, x1, x2)
        da0 = accel[b, 0] + f0 - accel[a, 0] - g0
        da1 = accel[b, 1] + f1 - accel[a, 1] - g1
        da2 = accel[b, 2] + f2 - accel[a, 2] - g2
        s0, s1, s2 = _cross(wb0 - wa0, wb1 - wa1, wb2 - wa2, xd0, xd1, xd2)
        h0, h1, h2 = da0 + s0, da1 + s1, da2 + s2
        bias_t[m] = td0 * dv0 + td1 * dv1 + td2 * dv2 + t0 * h0 + t1 * h1 + t2 * h2
        bias_r[m] = rd0 * dv0 + rd1 * dv1 + rd2 * dv2 + r0 * h0 + r1 * h1 + r2 * h2


@njit(cache=True)
def tooth_wrenches(joint_a, joint_b, force_on_b, pitch, origin, rot, wrench):
    """Tooth forces summed per joint as wrenches in the joint frame about the joint origin.

    Args:
        joint_a, joint_b: (m,) joint of gear A and of gear B; B gets +F at P, A gets −F.
        force_on_b: (m, 3) tooth force on B in world [N].
        pitch: (m, 3) pitch points in world [m].
        origin, rot: (njoints, 3) and (njoints, 3, 3) joint placements in world.
        wrench: (njoints, 6) output, [force, moment] in each joint's frame.
    """
    nj = wrench.shape[0]
    world = np.zeros((nj, 6))
    for m in range(force_on_b.shape[0]):
        f0, f1, f2 = force_on_b[m, 0], force_on_b[m, 1], force_on_b[m, 2]
        for j, sign in ((joint_b[m], 1.0), (joint_a[m], -1.0)):
            l0 = pitch[m, 0] - origin[j, 0]
            l1 = pitch[m, 1] - origin[j, 1]
            l2 = pitch[m, 2] - origin[j, 2]
            n0, n1, n2 = _cross(l0, l1, l2, f0, f1, f2)
            world[j, 0] += sign * f0
            world[j, 1] += sign * f1
            world[j, 2] += sign * f2
            world[j, 3] += sign * n0
            world[j, 4] += sign * n1
            world[j, 5] += sign * n2
    for j in range(nj):
        for i in range(3):
            wrench[j, i] = (
                rot[j, 0, i] * world[j, 0] + rot[j, 1, i] * world[j, 1] + rot[j, 2, i] * world[j, 2]
            )
            wrench[j, 3 + i] = (
                rot[j, 0, i] * world[j, 3] + rot[j, 1, i] * world[j, 4] + rot[j, 2, i] * world[j, 5]
            )
