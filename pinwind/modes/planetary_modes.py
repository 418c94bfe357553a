"""The mode classes of a planetary stage with identical, equally spaced planets (Lin & Parker 1999).

Lin & Parker (1999, "Analytical characterization of the unique properties of planetary gear free
vibration", J. Vib. Acoust. 121:316-321) show that a stage whose N planets are identical and
equally spaced has only three kinds of mode:

- **rotational**: the central members (sun, carrier, ring) rotate (and move axially) without
  translating, every planet moves like the others; single modes;
- **translational**: the central members translate (and tilt) without rotating; double modes;
- **planet**: the central members stand still, only the planets move; N − 3 fold with the
  planets' translations, N − 1 fold in a purely torsional model (one rotation per planet).

The classes follow from the stage's cyclic symmetry: turning the stage by one planet spacing
2π/N (planet i's motion onto planet i + 1, the central members' translations turned by 2π/N about
the stage axis, their rotations kept) maps a mode onto a mode of the same frequency. A rotational
mode is left unchanged by that turn; a translational mode keeps the central members from turning;
a planet mode keeps them still. The classification reads only each coordinate's kind (a rotation
or a translation) and its axis (``dynamics/coordinates.py``), so it holds for torsional models
and for models whose bearings let bodies translate (prismatic coordinates between a body's parent
and its rotation).

The stage is found from the meshes: the ring is an internal gear, the planets the bodies whose
gears mesh with it, the sun the body whose gear meshes with the planets, the carrier the body the
planets' bearings sit on. A stage whose linearisation is not symmetric (planets not equally
spaced, unlike planets, one planet held) gets ``"unclassified"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinwind.dynamics.coordinates import Coordinate
from pinwind.model.gear_roles import gearbox_planetary_gears
from pinwind.model.gearbox import Gearbox

#: A coordinate (scaled by √M_jj) below this fraction of the mode's largest stands still; also the
#: relative tolerance of the symmetry of M, K, C and of equal spacing [rad].
STILL_TOLERANCE = 1e-6

ROTATIONAL, TRANSLATIONAL, PLANET, UNCLASSIFIED = (
    "rotational",
    "translational",
    "planet",
    "unclassified",
)


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage of the train: its members as coordinate indices of the velocity vector.

    Attributes:
        ring: the ring gear's name (names the stage).
        axis: the stage axis, world [-].
        central: central member's joint name → its coordinates: the ring, the sun (every body
            besides the ring that the planets mesh with) and the carrier (unless the planets'
            bearings sit on the ground).
        planets: the planets' coordinates, in order of their angle about ``axis``.
        planet_names: the planets' joint names, same order.
        symmetry: S (nv, nv): a motion turned by one planet spacing (module docstring); ``None``
            when the planets are not equally spaced on one circle.
    """

    ring: str
    axis: np.ndarray
    central: dict[str, list[int]]
    planets: list[list[int]]
    planet_names: list[str]
    symmetry: np.ndarray | None


def planetary_stages(gearbox: Gearbox, coords: list[Coordinate]) -> list[PlanetaryStage]:
    """The planetary stages of ``gearbox``, one per internal gear that planets mesh with.

    Args:
        coords: the model's coordinates (``coordinates.coordinates(gearbox)``).
    """
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, gearbox.neutral())
    joint_of = {name: g.joint_id for name, g in gearbox.gears.items()}
    stages = []
    for found in gearbox_planetary_gears(gearbox):
        ring, gear = found.ring, gearbox.gears[found.ring]
        axis = data.oMi[gear.joint_id].rotation @ gear.axis_in_joint
        centre = data.oMi[gear.joint_id].act(gear.centre_in_joint)
        planets = sorted({joint_of[p] for p in found.planets})
        suns = {joint_of[s] for s in found.suns}
        carriers = {_member_top(model, coords, jid, axis)[1] for jid in planets}
        central_joints = [gear.joint_id, *sorted(suns), *(c for c in carriers if c != 0)]
        angles = [_angle_about(data.oMi[jid].translation - centre, axis) for jid in planets]
        order = np.argsort(angles)
        planets = [planets[i] for i in order]
        central = {
            model.names[jid]: _member_coordinates(model, coords, jid, axis)
            for jid in central_joints
        }
        planet_coords = [_member_coordinates(model, coords, jid, axis) for jid in planets]
        radii = [float(np.linalg.norm(data.oMi[jid].translation - centre)) for jid in planets]
        spaced = len(carriers) == 1 and _equally_spaced(sorted(angles), radii)
        symmetry = _turn(coords, central, planet_coords, axis, model.nv) if spaced else None
        stages.append(
            PlanetaryStage(
                ring,
                axis,
                central,
                planet_coords,
                [model.names[jid] for jid in planets],
                symmetry,
            )
        )
    return stages


