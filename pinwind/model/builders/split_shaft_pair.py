"""A spur pair on split shafts (Cai's rig, ``split_shaft_pair_urdf``)."""

from __future__ import annotations

import math

from pinwind.errors import InvalidGearTrain
from pinwind.gears.involute import pitch_radius
from pinwind.model.builders.arguments import (
    mass_properties,
    positive,
    pressure_angle_rad,
    teeth_count,
)
from pinwind.model.builders.gear_bodies import STEEL_DENSITY, MassProperties, part_at
from pinwind.model.builders.urdf_writer import Train, TrainGear, TrainJoint, TrainSpring


def split_shaft_pair_urdf(
    *,
    teeth: tuple[int, int],
    module: float,
    pressure_angle: float,
    face_width: tuple[float, float],
    shaft_stiffness: float,
    half_shaft: MassProperties,
    gear_inertias: tuple[MassProperties, MassProperties],
    shaft_damping: float = 0.0,
    name: str = "spur_pair",
) -> str:
    """URDF text of a spur pair whose input and output shafts are each split in two halves.

    After Kelso 2011 §3.4-3.5 (Cai's rig): the two halves of each shaft are joined
    by a torsional spring (the RSDA of the seed), so the drive and the brake see the shaft
    compliance. Joints, all continuous on the housing, axes along z:

    - ``input_shaft``: the driven half of the input shaft, axis through the origin, its origin at
      the spring (z = −L, L the half-shaft length), the half-shaft centred at z = −3L/2;
    - ``gear1``: gear 1 (z = 0) and the other input half-shaft (centred at z = −L/2);
    - ``gear2``: gear 2 at (a, 0, 0), a = m (z1 + z2)/2, and its half-shaft centred at z = +L/2;
    - ``output_shaft``: the brake half of the output shaft at (a, 0, L), centred at z = 3L/2.

    Springs ``input_spring`` (input_shaft–gear1) and ``output_spring`` (gear2–output_shaft); mesh
    ``gear_pair`` (gear1 drives gear2).

    The half-shaft length L follows from its mass properties as the steel solid cylinder with
    the same mass and Izz: r = √(2 Izz/m), L = m/(ρ π r²).

    Args:
        teeth: (z1, z2).
        module: module [m].
        pressure_angle: pressure angle [rad].
        face_width: face widths [m] of gear 1 and gear 2.
        shaft_stiffness: torsional stiffness k of each shaft [N·m/rad].
        half_shaft: (mass, Ixx = Iyy, Izz) of one half-shaft.
        gear_inertias: (mass, Ixx = Iyy, Izz) of gear 1 and of gear 2.
        shaft_damping: torsional damping of each shaft [N·m·s/rad].
        name: robot name.
    """
    z1, z2 = teeth_count("teeth[0]", teeth[0]), teeth_count("teeth[1]", teeth[1])
    module = positive("module", module, "m")
    alpha = pressure_angle_rad(pressure_angle)
    b1, b2 = (positive(f"face_width[{i}]", b, "m") for i, b in enumerate(face_width))
    if not (math.isfinite(shaft_stiffness) and shaft_stiffness >= 0):
        raise InvalidGearTrain(f"shaft_stiffness = {shaft_stiffness!r} N·m/rad; must be ≥ 0")
    shaft = mass_properties("half_shaft", half_shaft)
    gear_props = [mass_properties(f"gear{i}", p) for i, p in enumerate(gear_inertias, start=1)]
    mass, _, izz = shaft
    radius = math.sqrt(2.0 * izz / mass)
    length = mass / (STEEL_DENSITY * math.pi * radius**2)
    a = pitch_radius(z1, module) + pitch_radius(z2, module)

    train = Train(name, "pinwind.model.builders.split_shaft_pair_urdf")
    train.link("housing")
    layout = (
        ("input_shaft", (0.0, 0.0, -length), -length / 2.0),
        ("gear1", (0.0, 0.0, 0.0), -length / 2.0),
        ("gear2", (a, 0.0, 0.0), length / 2.0),
        ("output_shaft", (a, 0.0, length), length / 2.0),
    )
    for joint, xyz, shaft_z in layout:
        train.joints.append(TrainJoint(joint, "continuous", "housing", joint, xyz))
        link = train.link(joint)
        link.parts.append(part_at(shaft, shaft_z))
        link.visuals.append((shaft_z, radius, length))
    for i, (z, b) in enumerate(((z1, b1), (z2, b2)), start=1):
        train.gear(TrainGear(f"gear{i}", f"gear{i}", z, module, alpha, b), gear_props[i - 1])
    train.meshes.append(("gear_pair", "gear1", "gear2"))
    train.springs.append(
        TrainSpring("input_spring", "input_shaft", "gear1", shaft_stiffness, shaft_damping)
    )
    train.springs.append(
        TrainSpring("output_spring", "gear2", "output_shaft", shaft_stiffness, shaft_damping)
    )
    return train.render()
