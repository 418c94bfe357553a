"""Read a pinwind model file: a URDF with a ``<gearbox>`` extension (docs/model_format.md).

This module only reads and checks the file text; ``model/gearbox.py`` builds the Pinocchio model
and the mesh geometry from what it returns. Attribute units are converted to SI here (the file
edge), so ``module_mm="15"`` becomes ``module=0.015``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from typing import cast

import numpy as np
import pinocchio as pin

from pinwind.errors import (
    InputError,
    InvalidBearingCompliance,
    InvalidBearingRating,
    InvalidGearGeometry,
    InvalidInertia,
    InvalidMount,
    InvalidSupport,
    MalformedModel,
    UnknownAttribute,
    UnknownName,
)
from pinwind.gears.flank_modification import UNMODIFIED, FlankModification
from pinwind.gears.involute import half_tooth_angle
from pinwind.known_names import unknown_name
from pinwind.losses.oil import Lubricant
from pinwind.model.bearing import BEARING_TYPES, BearingRating, bearing_rating
from pinwind.model.bearing_compliance import RADIAL_LAWS, BearingCompliance
from pinwind.model.bearing_friction_data import (
    FRICTION_ATTRIBUTES,
    BearingFrictionData,
    friction_data,
)
from pinwind.model.bearing_life_data import LIFE_ATTRIBUTES, BearingLifeData, life_data
from pinwind.model.bearing_rows import BearingRow, row_springs
from pinwind.model.compliance import AUTO_SLICES, DEFAULT_DAMPING_RATIO, MeshCompliance
from pinwind.model.roller_sum import CONTACT_EXPONENTS
from pinwind.model.support import DIRECTIONS, MOUNT_AXES, Support, TowerMode

#: Largest magnitude of any number in a model file. No quantity of a gearbox model in SI units
#: comes near it (bearing stiffnesses reach 1e11 N/m, masses 1e6 kg, inertias 1e9 kg·m²); a
#: value beyond it is a typing slip, and its products in a run's step overflow (1e300 kg gave
#: "diverged at step 0" naming nothing, 1e300 m a numpy LinAlgError).
LARGEST_NUMBER = 1e20
#: Largest distance of a joint or centre of mass from its parent link's frame [m]: a
#: drivetrain is metres across (a rotor hub 150 m up the tower is inside it).
LARGEST_OFFSET = 1000.0


@dataclass(frozen=True)
class GearSpec:
    """One gear of the model file, in SI units."""

    name: str
    link: str
    teeth: int
    module: float
    pressure_angle: float
    face_width: float
    profile_shift: float
    helix_angle: float
    internal: bool
    centre_in_link: np.ndarray
    axis_in_link: np.ndarray | None
    #: Angle of tooth 0 from the link's reference direction about the axis [rad]
    #: (``model/phasing.py``: where its flank facing the positive turn crosses the pitch circle).
    tooth_phase: float = 0.0
    #: The file gives ``tooth_phase_deg``; otherwise the phase follows from the mating gears.
    tooth_phase_given: bool = False
    #: Position error of the gear centre (tangential, radial) [m] (dynamics/compliant.py).
    position_error: tuple[float, float] = (0.0, 0.0)
    #: Tip alteration k·m_n [m], negative for a shortened tip (ISO 21771; its tip circle and so
    #: its path of contact, contact ratio and ISO mesh stiffness: `gears.involute.tip_radius`).
    tip_alteration: float = 0.0
    #: Micro-geometry of its flanks: profile relief, lead crowning, end relief
    #: (`pinwind.gears.flank_modification`).
    modification: FlankModification = UNMODIFIED

    def half_tooth_angle(self, radius: float) -> float:
        """Half the tooth thickness at ``radius`` [m] as an angle about the axis [rad].

        ``gears/involute.half_tooth_angle`` of this gear.
        """
        return half_tooth_angle(
            self.teeth, module=self.module, pressure_angle=self.pressure_angle, radius=radius,
            profile_shift=self.profile_shift, helix_angle=self.helix_angle, internal=self.internal,
        )  # fmt: skip


@dataclass(frozen=True)
class MeshSpec:
    """One gear mesh of the model file: gear1 is A, gear2 is B; compliance None is rigid."""

    name: str
    gear_a: str
    gear_b: str
    compliance: MeshCompliance | None = None


@dataclass(frozen=True)
class SpringSpec:
    """A torsional spring-damper between two coaxial joints (Kelso 2011 "RSDA").

    ``joint_2`` None: the spring acts across ``joint_1`` alone, between its body and the body
    it turns in (a ``<torsional_spring>`` to the ground, or a ``<bearing>``'s torsional
    stiffness).
    """

    name: str
    joint_1: str
    joint_2: str | None
    stiffness: float
    damping: float
    preload_angle: float


@dataclass(frozen=True)
class VisualSpec:
    """One shape of a link's ``<visual>``: its pose in the link frame and its size [m].

    ``kind`` is ``cylinder`` (size = radius, length; axis z), ``box`` (x, y, z) or ``sphere``
    (radius); ``rotation`` is the link-from-visual rotation of the origin's roll-pitch-yaw.
    """

    link: str
    kind: str
    size: tuple[float, ...]
    xyz: np.ndarray
    rotation: np.ndarray


@dataclass
class ModelFile:
    """Everything read from a model file, before Pinocchio sees it."""

    path: str
    text: str
    robot_name: str
    links: dict[str, dict] = field(default_factory=dict)
    joints: dict[str, dict] = field(default_factory=dict)
    gears: dict[str, GearSpec] = field(default_factory=dict)
    meshes: list[MeshSpec] = field(default_factory=list)
    springs: list[SpringSpec] = field(default_factory=list)
    #: Joint name → its rolling bearing's ISO 281 data (``<bearing>``; the others are not rated).
    bearings: dict[str, BearingRating] = field(default_factory=dict)
    #: Joint name → how its bearing lets the body move (``<bearing radial_stiffness=...>`` or
    #: ``floating="true"``); the others are ideal (revolute joints).
    compliant_bearings: dict[str, BearingCompliance] = field(default_factory=dict)
    #: Joint name → the rolling bearings (``<row>``) its ``<bearing>`` stands for, each with its
    #: own position, type, rating and stiffness (``model/bearing_rows.py``); kept for the
    #: analyses, the step sees the ``<bearing>``'s equivalent compliance only.
    bearing_rows: dict[str, list[BearingRow]] = field(default_factory=dict)
    #: Joint name → its ``<bearing>``'s lubrication, cleanliness and inside, for the modified
    #: and reference lives (``model/bearing_life_data.py``; defaults where it gives none).
    bearing_life: dict[str, BearingLifeData] = field(default_factory=dict)
    #: Joint name → its ``<bearing>``'s friction model and, per ``<row>`` in the order of
    #: ``bearing_rows``, each row's (``model/bearing_friction_data.py``).
    bearing_friction: dict[str, BearingFrictionData] = field(default_factory=dict)
    row_friction: dict[str, list[BearingFrictionData]] = field(default_factory=dict)
    visuals: list[VisualSpec] = field(default_factory=list)
    gravity: np.ndarray | None = None
    root_link: str = ""
    #: The housing's mounts and tower modes (``<support>``); None: the housing is the ground.
    support: Support | None = None


def _describe(el: ET.Element) -> str:
    name = el.get("name")
    return f'<{el.tag} name="{name}">' if name is not None else f"<{el.tag}>"


def _number(
    path: str, el: ET.Element, attr: str, default: float | None = None, where: str | None = None
) -> float:
    """A finite number attribute; ``where`` names the owning element (a link, for its mass)."""
    where = where or _describe(el)
    at = f"<{el.tag}> " if where != _describe(el) else ""
    raw = el.get(attr)
    if raw is None:
        if default is None:
            raise MalformedModel(path, where, f'{at}missing attribute "{attr}"')
        return default
    try:
        value = float(raw)
    except ValueError as err:
        raise MalformedModel(path, where, f'{at}attribute {attr}="{raw}" is not a number') from err
    if not math.isfinite(value):
        raise MalformedModel(
            path, where, f'{at}attribute {attr}="{raw}" is not finite; give a finite number'
        )
    return value


def _vector(
    path: str, el: ET.Element | None, attr: str, default: str, where: str | None = None
) -> np.ndarray:
    """Three finite numbers; ``where`` names the owning element (a joint, for its origin)."""
    raw = default if el is None else el.get(attr, default)
    if not where:
        if el is None:
            raise TypeError("_vector: give where for an optional element")  # a caller's bug
        where = _describe(el)
    at = f"<{el.tag}> " if el is not None and where != _describe(el) else ""
    try:
        vec = np.array([float(x) for x in raw.split()], dtype=float)
    except ValueError as err:
        raise MalformedModel(
            path, where, f'{at}attribute {attr}="{raw}" is not three numbers'
        ) from err
    if vec.shape != (3,) or not np.all(np.isfinite(vec)):
        raise MalformedModel(
            path, where, f'{at}attribute {attr}="{raw}" is not three finite numbers'
        )
    return vec


def _bool(path: str, el: ET.Element, attr: str) -> bool:
    raw = el.get(attr, "false").strip().lower()
    if raw not in ("true", "false", "1", "0"):
        raise MalformedModel(path, _describe(el), f'attribute {attr}="{raw}" must be true or false')
    return raw in ("true", "1")


def _required(path: str, el: ET.Element, attr: str) -> str:
    value = el.get(attr)
    if value is None or not value.strip():
        raise MalformedModel(path, _describe(el), f'missing attribute "{attr}"')
    return value.strip()


def _check_offset(path: str, xyz: np.ndarray, where: str, what: str) -> None:
    """Refuse a position farther than ``LARGEST_OFFSET`` from its parent frame [m]."""
    distance = float(np.linalg.norm(xyz))
    if distance > LARGEST_OFFSET:
        raise MalformedModel(
            path,
            where,
            f'{what} xyz="{" ".join(f"{v:g}" for v in xyz)}" is {distance:.4g} m from its parent '
            f"link's frame, more than the {LARGEST_OFFSET:g} m any part of a drivetrain is; "
            "positions are in metres (not mm)",
        )


def _check_magnitudes(path: str, root: ET.Element) -> None:
    """Refuse a number beyond ``LARGEST_NUMBER`` in any attribute of the model file.

    Each finite number of an attribute's text (``"0 0 1e300"``, ``"0.2:1e9"``) is checked; the
    text that is not numbers (names, types) and the non-finite values (refused, with their
    own messages, where they are read) are left alone. ``<limit>`` is urdfdom's, not read.
    """

    def check(el: ET.Element, within: str) -> None:
        where = _label(el, within)
        for attr, raw in el.attrib.items():
            for token in raw.replace(":", " ").replace(",", " ").split():
                try:
                    value = float(token)
                except ValueError:
                    continue
                if math.isfinite(value) and abs(value) > LARGEST_NUMBER:
                    raise MalformedModel(
                        path,
                        where,
                        f'attribute {attr}="{raw}": {token} is beyond ±{LARGEST_NUMBER:g}, larger '
                        "than any quantity of a gearbox model in SI units (stiffnesses reach "
                        "1e11 N/m, masses 1e6 kg); check the value and its unit",
                    )
        for child in el:
            if isinstance(child.tag, str) and child.tag != "limit":
                check(child, where if el.tag not in ("robot", "gearbox") else "")

    check(root, "")


def _check_inertia(path: str, link: ET.Element) -> dict:
    inertial = link.find("inertial")
    if inertial is None:
        return {"mass": None}  # refused unless it is the root (the ground), see read_model_file
    where = _describe(link)
    mass_el = inertial.find("mass")
    if mass_el is None:
        raise MalformedModel(path, where, "<inertial> has no <mass>")
    origin = inertial.find("origin")
    com = _vector(path, origin, "xyz", "0 0 0", where=where)
    _check_offset(path, com, where, "<inertial> <origin>")
    rpy = _vector(path, origin, "rpy", "0 0 0", where=where)
    mass = _number(path, mass_el, "value", where=where)
    if mass <= 0.0:
        raise InvalidInertia(path, where, f"mass is {mass} kg; a body's mass must be positive")
    inertia_el = inertial.find("inertia")
    if inertia_el is None:
        raise MalformedModel(path, where, "<inertial> has no <inertia>")
    names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    ixx, iyy, izz, ixy, ixz, iyz = (_number(path, inertia_el, n, 0.0, where=where) for n in names)
    tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    if not np.any(tensor):
        raise InvalidInertia(
            path,
            where,
            "the inertia tensor is all zero; a real body has inertia (a solid steel disc of "
            "radius r and mass m: Izz = m r²/2 about its axis) — give its moments [kg·m²]",
        )
    principal = np.linalg.eigvalsh(tensor)
    scale = max(abs(principal).max(), 1e-300)
    if principal.min() < -1e-12 * scale:
        raise InvalidInertia(
            path, where, f"inertia tensor is not positive (principal moments {principal} kg·m²)"
        )
    a, b, c = principal
    # Triangle inequality of principal moments: each is at most the sum of the other two.
    if c > a + b + 1e-9 * scale:
        raise InvalidInertia(
            path,
            where,
            f"principal moments {a:.6g}, {b:.6g}, {c:.6g} kg·m² violate the triangle inequality "
            f"({c:.6g} > {a:.6g} + {b:.6g}); no real body has them — check the values and units",
        )
    return {"mass": mass, "com": com, "rpy": rpy, "inertia": tensor}


#: The sizes of a ``<visual>`` shape: attribute → how many numbers it holds.
_SHAPE_SIZES = {"cylinder": (("radius", 1), ("length", 1)), "box": (("size", 3),),
                "sphere": (("radius", 1),)}  # fmt: skip


def _visuals(path: str, link: ET.Element, name: str) -> list[VisualSpec]:
    """The cylinders, boxes and spheres of a link's ``<visual>`` elements.

    A shape whose size is missing or not numbers is left out, as urdfdom (Pinocchio's reader)
    leaves it out with a message and loads the model; meshes are not read.
    """
    out = []
    for visual in link.findall("visual"):
        origin = visual.find("origin")
        where = _describe(link)
        xyz = _vector(path, origin, "xyz", "0 0 0", where=where)
        rpy = _vector(path, origin, "rpy", "0 0 0", where=where)
        geometry = visual.find("geometry")
        for shape in geometry if geometry is not None else []:
            if shape.tag not in _SHAPE_SIZES:
                continue
            try:
                size = tuple(
                    float(v)
                    for attr, count in _SHAPE_SIZES[shape.tag]
                    for v in _numbers(shape.get(attr), count)
                )
            except ValueError:
                continue
            out.append(VisualSpec(name, shape.tag, size, xyz, pin.rpy.rpyToMatrix(rpy)))
    return out


def _numbers(raw: str | None, count: int) -> list[float]:
    """``count`` finite numbers from an attribute's text; ValueError otherwise."""
    values = [float(v) for v in (raw or "").split()]
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise ValueError(f"{raw!r} is not {count} finite numbers")
    return values


def _not_text(path: str, err: UnicodeDecodeError) -> str:
    """What to say of a model file that is not UTF-8 text (a log given as the model, ...)."""
    with open(path, "rb") as f:
        head = f.read(5)
    if head == b"\x89MCAP":
        return (
            "this is an MCAP log, not a model: give the model file (URDF with <gearbox>); "
            "for the log use pinwind report, replay, plot or export, and pinwind run "
            "--from-log to repeat its run"
        )
    return (
        f"not a text file: byte 0x{err.object[err.start]:02x} at position {err.start} is not "
        "UTF-8; give the model file (URDF with <gearbox>)"
    )


def read_model_file(path: str, text: str | None = None) -> ModelFile:
    """Parse and check a model file; raise a ``ModelError`` naming the element at fault."""
    if text is None:
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as err:
            raise MalformedModel(path, "<file>", f"cannot read the file: {err.strerror}") from err
        except UnicodeDecodeError as err:
            raise MalformedModel(path, "<file>", _not_text(path, err)) from err
    try:
        root = ET.fromstring(text)
    except ET.ParseError as err:
        line, col = err.position
        raise MalformedModel(
            path, "<file>", f"not well-formed XML at line {line}, column {col}: {err}"
        ) from err
    if root.tag != "robot":
        raise MalformedModel(path, f"<{root.tag}>", "the root element must be <robot> (a URDF)")
    if root.get("name") is None:
        raise MalformedModel(
            path,
            "<robot>",
            'missing attribute "name" (urdfdom refuses a URDF without it); give the model\'s '
            'name, e.g. <robot name="my_gearbox">',
        )
    _check_names(path, root)
    _check_magnitudes(path, root)

    out = ModelFile(path=path, text=text, robot_name=root.get("name", "gearbox"))
    for link in root.findall("link"):
        name = _required(path, link, "name")
        if name in out.links:
            raise MalformedModel(
                path, _describe(link), f'a link named "{name}" is defined twice; names are unique'
            )
        out.links[name] = _check_inertia(path, link)
        out.visuals += _visuals(path, link, name)
    if not out.links:
        raise MalformedModel(path, "<robot>", "the model has no <link>")
    children = set()
    for joint in root.findall("joint"):
        name = _required(path, joint, "name")
        if name in out.joints:
            raise MalformedModel(
                path, _describe(joint), f'a joint named "{name}" is defined twice; names are unique'
            )
        jtype = _required(path, joint, "type")
        parent_el, child_el = joint.find("parent"), joint.find("child")
        if parent_el is None or child_el is None:
            raise MalformedModel(path, _describe(joint), "a joint needs <parent> and <child>")
        parent, child = _required(path, parent_el, "link"), _required(path, child_el, "link")
        for link_name in (parent, child):
            if link_name not in out.links:
                raise UnknownName(path, _describe(joint), "link", link_name, out.links)
        if jtype not in ("revolute", "continuous", "fixed"):
            raise MalformedModel(
                path,
                _describe(joint),
                f'joint type "{jtype}" is not supported; bearings are revolute, continuous '
                "or fixed",
            )
        where = _describe(joint)
        origin = joint.find("origin")
        _check_offset(path, _vector(path, origin, "xyz", "0 0 0", where=where), where, "<origin>")
        _vector(path, origin, "rpy", "0 0 0", where=where)
        axis_el = joint.find("axis")
        if axis_el is not None and axis_el.get("xyz") is None:
            # urdfdom reads <axis/> as a zero axis (Pinocchio's joint turns about nothing),
            # not as the x axis of a joint without <axis>.
            raise MalformedModel(
                path, where, '<axis> has no xyz; give the shaft axis, e.g. <axis xyz="0 0 1"/>'
            )
        axis = _vector(path, axis_el, "xyz", "1 0 0", where=where)
        if jtype != "fixed" and np.linalg.norm(axis) < 1e-12:
            raise MalformedModel(
                path,
                where,
                '<axis> xyz="0 0 0" has no direction; give the shaft axis, e.g. "0 0 1"',
            )
        out.joints[name] = {
            "type": jtype,
            "parent": parent,
            "child": child,
            "axis": axis,
            "damping": _damping(path, joint),
        }
        children.add(child)
    roots = [name for name in out.links if name not in children]
    if len(roots) != 1:
        raise MalformedModel(
            path, "<robot>", f"the links must form one tree with one root; roots found: {roots}"
        )
    out.root_link = roots[0]
    for name, props in out.links.items():
        if props["mass"] is None and name != out.root_link:
            raise InvalidInertia(
                path,
                f'<link name="{name}">',
                "has no <inertial>; pinwind would give it zero mass and inertia (only the root "
                f'link, "{out.root_link}", is the ground and needs none). Give its <mass> and '
                "<inertia>",
            )

    boxes = root.findall("gearbox")
    if len(boxes) > 1:
        raise MalformedModel(path, "<gearbox>", "a model has at most one <gearbox> element")
    if not boxes:
        raise MalformedModel(
            path,
            "<robot>",
            "the model has no <gearbox> element, so no gears and no meshes: every body would "
            "turn on its own. Add <gearbox> with the gears and meshes (docs/model_format.md), or "
            "an empty <gearbox/> for a model without gears",
        )
    _read_gearbox(path, boxes[0], out)
    return out


def _damping(path: str, joint: ET.Element) -> float:
    """Viscous bearing damping c [N·m·s/rad] of a joint's <dynamics>, checked ≥ 0."""
    dynamics = joint.find("dynamics")
    if dynamics is None:
        return 0.0
    where = _describe(joint)
    c = _number(path, dynamics, "damping", 0.0, where=where)
    friction = _number(path, dynamics, "friction", 0.0, where=where)
    if c < 0.0 or friction < 0.0:
        raise InvalidMount(
            path,
            where,
            f"<dynamics> damping {c:g} N·m·s/rad and friction {friction:g} N·m must be ≥ 0; "
            "negative damping feeds energy into the train and the run diverges",
        )
    return c


#: A ``<gear>``'s flank modification attributes: (file attribute, `FlankModification` field,
#: factor to SI).
_MODIFICATION_ATTRIBUTES = (
    ("tip_relief_um", "tip_relief", 1e-6),
    ("tip_relief_length_mm", "tip_relief_length", 1e-3),
    ("root_relief_um", "root_relief", 1e-6),
    ("root_relief_length_mm", "root_relief_length", 1e-3),
    ("crowning_um", "crowning", 1e-6),
    ("end_relief_um", "end_relief", 1e-6),
    ("end_relief_length_mm", "end_relief_length", 1e-3),
    ("helix_slope_deviation_um", "helix_slope_deviation", 1e-6),
)
#: The attributes of ``<gear>`` (docs/model_format.md), each read in `_read_gearbox`.
_GEAR_ATTRIBUTES = (
    "name",
    "link",
    "teeth",
    "module_mm",
    "pressure_angle_deg",
    "face_width_mm",
    "profile_shift",
    "helix_angle_deg",
    "internal",
    "xyz",
    "axis",
    "tooth_phase_deg",
    "position_error_um",
    "tip_alteration_mm",
    *(attribute for attribute, _, _ in _MODIFICATION_ATTRIBUTES),
    "relief_shape",
)
#: The attributes of every ``<mesh>``; a compliant one's are `_COMPLIANCE_ATTRIBUTES`.
_MESH_ATTRIBUTES = ("name", "gear1", "gear2", "type")
#: The attributes of ``<torsional_spring>``.
_SPRING_ATTRIBUTES = ("name", "joint1", "joint2", "stiffness", "damping", "preload_angle")


def _read_gearbox(path: str, box: ET.Element, out: ModelFile) -> None:
    if box.get("gravity") is not None:
        out.gravity = _vector(path, box, "gravity", "0 0 0")
    for el in box.findall("gear"):
        name = _required(path, el, "name")
        where = _describe(el)
        if name in out.gears:
            raise MalformedModel(path, where, f'a gear named "{name}" is defined twice')
        link = _required(path, el, "link")
        if link not in out.links:
            raise UnknownName(path, where, "link", link, out.links)
        teeth = _number(path, el, "teeth")
        if teeth <= 0 or teeth != int(teeth):
            raise InvalidGearGeometry(
                path, where, f"teeth = {teeth:g}; the tooth count must be a positive whole number"
            )
        module_mm = _number(path, el, "module_mm")
        if module_mm <= 0:
            raise InvalidGearGeometry(path, where, f"module_mm = {module_mm:g}; must be positive")
        face_mm = _number(path, el, "face_width_mm")
        if face_mm <= 0:
            raise InvalidGearGeometry(path, where, f"face_width_mm = {face_mm:g}; must be positive")
        alpha_deg = _number(path, el, "pressure_angle_deg", 20.0)
        if not 0.0 < alpha_deg < 45.0:
            raise InvalidGearGeometry(
                path, where, f"pressure_angle_deg = {alpha_deg:g}; must lie in (0, 45) degrees"
            )
        beta_deg = _number(path, el, "helix_angle_deg", 0.0)
        if not -45.0 < beta_deg < 45.0:
            raise InvalidGearGeometry(
                path, where, f"helix_angle_deg = {beta_deg:g}; must lie in (-45, 45) degrees"
            )
        axis = None
        if el.get("axis") is not None:
            axis = _vector(path, el, "axis", "0 0 1")
            if np.linalg.norm(axis) < 1e-12:
                raise InvalidGearGeometry(path, where, "axis is the zero vector")
            axis = axis / np.linalg.norm(axis)
        out.gears[name] = GearSpec(
            name=name,
            link=link,
            teeth=int(teeth),
            module=module_mm * 1e-3,
            pressure_angle=math.radians(alpha_deg),
            face_width=face_mm * 1e-3,
            profile_shift=_number(path, el, "profile_shift", 0.0),
            helix_angle=math.radians(beta_deg),
            internal=_bool(path, el, "internal"),
            centre_in_link=_vector(path, el, "xyz", "0 0 0"),
            axis_in_link=axis,
            tooth_phase=math.radians(_number(path, el, "tooth_phase_deg", 0.0)),
            tooth_phase_given=el.get("tooth_phase_deg") is not None,
            position_error=_position_error(path, el),
            tip_alteration=_tip_alteration(path, el, module_mm),
            modification=_flank_modification(path, el, face_mm * 1e-3),
        )
    names = set()
    for el in box.findall("mesh"):
        name = _required(path, el, "name")
        where = _describe(el)
        if name in names:
            raise MalformedModel(path, where, f'a mesh named "{name}" is defined twice')
        names.add(name)
        gear_a, gear_b = _required(path, el, "gear1"), _required(path, el, "gear2")
        for g in (gear_a, gear_b):
            if g not in out.gears:
                raise UnknownName(path, where, "gear", g, out.gears)
        if gear_a == gear_b:
            raise InvalidGearGeometry(path, where, f'gear "{gear_a}" cannot mesh with itself')
        a, b = out.gears[gear_a], out.gears[gear_b]
        if a.link == b.link:
            raise InvalidGearGeometry(
                path, where, f'gears "{gear_a}" and "{gear_b}" sit on the same link "{a.link}"'
            )
        if a.internal and b.internal:
            raise InvalidGearGeometry(
                path, where, f'gears "{gear_a}" and "{gear_b}" are both internal; they cannot mesh'
            )
        if not math.isclose(a.module, b.module, rel_tol=1e-9):
            raise InvalidGearGeometry(
                path,
                where,
                f'modules differ: "{gear_a}" {a.module * 1e3:g} mm, "{gear_b}" '
                f"{b.module * 1e3:g} mm; meshing gears need the same module",
            )
        if not math.isclose(a.pressure_angle, b.pressure_angle, rel_tol=1e-9):
            raise InvalidGearGeometry(
                path,
                where,
                f'pressure angles differ: "{gear_a}" {math.degrees(a.pressure_angle):g}°, '
                f'"{gear_b}" {math.degrees(b.pressure_angle):g}°',
            )
        expected_b = a.helix_angle if (a.internal or b.internal) else -a.helix_angle
        if not math.isclose(b.helix_angle, expected_b, abs_tol=1e-12):
            raise InvalidGearGeometry(
                path,
                where,
                f"helix angles {math.degrees(a.helix_angle):g}° and "
                f"{math.degrees(b.helix_angle):g}° do not mesh: an external pair needs opposite "
                "hands (β2 = −β1), an internal pair the same hand",
            )
        out.meshes.append(
            MeshSpec(name=name, gear_a=gear_a, gear_b=gear_b, compliance=_compliance(path, el))
        )
    for el in box.findall("torsional_spring"):
        out.springs.append(_torsional_spring(path, el, out))
    seen: set[str] = set()
    for el in box.findall("bearing"):
        joint = _required(path, el, "joint")
        where = f'<bearing joint="{joint}">'
        if joint not in out.joints:
            raise UnknownName(path, where, "joint", joint, out.joints)
        if joint in seen:
            raise MalformedModel(path, where, f'joint "{joint}" is rated twice; keep one <bearing>')
        seen.add(joint)
        compliance = _bearing_compliance(path, el, joint, out)
        if compliance is not None:
            out.compliant_bearings[joint] = compliance
        torsion = _bearing_torsion(path, el, joint, out)
        if torsion is not None:
            out.springs.append(torsion)
        rated = any(el.get(a) is not None for a in _BEARING_RATING)
        rating_c = None
        if rated and el.get("rating_c_kN") is not None:
            rating_c = 1e3 * _number(path, el, "rating_c_kN", where=where)
        data = life_data(el.attrib, where=where, path=path, rating=rating_c)
        out.bearing_life[joint] = data
        rows = [_bearing_row(path, row, joint, data) for row in el.findall("row")]
        row_names = [row.name for row in rows]
        twice = sorted({n for n in row_names if row_names.count(n) > 1})
        if twice:
            raise MalformedModel(
                path,
                f'{where} <row name="{twice[0]}">',
                f'the bearing has two rows named "{twice[0]}": each row is a rolling bearing of '
                "its own (its stiffness adds to the others', its loads are the series "
                f"{joint}.{twice[0]}); give each row its own name, or remove the copy",
            )
        if rows:
            out.bearing_rows[joint] = rows
        friction = friction_data(el.attrib, where=where, path=path)
        out.bearing_friction[joint] = friction
        if rows:
            out.row_friction[joint] = [
                friction_data(
                    row.attrib,
                    where=f'{where} <row name="{row.get("name")}">',
                    path=path,
                    inherited=friction,
                )
                for row in el.findall("row")
            ]
        if (
            compliance is not None
            and row_springs(compliance, rows)
            and (compliance.clearance > 0.0 or compliance.law != "linear")
        ):
            raise MalformedModel(
                path,
                where,
                f'its rows are its springs (model/bearing_rows.py), so law="'
                f'{compliance.law}" and radial_clearance_mm='
                f"{compliance.clearance * 1e3:g} cannot apply; remove them (give each <row> its "
                "own radial_clearance_mm), or remove the rows' stiffness to keep the bearing's "
                "own law",
            )
        if (compliance is None and torsion is None and not rows) or rated:
            rating = _bearing(path, el, out)
            out.bearings[rating.joint] = rating
    supports = box.findall("support")
    if len(supports) > 1:
        raise MalformedModel(path, "<support>", "a model has at most one <support> element")
    if supports:
        out.support = _support(path, supports[0], out)


def _torsional_spring(path: str, el: ET.Element, out: ModelFile) -> SpringSpec:
    """A ``<torsional_spring>``: between joint1 and joint2, or joint1 and the ground."""
    name = _required(path, el, "name")
    where = _describe(el)
    j1 = _required(path, el, "joint1")
    j2 = el.get("joint2")
    for j in (j1, j2):
        if j is not None and j not in out.joints:
            raise UnknownName(path, where, "joint", j, out.joints)
    if j2 is None:
        _check_on_ground(path, where, j1, out)
    k = _number(path, el, "stiffness")
    c = _number(path, el, "damping", 0.0)
    if k < 0 or c < 0:
        raise MalformedModel(
            path, where, f"stiffness {k:g} N·m/rad and damping {c:g} N·m·s/rad must be ≥ 0"
        )
    return SpringSpec(name, j1, j2, k, c, _number(path, el, "preload_angle", 0.0))


def _check_on_ground(path: str, where: str, joint: str, out: ModelFile) -> None:
    """Refuse a spring to the ground on a joint whose parent turns (it would act on the parent).

    The parent stands still when it is the root link or welded to it by fixed joints.
    """
    link = out.joints[joint]["parent"]
    while link != out.root_link:
        parent = next(n for n, j in out.joints.items() if j["child"] == link)
        if out.joints[parent]["type"] != "fixed":
            raise MalformedModel(
                path,
                where,
                f'without joint2 the spring holds joint "{joint}" to the ground, but its parent '
                f'link "{out.joints[joint]["parent"]}" turns on joint "{parent}"; give joint2, '
                f'or a torsional_stiffness on <bearing joint="{joint}"> for a spring across the '
                "bearing",
            )
        link = out.joints[parent]["parent"]


def _bearing_torsion(path: str, el: ET.Element, joint: str, out: ModelFile) -> SpringSpec | None:
    """A ``<bearing>``'s torsional stiffness and damping as a spring across its joint, or None.

    The spring ``<joint>_torsion`` holds the body in torsion against the body the bearing sits
    in (a ring on its torsional support, Lin & Parker 1999's k_ru), −k θ − c ω on the joint.
    """
    if all(el.get(a) is None for a in _BEARING_TORSION):
        return None
    where = f'<bearing joint="{joint}">'
    k = _number(path, el, "torsional_stiffness", where=where)
    c = _number(path, el, "torsional_damping", 0.0, where=where)
    if k < 0 or c < 0:
        raise InvalidMount(
            path,
            where,
            f"torsional_stiffness {k:g} N·m/rad and torsional_damping {c:g} N·m·s/rad must be ≥ 0",
        )
    geared = any(g.link == out.joints[joint]["child"] for g in out.gears.values())
    if out.joints[joint]["type"] == "fixed" and not geared:
        raise MalformedModel(
            path,
            where,
            "is a fixed joint that carries no gear, a weld; a bearing held in torsion is a "
            "revolute or continuous joint (or the fixed mount of a gear, a ring)",
        )
    return SpringSpec(f"{joint}_torsion", joint, None, k, c, 0.0)


def _raw_number(path: str, el: ET.Element, attr: str, where: str, default: float) -> float:
    """A number attribute as read, NaN and infinities included (the caller says what is wrong)."""
    raw = el.get(attr)
    if raw is None:
        return default
    try:
        return float(raw)
    except ValueError as err:
        raise MalformedModel(path, where, f'attribute {attr}="{raw}" is not a number') from err


#: The attributes of ``<support>``, of its ``<mount>`` (a stiffness and a damping per axis) and
#: of its ``<tower_mode>``.
_SUPPORT_ATTRIBUTES = ("housing", "shaft_axis")
_MOUNT_ATTRIBUTES = tuple(
    f"{kind}_{axis}" for kind in ("stiffness", "damping") for axis in MOUNT_AXES
)
_TOWER_MODE_ATTRIBUTES = ("direction", "frequency_hz", "mass", "damping_ratio")


def _support(path: str, el: ET.Element, out: ModelFile) -> Support:
    """A ``<support>``: the housing's mounts and the tower modes (docs/model_format.md)."""
    housing = _required(path, el, "housing")
    where = f'<support housing="{housing}">'
    if housing not in out.links:
        raise UnknownName(path, where, "link", housing, out.links)
    link = housing
    while link != out.root_link:
        joint = next(n for n, j in out.joints.items() if j["child"] == link)
        if out.joints[joint]["type"] != "fixed":
            raise InvalidMount(
                path,
                where,
                f'the housing "{housing}" turns on joint "{joint}"; the housing is the body the '
                "ring and the bearings are fixed to: the root link, or a link welded (fixed "
                "joints) to it",
            )
        link = out.joints[joint]["parent"]
    axis = _vector(path, el, "shaft_axis", "0 0 1", where=where)
    if np.linalg.norm(axis) < 1e-12:
        raise MalformedModel(path, where, 'shaft_axis="0 0 0" has no direction; e.g. "0 0 1"')
    stiffness: dict[str, float] = {}
    damping: dict[str, float] = {}
    for mount in el.findall("mount"):
        for name in MOUNT_AXES:
            if mount.get(f"stiffness_{name}") is not None:
                stiffness[name] = _raw_number(path, mount, f"stiffness_{name}", where, 0.0)
            if mount.get(f"damping_{name}") is not None:
                damping[name] = _raw_number(path, mount, f"damping_{name}", where, 0.0)
    modes: list[TowerMode] = []
    for mode in el.findall("tower_mode"):
        direction = _required(path, mode, "direction")
        if direction not in DIRECTIONS:
            raise MalformedModel(
                path,
                where,
                f'<tower_mode direction="{direction}">: the directions are {", ".join(DIRECTIONS)}',
            )
        if any(m.direction == direction for m in modes):
            raise MalformedModel(
                path,
                where,
                f'two tower modes in direction "{direction}"; pinwind takes one mode per '
                "direction (the first)",
            )
        for attr in ("frequency_hz", "mass"):
            _required(path, mode, attr)
        modes.append(
            TowerMode(
                direction=direction,
                frequency=_raw_number(path, mode, "frequency_hz", where, math.nan),
                mass=_raw_number(path, mode, "mass", where, math.nan),
                damping_ratio=_raw_number(path, mode, "damping_ratio", where, 0.0),
            )
        )
    support = Support(
        housing=housing,
        shaft_axis=axis / np.linalg.norm(axis),
        mount_stiffness=stiffness,
        mount_damping=damping,
        tower_modes=tuple(modes),
    )
    problems = support.problems()
    if problems:
        attribute, value, _ = problems[0]
        raise InvalidSupport(
            housing, attribute, value, "; ".join(p[2] for p in problems), path=path
        )
    return support


#: The attributes of every ``<bearing>``: its joint and how it moves (`_bearing_compliance`).
_BEARING_ATTRIBUTES = ("joint", "floating", "law", "contact", "radial_axis")
#: The attributes of a rated ``<bearing>``: ISO 281 type, rating and load factors (`_bearing`).
_LOAD_FACTORS = ("e", "y1", "x2", "y2")
_BEARING_RATING = ("type", "rating_c_kN", *_LOAD_FACTORS)
#: The attributes of a ``<bearing>`` held in torsion (``_bearing_torsion``).
_BEARING_TORSION = ("torsional_stiffness", "torsional_damping")
#: The attributes of a compliant ``<bearing>`` (docs/model_format.md "Compliant bearings").
_BEARING_COMPLIANCE = (
    "radial_stiffness",
    "radial_damping",
    "radial_clearance_mm",
    "axial_stiffness",
    "axial_damping",
    "tilt_stiffness",
    "tilt_damping",
    "rollers",
    "contact_stiffness",
)


def _bearing_compliance(
    path: str, el: ET.Element, joint: str, out: ModelFile
) -> BearingCompliance | None:
    """A ``<bearing>``'s compliance (or floating), None for an ideal (rigid) bearing."""
    given = [a for a in _BEARING_COMPLIANCE if el.get(a) is not None]
    floating = _bool(path, el, "floating")
    law = el.get("law")
    where = f'<bearing joint="{joint}">'
    if not given and not floating and law is None:
        if el.get("radial_axis") is not None:
            raise MalformedModel(
                path,
                where,
                "radial_axis only applies to a compliant bearing (its slides' axes); give "
                "radial_stiffness or remove it",
            )
        return None
    law = (law or "linear").strip()
    if law not in RADIAL_LAWS:
        raise MalformedModel(
            path, where, f'law="{law}" is not a bearing law; give one of {", ".join(RADIAL_LAWS)}'
        )
    contact = el.get("contact", "line").strip()
    if contact not in CONTACT_EXPONENTS:
        raise MalformedModel(
            path,
            where,
            f'contact="{contact}" is not a contact kind; give one of '
            f"{', '.join(CONTACT_EXPONENTS)} (rollers: line, balls: point)",
        )
    if out.joints[joint]["type"] == "fixed":
        raise MalformedModel(
            path,
            where,
            "is a fixed joint, a rigid mount; a compliant or floating bearing is a revolute or "
            "continuous joint",
        )
    values: dict[str, float] = {}
    for attr in given:
        raw = cast(str, el.get(attr))
        try:
            values[attr] = float(raw)
        except ValueError as err:
            raise MalformedModel(path, where, f'attribute {attr}="{raw}" is not a number') from err
    radial_axis = _radial_axis(path, el, where, out.joints[joint]["axis"])
    rollers = values.get("rollers", 0.0)
    if not (math.isfinite(rollers) and rollers == int(rollers)):
        raise MalformedModel(
            path, where, f'rollers="{el.get("rollers")}" is not a whole number of rolling elements'
        )
    compliance = BearingCompliance(
        radial_stiffness=values.get("radial_stiffness", 0.0),
        radial_damping=values.get("radial_damping", 0.0),
        clearance=values.get("radial_clearance_mm", 0.0) * 1e-3,
        axial_stiffness=values.get("axial_stiffness"),
        axial_damping=values.get("axial_damping", 0.0),
        tilt_stiffness=values.get("tilt_stiffness"),
        tilt_damping=values.get("tilt_damping", 0.0),
        floating=floating,
        law=law,
        rollers=int(rollers),
        contact_stiffness=values.get("contact_stiffness", 0.0),
        load_exponent=CONTACT_EXPONENTS[contact],
        radial_axis=radial_axis,
    )
    problems = compliance.problems()
    if problems:
        attribute, value, _ = problems[0]
        raise InvalidBearingCompliance(
            joint, attribute, value, "; ".join(p[2] for p in problems), path=path
        )
    return compliance


def _radial_axis(
    path: str, el: ET.Element, where: str, axis: np.ndarray
) -> tuple[float, float, float] | None:
    """A compliant ``<bearing>``'s ``radial_axis="x y z"``: u in the joint frame, or None.

    Its part normal to the joint's axis must not vanish (docs/model_format.md "Bearing rows").
    """
    raw = el.get("radial_axis")
    if raw is None:
        return None
    try:
        values = [float(x) for x in raw.split()]
    except ValueError:
        values = []
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    ok = len(values) == 3 and all(math.isfinite(v) for v in values)
    given = np.asarray(values if ok else [0.0, 0.0, 0.0], dtype=float)
    size = float(np.linalg.norm(given))
    if size == 0.0 or float(np.linalg.norm(given - (given @ k) * k)) <= 1e-9 * size:
        raise MalformedModel(
            path,
            where,
            f'radial_axis="{raw}" must be three finite numbers, a direction not along the '
            f"bearing axis {tuple(float(x) for x in k)}: the first radial axis u (joint frame)",
        )
    return (values[0], values[1], values[2])


def _bearing(path: str, el: ET.Element, out: ModelFile) -> BearingRating:
    """A ``<bearing>``: the ISO 281 type and rating of the rolling bearing of a joint."""
    joint = _required(path, el, "joint")
    where = f'<bearing joint="{joint}">'
    if out.joints[joint]["type"] == "fixed":
        raise InvalidBearingRating(
            joint,
            "is a fixed joint, a rigid mount that does not turn; rate the revolute or "
            "continuous joint of the rolling bearing",
            path=path,
        )
    factors = {a: _number(path, el, a, where=where) for a in _LOAD_FACTORS if el.get(a) is not None}
    rating_kn = el.get("rating_c_kN")
    return bearing_rating(
        joint,
        _required(path, el, "type").lower(),
        dynamic_load_rating=None if rating_kn is None else 1e3 * _number(
            path, el, "rating_c_kN", where=where
        ),
        path=path,
        **factors,
    )  # fmt: skip


#: The attributes of a ``<row>`` of a ``<bearing>``: one rolling bearing of the shaft.
_ROW_ATTRIBUTES = (
    "name", "type", "position_mm", "rating_c_kN", *_LOAD_FACTORS, "stiffness", "damping",
    *LIFE_ATTRIBUTES, *FRICTION_ATTRIBUTES,
)  # fmt: skip


def _bearing_row(
    path: str, el: ET.Element, joint: str, inherited: BearingLifeData | None = None
) -> BearingRow:
    """A ``<row>``: one rolling bearing of the joint's shaft (``model/bearing_rows.py``)."""
    name = _required(path, el, "name")
    where = f'<bearing joint="{joint}"> <row name="{name}">'
    kind = _required(path, el, "type").strip().lower()
    if kind not in BEARING_TYPES:
        raise MalformedModel(
            path,
            where,
            f'type="{kind}" is not a bearing type; give one of {", ".join(BEARING_TYPES)}',
        )
    numbers = {}
    for attr, count, unit in (
        ("stiffness", 5, "K_x K_y K_z [N/m] K_β K_γ [N·m/rad]"),
        ("damping", 5, "c_x c_y c_z [N·s/m] c_β c_γ [N·m·s/rad]"),
        ("size_mm", 3, "D d B [mm]"),
    ):
        raw = el.get(attr)
        if raw is None:
            continue
        try:
            values = [float(x) for x in raw.split()]
        except ValueError:
            values = []
        if len(values) != count or not all(math.isfinite(v) and v >= 0.0 for v in values):
            raise MalformedModel(path, where, f'{attr}="{raw}" must be {count} numbers ≥ 0: {unit}')
        numbers[attr] = values
    factors = [el.get(a) for a in _LOAD_FACTORS]
    load_factors = None
    if any(f is not None for f in factors):
        if not all(f is not None for f in factors):
            raise MalformedModel(path, where, "give all four ISO 281 load factors e, y1, x2, y2")
        load_factors = tuple(_number(path, el, a, where=where) for a in _LOAD_FACTORS)
    rating = el.get("rating_c_kN")
    rating_n = None if rating is None else 1e3 * _number(path, el, "rating_c_kN", where=where)
    if rating_n is not None and rating_n <= 0.0:
        raise MalformedModel(path, where, f"rating_c_kN = {rating}; must be positive")
    stiffness = numbers.get("stiffness", [0.0] * 5)
    damping = numbers.get("damping", [0.0] * 5)
    size = numbers.get("size_mm")
    life = life_data(el.attrib, where=where, path=path, inherited=inherited, rating=rating_n)
    return BearingRow(
        life=life,
        name=name,
        kind=kind,
        position=_number(path, el, "position_mm", 0.0, where=where) * 1e-3,
        rating=rating_n,
        stiffness=(stiffness[0], stiffness[1], stiffness[2], stiffness[3], stiffness[4]),
        damping=(damping[0], damping[1], damping[2], damping[3], damping[4]),
        load_factors=cast(tuple[float, float, float, float], load_factors),
        size=None if size is None else (size[0] * 1e-3, size[1] * 1e-3, size[2] * 1e-3),
    )


def _tip_alteration(path: str, el: ET.Element, module_mm: float) -> float:
    """A ``<gear>``'s ``tip_alteration_mm`` k·m_n in metres; |k| ≤ 1 (a whole addendum)."""
    k_m_mm = _number(path, el, "tip_alteration_mm", 0.0)
    if abs(k_m_mm) > module_mm:
        raise InvalidGearGeometry(
            path,
            _describe(el),
            f"tip_alteration_mm = {k_m_mm:g} is more than a module ({module_mm:g} mm) from 0: "
            "the tip alteration k·m_n shortens (k < 0) or lengthens a tip by a fraction of the "
            "addendum; give k·m_n in mm (Nejad et al. 2016 Table V: −10.861 on m_n = 45 mm)",
        )
    return k_m_mm * 1e-3


def _flank_modification(path: str, el: ET.Element, face_width: float) -> FlankModification:
    """A ``<gear>``'s micro-geometry (``tip_relief_um``, ``crowning_um``, ...) in SI."""
    given = {
        field: _number(path, el, attribute, 0.0) * factor
        for attribute, field, factor in _MODIFICATION_ATTRIBUTES
    }
    try:
        modification = FlankModification(**given, relief_shape=el.get("relief_shape", "linear"))
    except InputError as err:
        raise InvalidGearGeometry(path, _describe(el), str(err)) from err
    if 2.0 * modification.end_relief_length > face_width:
        raise InvalidGearGeometry(
            path,
            _describe(el),
            f"end_relief_length_mm = {modification.end_relief_length * 1e3:g} at each end of a "
            f"face {face_width * 1e3:g} mm wide: the two end reliefs overlap; give at most half "
            "the face width",
        )
    return modification


def _position_error(path: str, el: ET.Element) -> tuple[float, float]:
    raw = el.get("position_error_um", "0 0")
    try:
        values = [float(x) * 1e-6 for x in raw.split()]
    except ValueError:
        values = []
    if len(values) != 2 or not all(math.isfinite(v) for v in values):
        raise MalformedModel(
            path,
            _describe(el),
            f'attribute position_error_um="{raw}" must be two numbers: the tangential and radial '
            "position errors of the gear centre in µm",
        )
    return values[0], values[1]


def _compliance(path: str, el: ET.Element) -> MeshCompliance | None:
    """The ``<mesh>`` element's compliance, or None for a rigid mesh (docs/model_format.md)."""
    where = _describe(el)
    kind = el.get("type", "rigid").strip().lower()
    if kind not in ("rigid", "compliant"):
        raise MalformedModel(path, where, f'type="{kind}" must be "rigid" or "compliant"')
    if kind == "rigid":
        extra = [a for a in _COMPLIANCE_ATTRIBUTES if el.get(a) is not None]
        if extra:
            raise MalformedModel(
                path,
                where,
                f'{", ".join(extra)} only apply to a compliant mesh; add type="compliant" or '
                "remove them",
            )
        return None
    table = None
    raw = el.get("pair_stiffness")
    if raw is not None:
        try:
            pairs = [item.split(":") for item in raw.split()]
            s_mm, k = zip(*((float(a), float(b)) for a, b in pairs), strict=True)
        except ValueError as err:
            raise MalformedModel(
                path,
                where,
                f'pair_stiffness="{raw}" must be "x_mm:k x_mm:k ..." (positions along the path '
                "of contact from its start [mm], stiffness of one tooth pair [N/m])",
            ) from err
        table = (np.array(s_mm) * 1e-3, np.array(k))
    stiffness = el.get("stiffness")
    mean = el.get("mean_stiffness")
    damping = el.get("damping")
    compliance = MeshCompliance(
        stiffness=None if stiffness is None else _number(path, el, "stiffness"),
        mean_stiffness=None if mean is None else _number(path, el, "mean_stiffness"),
        variation=el.get("stiffness_variation", "path").strip().lower(),
        pair_stiffness=table,
        damping=None if damping is None else _number(path, el, "damping"),
        damping_ratio=_number(path, el, "damping_ratio", DEFAULT_DAMPING_RATIO),
        backlash=_number(path, el, "backlash_mm", 0.0) * 1e-3,
        slices=_slices(path, el, where),
        friction_coefficient=_friction_coefficient(path, el),
        oil=_mesh_oil(path, el, where),
        roughness=None
        if el.get("roughness_um") is None
        else _number(path, el, "roughness_um") * 1e-6,
        base_oil=el.get("base_oil", "mineral").strip().lower(),
    )
    problems = compliance.problems()
    if problems:
        raise MalformedModel(path, where, "; ".join(problems))
    return compliance


def _friction_coefficient(path: str, el: ET.Element) -> float | str:
    """The ``friction_coefficient`` of a compliance: a number μ, or a law's name (lower case)."""
    raw = el.get("friction_coefficient")
    if raw is None:
        return 0.0
    try:
        float(raw)
    except ValueError:
        return raw.strip().lower()
    return _number(path, el, "friction_coefficient")


def _mesh_oil(path: str, el: ET.Element, where: str) -> Lubricant | None:
    """The oil of a mesh's ``iso14179`` friction, or None when no grade is given.

    From ``lubricant_vg``, ``temperature_C`` and (optional) ``viscosity_100C_cSt``.
    """
    raw = el.get("lubricant_vg")
    if raw is None:
        return None
    try:
        grade = int(raw.strip())
    except ValueError as err:
        raise MalformedModel(
            path, where, f'lubricant_vg="{raw}" must be an ISO 3448 grade (a whole number)'
        ) from err
    if el.get("temperature_C") is None:
        raise MalformedModel(
            path, where, "lubricant_vg needs the oil's temperature: give temperature_C"
        )
    nu_100 = el.get("viscosity_100C_cSt")
    return Lubricant(
        grade,
        _number(path, el, "temperature_C") + 273.15,
        None if nu_100 is None else _number(path, el, "viscosity_100C_cSt") * 1e-6,
    )


def _slices(path: str, el: ET.Element, where: str) -> int | str:
    """The ``slices`` attribute of a compliance: a whole number or "auto", 1 when absent."""
    raw = el.get("slices")
    if raw is None:
        return 1
    if raw.strip().lower() == AUTO_SLICES:
        return AUTO_SLICES
    try:
        return int(raw.strip())
    except ValueError as err:
        raise MalformedModel(
            path,
            where,
            f'slices="{raw}" must be a whole number ≥ 1 (slices across the face) or '
            f'"{AUTO_SLICES}" (the rule\'s N for the expected misalignment)',
        ) from err


_COMPLIANCE_ATTRIBUTES = (
    "stiffness",
    "mean_stiffness",
    "stiffness_variation",
    "pair_stiffness",
    "damping",
    "damping_ratio",
    "backlash_mm",
    "slices",
    "friction_coefficient",
    "lubricant_vg",
    "temperature_C",
    "viscosity_100C_cSt",
    "roughness_um",
    "base_oil",
)


#: The elements of ``<gearbox>`` (and those they hold): tag → (attributes, child elements). An
#: attribute not named here is refused (`_check_names`): name a new one in the tuple beside
#: the code that reads it.
GEARBOX_ELEMENTS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "gearbox": (("gravity",), ("gear", "mesh", "torsional_spring", "bearing", "support")),
    "gear": (_GEAR_ATTRIBUTES, ()),
    "mesh": (_MESH_ATTRIBUTES + _COMPLIANCE_ATTRIBUTES, ()),
    "torsional_spring": (_SPRING_ATTRIBUTES, ()),
    "bearing": (
        _BEARING_ATTRIBUTES
        + _BEARING_RATING
        + _BEARING_COMPLIANCE
        + _BEARING_TORSION
        + tuple(a for a in LIFE_ATTRIBUTES if a not in _BEARING_COMPLIANCE)
        + FRICTION_ATTRIBUTES,
        ("row",),
    ),
    "row": (_ROW_ATTRIBUTES, ()),
    "support": (_SUPPORT_ATTRIBUTES, ("mount", "tower_mode")),
    "mount": (_MOUNT_ATTRIBUTES, ()),
    "tower_mode": (_TOWER_MODE_ATTRIBUTES, ()),
}
#: The attributes of the standard URDF elements whose values pinwind reads (the URDF
#: specification's; urdfdom ignores any other, so ``<dynamics dampng="5"/>`` would be no damping).
#: Their other child elements (``<visual>``, ``<limit>``, ``<gazebo>``, ...) are left to urdfdom.
_URDF_ATTRIBUTES: dict[str, tuple[str, ...]] = {
    "link": ("name",),
    "inertial": (),
    "joint": ("name", "type"),
    "origin": ("xyz", "rpy"),
    "mass": ("value",),
    "inertia": ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
    "axis": ("xyz",),
    "dynamics": ("damping", "friction"),
    "parent": ("link",),
    "child": ("link",),
}
#: The child elements the URDF specification gives a link, a joint and an inertial: any other
#: (``<originx>``, a misspelt ``<origin>``) was ignored, leaving the joint at its parent's origin.
_URDF_CHILDREN = {
    "link": ("inertial", "visual", "collision"),
    "joint": ("origin", "parent", "child", "axis", "calibration", "dynamics", "limit", "mimic",
              "safety_controller"),
    "inertial": ("origin", "mass", "inertia"),
}  # fmt: skip
#: Where those elements are: a link's inertial and its parts, a joint's parts (one of each).
_URDF_PARTS = {
    "link": ("inertial",),
    "inertial": ("origin", "mass", "inertia"),
    "joint": ("origin", "axis", "dynamics", "parent", "child"),
}


