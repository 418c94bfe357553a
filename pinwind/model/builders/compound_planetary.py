"""Planetary stage with compound (stepped) planets and a fixed ring (``compound_planetary_urdf``).

After the CART 600 kW gearbox (IFToMM 2018 Table 1): each planet link carries two
gears on one shaft, planet A meshing the fixed ring and planet B meshing the sun, in two planes
along the shaft. Shafts along the world z axis, root link ``housing``, gravity along −y; parallel
stages after the sun as in ``builders/parallel.py``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from pinwind.errors import InvalidGearTrain
from pinwind.gears.involute import pitch_radius, tip_radius
from pinwind.model.builders.arguments import (
    inertia_table,
    per_stage,
    positive,
    pressure_angle_rad,
    teeth_count,
)
from pinwind.model.builders.carrier import add_carrier, check_planet_spacing, planet_centres
from pinwind.model.builders.centre_distance import shift_sum_for_centre_distance, working_pair
from pinwind.model.builders.gear_bodies import (
    MassProperties,
    part_at,
    steel_cylinder,
    steel_gear,
    steel_ring_gear,
)
from pinwind.model.builders.parallel import add_parallel_stages
from pinwind.model.builders.urdf_writer import Train, TrainGear, TrainJoint
from pinwind.model.gearbox import CENTRE_DISTANCE_RTOL


def compound_planetary_urdf(
    *,
    sun: int,
    planet_a: int,
    planet_b: int,
    ring: int,
    planets: int,
    ring_module: float,
    sun_module: float,
    pressure_angle: float,
    ring_face_width: float,
    sun_face_width: float,
    profile_shift: Mapping[str, float] | None = None,
    axial_gap: float | None = None,
    parallel: Sequence[tuple[int, int]] = (),
    parallel_module: float | Sequence[float] | None = None,
    parallel_face_width: float | Sequence[float] | None = None,
    name: str = "compound_planetary",
    inertias: Mapping[str, MassProperties] | None = None,
    bores: Mapping[str, float] | None = None,
    shafts: Mapping[str, tuple[float, float, float]] | None = None,
) -> str:
    """URDF text of a planetary stage with compound (stepped) planets and a fixed ring.

    Each planet link carries two gears on one shaft (IFToMM 2018 Table 1): planet
    A (``planet{i}_a``) meshes the fixed ring in the plane z = 0, planet B (``planet{i}_b``)
    meshes the sun in the plane z_B = ring_face_width/2 + axial_gap + sun_face_width/2. Both
    meshes share the planet centre distance, taken from the ring–A pair. Meshes
    ``planet{i}_ring`` (gear1 planet A, gear2 ring) and ``sun_planet{i}`` (gear1 sun, gear2
    planet B). Joints ``carrier``, ``sun`` (both at the origin), ``planet1..N`` (on the carrier),
    ``ring`` (fixed) and ``stage{k}_pinion`` for the parallel stages (as in ``planetary_urdf``;
    the stage-1 wheel is a gear on the sun link).

    Mass properties: the ``inertias`` overrides (``carrier`` with its centre of mass midway
    between the outer faces of planets A and B,
    ``sun``, ``ring``, ``planet`` for a whole compound planet at z_B/2, ``stage{k}_wheel``,
    ``stage{k}_pinion``), else steel geometry: gears are hollow cylinders of pitch diameter ×
    face width with the bore diameters of ``bores`` (keys ``sun``, ``planet_a``, ``planet_b``,
    ``stage{k}_wheel``, ``stage{k}_pinion``; solid if absent), the ring and the carrier as in
    ``planetary_urdf`` (carrier cheeks outside the two planet planes). ``shafts`` adds steel
    tubes (inner diameter, outer diameter, length [m]) to the links ``planet``, ``sun`` or
    ``stage{k}_pinion``, each centred midway between the first and last gear of its link.

    Args:
        sun: sun tooth count.
        planet_a: tooth count of planet gear A (meshes the ring).
        planet_b: tooth count of planet gear B (meshes the sun).
        ring: ring tooth count.
        planets: number of planets, equally spaced, planet 1 on +x.
        ring_module: module [m] of the ring–A pair.
        sun_module: module [m] of the sun–B pair.
        pressure_angle: normal pressure angle [rad].
        ring_face_width: face width [m] of the ring–A pair.
        sun_face_width: face width [m] of the sun–B pair.
        profile_shift: shifts by gear (``sun``, ``planet_a``, ``planet_b``, ``ring``), ISO sign
            convention; absent ones are zero.
        axial_gap: clear distance between the planet A and B faces [m] (default half the larger
            face width).
        parallel: parallel stages (wheel teeth, pinion teeth), as in ``planetary_urdf``.
        parallel_module: module [m] of the parallel stages (default ``sun_module``).
        parallel_face_width: face width [m] of the parallel stages (default ``sun_face_width``).
        name: robot name.
        inertias: body → (mass, Ixx = Iyy, Izz) overrides, see above.
        bores: gear → bore diameter [m], see above.
        shafts: link → steel tube (inner diameter, outer diameter, length) [m], see above.

    Raises:
        InvalidGearTrain: bad teeth, module or width, or the ring–A and sun–B working centre
            distances differ by more than the loader's tolerance (``gearbox.CENTRE_DISTANCE_RTOL``).
        PlanetsCollide: neighbouring planets overlap.
    """
    sun, ring = teeth_count("sun", sun), teeth_count("ring", ring)
    planet_a = teeth_count("planet_a", planet_a)
    planet_b = teeth_count("planet_b", planet_b)
    planets = teeth_count("planets", planets)
    m_r = positive("ring_module", ring_module, "m")
    m_s = positive("sun_module", sun_module, "m")
    alpha = pressure_angle_rad(pressure_angle)
    b_r = positive("ring_face_width", ring_face_width, "m")
    b_s = positive("sun_face_width", sun_face_width, "m")
    gap = 0.5 * max(b_r, b_s) if axial_gap is None else positive("axial_gap", axial_gap, "m")
    shifts = dict(profile_shift or {})
    unknown = sorted(set(shifts) - {"sun", "planet_a", "planet_b", "ring"})
    if unknown:
        raise InvalidGearTrain(f"profile_shift has unknown gears {unknown}")
    x = {g: float(shifts.get(g, 0.0)) for g in ("sun", "planet_a", "planet_b", "ring")}
    stages = list(parallel)
    allowed = ["sun", "planet", "ring", "carrier"]
    allowed += [f"stage{k}_{g}" for k in range(1, len(stages) + 1) for g in ("wheel", "pinion")]
    table = inertia_table(inertias, allowed)
    bores = dict(bores or {})
    shafts = dict(shafts or {})
    modules = per_stage("parallel_module", parallel_module, m_s, len(stages))
    widths = per_stage("parallel_face_width", parallel_face_width, b_s, len(stages))

    if ring <= planet_a:
        raise InvalidGearTrain(
            f"ring ({ring} teeth) must have more teeth than planet A ({planet_a})"
        )
    ring_pair = working_pair(
        planet_a, ring, module=m_r, alpha=alpha, x1=x["planet_a"], x2=x["ring"], internal=True
    )
    sun_pair = working_pair(sun, planet_b, module=m_s, alpha=alpha, x1=x["sun"], x2=x["planet_b"])
    a = ring_pair.centre_distance
    if abs(sun_pair.centre_distance - a) > CENTRE_DISTANCE_RTOL * a:
        needed = shift_sum_for_centre_distance(
            sun, planet_b, module=m_s, pressure_angle=alpha, centre_distance=a
        )
        raise InvalidGearTrain(
            f"ring–planet A working centre distance is {a * 1e3:.4f} mm but sun–planet B gives "
            f"{sun_pair.centre_distance * 1e3:.4f} mm ({sun}+{planet_b} teeth, module "
            f"{m_s * 1e3:g} mm, shifts {x['sun']:g}+{x['planet_b']:g}); more than "
            f"{CENTRE_DISTANCE_RTOL:g} relative apart. A total shift x_sun + x_planet_b = "
            f"{needed:.6f} would give {a * 1e3:.4f} mm"
        )
    tip_a = tip_radius(
        planet_a,
        m_r,
        profile_shift=x["planet_a"],
        helix_angle=0.0,
        internal=False,
        addendum_coefficient=1.0,
    )
    tip_b = tip_radius(
        planet_b,
        m_s,
        profile_shift=x["planet_b"],
        helix_angle=0.0,
        internal=False,
        addendum_coefficient=1.0,
    )
    check_planet_spacing(planets, a, max(tip_a, tip_b))

    z_b = 0.5 * b_r + gap + 0.5 * b_s
    r_a, r_b = pitch_radius(planet_a, m_r), pitch_radius(planet_b, m_s)
    train = Train(name, "pinwind.model.builders.compound_planetary_urdf")
    train.link("housing")
    span = z_b + 0.5 * (b_r + b_s)  # from the outer face of planet A to that of planet B
    z_mid = 0.5 * (z_b + 0.5 * b_s - 0.5 * b_r)
    add_carrier(train, table.get("carrier"), a + max(r_a, r_b), span, z_mid, max(b_r, b_s))
    train.joints.append(TrainJoint("carrier", "continuous", "housing", "carrier", (0.0, 0.0, 0.0)))
    train.joints.append(TrainJoint("sun", "continuous", "housing", "sun", (0.0, 0.0, 0.0)))
    train.gear(
        TrainGear("sun", "sun", sun, m_s, alpha, b_s, x["sun"], z=z_b),
        table.get("sun") or steel_gear(sun, module=m_s, face_width=b_s, bore=bores.get("sun", 0.0)),
    )
    for i, (cx, cy) in enumerate(planet_centres(planets, a), start=1):
        link = f"planet{i}"
        train.joints.append(TrainJoint(link, "continuous", "carrier", link, (cx, cy, 0.0)))
        whole = table.get("planet")
        props_a = props_b = None
        if whole is None:
            props_a = steel_gear(
                planet_a, module=m_r, face_width=b_r, bore=bores.get("planet_a", 0.0)
            )
            props_b = steel_gear(
                planet_b, module=m_s, face_width=b_s, bore=bores.get("planet_b", 0.0)
            )
        else:
            train.link(link).parts.append(part_at(whole, z_b / 2))
        train.gear(TrainGear(f"{link}_a", link, planet_a, m_r, alpha, b_r, x["planet_a"]), props_a)
        train.gear(
            TrainGear(f"{link}_b", link, planet_b, m_s, alpha, b_s, x["planet_b"], z=z_b), props_b
        )
    ring_props = table.get("ring") or steel_ring_gear(ring, module=m_r, face_width=b_r)
    train.joints.append(TrainJoint("ring", "fixed", "housing", "ring", (0.0, 0.0, 0.0)))
    train.gear(
        TrainGear("ring", "ring", ring, m_r, alpha, b_r, x["ring"], internal=True), ring_props
    )
    for i in range(1, planets + 1):
        train.meshes.append((f"sun_planet{i}", "sun", f"planet{i}_b"))
    for i in range(1, planets + 1):
        train.meshes.append((f"planet{i}_ring", f"planet{i}_a", "ring"))
    add_parallel_stages(
        train,
        stages=stages,
        first_link="sun",
        first_link_z=0.0,
        previous_face_end=z_b + 0.5 * b_s,
        pressure_angle=alpha,
        modules=modules,
        face_widths=widths,
        inertias=table,
        bores=bores,
    )
    _add_shafts(train, shafts, planets)
    return train.render()


def _add_shafts(
    train: Train, shafts: Mapping[str, tuple[float, float, float]], planets: int
) -> None:
    for key, (inner_d, outer_d, length) in shafts.items():
        links = [f"planet{i}" for i in range(1, planets + 1)] if key == "planet" else [key]
        for name in links:
            if name not in train.links or name in ("housing", "carrier", "ring"):
                raise InvalidGearTrain(
                    f'shafts["{key}"]: no geared shaft link "{name}"; shafts go on "planet", '
                    '"sun" or "stage{k}_pinion"'
                )
            zs = [g.z for g in train.gears if g.link == name]
            z = 0.5 * (min(zs) + max(zs))
            props = steel_cylinder(
                outer_radius=outer_d / 2, inner_radius=inner_d / 2, length=length
            )
            train.links[name].parts.append(part_at(props, z))
            train.links[name].visuals.append((z, outer_d / 2, length))
