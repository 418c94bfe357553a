"""The planet carrier of a planetary stage: planet centres, their clearance, the carrier body.

Planets are equally spaced on the carrier at the working centre distance a, planet 1 on +x. A
default carrier is a steel disc of radius a + planet pitch radius and total thickness
``CARRIER_THICKNESS_FRACTION`` · face width, split into two cheeks on both sides of the planets
(faces touching the gear faces), so that its centre of mass lies in the planets' mid-plane.
"""

from __future__ import annotations

import math

from pinwind.errors import PlanetsCollide
from pinwind.model.builders.gear_bodies import MassProperties, part_at, steel_cylinder
from pinwind.model.builders.urdf_writer import Train

#: Thickness of a default carrier (both cheeks together), as a fraction of the face width.
CARRIER_THICKNESS_FRACTION = 0.5


def planet_centres(planets: int, centre_distance: float) -> list[tuple[float, float]]:
    """(x, y) of each planet's centre [m], equally spaced at ``centre_distance``, planet 1 on +x."""
    angles = [2.0 * math.pi * i / planets for i in range(planets)]
    return [(centre_distance * math.cos(t), centre_distance * math.sin(t)) for t in angles]


def check_planet_spacing(planets: int, centre_distance: float, tip_radius: float) -> None:
    """Neighbouring planets must clear each other: 2 r_a < 2 a sin(π/N); else ``PlanetsCollide``.

    Args:
        planets: number of planets N.
        centre_distance: planet centre distance a [m].
        tip_radius: planet tip radius r_a [m] (the larger one of a compound planet).
    """
    if planets < 2:
        return
    chord = 2.0 * centre_distance * math.sin(math.pi / planets)
    if 2.0 * tip_radius >= chord:
        raise PlanetsCollide(tip_radius, chord, planets, centre_distance)


def add_carrier(
    train: Train,
    props: MassProperties | None,
    radius: float,
    gap: float,
    z_mid: float,
    face_width: float,
    link_name: str = "carrier",
) -> None:
    """Carrier link: given mass properties at ``z_mid``, or two steel cheeks around the planets.

    The cheeks (thickness ``CARRIER_THICKNESS_FRACTION/2 · face_width`` each, radius ``radius``
    [m]) sit face to face with the planets, whose faces span ``z_mid ± gap/2`` [m], on link
    ``link_name``.
    """
    link = train.link(link_name)
    t = CARRIER_THICKNESS_FRACTION / 2.0 * face_width
    cheeks = [z_mid - gap / 2.0 - t / 2.0, z_mid + gap / 2.0 + t / 2.0]
    for z in cheeks:
        link.visuals.append((z, radius, t))
    if props is not None:
        link.parts.append(part_at(props, z_mid))
    else:
        for z in cheeks:
            link.parts.append(part_at(steel_cylinder(outer_radius=radius, length=t), z))
