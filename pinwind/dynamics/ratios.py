"""Kinematic speed ratios of a gear train, from the null space of its constraint rows."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np
import pinocchio as pin

from pinwind.dynamics.mesh import MeshSet
from pinwind.errors import ConflictingConstraints, InputError, UnknownJoint
from pinwind.model.gearbox import Gearbox


def speed_ratio(gearbox: Gearbox, output: str, reference: str) -> float:
    """ω_output / ω_reference for a gear train with one degree of freedom (signed).

    Joint speeds are relative to the parent body, as everywhere in pinwind. The ratio comes from
    the null space of the mesh rows and the locks at the reference pose: no tooth-count
    bookkeeping, so it also holds for compound planets and several stages.

    Raises:
        UnknownJoint: a name is not a bearing of the gearbox.
        InputError: the train has more (or fewer) than one degree of freedom.
    """
    for name in (output, reference):
        if name not in gearbox.joint_names:
            raise UnknownJoint(name, "speed_ratio", gearbox.joint_names)
    # The compliant bearings' slides do not turn with the train.
    held = [*gearbox.locked_joints, *gearbox.slide_joints]
    rows = np.vstack([mesh_rows(gearbox), selector(gearbox, held)])
    _, sv, vt = np.linalg.svd(rows)
    rank = _rank(sv)
    free = gearbox.model.nv - rank
    if free != 1:
        raise InputError(
            f"the gear train has {free} degrees of freedom; a speed ratio needs exactly one"
        )
    mode = vt[-1]
    ref = mode[gearbox.v_index(reference)]
    if abs(ref) < 1e-12 * np.abs(mode).max():
        raise InputError(f'joint "{reference}" does not turn with the gear train')
    return float(mode[gearbox.v_index(output)] / ref)


def train_speeds(
    gearbox: Gearbox, given: Mapping[str, float], *, through_springs: bool = False
) -> np.ndarray:
    """Joint speeds [rad/s] at the reference pose that the gear meshes allow, with ``given`` held.

    The given joints keep their speeds exactly, the locked bearings stay at zero, and every other
    joint takes the speed the meshes impose (``v`` with J v = 0). Joints the given speeds do not
    fix (a second, undriven train) take the speeds of least kinetic energy, i.e. zero unless
    coupled.

    Args:
        given: joint name → speed [rad/s] (relative to the parent body).
        through_springs: the torsional springs hold their two joints at one speed too (the
            mean running speeds of spring-coupled shafts).

    Raises:
        UnknownJoint: a name is not a bearing of the gearbox.
        ConflictingConstraints: the given speeds contradict the gear ratios (e.g. carrier and sun
            of a planetary stage at speeds that are not in the ratio 6).
    """
    for name in given:
        if name not in gearbox.joint_names:
            raise UnknownJoint(name, "initial speeds", gearbox.joint_names)
    jac = mesh_rows(gearbox)
    if through_springs and gearbox.springs:
        twist = np.zeros((len(gearbox.springs), gearbox.model.nv))
        for i, spring in enumerate(gearbox.springs):
            twist[i] = spring.twist_row(gearbox.model.nv)
        jac = np.vstack([jac, twist])
    still = [*gearbox.locked_joints, *gearbox.slide_joints]  # the slides start at rest
    a = np.vstack([jac, selector(gearbox, [*still, *given])])
    b = np.concatenate([np.zeros(len(jac)), np.zeros(len(still)), list(given.values())])
    particular = np.linalg.lstsq(a, b, rcond=None)[0]
    mismatch = float(np.abs(a @ particular - b).max()) if len(b) else 0.0
    scale = 1.0 + float(np.abs(b).max()) if len(b) else 1.0
    if mismatch > 1e-9 * scale:
        raise ConflictingConstraints(0, 0.0, mismatch, list(given))
    # Joints left free by the given speeds: the least kinetic energy (M metric).
    _, sv, vt = np.linalg.svd(a)
    null = vt[_rank(sv) :].T
    if null.shape[1]:
        model = gearbox.model
        mass = pin.crba(model, model.createData(), gearbox.neutral())
        mass = np.triu(mass) + np.triu(mass, 1).T
        reduced = null.T @ mass @ null
        particular = particular - null @ np.linalg.solve(reduced, null.T @ mass @ particular)
    return particular


def train_modes(
    gearbox: Gearbox, held: Iterable[str] = (), extra_rows: np.ndarray | None = None
) -> np.ndarray:
    """The motions the gear train allows at the reference pose, one mode per row, (f, nv).

    Joint speeds v with J v = 0 for every mesh, the locked bearings, the compliant bearings'
    slides and the joints ``held`` at zero speed, and ``extra_rows`` @ v = 0 (e.g. torsional
    springs kept undeflected). The basis is in reduced row echelon form: each mode turns its own
    pivot joint at speed 1 with the other modes' pivot joints still, so that trains that share no
    joint get modes of their own.
    """
    rows = [
        mesh_rows(gearbox),
        selector(gearbox, [*gearbox.locked_joints, *gearbox.slide_joints, *held]),
    ]
    if extra_rows is not None:
        rows.append(np.asarray(extra_rows, dtype=float).reshape(-1, gearbox.model.nv))
    a = np.vstack(rows)
    nv = gearbox.model.nv
    if a.shape[0] == 0:
        return np.eye(nv)
    _, sv, vt = np.linalg.svd(a)
    return _row_echelon(vt[_rank(sv) :])


def _row_echelon(basis: np.ndarray) -> np.ndarray:
    """Reduced row echelon form of the rows of ``basis`` (Gauss-Jordan, partial pivoting)."""
    b = basis.copy()
    scale = float(np.abs(b).max()) if b.size else 0.0
    pivot_row = 0
    for column in range(b.shape[1]):
        if pivot_row == b.shape[0]:
            break
        best = pivot_row + int(np.argmax(np.abs(b[pivot_row:, column])))
        if abs(b[best, column]) <= 1e-9 * scale:
            continue
        b[[pivot_row, best]] = b[[best, pivot_row]]
        b[pivot_row] /= b[pivot_row, column]
        for other in range(b.shape[0]):
            if other != pivot_row:
                b[other] -= b[other, column] * b[pivot_row]
        pivot_row += 1
    b[np.abs(b) < 1e-12] = 0.0
    return b


def mesh_rows(gearbox: Gearbox) -> np.ndarray:
    """The mesh rows J (J v = 0) at the reference pose, (meshes, nv).

    The rows of the flanks the step loop starts on (+1); with fixed axes both flanks agree.
    """
    model = gearbox.model
    data = model.createData()
    v = np.zeros(model.nv)
    pin.computeJointJacobiansTimeVariation(model, data, gearbox.neutral(), v)
    meshes = MeshSet(gearbox)
    meshes.set_velocity(v)
    jac, _ = meshes.combine(meshes.evaluate(model, data), np.ones(meshes.count))
    return jac


def selector(gearbox: Gearbox, names: list[str]) -> np.ndarray:
    """Rows that pick the speeds of the joints ``names``, (len(names), nv)."""
    rows = np.zeros((len(names), gearbox.model.nv))
    for i, name in enumerate(names):
        rows[i, gearbox.v_index(name)] = 1.0
    return rows


def _rank(singular_values: np.ndarray) -> int:
    """Numerical rank from singular values (largest first): those above 1e-10 of the largest."""
    sv = singular_values
    return int(np.sum(sv > 1e-10 * sv[0])) if sv.size else 0
