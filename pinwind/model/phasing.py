"""Tooth phases: where each gear's teeth stand at the reference pose, meshing teeth interlocked.

A gear's tooth phase is the angle of the centre line of its tooth 0 about its axis [rad]. The
centre line is used rather than a flank because it is the same at every radius: a planet works
on two pitch circles (its sun mesh's and its ring mesh's working pitch circles differ with
profile shift, 24.5° and 22.1° working pressure angles in ``models/dtu500_planetary.urdf``), and
a flank's angle moves with the radius by the involute function (ISO 21771).

Interlock. At a mesh's pitch point P, the pitch fraction f of a gear is where P falls in its
tooth pitch, 0 at a tooth centre and ½ at a gap centre. Meshing teeth interlock when

    f_B = ½ + s f_A   (mod 1),   s = +1 when both gears' positive turns move their pitch
                                 circles the same way at P (an internal pair), −1 otherwise.

Derivation (by hand, from the pitch circles rolling without slip): when A's flank is at P, the
mating flank of B is at P too. With the flank facing A's positive turn at A's tooth centre plus
half its thickness t_A (as a fraction of the working circular pitch), and B's mating flank at
B's tooth centre ∓ ½ t_B, that gives f_B = ½ (t_A + t_B) + s f_A. The working pressure angle of
ISO 21771 (``gears/involute.pair_geometry``) is the one at which the teeth mesh without
backlash, t_A + t_B = 1, so the rule holds whatever the profile shifts. A backlash j would move
B's tooth centres by j/2 along the pitch circle; the phases ignore it (tens of µm against a
pitch of tens of mm). It is the rule behind Parker & Lin's mesh phasing relations
(J. Mech. Des. 126(2):365-370, 2004): carried round a planetary stage it gives the sun-planet
and ring-planet mesh phases of every planet (tests/dynamics/test_mesh_phasing.py checks them).

Propagation (``interlocking_phases``): gears with a given phase keep it; the others are reached
mesh by mesh in file order from an already-phased mating gear; a gear that starts a new train
(no phased gear in reach) keeps its own phase. In a loop (sun, planets, ring) the first mesh to
reach a gear decides; the others agree when the stage satisfies its assembly condition.

The physics (``dynamics/compliant.py``) and the replay drawing (``io/replay_scene.py``) both
phase their gears with ``interlocking_phases``, each with its own zero direction per gear. This
module takes plain geometry (names, vectors, gear specs); ``Gearbox`` gives it its own at the
reference pose (``tooth_phases``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from pinwind.model.urdf import GearSpec


@dataclass(frozen=True)
class MeshPoint:
    """One mesh as the interlock sees it.

    Attributes:
        gear_a, gear_b: the gears' names.
        angle_a, angle_b: angle of the pitch point P about each gear's axis, from the direction
            its phase is measured from [rad].
        same_direction: both gears' positive turns move their pitch circles the same way at P
            (an internal pair with parallel axes); False for an external pair.
    """

    gear_a: str
    gear_b: str
    angle_a: float
    angle_b: float
    same_direction: bool


def mating_fraction(fraction: float, same_direction: bool) -> float:
    """Pitch fraction at P of the mating gear's teeth, given the other gear's (module docstring).

    Args:
        fraction: where P falls in the phased gear's tooth pitch, 0 at a tooth centre [-].
        same_direction: ``MeshPoint.same_direction``.

    Returns:
        f = ½ + s·fraction mod 1, s = +1 for the same direction, else −1 [-].
    """
    s = 1.0 if same_direction else -1.0
    return (0.5 + s * fraction) % 1.0


def interlocking_phases(
    meshes: Sequence[MeshPoint],
    teeth: Mapping[str, int],
    given: Mapping[str, float] | None = None,
    own: Mapping[str, float] | None = None,
) -> dict[str, float]:
    """Tooth phase of every gear of the meshes so that meshing teeth interlock [rad].

    Args:
        meshes: the meshes, in file order, with the pitch point's angle about each gear.
        teeth: tooth count of each gear.
        given: phases kept as they are (a model file's explicit ``tooth_phase_deg``).
        own: the phase a gear keeps when it starts a train (gear A of the first mesh not yet
            reached); without one, that gear puts a tooth centre on its first pitch point.

    Returns:
        gear name → angle of its tooth 0's centre line from the gear's zero direction [rad], for
        every gear of ``meshes`` and of ``given``.
    """
    phases: dict[str, float] = dict(given or {})
    own = own or {}
    pending = list(meshes)
    while True:
        pending = [m for m in pending if not (m.gear_a in phases and m.gear_b in phases)]
        if not pending:
            return phases
        step = next((m for m in pending if m.gear_a in phases or m.gear_b in phases), None)
        if step is None:  # a new train: its first gear keeps its own phase
            first = pending[0]
            phases[first.gear_a] = own.get(first.gear_a, first.angle_a)
            continue
        if step.gear_a in phases:
            known, angle_known, other, angle_other = (
                step.gear_a,
                step.angle_a,
                step.gear_b,
                step.angle_b,
            )
        else:
            known, angle_known, other, angle_other = (
                step.gear_b,
                step.angle_b,
                step.gear_a,
                step.angle_a,
            )
        pitch_known = 2.0 * math.pi / teeth[known]
        fraction = ((angle_known - phases[known]) / pitch_known) % 1.0
        target = mating_fraction(fraction, step.same_direction)
        phases[other] = angle_other - target * 2.0 * math.pi / teeth[other]


def zero_direction(axis: np.ndarray) -> np.ndarray:
    """The direction a gear's phase is measured from, in its joint frame: unit, ⟂ ``axis``.

    The frame's x axis projected ⟂ the axis, or y when x is along the axis.
    """
    for e in (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        p = e - (e @ axis) * axis
        if np.linalg.norm(p) > 0.5:
            return p / np.linalg.norm(p)
    raise AssertionError("unreachable: x and y cannot both be along one axis")


def direction_at(axis: np.ndarray, angle: float) -> np.ndarray:
    """Unit vector ⟂ ``axis`` at ``angle`` [rad] about it from ``zero_direction`` (joint frame)."""
    e = zero_direction(axis)
    return math.cos(angle) * e + math.sin(angle) * np.cross(axis, e)


def _angle_of(axis: np.ndarray, v: np.ndarray) -> float:
    """Angle of v about ``axis`` from ``zero_direction(axis)`` [rad] (all in the joint frame)."""
    e = zero_direction(axis)
    return math.atan2(float(axis @ np.cross(e, v)), float(e @ v))


def mesh_point(
    gear_a: str,
    gear_b: str,
    *,
    centre_a: np.ndarray,
    centre_b: np.ndarray,
    world_from_a: np.ndarray,
    world_from_b: np.ndarray,
    axis_a: np.ndarray,
    axis_b: np.ndarray,
    pitch_fraction: float,
) -> MeshPoint:
    """A mesh as the interlock sees it, from where its two gears stand at the reference pose.

    Args:
        gear_a, gear_b: the gears' names.
        centre_a, centre_b: the gears' centres in world [m].
        world_from_a, world_from_b: rotations of the gears' joint frames in world (3 × 3).
        axis_a, axis_b: the gears' unit axes in their joint frames.
        pitch_fraction: μ with pitch point P = C_A + μ d⊥, d⊥ the centre offset B − A normal
            to A's axis (``Mesh.pitch_fraction``) [-].
    """
    world_axis_a = world_from_a @ axis_a
    offset = centre_b - centre_a
    offset = offset - (offset @ world_axis_a) * world_axis_a
    return mesh_point_through(
        gear_a,
        gear_b,
        centre_a + pitch_fraction * offset,
        centre_a=centre_a,
        centre_b=centre_b,
        world_from_a=world_from_a,
        world_from_b=world_from_b,
        axis_a=axis_a,
        axis_b=axis_b,
    )


def mesh_point_through(
    gear_a: str,
    gear_b: str,
    point: np.ndarray,
    *,
    centre_a: np.ndarray,
    centre_b: np.ndarray,
    world_from_a: np.ndarray,
    world_from_b: np.ndarray,
    axis_a: np.ndarray,
    axis_b: np.ndarray,
) -> MeshPoint:
    """A mesh as the interlock sees it, given its pitch point in world [m].

    The angles of the pitch point about each gear's axis from its ``zero_direction``, and
    whether both gears' positive turns move their pitch circles the same way there; the other
    arguments as for ``mesh_point``. The replay gives the pitch point a run logged.
    """
    world_axis_a = world_from_a @ axis_a
    world_axis_b = world_from_b @ axis_b
    # The pitch point in each gear's transverse plane (helical gears may sit apart axially).
    to_a = point - centre_a
    to_b = point - centre_b
    to_a = to_a - (to_a @ world_axis_a) * world_axis_a
    to_b = to_b - (to_b @ world_axis_b) * world_axis_b
    same = float(np.cross(world_axis_a, to_a) @ np.cross(world_axis_b, to_b)) > 0.0
    return MeshPoint(
        gear_a,
        gear_b,
        _angle_of(axis_a, world_from_a.T @ to_a),
        _angle_of(axis_b, world_from_b.T @ to_b),
        same,
    )


def tooth_phases(
    meshes: Sequence[MeshPoint],
    gears: Mapping[str, GearSpec],
    flank_radius: Mapping[str, float],
) -> dict[str, float]:
    """Tooth phase of every gear of a gearbox at the reference pose [rad], in its joint frame.

    Each gear's phase is the angle of tooth 0's centre line about its axis from
    ``zero_direction`` (its joint frame's x axis projected ⟂ the axis). A gear that sets
    ``tooth_phase_deg`` keeps it, and so does the first gear of each train (default 0); every
    other gear interlocks with its already-phased mating gear (``interlocking_phases``).

    ``tooth_phase_deg`` φ is where the flank of tooth 0 facing the gear's positive turn (A's
    front flank, docs/model_format.md) crosses the working pitch circle r_w of the gear's first
    mesh (in file order, where it is A, else B): the tooth centre is at φ − ψ(r_w)
    (``GearSpec.half_tooth_angle``).

    Args:
        meshes: the meshes in file order (``mesh_point``).
        gears: gear name → its spec from the model file.
        flank_radius: gear name → r_w above [m], for every gear that meshes.
    """
    own = {}
    for name, spec in gears.items():
        radius = flank_radius.get(name)
        shift = spec.half_tooth_angle(radius) if radius is not None else 0.0
        own[name] = spec.tooth_phase - shift
    given = {n: own[n] for n, spec in gears.items() if spec.tooth_phase_given}
    teeth = {n: spec.teeth for n, spec in gears.items()}
    phases = interlocking_phases(meshes, teeth, given, own)
    return {name: phases.get(name, own[name]) for name in gears}
