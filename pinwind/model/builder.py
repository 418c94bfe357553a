"""Write pinwind model files (docs/model_format.md) for planetary and parallel gear trains.

The builders turn tooth counts, modules and face widths into URDF text with a ``<gearbox>``
extension that ``pinwind.model.gearbox.load`` accepts. Arguments are SI (module and face width
[m], pressure angle [rad]); the file carries the ``_mm`` / ``_deg`` attributes of the format.

Layout (every builder): shafts along the world z axis, root link ``housing``, gravity along −y.

Planetary stage (``planetary_urdf``), after 000_3b7c4a8fe52a6eee.txt §4.1-4.2 (Tables 2-3):

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

Parallel stages: stage k is given as (wheel teeth, pinion teeth), e.g. 83/23. A wheel turns with
the shaft that drives it, so it is not a joint of its own: gear ``stage{k}_wheel`` sits on the
driving link — ``sun`` for k = 1, ``stage{k-1}_pinion`` for k > 1 — at an axial offset
(``xyz`` of the gear element), and its mass is added to that link. The pinion is a continuous
joint and link ``stage{k}_pinion`` on the housing, parallel to the wheel at the exact centre
distance m (z_wheel + z_pinion)/2, offset along +y from the wheel (the high-speed shaft above the
low-speed one, as in wind-turbine gearboxes). Mesh ``stage{k}``: gear1 the wheel, gear2 the
pinion. (A wheel on its own link welded to the shaft by a fixed joint would not work: the loader
keeps a fixed joint that carries a gear as a locked bearing.)

Mass properties, unless ``inertias`` gives them as (mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²])
about the body's centre of mass:

- sun, planet, wheel and pinion: solid steel cylinders (7850 kg/m³) of pitch diameter × face
  width, centred on the gear;
- ring: a steel hollow cylinder from the pitch diameter to the pitch diameter + 2·3.5 module (a
  rim 3.5 modules deep: tooth depth 2.25 m plus a rim of about 1.2 m), face width long;
- carrier: a steel disc of radius centre distance + planet pitch radius and total thickness
  0.5·face width, split into two cheeks of 0.25·face width on both sides of the planets (faces
  touching the gear faces), so its centre of mass lies in the planets' mid-plane.
"""

from __future__ import annotations

import math
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from pinwind.errors import InputError, InvalidGearTrain, PinwindWarning, PlanetsCollide
from pinwind.gears.involute import pair_geometry
from pinwind.model.gearbox import CENTRE_DISTANCE_RTOL

#: Density of steel [kg/m³].
STEEL_DENSITY = 7850.0
#: Radial depth of a ring gear's rim beyond its pitch circle, in modules.
RING_RIM_MODULES = 3.5
#: Thickness of a default carrier (both cheeks together), as a fraction of the face width.
CARRIER_THICKNESS_FRACTION = 0.5
#: Gravity of the written models [m/s²] (docs/model_format.md: gravity along −y).
GRAVITY = (0.0, -9.81, 0.0)

MassProperties = tuple[float, float, float]
"""(mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²]) about the centre of mass, z the shaft axis."""


# --- mass properties ---------------------------------------------------------------------------


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


def shift_sum_for_centre_distance(
    teeth_1: int,
    teeth_2: int,
    *,
    module: float,
    pressure_angle: float,
    centre_distance: float,
    internal_2: bool = False,
) -> float:
    """Total profile shift x1 + x2 that gives a pair exactly ``centre_distance`` [m].

    Solves ``pair_geometry(...).centre_distance = centre_distance`` for x1 + x2 (ISO 21771; for
    an internal gear 2 the ISO sign convention of ``gears/involute.py``).
    """

    def excess(x_sum: float) -> float:
        geo = pair_geometry(
            teeth_1,
            teeth_2,
            module=module,
            pressure_angle=pressure_angle,
            profile_shift_1=x_sum,
            internal_2=internal_2,
        )
        return geo.centre_distance - centre_distance

    reference = module * abs(teeth_1 + (-teeth_2 if internal_2 else teeth_2)) / 2.0
    span = 2.0 * abs(centre_distance - reference) / module + 0.1
    try:
        return float(brentq(excess, -span, span, xtol=1e-14))
    except ValueError as err:
        raise InvalidGearTrain(
            f"no profile shift puts {teeth_1} and {teeth_2} teeth of module {module * 1e3:g} mm "
            f"at {centre_distance * 1e3:g} mm (reference {reference * 1e3:g} mm)"
        ) from err


