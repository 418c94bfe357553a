"""A gearbox of any sequence of stages joined through named shafts (``stages_urdf``).

Each stage is planetary (``PlanetaryStage``: sun, planets on a carrier, ring; any one member
fixed to the housing, the other two on shafts) or parallel (``ParallelStage``: a wheel and a
pinion on parallel shafts), spur or helical, with its own normal module, helix angle, face
width, working centre distance a_w, profile shifts and tip alterations. A stage names the shaft
of each turning member; stages that name the same shaft are joined by it (stage 1's sun shaft is
stage 2's carrier when both name it ``iss``). Each shaft is one continuous joint (and link) of
that name on the housing; a planet is a joint ``<stage>_planet<i>`` on its carrier. End bodies
(``EndBody``: a rotor, a generator) turn on their own joints, coupled to a shaft by a torsional
spring (a shaft's torsional stiffness).

Meshing at a_w. Profile-shifted gears need not satisfy z_ring = z_sun + 2 z_planet: a pair meshes
without backlash at the working centre distance its teeth and shifts give (ISO 21771; Niemann &
Winter 2003 §21),

    inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2),  a_w = m_t (z1 + z2) cos α_t / (2 cos α_wt)

with signed tooth numbers (an internal gear's negative, so the internal pair's is the difference
form z_planet − z_ring), and every pair of a stage must give the stage's a_w to the loader's
tolerance (``gearbox.CENTRE_DISTANCE_RTOL``, 1e-4 relative); else ``InvalidGearTrain`` names the
stage, the numbers and the total shift that would give a_w. Profile shift x of an internal gear:
the sign convention of ISO 21771 (`gears.involute.tip_radius`): a positive x moves the ring's
tips towards the axis (d_a = d − 2 m_n (h_a* + x + k)) and thickens its teeth.

Layout: shafts along the world z axis, root link ``housing``, gravity along −y. Stage k's gears
are centred on the plane z_k, z_1 = 0, each stage half its larger neighbour's face width after
the previous one; a planetary stage is coaxial with the shaft it shares with an earlier stage
(else on the z axis), a parallel stage's pinion shaft is a_w along +y from its wheel's shaft.
Rolling bearings (``StageBearing``) keep their own data in the file (``<row>``); each shaft's
joint sits at its bearings' stiffness centre and carries their equivalent compliant bearing
(``model/bearing_rows.py``). Default mass properties: steel gears, rings and carrier cheeks
(``gear_bodies.py``, ``carrier.py``), unless a stage's ``inertias`` give them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from pinwind.errors import InvalidGearTrain
from pinwind.gears.involute import pitch_radius, tip_radius
from pinwind.model.bearing_rows import BearingRow, equivalent_bearing
from pinwind.model.builders.arguments import mass_properties, positive, teeth_count
from pinwind.model.builders.carrier import add_carrier, check_planet_spacing, planet_centres
from pinwind.model.builders.centre_distance import shift_sum_for_centre_distance, working_pair
from pinwind.model.builders.gear_bodies import (
    MassProperties,
    part_at,
    steel_gear,
    steel_ring_gear,
)
from pinwind.model.builders.urdf_writer import (
    Train,
    TrainBearing,
    TrainGear,
    TrainJoint,
    TrainSpring,
)
from pinwind.model.gearbox import CENTRE_DISTANCE_RTOL

#: A member held by the housing instead of turning on a shaft.
FIXED = "fixed"
#: The members of a planetary stage that a shaft (or the housing) holds.
PLANETARY_MEMBERS: tuple[str, ...] = ("sun", "carrier", "ring")
#: The members of a parallel stage.
PARALLEL_MEMBERS: tuple[str, ...] = ("wheel", "pinion")


@dataclass(frozen=True)
class StageGear:
    """A stage's gear: tooth count, profile shift x (ISO 21771 sign), tip alteration k·m_n [m]."""

    teeth: int
    profile_shift: float = 0.0
    tip_alteration: float = 0.0


