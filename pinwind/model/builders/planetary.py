"""Planetary stage with a fixed ring, plus optional parallel stages (``planetary_urdf``).

After Saleh et al. 2017 §4.1-4.2 (Tables 2-3). Shafts along the world z axis, root link
``housing``, gravity along −y:

- ``carrier`` and ``sun``: continuous joints on the housing at the origin.
- ``planet1..N``: continuous joints whose parent is the carrier, at the sun–planet working centre
  distance, equally spaced, planet 1 on +x.
- ``ring``: fixed joint on the housing; the ring link carries the internal gear (the loader turns
  it into a locked bearing so that its mount reaction is reported).
- ``pin1..N`` (only when ``inertias`` has a ``"pin"`` entry): links welded to the carrier by
  fixed joints at the planet centres (Table 3's rigid carrier–pin joints); Pinocchio merges them
  into the carrier body.
- Gears ``sun``, ``planet{i}``, ``ring``; meshes ``sun_planet{i}`` (gear1 sun, gear2 planet i)
  and ``planet{i}_ring`` (gear1 planet i, gear2 ring).
- Parallel stages after the sun as in ``builders/parallel.py`` (the stage-1 wheel on the sun).

Mass properties, unless ``inertias`` gives them as (mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²])
about the body's centre of mass: steel gears and ring (``builders/gear_bodies.py``) and a steel
carrier of two cheeks (``builders/carrier.py``).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path

from pinwind.errors import InputError, InvalidGearTrain, PinwindWarning
from pinwind.gears.involute import pitch_radius, tip_radius
from pinwind.model.builders.arguments import (
    helix_angles,
    inertia_table,
    per_stage,
    positive,
    pressure_angle_rad,
    teeth_count,
)
from pinwind.model.builders.carrier import (
    CARRIER_THICKNESS_FRACTION,
    add_carrier,
    check_planet_spacing,
    planet_centres,
)
from pinwind.model.builders.centre_distance import working_pair
from pinwind.model.builders.gear_bodies import (
    MassProperties,
    part_at,
    steel_gear,
    steel_ring_gear,
)
from pinwind.model.builders.parallel import add_parallel_stages, load_matched_modules
from pinwind.model.builders.urdf_writer import Train, TrainGear, TrainJoint
from pinwind.model.gearbox import CENTRE_DISTANCE_RTOL


def planetary_urdf(
    *,
    sun: int,
    planet: int,
    ring: int,
    planets: int,
    module: float,
    pressure_angle: float,
    face_width: float,
    parallel: Sequence[tuple[int, int]] = (),
    profile_shift: tuple[float, float, float] = (0.0, 0.0, 0.0),
    name: str = "planetary",
    inertias: Mapping[str, MassProperties] | None = None,
    parallel_module: float | Sequence[float] | None = None,
    parallel_face_width: float | Sequence[float] | None = None,
    parallel_helix_angle: float | Sequence[float] = 0.0,
) -> str:
    """URDF text of a planetary stage with fixed ring, plus optional parallel stages.

    Layout, names and default mass properties: see the module docstring.

    Args:
        sun: sun tooth count.
        planet: planet tooth count.
        ring: ring tooth count.
        planets: number of planets, equally spaced.
        module: normal module [m] of the planetary stage.
        pressure_angle: normal pressure angle [rad] (every stage).
        face_width: face width [m] of the planetary gears.
        parallel: parallel stages as (wheel teeth, pinion teeth), input side first.
        profile_shift: (x_sun, x_planet, x_ring), ISO sign convention (internal ring negative
            tooth count; ``gears/involute.py``).
        name: robot name.
        inertias: body → (mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²]) about the centre of mass;
            bodies ``sun``, ``planet``, ``ring``, ``carrier``, ``pin`` (adds pins) and
            ``stage{k}_wheel`` / ``stage{k}_pinion``.
        parallel_module: normal module [m] of the parallel stages, one value or one per stage
            (default: sized from each stage's torque, ``parallel.load_matched_modules``).
        parallel_face_width: face width [m] of the parallel stages, one value or one per stage
            (default: as many modules as the planetary's, b_k = m_k · face_width/module).
        parallel_helix_angle: helix angle β [rad] of each parallel stage's wheel (its pinion
            gets −β), one value or one per stage; 0 (spur) by default.

    Raises:
        InvalidGearTrain: non-positive teeth, module or width, |β| ≥ 45°, a per-stage list of
            the wrong length; a ring that does not fit sun and planets (z_ring ≠ z_sun +
            2 z_planet without profile shift, or unequal working
            centre distances with it).
        PlanetsCollide: neighbouring planets overlap.

    Warns:
        PinwindWarning: (z_sun + z_ring)/planets is not a whole number, so equally spaced
            identical planets cannot be assembled.
    """
    sun, planet = teeth_count("sun", sun), teeth_count("planet", planet)
    ring = teeth_count("ring", ring)
    planets = teeth_count("planets", planets)
    module = positive("module", module, "m")
    alpha = pressure_angle_rad(pressure_angle)
    face_width = positive("face_width", face_width, "m")
    if len(profile_shift) != 3:
        raise InvalidGearTrain(f"profile_shift = {profile_shift!r}; give (x_sun, x_planet, x_ring)")
    x_sun, x_planet, x_ring = (float(x) for x in profile_shift)
    stages = list(parallel)
    allowed = ["sun", "planet", "ring", "carrier", "pin"]
    allowed += [f"stage{k}_{g}" for k in range(1, len(stages) + 1) for g in ("wheel", "pinion")]
    table = inertia_table(inertias, allowed)
    if parallel_module is None:
        modules = load_matched_modules(stages, module=module, sun_teeth=sun, planets=planets)
    else:
        modules = per_stage("parallel_module", parallel_module, math.nan, len(stages))
    if parallel_face_width is None:
        widths = [m_k * face_width / module for m_k in modules]
    else:
        widths = per_stage("parallel_face_width", parallel_face_width, math.nan, len(stages))
    betas = helix_angles("parallel_helix_angle", parallel_helix_angle, len(stages))

    if ring <= planet:
        raise InvalidGearTrain(f"ring ({ring} teeth) must have more teeth than a planet ({planet})")
    if x_sun == x_planet == x_ring == 0.0 and ring != sun + 2 * planet:
        raise InvalidGearTrain(
            f"ring has {ring} teeth but sun + 2·planet = {sun} + 2·{planet} = {sun + 2 * planet}; "
            "without profile shift the planets only reach from the sun to the ring when "
            "z_ring = z_sun + 2 z_planet (Saleh et al. 2017 §4.1); with profile shifts give them "
            "(profile_shift), or build the stage with pinwind build stages"
        )
    sun_planet = working_pair(sun, planet, module=module, alpha=alpha, x1=x_sun, x2=x_planet)
    planet_ring = working_pair(
        planet, ring, module=module, alpha=alpha, x1=x_planet, x2=x_ring, internal=True
    )
    a = sun_planet.centre_distance
    if abs(planet_ring.centre_distance - a) > CENTRE_DISTANCE_RTOL * a:
        raise InvalidGearTrain(
            f"sun–planet working centre distance {a * 1e3:.4f} mm and planet–ring "
            f"{planet_ring.centre_distance * 1e3:.4f} mm differ by more than "
            f"{CENTRE_DISTANCE_RTOL:g} relative (teeth {sun}/{planet}/{ring}, profile shifts "
            f"{x_sun:g}/{x_planet:g}/{x_ring:g}); adjust the profile shifts"
        )
    check_planet_spacing(
        planets,
        a,
        tip_radius(
            planet,
            module,
            profile_shift=x_planet,
            helix_angle=0.0,
            internal=False,
            addendum_coefficient=1.0,
        ),
    )
    if (sun + ring) % planets:
        warnings.warn(
            PinwindWarning(
                f"(z_sun + z_ring)/planets = ({sun} + {ring})/{planets} = "
                f"{(sun + ring) / planets:.4g} is not a whole number: {planets} identical planets "
                "cannot be assembled equally spaced (the rigid model ignores tooth phasing)"
            ),
            stacklevel=2,
        )

    r_planet = pitch_radius(planet, module)
    train = Train(name, "pinwind.model.builders.planetary_urdf")
    train.link("housing")
    add_carrier(train, table.get("carrier"), a + r_planet, face_width, 0.0, face_width)
    train.joints.append(TrainJoint("carrier", "continuous", "housing", "carrier", (0.0, 0.0, 0.0)))
    train.joints.append(TrainJoint("sun", "continuous", "housing", "sun", (0.0, 0.0, 0.0)))
    train.gear(
        TrainGear("sun", "sun", sun, module, alpha, face_width, x_sun),
        table.get("sun") or steel_gear(sun, module=module, face_width=face_width),
    )
    planet_props = table.get("planet") or steel_gear(planet, module=module, face_width=face_width)
    for i, (x, y) in enumerate(planet_centres(planets, a), start=1):
        train.joints.append(
            TrainJoint(f"planet{i}", "continuous", "carrier", f"planet{i}", (x, y, 0))
        )
        train.gear(
            TrainGear(f"planet{i}", f"planet{i}", planet, module, alpha, face_width, x_planet),
            planet_props,
        )
    ring_props = table.get("ring") or steel_ring_gear(ring, module=module, face_width=face_width)
    train.joints.append(TrainJoint("ring", "fixed", "housing", "ring", (0.0, 0.0, 0.0)))
    train.gear(
        TrainGear("ring", "ring", ring, module, alpha, face_width, x_ring, internal=True),
        ring_props,
    )
    if "pin" in table:
        _add_pins(train, table["pin"], planet_centres(planets, a), r_planet, face_width)
    for i in range(1, planets + 1):
        train.meshes.append((f"sun_planet{i}", "sun", f"planet{i}"))
    for i in range(1, planets + 1):
        train.meshes.append((f"planet{i}_ring", f"planet{i}", "ring"))
    add_parallel_stages(
        train,
        stages=stages,
        first_link="sun",
        first_link_z=0.0,
        previous_face_end=(0.5 + CARRIER_THICKNESS_FRACTION / 2.0) * face_width,
        pressure_angle=alpha,
        modules=modules,
        face_widths=widths,
        inertias=table,
        helix_angles=betas,
    )
    return train.render()


def write_planetary(path: str | Path, **kwargs) -> Path:
    """Write ``planetary_urdf(**kwargs)`` to ``path``; return the path."""
    path = Path(path)
    text = planetary_urdf(**kwargs)
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as err:
        raise InputError(
            f"cannot write the model to {path}: {err.strerror or err}; choose another --output "
            "or fix the folder's permissions"
        ) from err
    return path


def _add_pins(
    train: Train,
    props: MassProperties,
    centres: Sequence[tuple[float, float]],
    planet_radius: float,
    face_width: float,
) -> None:
    """Planet pins welded to the carrier at the planet centres (Saleh et al. 2017 Table 3).

    The visual is a cylinder through both carrier cheeks, of the radius whose solid cylinder has
    the pin's Izz (r = √(2 Izz/m)), capped at half the planet pitch radius.
    """
    mass, _, izz = props
    radius = min(math.sqrt(2.0 * izz / mass), 0.5 * planet_radius)
    length = (1.0 + CARRIER_THICKNESS_FRACTION) * face_width
    for i, (x, y) in enumerate(centres, start=1):
        link = train.link(f"pin{i}")
        link.parts.append(part_at(props))
        link.visuals.append((0.0, radius, length))
        train.joints.append(TrainJoint(f"pin{i}", "fixed", "carrier", f"pin{i}", (x, y, 0.0)))
