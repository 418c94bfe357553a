"""Static free-body balance of a whole gearbox: what holds it equals what loads it.

Take every moving body of the model as one free body, the ground (the housing, or the bedplate
under a ``<support>``) outside it. Inside it the meshes, springs, bearings between moving bodies
and the torques applied across them are pairs that cancel; from outside act only

- the wrench the ground transmits through each bearing on the ground (``bearing_force`` and
  ``bearing_moment``, world axes, at the bearing centre: Pinocchio's RNEA transmitted force, the
  reaction and the net torque applied at that joint about its axis; for a compliant bearing the
  wrench through its massless slides, read at its bearing joint; for a support, its slides'),
- the weights m_b g at the bodies' centres of mass,

and Newton-Euler for the whole gearbox reads

    Σ_ground bearings F_j + Σ_b m_b g = Ṗ,     Σ (p_j × F_j + M_j) + Σ c_b × m_b g = L̇_O,

P, L_O the gearbox's momentum and its angular momentum about the world origin, whose rates are
zero in static equilibrium (and at constant speed on axes that keep their place). The rates are
taken from the Result's joint angles, speeds and accelerations (Pinocchio's centroidal momentum
and its time variation), so that a sample off equilibrium is checked too. A run's added rotor
inertia (the joint-space armature) is not a body and is left out: check a static sample there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinwind.dynamics.result import Result
from pinwind.errors import InputError, UnknownElement
from pinwind.model.gearbox import Gearbox
from pinwind.testing.figure import CheckFigure


@dataclass(frozen=True)
class FreeBody:
    """The wrenches on the whole gearbox at one sample, world axes, about the world origin.

    Attributes:
        reactions: Σ of the ground's wrenches through its bearings, (6,) [N, N·m].
        weights: Σ m_b g and its moment, (6,) [N, N·m].
        inertia: Ṗ and L̇_O, (6,) [N, N·m].
        force_scale, moment_scale: the sums of the magnitudes of every contribution [N, N·m].
        bearings: the bearings on the ground whose wrenches are in ``reactions``.
    """

    reactions: np.ndarray
    weights: np.ndarray
    inertia: np.ndarray
    force_scale: float
    moment_scale: float
    bearings: list[str]

    @property
    def imbalance(self) -> np.ndarray:
        """The reactions + weights − inertia, (6,) [N, N·m]: zero for a gearbox in balance."""
        return self.reactions + self.weights - self.inertia


def _state(result: Result, gearbox: Gearbox, sample: int) -> tuple[np.ndarray, ...]:
    """q, v, a of the model at ``sample`` from the Result's joint series."""
    model = gearbox.model
    if model.nq != model.nv:
        raise InputError("free_body_balance needs a model whose joints have one coordinate each")
    q, v, a = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
    for name in gearbox.joint_names:
        joint = result.joint(name)
        i = gearbox.v_index(name)
        q[i], v[i], a[i] = joint.angle[sample], joint.speed[sample], joint.acceleration[sample]
    return q, v, a


def _ground_bearings(gearbox: Gearbox) -> list[str]:
    """The bearings through which the ground holds the gearbox (module docstring)."""
    model = gearbox.model
    through_slides = {
        slide: bearing.joint
        for bearing in gearbox.compliant_bearings.values()
        for slide in bearing.slides.values()
    }
    out = []
    for jid in range(1, model.njoints):
        if model.parents[jid] != 0:
            continue
        name = model.names[jid]
        out.append(through_slides.get(name, name))
    return out


def free_body(result: Result, gearbox: Gearbox, sample: int) -> FreeBody:
    """The wrenches on the whole gearbox at ``sample`` (module docstring)."""
    model = gearbox.model
    data = model.createData()
    q, v, a = _state(result, gearbox, sample)
    pin.forwardKinematics(model, data, q)
    bearings = _ground_bearings(gearbox)
    reactions = np.zeros(6)
    force_scale = moment_scale = 0.0
    for name in bearings:
        try:
            bearing = result.bearing(name)
        except UnknownElement:
            raise InputError(
                f'the Result has no bearing "{name}": check it with the gearbox of its run'
            ) from None
        force, moment = bearing.force[sample], bearing.moment[sample]
        at = data.oMi[model.getJointId(name)].translation
        arm = np.cross(at, force)
        reactions += np.concatenate([force, arm + moment])
        force_scale += float(np.linalg.norm(force))
        moment_scale += float(np.linalg.norm(arm) + np.linalg.norm(moment))
    g = np.asarray(result.metadata.get("gravity", gearbox.gravity), dtype=float)
    weights = np.zeros(6)
    for jid in range(1, model.njoints):
        inertia = model.inertias[jid]
        if inertia.mass <= 0.0:
            continue
        centre = data.oMi[jid].act(inertia.lever)
        weight = inertia.mass * g
        weights += np.concatenate([weight, np.cross(centre, weight)])
        force_scale += float(np.linalg.norm(weight))
        moment_scale += float(np.linalg.norm(np.cross(centre, weight)))
    pin.computeCentroidalMomentumTimeVariation(model, data, q, v, a)
    rate = data.dhg  # about the centre of mass, world axes
    com = data.com[0]
    inertial = np.concatenate([rate.linear, rate.angular + np.cross(com, rate.linear)])
    force_scale += float(np.linalg.norm(inertial[:3]))
    moment_scale += float(np.linalg.norm(inertial[3:]))
    return FreeBody(reactions, weights, inertial, force_scale, moment_scale, bearings)


def free_body_balance(
    result: Result, gearbox: Gearbox, *, sample: int = -1, rtol: float = 1e-6
) -> CheckFigure:
    """The bearings on the ground balance the weights and loads of the whole gearbox.

    Σ forces and Σ moments about the world origin on the gearbox as one free body (module
    docstring), each against the sum of the magnitudes of its contributions.

    Args:
        result: a run of ``gearbox`` (every joint's angle, speed and acceleration at ``sample``).
        gearbox: the model of the run.
        sample: the sample to check (default the last), best one in static equilibrium.
        rtol: the largest imbalance accepted, relative to the force and moment scales [-].

    Returns:
        The figure: max(|ΣF| / force scale, |ΣM| / moment scale).

    Raises:
        CheckFailed: beyond ``rtol``, with the imbalance and its parts.
        InputError: a Result that is not of this gearbox.
    """
    body = free_body(result, gearbox, sample)
    off = body.imbalance
    force = float(np.linalg.norm(off[:3]) / body.force_scale) if body.force_scale else 0.0
    moment = float(np.linalg.norm(off[3:]) / body.moment_scale) if body.moment_scale else 0.0
    with np.printoptions(precision=4):
        detail = (
            f"at sample {sample % len(result)} (t = {result.time[sample]:.6g} s): ΣF = "
            f"{off[:3]} N of {body.force_scale:.4g} N, ΣM = {off[3:]} N·m of "
            f"{body.moment_scale:.4g} N·m; reactions of {', '.join(body.bearings)} "
            f"{body.reactions[:3]} N, weights {body.weights[:3]} N, Ṗ {body.inertia[:3]} N"
        )
    return CheckFigure(
        "free_body_balance",
        "resultant force and moment on the whole gearbox (ground bearings' reactions, weights, "
        "less the momentum's rate) over the sum of their magnitudes",
        max(force, moment),
        rtol,
        detail,
    ).enforced()