@dataclass(frozen=True)
class StageBearing:
    """A rolling bearing of a stage member.

    The member is ``sun``, ``carrier``, ``ring``, ``planet``, ``wheel`` or ``pinion``; the row's
    ``position`` is from the member's gear plane along +z [m].
    """

    member: str
    row: BearingRow


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage: sun, ``planets`` equal planets on a carrier, internal ring.

    Attributes:
        name: the stage's name (prefix of its gears, planets and meshes).
        sun, planet, ring: the gears (the ring internal).
        planets: number of planets, equally spaced.
        module: normal module m_n [m].
        pressure_angle: normal pressure angle α_n [rad].
        face_width: face width b [m].
        centre_distance: working centre distance a_w sun–planet = planet–ring [m].
        shafts: member (``sun``, ``carrier``, ``ring``) → shaft name, or ``FIXED`` for one.
        helix_angle: β [rad] of the sun (the planets the opposite hand, the ring the planets').
        bearings: the members' rolling bearings.
        inertias: member (``sun``, ``planet``, ``ring``, ``carrier``) → (mass [kg], Ixx = Iyy,
            Izz [kg·m²]) about its centre of mass, replacing the steel default.
    """

    name: str
    sun: StageGear
    planet: StageGear
    ring: StageGear
    planets: int
    module: float
    pressure_angle: float
    face_width: float
    centre_distance: float
    shafts: Mapping[str, str]
    helix_angle: float = 0.0
    bearings: tuple[StageBearing, ...] = ()
    inertias: Mapping[str, MassProperties] = field(default_factory=dict)


@dataclass(frozen=True)
class ParallelStage:
    """A parallel-axis stage: a wheel and a pinion (external pair), spur or helical.

    Attributes as ``PlanetaryStage``; ``shafts`` maps ``wheel`` and ``pinion`` to shaft names,
    ``helix_angle`` is the wheel's (the pinion has the opposite hand).
    """

    name: str
    wheel: StageGear
    pinion: StageGear
    module: float
    pressure_angle: float
    face_width: float
    centre_distance: float
    shafts: Mapping[str, str]
    helix_angle: float = 0.0
    bearings: tuple[StageBearing, ...] = ()
    inertias: Mapping[str, MassProperties] = field(default_factory=dict)


Stage = PlanetaryStage | ParallelStage


@dataclass(frozen=True)
class EndBody:
    """A body outside the gearbox (rotor, generator) coupled to a shaft by a torsional spring.

    Attributes:
        name: its joint and link.
        shaft: the gearbox shaft it is coupled to.
        mass_properties: (mass [kg], Ixx = Iyy, Izz [kg·m²]).
        stiffness: torsional stiffness of the coupling shaft [N·m/rad].
        position: world z of its joint, on the shaft's axis [m] (stage 1's plane is z = 0).
        damping: torsional damping of the coupling [N·m·s/rad].
    """

    name: str
    shaft: str
    mass_properties: MassProperties
    stiffness: float
    position: float
    damping: float = 0.0


def stage_pairs(stage: Stage) -> list[tuple[str, StageGear, StageGear, bool]]:
    """The pairs of a stage: (label, gear 1, gear 2, gear 2 internal)."""
    if isinstance(stage, PlanetaryStage):
        return [
            ("sun–planet", stage.sun, stage.planet, False),
            ("planet–ring", stage.planet, stage.ring, True),
        ]
    return [("wheel–pinion", stage.wheel, stage.pinion, False)]


def check_stage_meshes(stage: Stage) -> None:
    """Every pair of ``stage`` meshes without backlash at its centre distance a_w.

    The working centre distance of each pair from its teeth and profile shifts (ISO 21771,
    module docstring) must equal a_w within ``CENTRE_DISTANCE_RTOL``.

    Raises:
        InvalidGearTrain: one message naming the stage, each pair's a_w from its shifts, the
            stage's a_w and the total profile shift of each pair that would mesh there.
    """
    a_w = stage.centre_distance
    alpha, beta, m = stage.pressure_angle, stage.helix_angle, stage.module
    wrong = []
    for label, g1, g2, internal in stage_pairs(stage):
        if internal and g2.teeth <= g1.teeth:
            raise InvalidGearTrain(
                f'stage "{stage.name}": the ring ({g2.teeth} teeth) must have more teeth than '
                f"a planet ({g1.teeth})"
            )
        geometry = working_pair(
            g1.teeth, g2.teeth, module=m, alpha=alpha, x1=g1.profile_shift,
            x2=g2.profile_shift, internal=internal, helix_angle=beta,
        )  # fmt: skip
        if abs(geometry.centre_distance - a_w) > CENTRE_DISTANCE_RTOL * a_w:
            wrong.append((label, g1, g2, internal, geometry.centre_distance))
    if not wrong:
        return
    parts, fixes = [], []
    for label, g1, g2, internal, a in wrong:
        sign = "−" if internal else "+"
        parts.append(
            f"the {label} pair ({g1.teeth} {sign} {g2.teeth} teeth, x {g1.profile_shift:g} + "
            f"{g2.profile_shift:g}) meshes at a_w = {a * 1e3:.3f} mm"
        )
        try:
            needed = shift_sum_for_centre_distance(
                g1.teeth, g2.teeth, module=m, pressure_angle=alpha, centre_distance=a_w,
                internal_2=internal, helix_angle=beta,
            )  # fmt: skip
        except InvalidGearTrain:
            fixes.append(f"no profile shift puts the {label} pair at {a_w * 1e3:g} mm")
        else:
            fixes.append(f"x1 + x2 = {needed:.4f} for the {label} pair")
    raise InvalidGearTrain(
        f'stage "{stage.name}" cannot mesh at its centre distance {a_w * 1e3:g} mm (m_n '
        f"{m * 1e3:g} mm, α_n {math.degrees(alpha):g}°, β {math.degrees(beta):g}°): "
        + "; ".join(parts)
        + f", more than {CENTRE_DISTANCE_RTOL:g} relative from it (ISO 21771: inv α_w = inv α + "
        "2 tan α (x1 + x2)/(z1 + z2), an internal gear's z negative). Fix the profile shifts ("
        + "; ".join(fixes)
        + ") or the centre distance"
    )


@dataclass
class _Shaft:
    """A shaft being laid out: its axis (x, y) [m], gears' and bearings' world z [m]."""

    name: str
    axis: tuple[float, float]
    gear_z: list[float] = field(default_factory=list)
    rows: list[BearingRow] = field(default_factory=list)  # positions in world z
    carries_carrier: bool = False

    def joint_z(self) -> float:
        """The joint's z: the bearings' stiffness centre, else the first gear's plane."""
        return equivalent_bearing(self.rows).centre if self.rows else self.gear_z[0]