def _label(el: ET.Element, within: str = "") -> str:
    """An element as messages name it: ``<bearing joint="sun">``, after the one holding it."""
    key = next((k for k in ("name", "joint", "housing", "direction") if el.get(k) is not None), "")
    own = f'<{el.tag} {key}="{el.get(key)}">' if key else f"<{el.tag}>"
    return f"{within} {own}" if within else own


def _check_attributes(path: str, el: ET.Element, known: tuple[str, ...], where: str) -> None:
    """Refuse an attribute of ``el`` that is not one of ``known``, naming the nearest."""
    name = unknown_name(el.attrib, known)
    if name is not None:
        raise UnknownAttribute(path, where, name, known, kind="attribute", tag=el.tag)


def _check_names(path: str, root: ET.Element) -> None:
    """Refuse a misspelt element or attribute of ``<gearbox>``, or attribute of a URDF part.

    Raises:
        UnknownAttribute: naming the element, the name and the nearest known one.
    """

    def urdf(el: ET.Element, within: str) -> None:
        where = _label(el, within)
        _check_attributes(path, el, _URDF_ATTRIBUTES[el.tag], where)
        children = _URDF_CHILDREN.get(el.tag, ())
        for child in el if children else ():
            if isinstance(child.tag, str) and child.tag not in children:
                raise UnknownAttribute(path, where, child.tag, children, kind="element", tag=el.tag)
        for tag in _URDF_PARTS.get(el.tag, ()):
            parts = el.findall(tag)
            if len(parts) > 1:
                raise MalformedModel(
                    path,
                    where,
                    f"has {len(parts)} <{tag}> elements; it takes one (a URDF reader reads the "
                    "first and ignores the others): keep the one you mean",
                )
            for part in parts:
                urdf(part, where)

    def gearbox(el: ET.Element, within: str) -> None:
        attributes, children = GEARBOX_ELEMENTS[el.tag]
        where = _label(el, within)
        _check_attributes(path, el, attributes, where)
        for child in el:
            if not isinstance(child.tag, str):  # a comment or processing instruction
                continue
            if child.tag not in children:
                raise UnknownAttribute(path, where, child.tag, children, kind="element", tag=el.tag)
            gearbox(child, where if el.tag != "gearbox" else "")

    for tag in ("link", "joint"):
        for el in root.findall(tag):
            urdf(el, "")
    for box in root.findall("gearbox"):
        gearbox(box, "")
