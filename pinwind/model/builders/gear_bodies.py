"""Mass properties of the bodies the builders write: steel gears, rings, discs, shafts.

A body is given as (mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²]) about its centre of mass, z the
shaft axis (``MassProperties``). The defaults of the builders are steel (7850 kg/m³):

- an external gear: a solid (or bored) cylinder of pitch diameter × face width;
- a ring gear: a hollow cylinder from the pitch diameter to the pitch diameter + 2·3.5 module (a
  rim 3.5 modules deep: tooth depth 2.25 m plus a rim of about 1.2 m), face width long.

A link that carries several bodies gets their sum (``combine``: masses add, inertias move by the
parallel-axis theorem).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pinwind.gears.involute import pitch_radius

#: Density of steel [kg/m³].
STEEL_DENSITY = 7850.0
#: Radial depth of a ring gear's rim beyond its pitch circle, in modules.
RING_RIM_MODULES = 3.5

MassProperties = tuple[float, float, float]
"""(mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²]) about the centre of mass, z the shaft axis."""


def cylinder_inertia(
    mass: float, *, outer_radius: float, length: float, inner_radius: float = 0.0
) -> tuple[float, float]:
    """(Ixx = Iyy, Izz) of a uniform (hollow) cylinder about its centre, axis along z [kg·m²].

    Izz = m (r_o² + r_i²)/2 and Ixx = m (3 (r_o² + r_i²) + L²)/12.
    """
    r2 = outer_radius**2 + inner_radius**2
    return mass * (3.0 * r2 + length**2) / 12.0, mass * r2 / 2.0


def steel_cylinder(
    *, outer_radius: float, length: float, inner_radius: float = 0.0
) -> MassProperties:
    """Mass properties of a steel (hollow) cylinder, axis along z (7850 kg/m³)."""
    mass = STEEL_DENSITY * math.pi * (outer_radius**2 - inner_radius**2) * length
    ixx, izz = cylinder_inertia(
        mass, outer_radius=outer_radius, inner_radius=inner_radius, length=length
    )
    return mass, ixx, izz


def steel_gear(
    teeth: int, *, module: float, face_width: float, bore: float = 0.0, helix_angle: float = 0.0
) -> MassProperties:
    """An external steel gear: a cylinder of pitch diameter × face width, bore diameter ``bore``.

    Args:
        teeth: tooth count.
        module: normal module [m].
        face_width: face width [m].
        bore: bore diameter [m] (0: solid).
        helix_angle: helix angle [rad] (the pitch diameter is z m_n / cos β).
    """
    return steel_cylinder(
        outer_radius=pitch_radius(teeth, module, helix_angle),
        inner_radius=bore / 2.0,
        length=face_width,
    )


def steel_ring_gear(teeth: int, *, module: float, face_width: float) -> MassProperties:
    """A steel ring gear: a hollow cylinder from its pitch circle out to a rim of 3.5 modules."""
    radius = pitch_radius(teeth, module)
    return steel_cylinder(
        outer_radius=radius + RING_RIM_MODULES * module, inner_radius=radius, length=face_width
    )


@dataclass
class Part:
    """A rigid part of a link: mass [kg], centre of mass [m] and inertia about it [kg·m²].

    Centre and inertia are in the link frame.
    """

    mass: float
    com: np.ndarray
    inertia: np.ndarray


def part_at(props: MassProperties, z: float = 0.0) -> Part:
    """A body of mass properties ``props`` centred on the link's z axis at ``z`` [m]."""
    mass, ixx, izz = props
    return Part(mass, np.array([0.0, 0.0, z]), np.diag([ixx, ixx, izz]))


def combine(parts: Sequence[Part]) -> Part:
    """One rigid body from several: masses add, inertias move by the parallel-axis theorem."""
    mass = sum(p.mass for p in parts)
    com = sum((p.mass * p.com for p in parts), np.zeros(3)) / mass
    inertia = np.zeros((3, 3))
    for p in parts:
        d = p.com - com
        inertia += p.inertia + p.mass * (d @ d * np.eye(3) - np.outer(d, d))
    return Part(mass, com, inertia)