def stages_urdf(
    stages: Sequence[Stage],
    *,
    name: str = "gearbox",
    end_bodies: Sequence[EndBody] = (),
    source: str = "pinwind.model.builders.stages_urdf",
) -> str:
    """URDF text of the gearbox of ``stages`` joined by their shafts (module docstring).

    Args:
        stages: the stages, input side first.
        name: robot name.
        end_bodies: rotor, generator, ... coupled to shafts by torsional springs.
        source: what the file's header comment names as its generator.

    Raises:
        InvalidGearTrain: no stage, a bad tooth count, module or width, a stage whose gears
            cannot mesh at its centre distance (``check_stage_meshes``), a planetary stage
            with no or two fixed members, a bearing on a fixed member or an unknown member, an
            end body on an unknown shaft.
        PlanetsCollide: neighbouring planets overlap.
    """
    if not stages:
        raise InvalidGearTrain("a gearbox needs at least one stage")
    names = [s.name for s in stages]
    if len(set(names)) != len(names):
        raise InvalidGearTrain(f"stage names must be unique; got {names}")
    for stage in stages:
        _check_stage(stage)
    shafts: dict[str, _Shaft] = {}
    planes = _stage_planes(stages)
    for stage, z in zip(stages, planes, strict=True):
        _lay_out(stage, z, shafts)
    train = Train(name, source)
    train.link("housing")
    for shaft in shafts.values():
        x, y = shaft.axis
        train.joints.append(
            TrainJoint(shaft.name, "continuous", "housing", shaft.name, (x, y, shaft.joint_z()))
        )
        train.link(shaft.name)
    for stage, z in zip(stages, planes, strict=True):
        if isinstance(stage, PlanetaryStage):
            _add_planetary(train, stage, z, shafts)
        else:
            _add_parallel(train, stage, z, shafts)
    for shaft in shafts.values():
        if shaft.rows:
            z0 = shaft.joint_z()
            rows = [_moved(r, r.position - z0) for r in shaft.rows]
            train.bearings.append(TrainBearing(shaft.name, rows))
    for body in end_bodies:
        _add_end_body(train, body, shafts)
    return train.render()