# --- an in-memory model, rendered as URDF -------------------------------------------------------


@dataclass
class _Part:
    """A rigid part of a link: mass [kg], centre of mass and inertia about it, in the link."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray


def _part(props: MassProperties, z: float = 0.0) -> _Part:
    mass, ixx, izz = props
    return _Part(mass, np.array([0.0, 0.0, z]), np.diag([ixx, ixx, izz]))


def _combine(parts: Sequence[_Part]) -> _Part:
    """One rigid body from several: masses add, inertias move by the parallel-axis theorem."""
    mass = sum(p.mass for p in parts)
    com = sum((p.mass * p.com for p in parts), np.zeros(3)) / mass
    inertia = np.zeros((3, 3))
    for p in parts:
        d = p.com - com
        inertia += p.inertia + p.mass * (d @ d * np.eye(3) - np.outer(d, d))
    return _Part(mass, com, inertia)


@dataclass
class _Link:
    name: str
    parts: list[_Part] = field(default_factory=list)
    visuals: list[tuple[float, float, float]] = field(default_factory=list)  # z, radius, length


@dataclass
class _Joint:
    name: str
    kind: str
    parent: str
    child: str
    xyz: tuple[float, float, float]
    damping: float = 0.0


@dataclass
class _Gear:
    name: str
    link: str
    teeth: int
    module: float
    pressure_angle: float
    face_width: float
    profile_shift: float = 0.0
    internal: bool = False
    z: float = 0.0
    helix_angle: float = 0.0


@dataclass
class _Train:
    """Links, joints, gears, meshes and springs of a model being built."""

    name: str
    source: str
    links: dict[str, _Link] = field(default_factory=dict)
    joints: list[_Joint] = field(default_factory=list)
    gears: list[_Gear] = field(default_factory=list)
    meshes: list[tuple[str, str, str]] = field(default_factory=list)
    springs: list[tuple[str, str, str, float, float]] = field(default_factory=list)

    def link(self, name: str) -> _Link:
        return self.links.setdefault(name, _Link(name))

    def gear(self, gear: _Gear, props: MassProperties | None) -> None:
        """Add a gear, its pitch-cylinder visual and (if given) its mass to its link."""
        self.gears.append(gear)
        link = self.link(gear.link)
        radius = gear.teeth * gear.module / (2.0 * math.cos(gear.helix_angle))
        link.visuals.append((gear.z, radius, gear.face_width))
        if props is not None:
            link.parts.append(_part(props, gear.z))

    def render(self) -> str:
        """Render the model as URDF text (docs/model_format.md)."""
        robot = ET.Element("robot", name=self.name)
        robot.append(ET.Comment(f" generated by {self.source}; edit the call, not this file "))
        for link in self.links.values():
            el = ET.SubElement(robot, "link", name=link.name)
            if link.parts:
                body = _combine(link.parts)
                inertial = ET.SubElement(el, "inertial")
                ET.SubElement(inertial, "origin", xyz=_vec(body.com), rpy="0 0 0")
                ET.SubElement(inertial, "mass", value=_num(body.mass))
                i = body.inertia
                ET.SubElement(
                    inertial,
                    "inertia",
                    ixx=_num(i[0, 0]),
                    ixy=_num(i[0, 1]),
                    ixz=_num(i[0, 2]),
                    iyy=_num(i[1, 1]),
                    iyz=_num(i[1, 2]),
                    izz=_num(i[2, 2]),
                )
            for z, radius, length in link.visuals:
                visual = ET.SubElement(el, "visual")
                ET.SubElement(visual, "origin", xyz=_vec((0.0, 0.0, z)), rpy="0 0 0")
                geometry = ET.SubElement(visual, "geometry")
                ET.SubElement(geometry, "cylinder", radius=_num(radius), length=_num(length))
        for joint in self.joints:
            el = ET.SubElement(robot, "joint", name=joint.name, type=joint.kind)
            ET.SubElement(el, "parent", link=joint.parent)
            ET.SubElement(el, "child", link=joint.child)
            ET.SubElement(el, "origin", xyz=_vec(joint.xyz), rpy="0 0 0")
            if joint.kind != "fixed":
                ET.SubElement(el, "axis", xyz="0 0 1")
                if joint.damping:
                    ET.SubElement(el, "dynamics", damping=_num(joint.damping))
        box = ET.SubElement(robot, "gearbox", gravity=_vec(GRAVITY))
        for g in self.gears:
            el = ET.SubElement(
                box,
                "gear",
                name=g.name,
                link=g.link,
                teeth=str(g.teeth),
                module_mm=_num(g.module * 1e3),
                pressure_angle_deg=_num(math.degrees(g.pressure_angle)),
                face_width_mm=_num(g.face_width * 1e3),
                profile_shift=_num(g.profile_shift),
                internal="true" if g.internal else "false",
                xyz=_vec((0.0, 0.0, g.z)),
                axis="0 0 1",
            )
            if g.helix_angle:
                el.set("helix_angle_deg", _num(math.degrees(g.helix_angle)))
        for name, gear_1, gear_2 in self.meshes:
            ET.SubElement(box, "mesh", name=name, gear1=gear_1, gear2=gear_2)
        for name, joint_1, joint_2, stiffness, damping in self.springs:
            ET.SubElement(
                box,
                "torsional_spring",
                name=name,
                joint1=joint_1,
                joint2=joint_2,
                stiffness=_num(stiffness),
                damping=_num(damping),
            )
        ET.indent(robot, space="  ")
        return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def _num(value: float) -> str:
    """Format a number for the file: 12 significant digits, no ``-0``."""
    text = f"{float(value):.12g}"
    return "0" if text == "-0" else text


def _vec(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


# --- argument checks ----------------------------------------------------------------------------


def _teeth(name: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value <= 0:
        raise InvalidGearTrain(f"{name} = {value!r}; a tooth count must be a positive whole number")
    return int(value)


def _positive(name: str, value: float, unit: str) -> float:
    if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value) and value > 0):
        raise InvalidGearTrain(f"{name} = {value!r} {unit}; it must be a positive finite number")
    return float(value)


def _pressure_angle(value: float) -> float:
    value = _positive("pressure_angle", value, "rad")
    if value >= math.pi / 4:
        raise InvalidGearTrain(
            f"pressure_angle = {value:g} rad ({math.degrees(value):g}°) must lie in (0, 45°); the "
            f"builder takes radians: did you mean math.radians({value:g})?"
        )
    return value


def _mass_properties(key: str, props: Sequence[float]) -> MassProperties:
    if len(props) != 3:
        raise InvalidGearTrain(
            f'inertias["{key}"] = {props!r}; give (mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²])'
        )
    mass, ixx, izz = (float(v) for v in props)
    if not all(math.isfinite(v) and v > 0 for v in (mass, ixx, izz)):
        raise InvalidGearTrain(
            f'inertias["{key}"] = ({mass:g}, {ixx:g}, {izz:g}); mass and moments must be positive'
        )
    if izz > 2.0 * ixx:
        raise InvalidGearTrain(
            f'inertias["{key}"]: Izz = {izz:g} kg·m² exceeds Ixx + Iyy = {2 * ixx:g} kg·m² '
            "(triangle inequality); no real body has these moments"
        )
    return mass, ixx, izz


def _inertia_table(
    inertias: Mapping[str, Sequence[float]] | None, allowed: Sequence[str]
) -> dict[str, MassProperties]:
    table = dict(inertias or {})
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise InvalidGearTrain(
            f"inertias has unknown bodies {unknown}; known bodies are: {', '.join(allowed)}"
        )
    return {key: _mass_properties(key, value) for key, value in table.items()}


def _per_stage(name: str, value: float | Sequence[float] | None, default: float, n: int) -> list:
    if value is None:
        return [default] * n
    if isinstance(value, (int, float)):
        return [_positive(name, value, "m")] * n
    values = list(value)
    if len(values) != n:
        raise InvalidGearTrain(f"{name} has {len(values)} values for {n} parallel stages")
    return [_positive(f"{name}[{k}]", v, "m") for k, v in enumerate(values)]


def _check_spacing(planets: int, centre_distance: float, tip_radius: float) -> None:
    """Neighbouring planets must clear each other: 2 r_a < 2 a sin(π/N)."""
    if planets < 2:
        return
    chord = 2.0 * centre_distance * math.sin(math.pi / planets)
    if 2.0 * tip_radius >= chord:
        raise PlanetsCollide(tip_radius, chord, planets, centre_distance)


def _pair(z1: int, z2: int, *, module: float, alpha: float, x1: float, x2: float, internal=False):
    try:
        return pair_geometry(
            z1,
            z2,
            module=module,
            pressure_angle=alpha,
            profile_shift_1=x1,
            profile_shift_2=x2,
            internal_2=internal,
        )
    except ValueError as err:
        kind = "internal" if internal else "external"
        raise InvalidGearTrain(
            f"an {kind} pair of {z1} and {z2} teeth with profile shifts {x1:g} and {x2:g} has no "
            f"working geometry: {err}"
        ) from err


# --- parallel stages ----------------------------------------------------------------------------


def _add_parallel_stages(
    train: _Train,
    *,
    stages: Sequence[tuple[int, int]],
    first_link: str,
    first_link_z: float,
    previous_face_end: float,
    pressure_angle: float,
    modules: Sequence[float],
    face_widths: Sequence[float],
    inertias: Mapping[str, MassProperties],
    bores: Mapping[str, float] | None = None,
    helix_angles: Sequence[float] | None = None,
) -> None:
    """Stage k: wheel gear on the driving link, pinion joint ``stage{k}_pinion`` on the housing.

    Axial layout: the face of each stage's gears starts one half face width after the previous
    gear's face ends (``previous_face_end`` [m], world z of the last face before stage 1).
    Helical stages (``helix_angles`` [rad], default spur): the wheel has +β, the pinion −β (an
    external pair needs opposite hands, docs/model_format.md); the centre distance is then
    m_n (z_wheel + z_pinion)/(2 cos β).
    """
    bores = bores or {}
    helix_angles = list(helix_angles) if helix_angles is not None else [0.0] * len(stages)
    link, link_xyz = first_link, np.array([0.0, 0.0, first_link_z])
    face_end = previous_face_end

    def props(gear: str, teeth: int, m: float, b: float) -> MassProperties:
        return inertias.get(gear) or steel_cylinder(
            outer_radius=teeth * m / 2.0, inner_radius=bores.get(gear, 0.0) / 2.0, length=b
        )

    for k, (wheel, pinion) in enumerate(stages, start=1):
        wheel = _teeth(f"parallel stage {k} wheel teeth", wheel)
        pinion = _teeth(f"parallel stage {k} pinion teeth", pinion)
        m, b, beta = modules[k - 1], face_widths[k - 1], helix_angles[k - 1]
        z = face_end + b  # the face starts b/2 after the previous one ends
        face_end = z + 0.5 * b
        wheel_name, pinion_name = f"stage{k}_wheel", f"stage{k}_pinion"
        centre_distance = m * (wheel + pinion) / (2.0 * math.cos(beta))
        pinion_xyz = link_xyz + np.array([0.0, centre_distance, 0.0])
        pinion_xyz[2] = z
        train.joints.append(
            _Joint(pinion_name, "continuous", "housing", pinion_name, tuple(pinion_xyz))
        )
        train.gear(
            _Gear(wheel_name, link, wheel, m, pressure_angle, b, z=z - link_xyz[2],
                  helix_angle=beta),
            props(wheel_name, wheel, m / math.cos(beta), b),
        )  # fmt: skip
        train.gear(
            _Gear(pinion_name, pinion_name, pinion, m, pressure_angle, b, helix_angle=-beta),
            props(pinion_name, pinion, m / math.cos(beta), b),
        )
        train.meshes.append((f"stage{k}", wheel_name, pinion_name))
        link, link_xyz = pinion_name, pinion_xyz


def parallel_urdf(
    *,
    stages: Sequence[tuple[int, int]],
    module: float | Sequence[float],
    pressure_angle: float,
    face_width: float | Sequence[float],
    helix_angle: float | Sequence[float] = 0.0,
    name: str = "parallel",
    inertias: Mapping[str, MassProperties] | None = None,
) -> str:
    """URDF text of a parallel-axis gear train alone (no planetary stage before it).

    Joint ``input`` (continuous, on the housing at the origin) is the low-speed input shaft and
    carries ``stage1_wheel``; stage k's pinion ``stage{k}_pinion`` drives stage k + 1's wheel,
    as in the parallel stages of `planetary_urdf` (module docstring), the first wheel's face
    centred on z = 0. Default mass properties: steel cylinders of pitch diameter × face width.

    Args:
        stages: (wheel teeth, pinion teeth) per stage, input side first (000's 83/23, 103/26).
        module: normal module m_n [m], one value or one per stage.
        pressure_angle: normal pressure angle [rad].
        face_width: face width [m], one value or one per stage.
        helix_angle: helix angle β [rad] of each stage's wheel (its pinion gets −β), one value or
            one per stage; 0 for spur gears.
        name: robot name.
        inertias: ``stage{k}_wheel`` / ``stage{k}_pinion`` → (mass [kg], Ixx = Iyy, Izz [kg·m²]).

    Raises:
        InvalidGearTrain: no stage, non-positive teeth, module or width, or |β| ≥ 45°.
    """
    stages = list(stages)
    if not stages:
        raise InvalidGearTrain("parallel_urdf needs at least one stage (wheel teeth, pinion teeth)")
    allowed = [f"stage{k}_{g}" for k in range(1, len(stages) + 1) for g in ("wheel", "pinion")]
    table = _inertia_table(inertias, allowed)
    modules = _per_stage("module", module, math.nan, len(stages))
    widths = _per_stage("face_width", face_width, math.nan, len(stages))
    if isinstance(helix_angle, (int, float)):
        betas = [float(helix_angle)] * len(stages)
    else:
        betas = [float(b) for b in helix_angle]
        if len(betas) != len(stages):
            raise InvalidGearTrain(f"helix_angle has {len(betas)} values for {len(stages)} stages")
    for beta in betas:
        if not (math.isfinite(beta) and abs(beta) < math.pi / 4.0):
            raise InvalidGearTrain(
                f"helix_angle = {math.degrees(beta):g}°; give |β| < 45° (0 for spur gears)"
            )
    train = _Train(name, "pinwind.model.builder.parallel_urdf")
    train.link("housing")
    train.joints.append(_Joint("input", "continuous", "housing", "input", (0.0, 0.0, 0.0)))
    train.link("input")
    _add_parallel_stages(
        train,
        stages=stages,
        first_link="input",
        first_link_z=0.0,
        previous_face_end=-widths[0],
        pressure_angle=_pressure_angle(pressure_angle),
        modules=modules,
        face_widths=widths,
        inertias=table,
        helix_angles=betas,
    )
    return train.render()


# --- planetary stage ----------------------------------------------------------------------------


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
        parallel_module: module [m] of the parallel stages, one value or one per stage
            (default: ``module``).
        parallel_face_width: face width [m] of the parallel stages, one value or one per stage
            (default: ``face_width``).

    Raises:
        InvalidGearTrain: non-positive teeth, module or width; a ring that does not fit sun and
            planets (z_ring ≠ z_sun + 2 z_planet without profile shift, or unequal working
            centre distances with it).
        PlanetsCollide: neighbouring planets overlap.

    Warns:
        PinwindWarning: (z_sun + z_ring)/planets is not a whole number, so equally spaced
            identical planets cannot be assembled.
    """
    sun, planet, ring = _teeth("sun", sun), _teeth("planet", planet), _teeth("ring", ring)
    planets = _teeth("planets", planets)
    module = _positive("module", module, "m")
    alpha = _pressure_angle(pressure_angle)
    face_width = _positive("face_width", face_width, "m")
    if len(profile_shift) != 3:
        raise InvalidGearTrain(f"profile_shift = {profile_shift!r}; give (x_sun, x_planet, x_ring)")
    x_sun, x_planet, x_ring = (float(x) for x in profile_shift)
    stages = list(parallel)
    allowed = ["sun", "planet", "ring", "carrier", "pin"]
    allowed += [f"stage{k}_{g}" for k in range(1, len(stages) + 1) for g in ("wheel", "pinion")]
    table = _inertia_table(inertias, allowed)
    modules = _per_stage("parallel_module", parallel_module, module, len(stages))
    widths = _per_stage("parallel_face_width", parallel_face_width, face_width, len(stages))

    if ring <= planet:
        raise InvalidGearTrain(f"ring ({ring} teeth) must have more teeth than a planet ({planet})")
    if x_sun == x_planet == x_ring == 0.0 and ring != sun + 2 * planet:
        raise InvalidGearTrain(
            f"ring has {ring} teeth but sun + 2·planet = {sun} + 2·{planet} = {sun + 2 * planet}; "
            "without profile shift the planets only reach from the sun to the ring when "
            "z_ring = z_sun + 2 z_planet (000_3b7c4a8fe52a6eee.txt §4.1)"
        )
    sun_planet = _pair(sun, planet, module=module, alpha=alpha, x1=x_sun, x2=x_planet)
    planet_ring = _pair(
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
    _check_spacing(planets, a, module * (planet / 2.0 + 1.0 + x_planet))
    if (sun + ring) % planets:
        warnings.warn(
            PinwindWarning(
                f"(z_sun + z_ring)/planets = ({sun} + {ring})/{planets} = "
                f"{(sun + ring) / planets:.4g} is not a whole number: {planets} identical planets "
                "cannot be assembled equally spaced (the rigid model ignores tooth phasing)"
            ),
            stacklevel=2,
        )

    r_sun, r_planet, r_ring = (z * module / 2.0 for z in (sun, planet, ring))
    train = _Train(name, "pinwind.model.builder.planetary_urdf")
    train.link("housing")
    _add_carrier(train, table.get("carrier"), a + r_planet, face_width, 0.0, face_width)
    train.joints.append(_Joint("carrier", "continuous", "housing", "carrier", (0.0, 0.0, 0.0)))
    train.joints.append(_Joint("sun", "continuous", "housing", "sun", (0.0, 0.0, 0.0)))
    train.gear(
        _Gear("sun", "sun", sun, module, alpha, face_width, x_sun),
        table.get("sun") or steel_cylinder(outer_radius=r_sun, length=face_width),
    )
    planet_props = table.get("planet") or steel_cylinder(outer_radius=r_planet, length=face_width)
    for i, (x, y) in enumerate(_planet_centres(planets, a), start=1):
        train.joints.append(_Joint(f"planet{i}", "continuous", "carrier", f"planet{i}", (x, y, 0)))
        train.gear(
            _Gear(f"planet{i}", f"planet{i}", planet, module, alpha, face_width, x_planet),
            planet_props,
        )
    ring_props = table.get("ring") or steel_cylinder(
        outer_radius=r_ring + RING_RIM_MODULES * module, inner_radius=r_ring, length=face_width
    )
    train.joints.append(_Joint("ring", "fixed", "housing", "ring", (0.0, 0.0, 0.0)))
    train.gear(
        _Gear("ring", "ring", ring, module, alpha, face_width, x_ring, internal=True), ring_props
    )
    if "pin" in table:
        _add_pins(train, table["pin"], _planet_centres(planets, a), r_planet, face_width)
    for i in range(1, planets + 1):
        train.meshes.append((f"sun_planet{i}", "sun", f"planet{i}"))
    for i in range(1, planets + 1):
        train.meshes.append((f"planet{i}_ring", f"planet{i}", "ring"))
    _add_parallel_stages(
        train,
        stages=stages,
        first_link="sun",
        first_link_z=0.0,
        previous_face_end=(0.5 + CARRIER_THICKNESS_FRACTION / 2.0) * face_width,
        pressure_angle=alpha,
        modules=modules,
        face_widths=widths,
        inertias=table,
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


def _planet_centres(planets: int, centre_distance: float) -> list[tuple[float, float]]:
    angles = [2.0 * math.pi * i / planets for i in range(planets)]
    return [(centre_distance * math.cos(t), centre_distance * math.sin(t)) for t in angles]


def _add_carrier(
    train: _Train,
    props: MassProperties | None,
    radius: float,
    gap: float,
    z_mid: float,
    face_width: float,
) -> None:
    """Carrier link: given mass properties at ``z_mid``, or two steel cheeks around the planets.

    The cheeks (thickness ``CARRIER_THICKNESS_FRACTION/2 · face_width`` each, radius ``radius``)
    sit face to face with the planets, whose faces span ``z_mid ± gap/2``.
    """
    link = train.link("carrier")
    t = CARRIER_THICKNESS_FRACTION / 2.0 * face_width
    cheeks = [z_mid - gap / 2.0 - t / 2.0, z_mid + gap / 2.0 + t / 2.0]
    for z in cheeks:
        link.visuals.append((z, radius, t))
    if props is not None:
        link.parts.append(_part(props, z_mid))
    else:
        for z in cheeks:
            link.parts.append(_part(steel_cylinder(outer_radius=radius, length=t), z))


def _add_pins(
    train: _Train,
    props: MassProperties,
    centres: Sequence[tuple[float, float]],
    planet_radius: float,
    face_width: float,
) -> None:
    """Planet pins welded to the carrier at the planet centres (000_3b7c4a8fe52a6eee.txt T. 3).

    The visual is a cylinder through both carrier cheeks, of the radius whose solid cylinder has
    the pin's Izz (r = √(2 Izz/m)), capped at half the planet pitch radius.
    """
    mass, _, izz = props
    radius = min(math.sqrt(2.0 * izz / mass), 0.5 * planet_radius)
    length = (1.0 + CARRIER_THICKNESS_FRACTION) * face_width
    for i, (x, y) in enumerate(centres, start=1):
        link = train.link(f"pin{i}")
        link.parts.append(_part(props))
        link.visuals.append((0.0, radius, length))
        train.joints.append(_Joint(f"pin{i}", "fixed", "carrier", f"pin{i}", (x, y, 0.0)))


# --- compound planetary stage -------------------------------------------------------------------


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

    Each planet link carries two gears on one shaft (001_2d0e0f624d8db633.txt Table 1): planet
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
    sun, ring = _teeth("sun", sun), _teeth("ring", ring)
    planet_a, planet_b = _teeth("planet_a", planet_a), _teeth("planet_b", planet_b)
    planets = _teeth("planets", planets)
    m_r, m_s = _positive("ring_module", ring_module, "m"), _positive("sun_module", sun_module, "m")
    alpha = _pressure_angle(pressure_angle)
    b_r = _positive("ring_face_width", ring_face_width, "m")
    b_s = _positive("sun_face_width", sun_face_width, "m")
    gap = 0.5 * max(b_r, b_s) if axial_gap is None else _positive("axial_gap", axial_gap, "m")
    shifts = dict(profile_shift or {})
    unknown = sorted(set(shifts) - {"sun", "planet_a", "planet_b", "ring"})
    if unknown:
        raise InvalidGearTrain(f"profile_shift has unknown gears {unknown}")
    x = {g: float(shifts.get(g, 0.0)) for g in ("sun", "planet_a", "planet_b", "ring")}
    stages = list(parallel)
    allowed = ["sun", "planet", "ring", "carrier"]
    allowed += [f"stage{k}_{g}" for k in range(1, len(stages) + 1) for g in ("wheel", "pinion")]
    table = _inertia_table(inertias, allowed)
    bores = dict(bores or {})
    shafts = dict(shafts or {})
    modules = _per_stage("parallel_module", parallel_module, m_s, len(stages))
    widths = _per_stage("parallel_face_width", parallel_face_width, b_s, len(stages))

    if ring <= planet_a:
        raise InvalidGearTrain(
            f"ring ({ring} teeth) must have more teeth than planet A ({planet_a})"
        )
    ring_pair = _pair(
        planet_a, ring, module=m_r, alpha=alpha, x1=x["planet_a"], x2=x["ring"], internal=True
    )
    sun_pair = _pair(sun, planet_b, module=m_s, alpha=alpha, x1=x["sun"], x2=x["planet_b"])
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
    _check_spacing(
        planets,
        a,
        max(m_r * (planet_a / 2.0 + 1.0 + x["planet_a"]), m_s * (planet_b / 2 + 1 + x["planet_b"])),
    )

    z_b = 0.5 * b_r + gap + 0.5 * b_s
    r_a, r_b = planet_a * m_r / 2.0, planet_b * m_s / 2.0
    r_sun, r_ring = sun * m_s / 2.0, ring * m_r / 2.0
    train = _Train(name, "pinwind.model.builder.compound_planetary_urdf")
    train.link("housing")
    span = z_b + 0.5 * (b_r + b_s)  # from the outer face of planet A to that of planet B
    z_mid = 0.5 * (z_b + 0.5 * b_s - 0.5 * b_r)
    _add_carrier(train, table.get("carrier"), a + max(r_a, r_b), span, z_mid, max(b_r, b_s))
    train.joints.append(_Joint("carrier", "continuous", "housing", "carrier", (0.0, 0.0, 0.0)))
    train.joints.append(_Joint("sun", "continuous", "housing", "sun", (0.0, 0.0, 0.0)))
    train.gear(
        _Gear("sun", "sun", sun, m_s, alpha, b_s, x["sun"], z=z_b),
        table.get("sun")
        or steel_cylinder(outer_radius=r_sun, inner_radius=bores.get("sun", 0.0) / 2, length=b_s),
    )
    for i, (cx, cy) in enumerate(_planet_centres(planets, a), start=1):
        link = f"planet{i}"
        train.joints.append(_Joint(link, "continuous", "carrier", link, (cx, cy, 0.0)))
        whole = table.get("planet")
        props_a = props_b = None
        if whole is None:
            props_a = steel_cylinder(
                outer_radius=r_a, inner_radius=bores.get("planet_a", 0.0) / 2, length=b_r
            )
            props_b = steel_cylinder(
                outer_radius=r_b, inner_radius=bores.get("planet_b", 0.0) / 2, length=b_s
            )
        else:
            train.link(link).parts.append(_part(whole, z_b / 2))
        train.gear(_Gear(f"{link}_a", link, planet_a, m_r, alpha, b_r, x["planet_a"]), props_a)
        train.gear(
            _Gear(f"{link}_b", link, planet_b, m_s, alpha, b_s, x["planet_b"], z=z_b), props_b
        )
    ring_props = table.get("ring") or steel_cylinder(
        outer_radius=r_ring + RING_RIM_MODULES * m_r, inner_radius=r_ring, length=b_r
    )
    train.joints.append(_Joint("ring", "fixed", "housing", "ring", (0.0, 0.0, 0.0)))
    train.gear(_Gear("ring", "ring", ring, m_r, alpha, b_r, x["ring"], internal=True), ring_props)
    for i in range(1, planets + 1):
        train.meshes.append((f"sun_planet{i}", "sun", f"planet{i}_b"))
    for i in range(1, planets + 1):
        train.meshes.append((f"planet{i}_ring", f"planet{i}_a", "ring"))
    _add_parallel_stages(
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


def write_compound_planetary(path: str | Path, **kwargs) -> Path:
    """Write ``compound_planetary_urdf(**kwargs)`` to ``path``; return the path."""
    path = Path(path)
    path.write_text(compound_planetary_urdf(**kwargs), encoding="utf-8")
    return path


def _add_shafts(
    train: _Train, shafts: Mapping[str, tuple[float, float, float]], planets: int
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
            train.links[name].parts.append(_part(props, z))
            train.links[name].visuals.append((z, outer_d / 2, length))


# --- a spur pair on split shafts ----------------------------------------------------------------


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

    After 002_bb0c67d52fe8a188.txt §3.4-3.5 (Cai's rig): the two halves of each shaft are joined
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
    z1, z2 = _teeth("teeth[0]", teeth[0]), _teeth("teeth[1]", teeth[1])
    module = _positive("module", module, "m")
    alpha = _pressure_angle(pressure_angle)
    b1, b2 = (_positive(f"face_width[{i}]", b, "m") for i, b in enumerate(face_width))
    if not (math.isfinite(shaft_stiffness) and shaft_stiffness >= 0):
        raise InvalidGearTrain(f"shaft_stiffness = {shaft_stiffness!r} N·m/rad; must be ≥ 0")
    shaft = _mass_properties("half_shaft", half_shaft)
    gear_props = [_mass_properties(f"gear{i}", p) for i, p in enumerate(gear_inertias, start=1)]
    mass, _, izz = shaft
    radius = math.sqrt(2.0 * izz / mass)
    length = mass / (STEEL_DENSITY * math.pi * radius**2)
    a = module * (z1 + z2) / 2.0

    train = _Train(name, "pinwind.model.builder.split_shaft_pair_urdf")
    train.link("housing")
    layout = (
        ("input_shaft", (0.0, 0.0, -length), -length / 2.0),
        ("gear1", (0.0, 0.0, 0.0), -length / 2.0),
        ("gear2", (a, 0.0, 0.0), length / 2.0),
        ("output_shaft", (a, 0.0, length), length / 2.0),
    )
    for joint, xyz, shaft_z in layout:
        train.joints.append(_Joint(joint, "continuous", "housing", joint, xyz))
        link = train.link(joint)
        link.parts.append(_part(shaft, shaft_z))
        link.visuals.append((shaft_z, radius, length))
    for i, (z, b) in enumerate(((z1, b1), (z2, b2)), start=1):
        train.gear(_Gear(f"gear{i}", f"gear{i}", z, module, alpha, b), gear_props[i - 1])
    train.meshes.append(("gear_pair", "gear1", "gear2"))
    train.springs.append(("input_spring", "input_shaft", "gear1", shaft_stiffness, shaft_damping))
    train.springs.append(("output_spring", "gear2", "output_shaft", shaft_stiffness, shaft_damping))
    return train.render()
