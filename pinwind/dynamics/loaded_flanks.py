"""Which flank of each mesh the static load presses: the flanks a linearisation is taken on.

A mesh has two lines of contact, one per flank; with translating members (compliant bearings,
floating suns) their rows differ in the radial part, n = s cos α_w t + ε sin α_w r̂
(``dynamics/mesh.py``), so the stiffness a mesh adds to K, or the row a rigid mesh adds to J,
depends on the flank in contact. The contact is a fact of the machine, not of the order its
meshes are written in: mesh (A, B)'s front flank is mesh (B, A)'s back flank, the same row.

``loaded_flanks`` finds the flanks as a run's static start does (``cpp/stepper.hpp``
Stepper::equilibrium), linearly at the reference pose: with the mesh rows on the current flanks,
the rigid rows J (rigid meshes, held joints, locks) and the stiffness K, the train shares one
acceleration ā along the motions nothing resists (B, the null space of J and K), and the rest
of the load deflects the springs:

    ā = B (Bᵀ M B)⁻¹ Bᵀ F,     K x − Jᵀ λ = F − M ā,     J x = 0

(least norm: x has no part along B, λ none along the redundant rows' null space: equal sharing
in a rigid multi-planet stage). A compliant mesh on flank s carries F_n = −k (J_s x) (the
overlap grows as B moves against n relative to A), a rigid one F_n = λ; a mesh whose F_n would
pull hands its load to the other flank, and the solve is repeated until no mesh pulls.

A mesh whose static force is below ``UNLOADED_FRACTION`` of the gross load (every applied
torque, law and body weight taken by its size, so that loads that cancel, like the weights of
equally spaced planets on the carrier, count as no load) carries none: there is no loaded flank,
and it is taken on the flank on which its gear first in the joint order (lowest velocity index)
drives the other turning forward (about its joint axis), a choice the linearisation states.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinwind.dynamics.mesh import MeshRows
from pinwind.dynamics.normal_modes import free_motions
from pinwind.model.gearbox import Gearbox, Mesh

#: A static mesh force below this fraction of the gross load's mesh-force scale is no load.
UNLOADED_FRACTION = 1e-9
#: ω²-like eigenvalues of the stiffness over the free motions below this fraction of the
#: largest are motions nothing resists (as ``normal_modes.RIGID_TOLERANCE``).
FREE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class FlankChoice:
    """The flank each mesh is linearised on and why.

    Attributes:
        names: the meshes, in the order of the rows.
        flank: +1 (front) or −1 (back) per mesh (``MeshSet.combine``'s convention).
        force: the static normal force on that flank [N] (0 where unloaded).
        unloaded: mesh name → (its gear first in the joint order, the other gear) for the
            meshes with no static load, taken on the flank on which the first drives the
            other turning forward (module docstring).
    """

    names: list[str]
    flank: np.ndarray
    force: np.ndarray
    unloaded: dict[str, tuple[str, str]]

    def notes(self) -> list[str]:
        """One line stating the flank assumed for the meshes without static load, if any."""
        if not self.unloaded:
            return []
        which = ", ".join(
            f"{name} ({first} turning forward drives {other})"
            for name, (first, other) in self.unloaded.items()
        )
        return [
            f"no static load on mesh {which}: each linearised on that flank, as the loads "
            "press none (a scenario's torques, generator and rotor give the loaded flanks)"
        ]


def loaded_flanks(
    gearbox: Gearbox,
    meshes: list[Mesh],
    rows: MeshRows,
    *,
    mesh_stiffness: dict[int, float],
    other_stiffness: np.ndarray,
    holds: np.ndarray,
    mass: np.ndarray,
    load: np.ndarray,
    gross: np.ndarray,
) -> FlankChoice:
    """The flanks the static ``load`` presses (module docstring).

    Args:
        meshes: the meshes of ``rows``, in their order; the compliant ones are the keys of
            ``mesh_stiffness``.
        rows: the meshes' rows at the reference pose (``MeshSet.evaluate``).
        mesh_stiffness: mesh index → stiffness along the line of action [N/m] (compliant ones).
        other_stiffness: K (nv, nv) of every other element (springs, bearings, support).
        holds: rows (r, nv) of the held joints and locks.
        mass: M (nv, nv) with the added inertias.
        load: generalised static load F (nv,) [N·m, N].
        gross: the load's size per coordinate: the sum of its contributions' magnitudes (nv,).
    """
    count = len(meshes)
    nv = mass.shape[0]
    first = [_first_gear(gearbox, m) for m in meshes]
    index = [int(i) for i, _ in first]
    flank = np.array(
        [_forward_flank(rows, i, index[i]) for i in range(count)], dtype=float
    ).reshape(count)
    levers = np.abs(np.asarray(rows.row_front))
    lever = float(levers[levers > 0].min(initial=1.0))
    scale = float(np.abs(gross).max(initial=0.0)) / min(lever, 1.0)
    force = np.zeros(count)
    rigid = [i for i in range(count) if i not in mesh_stiffness]
    for _ in range(2 * count + 2):
        jac = np.where(flank[:, None] > 0, rows.row_front, rows.row_back).reshape(count, nv)
        stiffness = other_stiffness.copy()
        for i, k in mesh_stiffness.items():
            stiffness += k * np.outer(jac[i], jac[i])
        constraints = np.vstack([jac[rigid].reshape(-1, nv), holds.reshape(-1, nv)])
        x, multipliers = _static_solve(mass, stiffness, constraints, load)
        force = np.zeros(count)
        for i, k in mesh_stiffness.items():
            force[i] = -k * float(jac[i] @ x)
        force[rigid] = multipliers[: len(rigid)]
        pulling = force < -UNLOADED_FRACTION * scale
        if not pulling.any():
            break
        flank[pulling] = -flank[pulling]
        force[pulling] = -force[pulling]
    unloaded = [i for i in range(count) if abs(force[i]) <= UNLOADED_FRACTION * scale]
    for i in unloaded:
        flank[i] = _forward_flank(rows, i, index[i])
        force[i] = 0.0
    named = {meshes[i].name: first[i][1] for i in unloaded}
    return FlankChoice([m.name for m in meshes], flank, force, named)


def _static_solve(
    mass: np.ndarray, stiffness: np.ndarray, constraints: np.ndarray, load: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Deflection x and row multipliers λ under ``load`` (module docstring), least norm."""
    nv = mass.shape[0]
    allowed = free_motions(constraints, nv)
    if allowed.shape[1]:
        reduced = allowed.T @ stiffness @ allowed
        values, vectors = np.linalg.eigh(0.5 * (reduced + reduced.T))
        top = max(float(values[-1]), 0.0) if values.size else 0.0
        free = allowed @ vectors[:, values <= FREE_TOLERANCE * top] if top > 0 else allowed
        if free.shape[1]:
            shared = free.T @ mass @ free
            accel = free @ np.linalg.solve(shared, free.T @ load)
            load = load - mass @ accel
    rows = constraints.shape[0]
    kkt = np.zeros((nv + rows, nv + rows))
    kkt[:nv, :nv] = stiffness
    kkt[:nv, nv:] = constraints.T
    kkt[nv:, :nv] = constraints
    rhs = np.concatenate([load, np.zeros(rows)])
    solution = np.linalg.lstsq(kkt, rhs, rcond=None)[0]
    return solution[:nv], -solution[nv:]


def _first_gear(gearbox: Gearbox, mesh: Mesh) -> tuple[int, tuple[str, str]]:
    """The velocity index of the mesh's gear first in the joint order, and (its name, the other's).

    Of the gears on a joint that turns (−1 and gear A's name if neither does).
    """
    model = gearbox.model
    found = []
    for gear, other in ((mesh.gear_a, mesh.gear_b), (mesh.gear_b, mesh.gear_a)):
        joint = gear.joint_id
        if joint > 0 and model.joints[joint].shortname().startswith("JointModelR"):
            found.append((int(model.joints[joint].idx_v), (gear.name, other.name)))
    return min(found) if found else (-1, (mesh.gear_a.name, mesh.gear_b.name))


def _forward_flank(rows: MeshRows, mesh: int, index: int) -> float:
    """The flank (±1) on which the gear at velocity ``index`` drives the other turning forward.

    Driving forward, the gear feels the tooth force against its turning: the flank whose row
    has a negative entry at its coordinate (the force F_n > 0 acts on the coordinates as
    F_n J). The front flank when ``index`` is −1 (no turning gear).
    """
    if index < 0:
        return 1.0
    return 1.0 if float(rows.row_front[mesh][index]) < 0.0 else -1.0