def _check_stage(stage: Stage) -> None:
    """Arguments of one stage, then its meshing at a_w."""
    where = f'stage "{stage.name}"'
    positive(f"{where} module", stage.module, "m")
    positive(f"{where} face_width", stage.face_width, "m")
    positive(f"{where} centre_distance", stage.centre_distance, "m")
    if not 0.0 < stage.pressure_angle < math.pi / 4:
        raise InvalidGearTrain(
            f"{where}: pressure angle {math.degrees(stage.pressure_angle):g}° must lie in (0, 45°)"
        )
    if not abs(stage.helix_angle) < math.pi / 4:
        raise InvalidGearTrain(
            f"{where}: helix angle {math.degrees(stage.helix_angle):g}°; give |β| < 45°"
        )
    if isinstance(stage, PlanetaryStage):
        members, gears = PLANETARY_MEMBERS, {"sun": stage.sun, "planet": stage.planet}
        gears["ring"] = stage.ring
        teeth_count(f"{where} planets", stage.planets)
        fixed = [m for m in members if stage.shafts.get(m) == FIXED]
        if len(fixed) != 1:
            raise InvalidGearTrain(
                f"{where}: give exactly one of sun, carrier, ring as fixed (to the housing); "
                f"got {', '.join(fixed) or 'none'}"
            )
    else:
        members, gears = PARALLEL_MEMBERS, {"wheel": stage.wheel, "pinion": stage.pinion}
        fixed = [m for m in members if stage.shafts.get(m) == FIXED]
        if fixed:
            raise InvalidGearTrain(f"{where}: a parallel stage's {fixed[0]} cannot be fixed")
    missing = [m for m in members if not stage.shafts.get(m)]
    unknown = sorted(set(stage.shafts) - set(members))
    if missing or unknown:
        raise InvalidGearTrain(
            f"{where}: give a shaft name (or fixed) for each of {', '.join(members)}"
            + (f"; unknown members {unknown}" if unknown else "")
        )
    for gear_name, gear in gears.items():
        teeth_count(f"{where} {gear_name} teeth", gear.teeth)
        if abs(gear.tip_alteration) > stage.module:
            raise InvalidGearTrain(
                f"{where}: {gear_name} tip alteration {gear.tip_alteration * 1e3:g} mm exceeds a "
                f"module ({stage.module * 1e3:g} mm); give k·m_n in mm"
            )
    bearing_members = set(members) | ({"planet"} if isinstance(stage, PlanetaryStage) else set())
    for bearing in stage.bearings:
        if bearing.member not in bearing_members:
            raise InvalidGearTrain(
                f'{where}: bearing "{bearing.row.name}" is on "{bearing.member}"; members are '
                f"{', '.join(sorted(bearing_members))}"
            )
        if stage.shafts.get(bearing.member) == FIXED:
            raise InvalidGearTrain(
                f'{where}: bearing "{bearing.row.name}" is on the fixed {bearing.member}, which '
                "turns on no bearing"
            )
    for key, props in stage.inertias.items():
        mass_properties(f"{where} {key}", props)
    check_stage_meshes(stage)


def _stage_planes(stages: Sequence[Stage]) -> list[float]:
    """The z of each stage's gear plane: z_1 = 0, then b_prev/2 + max(b)/2 + b/2 further on."""
    planes = [0.0]
    for prev, stage in zip(stages, stages[1:], strict=False):
        gap = 0.5 * max(prev.face_width, stage.face_width)
        planes.append(planes[-1] + 0.5 * prev.face_width + gap + 0.5 * stage.face_width)
    return planes