def _angle_about(offset: np.ndarray, axis: np.ndarray) -> float:
    """Angle of ``offset`` about ``axis`` from a fixed in-plane reference [rad], in [0, 2π)."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - (ref @ axis) * axis
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    return math.atan2(float(offset @ e2), float(offset @ e1)) % (2.0 * math.pi)


def _equally_spaced(angles: list[float], radii: list[float]) -> bool:
    """Planets on one circle at 2π/N from each other (angles sorted)."""
    n = len(angles)
    gaps = np.diff([*angles, angles[0] + 2.0 * math.pi])
    same_radius = max(radii) - min(radii) <= STILL_TOLERANCE * max(radii)
    return n >= 2 and same_radius and bool(np.all(np.abs(gaps - 2.0 * math.pi / n) <= 1e-6))


def _is_stage_rotation(c: Coordinate, axis: np.ndarray) -> bool:
    return c.kind == "rotation" and abs(abs(float(c.axis @ axis)) - 1.0) < 1e-9


def _member_top(
    model: pin.Model, coords: list[Coordinate], jid: int, axis: np.ndarray
) -> tuple[list[int], int]:
    """A body's joints and its parent body's joint (0: the ground).

    The body's joints are its rotation about the stage axis and the bearing translations or tilts
    between it and its parent body.
    """
    joints, turned = [], False
    while jid != 0:
        rotation = _is_stage_rotation(coords[model.joints[jid].idx_v], axis)
        if rotation and turned:
            break
        turned |= rotation
        joints.append(jid)
        jid = model.parents[jid]
    return joints, jid


def _member_coordinates(
    model: pin.Model, coords: list[Coordinate], jid: int, axis: np.ndarray
) -> list[int]:
    joints, _ = _member_top(model, coords, jid, axis)
    return sorted(model.joints[j].idx_v + k for j in joints for k in range(model.joints[j].nv))


def _turn(
    coords: list[Coordinate],
    central: dict[str, list[int]],
    planets: list[list[int]],
    axis: np.ndarray,
    nv: int,
) -> np.ndarray | None:
    """S (nv, nv): the motion turned by one planet spacing about ``axis`` (module docstring).

    Each body's motion along its coordinates (axes A, 3 × k per kind) is turned by R and read
    back on the target body's coordinates, x' = A_target⁺ R A_source x; ``None`` when the turned
    motion leaves the target's coordinates (bodies whose bearings do not repeat round the stage).
    """
    n = len(planets)
    turn = pin.AngleAxis(2.0 * math.pi / n, axis).matrix()
    s = np.eye(nv)
    pairs = [(c, c) for c in central.values()]
    pairs += [(planets[i], planets[(i + 1) % n]) for i in range(n)]
    for source, target in pairs:
        for kind in ("rotation", "translation"):
            src = [j for j in source if coords[j].kind == kind]
            tgt = [j for j in target if coords[j].kind == kind]
            if len(src) != len(tgt):
                return None
            if not src:
                continue
            a_src = np.array([coords[j].axis for j in src]).T
            a_tgt = np.array([coords[j].axis for j in tgt]).T
            block = np.linalg.pinv(a_tgt) @ turn @ a_src
            if np.abs(a_tgt @ block - turn @ a_src).max() > 1e-9:
                return None
            for j in src:
                s[:, j] = 0.0
            s[np.ix_(tgt, src)] = block
    return s


def is_symmetric(
    stage: PlanetaryStage,
    mass: np.ndarray,
    stiffness: np.ndarray,
    damping: np.ndarray,
    constraints: np.ndarray,
) -> bool:
    """The stage's linearisation is unchanged by its turn S.

    Sᵀ M S = M, Sᵀ K S = K, Sᵀ C S = C, and S keeps the rigid rows' allowed motions (J S q = 0
    whenever J q = 0).
    """
    s = stage.symmetry
    if s is None:
        return False
    for matrix in (mass, stiffness, damping):
        scale = max(float(np.abs(matrix).max()), 1e-300)
        if np.abs(s.T @ matrix @ s - matrix).max() > STILL_TOLERANCE * scale:
            return False
    if constraints.shape[0] == 0:
        return True
    rank = np.linalg.matrix_rank(constraints, tol=1e-10 * np.abs(constraints).max())
    both = np.vstack([constraints, constraints @ s])
    return int(np.linalg.matrix_rank(both, tol=1e-10 * np.abs(both).max())) == rank


def mode_kind(
    stage: PlanetaryStage, shape: np.ndarray, mass: np.ndarray, coords: list[Coordinate]
) -> str | None:
    """The class of mode ``shape`` in a symmetric ``stage``; ``None`` when it does not move.

    Module docstring. Components are compared scaled by √M_jj (rotations and translations in one
    unit, √J).
    """
    if stage.symmetry is None:
        return UNCLASSIFIED
    scale = np.sqrt(np.abs(np.diag(mass)))
    tol = STILL_TOLERANCE * float(np.abs(shape * scale).max())
    central = [j for c in stage.central.values() for j in c]
    moved = [j for p in stage.planets for j in p] + central

    def still(indices: list[int], vector: np.ndarray = shape) -> bool:
        return bool(np.all(np.abs(vector[indices] * scale[indices]) <= tol))

    if still(moved):
        return None
    if still(moved, stage.symmetry @ shape - shape):
        return ROTATIONAL
    if still(central):
        return PLANET
    # Rotations about the stage axis and axial translations: what a translational mode keeps still.
    axial = [j for j in central if abs(float(coords[j].axis @ stage.axis)) > 0.5]
    if still(axial):
        return TRANSLATIONAL
    return UNCLASSIFIED


def mode_kinds(
    stages: list[PlanetaryStage],
    coords: list[Coordinate],
    shapes: list[np.ndarray],
    mass: np.ndarray,
    stiffness: np.ndarray,
    damping: np.ndarray,
    constraints: np.ndarray,
) -> list[str]:
    """Each mode's class: ``rotational``, ``translational``, ``planet`` or ``unclassified``.

    With several stages, the class of each stage the mode moves, as ``ring: planet; ring2:
    rotational`` when they differ; ``""`` for every mode of a train without a planetary stage.
    """
    if not stages:
        return ["" for _ in shapes]
    symmetric = [is_symmetric(s, mass, stiffness, damping, constraints) for s in stages]
    out = []
    for shape in shapes:
        kinds = {}
        for stage, ok in zip(stages, symmetric, strict=True):
            kind = mode_kind(stage, shape, mass, coords) if ok else UNCLASSIFIED
            if kind is not None:
                kinds[stage.ring] = kind
        if len(set(kinds.values())) <= 1:
            out.append(next(iter(kinds.values()), ROTATIONAL))
        else:
            out.append("; ".join(f"{ring}: {kind}" for ring, kind in kinds.items()))
    return out