def _lay_out(stage: Stage, z: float, shafts: dict[str, _Shaft]) -> None:
    """Axes of the stage's shafts, their gear planes and bearing rows (world z)."""
    if isinstance(stage, PlanetaryStage):
        known = [shafts[s].axis for s in stage.shafts.values() if s in shafts]
        axis = known[0] if known else (0.0, 0.0)
        axes = {m: axis for m in PLANETARY_MEMBERS}
    else:
        wheel, pinion = stage.shafts["wheel"], stage.shafts["pinion"]
        if wheel in shafts:
            wx, wy = shafts[wheel].axis
        elif pinion in shafts:
            px, py = shafts[pinion].axis
            wx, wy = px, py - stage.centre_distance
        else:
            wx, wy = 0.0, 0.0
        axes = {"wheel": (wx, wy), "pinion": (wx, wy + stage.centre_distance)}
    for member, axis in axes.items():
        shaft_name = stage.shafts[member]
        if shaft_name == FIXED:
            continue
        shaft = shafts.setdefault(shaft_name, _Shaft(shaft_name, axis))
        if max(abs(shaft.axis[0] - axis[0]), abs(shaft.axis[1] - axis[1])) > 1e-9:
            raise InvalidGearTrain(
                f'stage "{stage.name}": shaft "{shaft_name}" would lie on two axes, '
                f"({shaft.axis[0]:g}, {shaft.axis[1]:g}) and ({axis[0]:g}, {axis[1]:g}) m"
            )
        shaft.gear_z.append(z)
        shaft.carries_carrier |= member == "carrier"
        for bearing in stage.bearings:
            if bearing.member == member:
                shaft.rows.append(_moved(bearing.row, z + bearing.row.position))


def _moved(row: BearingRow, position: float) -> BearingRow:
    """``row`` at another axial position [m]."""
    return BearingRow(
        row.name, row.kind, position, row.rating, row.stiffness, row.damping,
        row.load_factors, row.size,
    )  # fmt: skip


def _gear(
    train: Train,
    name: str,
    link: str,
    gear: StageGear,
    stage: Stage,
    z: float,
    helix_angle: float,
    props: MassProperties,
    *,
    internal: bool = False,
) -> None:
    train.gear(
        TrainGear(
            name, link, gear.teeth, stage.module, stage.pressure_angle, stage.face_width,
            gear.profile_shift, internal, z, helix_angle, gear.tip_alteration,
        ),
        props,
    )  # fmt: skip


def _member_link(
    train: Train, stage: Stage, member: str, z: float, shafts: dict[str, _Shaft], axis
) -> tuple[str, float]:
    """The link of a member and the member's plane z relative to that link's joint [m].

    A fixed member gets its own link ``<stage>_<member>`` welded to the housing at its plane. A
    gear on a shaft that also carries a planet carrier sits on its own hub link ``<stage>_<member>``
    welded to the shaft (docs/model_format.md: it turns with the shaft as if on its link), so
    that each link's inertia is that of its gears (the loader's plausibility check compares
    them) and the carrier's stays on the shaft.
    """
    shaft = stage.shafts[member]
    if shaft == FIXED:
        link = f"{stage.name}_{member}"
        train.joints.append(TrainJoint(link, "fixed", "housing", link, (axis[0], axis[1], z)))
        return link, 0.0
    z_rel = z - shafts[shaft].joint_z()
    if member != "carrier" and shafts[shaft].carries_carrier:
        link = f"{stage.name}_{member}"
        train.joints.append(TrainJoint(link, "fixed", shaft, link, (0.0, 0.0, z_rel)))
        return link, 0.0
    return shaft, z_rel


def _add_planetary(
    train: Train, stage: PlanetaryStage, z: float, shafts: dict[str, _Shaft]
) -> None:
    axis = next(shafts[s].axis for s in stage.shafts.values() if s in shafts)
    b, m, beta = stage.face_width, stage.module, stage.helix_angle
    a = stage.centre_distance
    check_planet_spacing(
        stage.planets, a,
        tip_radius(stage.planet.teeth, m, stage.planet.profile_shift, beta, False, 1.0,
                   stage.planet.tip_alteration),
    )  # fmt: skip
    table = stage.inertias
    sun_link, sun_z = _member_link(train, stage, "sun", z, shafts, axis)
    sun_props = table.get("sun") or steel_gear(
        stage.sun.teeth, module=m, face_width=b, helix_angle=beta
    )
    _gear(train, f"{stage.name}_sun", sun_link, stage.sun, stage, sun_z, beta, sun_props)
    ring_link, ring_z = _member_link(train, stage, "ring", z, shafts, axis)
    _gear(train, f"{stage.name}_ring", ring_link, stage.ring, stage, ring_z, -beta,
          table.get("ring") or steel_ring_gear(stage.ring.teeth, module=m, face_width=b),
          internal=True)  # fmt: skip
    carrier_link, carrier_z = _member_link(train, stage, "carrier", z, shafts, axis)
    r_planet = pitch_radius(stage.planet.teeth, m, beta)
    add_carrier(train, table.get("carrier"), a + r_planet, b, carrier_z, b, carrier_link)
    rows = [bg.row for bg in stage.bearings if bg.member == "planet"]
    centre = equivalent_bearing(rows).centre if rows else 0.0
    planet_props = table.get("planet") or steel_gear(
        stage.planet.teeth, module=m, face_width=b, helix_angle=beta
    )
    for i, (x, y) in enumerate(planet_centres(stage.planets, a), start=1):
        planet = f"{stage.name}_planet{i}"
        train.joints.append(
            TrainJoint(planet, "continuous", carrier_link, planet, (x, y, carrier_z + centre))
        )
        _gear(train, planet, planet, stage.planet, stage, -centre, -beta, planet_props)
        if rows:
            # u away from the carrier's axis: each planet's rows act radially and tangentially
            # alike (K_y radial, K_z tangential; docs/model_format.md "Bearing rows")
            radius = math.hypot(x, y)
            train.bearings.append(
                TrainBearing(
                    planet,
                    [_moved(r, r.position - centre) for r in rows],
                    (x / radius, y / radius, 0.0),
                )
            )
    for i in range(1, stage.planets + 1):
        train.meshes.append(
            (f"{stage.name}_sun_planet{i}", f"{stage.name}_sun", f"{stage.name}_planet{i}")
        )
    for i in range(1, stage.planets + 1):
        train.meshes.append(
            (f"{stage.name}_planet{i}_ring", f"{stage.name}_planet{i}", f"{stage.name}_ring")
        )


def _add_parallel(train: Train, stage: ParallelStage, z: float, shafts: dict[str, _Shaft]) -> None:
    b, m, beta = stage.face_width, stage.module, stage.helix_angle
    table = stage.inertias
    for member, gear, hand in (("wheel", stage.wheel, beta), ("pinion", stage.pinion, -beta)):
        shaft = stage.shafts[member]
        props = table.get(member) or steel_gear(
            gear.teeth, module=m, face_width=b, helix_angle=beta
        )
        _gear(train, f"{stage.name}_{member}", shaft, gear, stage, z - shafts[shaft].joint_z(),
              hand, props)  # fmt: skip
    train.meshes.append((stage.name, f"{stage.name}_wheel", f"{stage.name}_pinion"))


def _add_end_body(train: Train, body: EndBody, shafts: dict[str, _Shaft]) -> None:
    if body.shaft not in shafts:
        raise InvalidGearTrain(
            f'end body "{body.name}" is coupled to shaft "{body.shaft}"; shafts are: '
            f"{', '.join(shafts)}"
        )
    if body.name in shafts or body.name in train.links:
        raise InvalidGearTrain(f'end body "{body.name}" has the name of a shaft or body')
    props = mass_properties(f'end body "{body.name}"', body.mass_properties)
    shaft = shafts[body.shaft]
    xyz = (shaft.axis[0], shaft.axis[1], body.position)
    train.joints.append(TrainJoint(body.name, "continuous", "housing", body.name, xyz))
    link = train.link(body.name)
    link.parts.append(part_at(props))
    radius = math.sqrt(2.0 * props[2] / props[0])  # the solid disc of its mass and Izz
    link.visuals.append((0.0, radius, 0.1 * radius))
    stiffness = positive(f'end body "{body.name}" stiffness', body.stiffness, "N·m/rad")
    train.springs.append(
        TrainSpring(f"{body.name}_coupling", body.name, body.shaft, stiffness, body.damping)
    )
