"""The Gearbox: a Pinocchio model of the bodies and bearings plus the gears and meshes on them.

``load(path)`` reads a model file (``model/urdf.py``), hands the URDF to Pinocchio and checks the
gear geometry in the reference pose. Everything downstream (simulate, logs, replay) starts here.
"""

from __future__ import annotations

import math
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

import numpy as np
import pinocchio as pin

from pinwind.errors import (
    ImplausibleGear,
    InconsistentCentreDistance,
    InvalidGearGeometry,
    InvalidInertia,
    InvalidMount,
    InvalidSupport,
    MalformedModel,
    NonParallelAxes,
    PinwindError,
    PinwindWarning,
    UnknownElement,
)
from pinwind.gears.contact import PathOfContact
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.involute import base_helix_angle, pitch_radius, tip_radius
from pinwind.model.bearing_compliance import SLIDES, BearingCompliance
from pinwind.model.bearing_rows import BearingRow, row_name, row_springs
from pinwind.model.compliance import MeshCompliance
from pinwind.model.phasing import mesh_point, tooth_phases
from pinwind.model.support import Support, SupportSlide
from pinwind.model.urdf import GearSpec, ModelFile, SpringSpec, read_model_file

#: Relative tolerance between the centre distance in the file and the one the gear data give.
CENTRE_DISTANCE_RTOL = 1e-4
#: Largest angle between two meshing gears' axes [rad].
AXIS_PARALLEL_TOL = 1e-6
#: Pinocchio's prismatic joints (``JointModel.shortname()``): slides along an axis.
_PRISMATIC = {"JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"}
#: Density of the solid steel disc a gear's mass and inertia are compared with [kg/m³].
STEEL_DENSITY = 7850.0
#: A gear link's mass or axial inertia more than this many times that of the steel discs of its
#: gears' pitch diameters and face widths gets an ``ImplausibleGear`` warning: a shaft or a hub
#: adds a few times the disc's, a generator rotor lumped on the high-speed pinion a few hundred
#: times its inertia (a 1 t·m² class rotor on a 0.2 m pinion), a slip of units 1000 or more.
HEAVIEST_LINK = 1000.0
#: ISO 53 basic rack profile: addendum and dedendum [modules]; the tooth thickness on the
#: reference line is half the pitch.
ADDENDUM, DEDENDUM = 1.0, 1.25


def teeth_mass_inertia(spec: Any) -> tuple[float, float]:
    """Mass [kg] and least axial inertia [kg·m²] of a steel external gear's teeth alone.

    ISO 53 basic rack: the teeth fill half the ring between the root circle
    r_f = r − (1.25 − x) m_n and the tip circle r_a = r + (1 + x) m_n (their thickness is half
    the pitch on the reference circle), of the face width b; all that mass lies at r_f or
    beyond, so its inertia is at least m r_f². No gear link weighs less.
    """
    r = pitch_radius(spec.teeth, spec.module, spec.helix_angle)
    root = max(r - (DEDENDUM - spec.profile_shift) * spec.module, 0.0)
    tip = r + (ADDENDUM + spec.profile_shift) * spec.module
    mass = 0.5 * STEEL_DENSITY * math.pi * (tip**2 - root**2) * spec.face_width
    return mass, mass * root**2


@dataclass(frozen=True)
class Gear:
    """A gear attached to a Pinocchio joint.

    Attributes:
        spec: the file's data (teeth, module, ...), SI units.
        joint_id: Pinocchio joint that carries the gear.
        centre_in_joint: gear centre in that joint's frame [m].
        axis_in_joint: unit gear axis in that joint's frame.
    """

    spec: GearSpec
    joint_id: int
    centre_in_joint: np.ndarray
    axis_in_joint: np.ndarray

    @property
    def name(self) -> str:
        """The gear's name in the model file."""
        return self.spec.name


@dataclass(frozen=True)
class Mesh:
    """A gear mesh A–B and its working geometry (docs/model_format.md "Mesh sign convention").

    Attributes:
        name: mesh name from the file.
        gear_a, gear_b: the two gears (A is ``gear1``).
        working_pressure_angle: α_wt [rad].
        centre_distance: working centre distance a_w [m].
        pitch_fraction: μ with pitch point P = C_A + μ d⊥, d⊥ the centre offset B − A normal
            to the axis (negative when B is internal: P lies beyond A, away from B's centre).
        line_sign: σ, r̂ = σ d⊥/|d⊥| points from A's centre to P.
        radial_sign: ε, +1 unless A is internal: the radial force separates the gears.
        working_radius_a, working_radius_b: working pitch radii [m].
        base_radius_a, base_radius_b: base radii [m].
        helix_angle: helix angle β of gear A [rad] (signed; right hand positive).
        path: the path of contact (contact ratio, single- and double-pair zones), or None when
            the gear data give no valid one (a warning said why; a rigid mesh still runs).
        compliance: None for a rigid mesh (a constraint row), else its spring-damper.
    """

    name: str
    gear_a: Gear
    gear_b: Gear
    working_pressure_angle: float
    centre_distance: float
    pitch_fraction: float
    line_sign: float
    radial_sign: float
    working_radius_a: float
    working_radius_b: float
    base_radius_a: float
    base_radius_b: float
    helix_angle: float
    path: PathOfContact | None = None
    compliance: MeshCompliance | None = None

    @property
    def face_width(self) -> float:
        """Face width in contact, the narrower gear's [m]."""
        return min(self.gear_a.spec.face_width, self.gear_b.spec.face_width)

    @property
    def base_helix_angle(self) -> float:
        """β_b of gear A, tan β_b = tan β cos α_t [rad] (signed like ``helix_angle``)."""
        return base_helix_angle(self.gear_a.spec.pressure_angle, self.helix_angle)


@dataclass(frozen=True)
class CompliantBearing:
    """A bearing whose body translates (and tilts) in it on massless slides (``BearingCompliance``).

    Attributes:
        joint: the bearing's revolute joint (its name, series and reaction as an ideal one's).
        compliance: its stiffness, damping and clearance.
        slides: slide (``radial_x``, ...) → the name of its joint in the Pinocchio model.
        v_index: slide → its index in the velocity vector.
        axes_in_joint: (3, 3) rows u, w, k: the radial axes and the bearing axis in the
            bearing's joint frame (the frame of the displacement and elastic force series).
        rows: its rows when they are its springs (``model/bearing_rows.py`` ``row_springs``):
            each a linear spring-damper at its position (``cpp/bearing_rows.hpp``), in place of
            the compliance's stiffness and damping; empty: the compliance's laws hold it.
    """

    joint: str
    compliance: BearingCompliance
    slides: dict[str, str]
    v_index: dict[str, int]
    axes_in_joint: np.ndarray
    rows: tuple[BearingRow, ...] = ()


@dataclass(frozen=True)
class TorsionalSpring:
    """Torque −k(θ₁ − θ₂ − θ₀) − c(ω₁ − ω₂) on joint 1 and its opposite on joint 2.

    Without joint 2 (``joint_2`` None) the spring acts across joint 1 alone, −k(θ₁ − θ₀) − cω₁,
    between its body and the body it turns in: the ground for a ``<torsional_spring>`` without
    joint2, the bearing's parent for a ``<bearing>``'s torsional stiffness.
    """

    name: str
    joint_1: str
    joint_2: str | None
    v_index_1: int
    v_index_2: int | None
    stiffness: float
    damping: float
    preload_angle: float

    def twist_row(self, nv: int) -> np.ndarray:
        """Row r (nv,) of the twist r·q = θ₁ − θ₂ (θ₁ alone without joint 2) [-]."""
        row = np.zeros(nv)
        row[self.v_index_1] = 1.0
        if self.v_index_2 is not None:
            row[self.v_index_2] = -1.0
        return row


class Gearbox:
    """A gearbox model ready to simulate.

    Attributes:
        path: the model file.
        name: the URDF robot name.
        model: the ``pinocchio.Model`` (gb.model).
        gears: gear name → Gear.
        tooth_phases: gear name → angle of its tooth 0's centre line about its axis in its joint
            frame at the reference pose [rad], meshing teeth interlocked (``model/phasing.py``).
        meshes: the meshes, in file order.
        springs: torsional spring-dampers.
        compliant_bearings: joint name → its compliant or floating bearing (its slides).
        slide_joints: the slides of the compliant bearings (joints of ``joint_names``).
        joint_names: the bearings and the compliant bearings' slides, in the order of the
            velocity vector (one DoF each).
        bearing_names: the joints whose reactions are the run's bearing series: every joint
            but a compliant bearing's slides, massless links inside the bearing whose reaction is
            the bearing's own (its revolute joint's) in other axes.
        slide_links: the massless links of the compliant bearings' slides, which the run's body
            series leave out (the body is the link on the bearing's revolute joint).
        locked_joints: bearings held at zero speed (gears on fixed mounts, e.g. the ring).
        support_slides: joint name → the support's slides (``model/support.py``), from the
            ground to the housing; empty for a housing that is the ground.
        world_from_housing: the housing frame's rotation at rest, (3, 3) (the frame of the
            support slides' axes).
        gravity: gravity in world [m/s²].
        source_text: the model file as read (logged with every run).
    """

    def __init__(self, source: ModelFile):
        self._axes: dict[int, np.ndarray] = {}
        self._neutral_jacobians: Any = None  # pin.Data with every joint's Jacobian at q = 0
        self.path = source.path
        self.name = source.robot_name
        self.source_text = source.text
        self.source = source
        pin_xml, self.locked_joints, slides = _pinocchio_urdf(source)
        self.world_from_housing, support = _support_chain(source)
        if support:
            pin_xml = _add_support(source, pin_xml, support)
            # A housing welded to the ground (a ring on its fixed joint) turns into a body on
            # the support's slides, which replace its weld: nothing is left to lock.
            housing = cast(Support, source.support).housing
            if housing != source.root_link:
                weld = _parent_joint(source, housing)
                self.locked_joints = [j for j in self.locked_joints if j != weld]
        self.support_slides = {s.name: s for s in support}
        try:
            self.model = pin.buildModelFromXML(pin_xml)
        except Exception as err:  # Pinocchio raises plain RuntimeError/ValueError here
            raise MalformedModel(
                source.path, "<robot>", f"Pinocchio cannot build the model: {err}"
            ) from err
        for jid in range(1, self.model.njoints):
            if self.model.joints[jid].nv != 1:
                raise MalformedModel(source.path, "<robot>", "only 1-DoF bearings are supported")
        self.joint_names = [self.model.names[j] for j in range(1, self.model.njoints)]
        self.compliant_bearings = {
            joint: self._compliant_bearing(joint, source.compliant_bearings[joint], names)
            for joint, names in slides.items()
        }
        self.slide_joints = [n for b in self.compliant_bearings.values() for n in b.slides.values()]
        #: The rows that are their bearings' springs, ``<joint>.<row>``, in the order of the
        #: row series' columns (``model/bearing_rows.py``, ``cpp/bearing_rows.hpp``).
        self.row_names = [
            row_name(joint, row.name)
            for joint, bearing in self.compliant_bearings.items()
            for row in bearing.rows
        ]
        bearing_slides = set(self.slide_joints)
        self.bearing_names = [n for n in self.joint_names if n not in bearing_slides]
        self.slide_links = {slide_link(n) for n in bearing_slides}
        self.slide_joints += list(self.support_slides)
        self._check_axial_inertia()
        self.gears = {name: self._attach(spec) for name, spec in source.gears.items()}
        #: (link, note) of implausible gear links (``ImplausibleGear``), issued as warnings by
        #: ``load``/``loads``.
        self.warnings = self._implausible_gears()
        self.gravity = (
            source.gravity.copy() if source.gravity is not None else self._default_gravity()
        )
        self.model.gravity = pin.Motion(self.gravity, np.zeros(3))
        self.meshes = [self._mesh(m.name, m.gear_a, m.gear_b, m.compliance) for m in source.meshes]
        self._check_gears_apart()
        self.springs = [self._spring(s) for s in source.springs]
        #: Gear name → angle of tooth 0's centre line about the gear axis in its joint frame at
        #: the reference pose [rad], meshing teeth interlocked (``model/phasing.py``).
        self.tooth_phases = self._tooth_phases()

    # --- lookups ---------------------------------------------------------------------------------

    @property
    def sha256(self) -> str:
        """SHA-256 of the model file text."""
        import hashlib  # here: OpenSSL's load is a cost ``pinwind modes`` has no use for

        return hashlib.sha256(self.source_text.encode("utf-8")).hexdigest()

    @property
    def joint_kinds(self) -> list[str]:
        """Each joint's kind, in ``joint_names`` order, as Pinocchio built it.

        ``prismatic`` (a slide along its axis) or ``revolute`` (about it): ``series.JointKind``.
        """
        return [
            "prismatic" if self.model.joints[j].shortname() in _PRISMATIC else "revolute"
            for j in range(1, self.model.njoints)
        ]

    def v_index(self, joint: str) -> int:
        """Index of a bearing in the velocity vector."""
        return self.model.joints[self.model.getJointId(joint)].idx_v

    def body_frames(self) -> list[int]:
        """Ids of the link frames whose world poses a run records: its bodies.

        Every link but the massless links of the compliant bearings' slides (``slide_links``):
        the body in a bearing is the link on its revolute joint, and its pose holds the slides'
        motion.
        """
        model = self.model
        return [
            f
            for f in range(model.nframes)
            if model.frames[f].type == pin.FrameType.BODY
            and model.frames[f].name not in self.slide_links
        ]

    def joint_axis(self, joint: str) -> np.ndarray:
        """Unit axis of a bearing (joint) in its joint frame [-]."""
        return self._joint_axis(self.model.getJointId(joint))

    def mesh(self, name: str) -> Mesh:
        """The mesh of that name.

        Raises:
            UnknownElement: no mesh has that name; the message lists the meshes.
        """
        for m in self.meshes:
            if m.name == name:
                return m
        raise UnknownElement("mesh", name, [m.name for m in self.meshes])

    def neutral(self) -> np.ndarray:
        """Reference configuration q (all bearing angles zero)."""
        return pin.neutral(self.model)

    def __repr__(self) -> str:
        return (
            f"Gearbox({self.name!r}, {len(self.joint_names)} bearings, {len(self.gears)} gears, "
            f"{len(self.meshes)} meshes, from {self.path})"
        )

    # --- construction ----------------------------------------------------------------------------

    def _compliant_bearing(
        self, joint: str, compliance: BearingCompliance, slides: dict[str, str]
    ) -> CompliantBearing:
        k = self._joint_axis(self.model.getJointId(joint))
        u, w = (self._joint_axis(self.model.getJointId(slides[s])) for s in SLIDES[:2])
        return CompliantBearing(
            joint=joint,
            compliance=compliance,
            slides=slides,
            v_index={s: self.v_index(name) for s, name in slides.items()},
            axes_in_joint=np.array([u, w, k]),
            rows=tuple(row_springs(compliance, self.source.bearing_rows.get(joint, []))),
        )

    def _default_gravity(self) -> np.ndarray:
        """9.81 m/s² perpendicular to the shafts: along −y unless the shafts lie along y."""
        data = self.model.createData()
        pin.forwardKinematics(self.model, data, pin.neutral(self.model))
        axes = [data.oMi[g.joint_id].rotation @ g.axis_in_joint for g in self.gears.values()]
        return 9.81 * _default_down(axes[0] if axes else np.array([0.0, 0.0, 1.0]))

    def _attach(self, spec: GearSpec) -> Gear:
        where = f'<gear name="{spec.name}">'
        if spec.link == self.source.root_link:
            raise InvalidGearGeometry(
                self.path,
                where,
                f'the gear sits on the root link "{spec.link}" (the ground); put it on its own '
                "link with a fixed joint to the ground so that its mount reaction is reported",
            )
        frame = self.model.frames[self.model.getFrameId(spec.link, pin.BODY)]
        joint_id = frame.parentJoint
        joint_from_link = frame.placement
        centre = joint_from_link.act(spec.centre_in_link)
        if self.model.joints[joint_id].shortname() in _PRISMATIC:
            # A gear on a housing that slides on its support's mounts (a ring on a <support>
            # without roll): it turns with no joint of its own, about its own axis.
            own = spec.axis_in_link if spec.axis_in_link is not None else np.array([0, 0, 1.0])
            axis = joint_from_link.rotation @ own
            return Gear(spec=spec, joint_id=joint_id, centre_in_joint=centre, axis_in_joint=axis)
        joint_axis = self._joint_axis(joint_id)
        if spec.axis_in_link is None:
            axis = joint_axis
        else:
            axis = joint_from_link.rotation @ spec.axis_in_link
        if np.linalg.norm(np.cross(axis, joint_axis)) > AXIS_PARALLEL_TOL:
            raise NonParallelAxes(
                self.path,
                where,
                f"gear axis {np.round(axis, 6)} is not parallel to the axis "
                f'{np.round(joint_axis, 6)} of its bearing "{self.model.names[joint_id]}"',
            )
        off_axis = centre - (centre @ joint_axis) * joint_axis
        bearing_child = self._links_on(joint_id)[0] if joint_id else self.source.root_link
        if np.linalg.norm(off_axis) > 1e-9 and spec.link != bearing_child:
            raise InvalidMount(
                self.path,
                where,
                f'the gear\'s link "{spec.link}" is welded (fixed joints) to link '
                f'"{bearing_child}", which turns on bearing "{self.model.names[joint_id]}"; the '
                f"gear centre is {np.linalg.norm(off_axis) * 1e3:.4f} mm off that bearing's axis, "
                "so the gear would orbit with the body instead of turning about its own centre. "
                f'Mount "{spec.link}" on its own bearing (a revolute or continuous joint)',
            )
        if np.linalg.norm(off_axis) > 1e-9:
            raise InvalidGearGeometry(
                self.path,
                where,
                f"gear centre is {np.linalg.norm(off_axis) * 1e3:.4f} mm off the axis of its "
                f'bearing "{self.model.names[joint_id]}"; a gear turns about its own centre',
            )
        axis = np.sign(axis @ joint_axis) * joint_axis
        return Gear(spec=spec, joint_id=joint_id, centre_in_joint=centre, axis_in_joint=axis)

    def _check_gears_apart(self) -> None:
        """Refuse two external gears that do not mesh but whose tip circles overlap.

        At the reference pose, two gears on parallel axes whose faces share a plane (axial
        distance below half the sum of their face widths) and whose centres are closer than the
        sum of their tip radii (``gears.involute.tip_radius``) would cut through each other: a
        planet moved onto its neighbour's place (a sign slip in a coordinate) ran without a
        word. Meshing pairs are closer by design; gears on one body, and internal gears (which
        hold the others inside), are left out.
        """
        data = self.model.createData()
        pin.forwardKinematics(self.model, data, pin.neutral(self.model))
        meshing = {frozenset((m.gear_a, m.gear_b)) for m in self.source.meshes}
        placed = []
        for name, gear in self.gears.items():
            if gear.spec.internal:
                continue
            s = gear.spec
            tip = tip_radius(s.teeth, s.module, s.profile_shift, s.helix_angle, False, ADDENDUM,
                             s.tip_alteration)  # fmt: skip
            pose = data.oMi[gear.joint_id]
            placed.append((name, gear, pose.act(gear.centre_in_joint),
                           pose.rotation @ gear.axis_in_joint, tip))  # fmt: skip
        for i, (name_a, a, centre_a, axis, tip_a) in enumerate(placed):
            for name_b, b, centre_b, axis_b, tip_b in placed[i + 1 :]:
                if a.joint_id == b.joint_id or frozenset((name_a, name_b)) in meshing:
                    continue
                if np.linalg.norm(np.cross(axis, axis_b)) > AXIS_PARALLEL_TOL:
                    continue
                d = centre_b - centre_a
                along = float(d @ axis)
                apart = float(np.linalg.norm(d - along * axis))
                if abs(along) < 0.5 * (a.spec.face_width + b.spec.face_width) and apart < (
                    tip_a + tip_b
                ):
                    raise InvalidGearGeometry(
                        self.path,
                        f'<gear name="{name_a}">',
                        f"its tip circle (radius {tip_a * 1e3:.2f} mm) and that of gear "
                        f'"{name_b}" ({tip_b * 1e3:.2f} mm) overlap: their centres are '
                        f"{apart * 1e3:.2f} mm apart in one plane ({abs(along) * 1e3:.2f} mm "
                        f"along the axis), less than the {(tip_a + tip_b) * 1e3:.2f} mm of "
                        "their tip radii, and they do not mesh, so they would cut through each "
                        "other; check the positions of their joints (<origin xyz>)",
                    )

    def _check_carried_axes(
        self,
        where: str,
        first: tuple[str, Gear],
        second: tuple[str, Gear],
        axis: np.ndarray,
        data: Any,
    ) -> None:
        """Refuse a bearing that carries one gear of a mesh, not the other, about another axis.

        A carrier turning about an axis that is not the gears' (a joint left without
        ``<axis>``: URDF's default is x) swings its planet's axis out of parallel with the sun's
        as it turns, so the mesh geometry breaks. The bearings the two gears share move both
        alike; the slides of compliant bearings and supports tilt by their own small angles.

        Args:
            where: the ``<mesh>`` as messages name it.
            first, second: (name, Gear) of the two gears.
            axis: the gears' axis in world at the reference pose.
            data: Pinocchio data after forward kinematics at the reference pose.
        """

        def bearings(joint_id: int) -> list[int]:
            chain = []
            while joint_id:
                chain.append(joint_id)
                joint_id = self.model.parents[joint_id]
            return chain

        slides = set(self.slide_joints)
        chains = [bearings(first[1].joint_id), bearings(second[1].joint_id)]
        for (name, _), (other, _), chain, rest in (
            (first, second, chains[0], chains[1]),
            (second, first, chains[1], chains[0]),
        ):
            for jid in chain:
                joint = self.model.names[jid]
                if jid in rest or joint in slides:
                    continue
                if not self.model.joints[jid].shortname().startswith("JointModelR"):
                    continue
                k = data.oMi[jid].rotation @ self._joint_axis(jid)
                angle = _angle_between(k, axis)
                if angle > AXIS_PARALLEL_TOL:
                    raise NonParallelAxes(
                        self.path,
                        where,
                        f'bearing "{joint}" carries gear "{name}" (not "{other}") about the axis '
                        f"{np.round(k, 6)}, {math.degrees(angle):.4g}° from the gears' axis "
                        f"{np.round(axis, 6)}: as it turns, the gears' axes would tilt apart. "
                        f'Give <joint name="{joint}"> an <axis xyz="..."/> parallel to the '
                        'gears\' (without <axis> a URDF joint turns about x, "1 0 0")',
                    )

    def _links_on(self, joint_id: int) -> list[str]:
        return [
            f.name
            for f in self.model.frames
            if f.type == pin.FrameType.BODY and f.parentJoint == joint_id
        ]

    def _check_axial_inertia(self) -> None:
        """Refuse a bearing whose body (its links welded together) has no inertia about its axis."""
        slides = set(self.slide_joints)
        for jid in range(1, self.model.njoints):
            if self.model.names[jid] in slides:
                continue  # massless: the body is on the bearing's revolute joint after them
            inertia = self.model.inertias[jid]
            k = self._joint_axis(jid)
            c = np.asarray(inertia.lever)
            about_origin = inertia.inertia + inertia.mass * ((c @ c) * np.eye(3) - np.outer(c, c))
            axial = float(k @ about_origin @ k)
            scale = float(np.abs(np.linalg.eigvalsh(inertia.inertia)).max())
            if axial <= 1e-12 * scale:
                links = ", ".join(f'"{n}"' for n in self._links_on(jid))
                raise InvalidInertia(
                    self.path,
                    f'<link name="{self._links_on(jid)[0]}">',
                    f'the body on bearing "{self.model.names[jid]}" (links {links}) has no '
                    f"inertia about the bearing axis {np.round(k, 6)} ({axial:.3g} kg·m²): "
                    "it would spin up infinitely fast. Give the moment of inertia about the "
                    "shaft axis (a solid disc: m r²/2)",
                )

    def _implausible_gears(self) -> list[tuple[str, str]]:
        """(link, note) of gear links whose mass or axial inertia no real gear link has.

        Below the teeth alone (``teeth_mass_inertia``: no gear weighs less than its teeth) or
        above ``HEAVIEST_LINK`` times the solid steel discs of its gears (more than a shaft, a
        hub or a lumped generator rotor add: a unit slip, g for kg or kg·cm² for kg·m²). A
        ring's rim is not a disc: links with internal gears are left out.
        """
        notes = []
        by_link: dict[str, list[Gear]] = {}
        for gear in self.gears.values():
            by_link.setdefault(gear.spec.link, []).append(gear)
        for link, gears in by_link.items():
            data = self.source.links[link]
            if any(g.spec.internal for g in gears) or data.get("mass") is None:
                continue  # a ring's rim is not a disc
            frame = self.model.frames[self.model.getFrameId(link, pin.BODY)]
            rotation = pin.rpy.rpyToMatrix(*data["rpy"])
            tensor = rotation @ data["inertia"] @ rotation.T  # about the COM, link axes
            axis = frame.placement.rotation.T @ gears[0].axis_in_joint  # link axes
            mass, axial = data["mass"], float(axis @ tensor @ axis)
            disc_mass = disc_inertia = teeth_mass = teeth_inertia = 0.0
            sizes = []
            for g in gears:
                r = pitch_radius(g.spec.teeth, g.spec.module, g.spec.helix_angle)
                m = STEEL_DENSITY * math.pi * r**2 * g.spec.face_width
                disc_mass += m
                disc_inertia += 0.5 * m * r**2
                tm, ti = teeth_mass_inertia(g.spec)
                teeth_mass += tm
                teeth_inertia += ti
                sizes.append(f'"{g.name}" {2 * r * 1e3:.4g} mm × {g.spec.face_width * 1e3:.4g} mm')
            discs = f"solid steel disc{'s' if len(gears) > 1 else ''} ({', '.join(sizes)})"
            for what, value, disc, teeth, unit in (
                ("mass", mass, disc_mass, teeth_mass, "kg"),
                ("axial inertia", axial, disc_inertia, teeth_inertia, "kg·m²"),
            ):
                where = f'{self.path}: <link name="{link}">: {what} {value:.4g} {unit} is '
                if value < teeth:
                    notes.append((link, where + (
                        f"less than its gears' teeth alone give, {teeth:.4g} {unit} (ISO 53 "
                        "basic rack: half the ring from the root to the tip circle, at the root "
                        f"circle or beyond); the {discs} its gears imply has {disc:.4g} {unit} "
                        f"(the value is {value / disc:.3g} times that). Give the {what} of "
                        "the whole gear and what turns with it on this link"
                    )))  # fmt: skip
                elif value > HEAVIEST_LINK * disc:
                    notes.append((link, where + (
                        f"{value / disc:.4g} times that of the {discs} its gears imply, "
                        f"{disc:.4g} {unit}: more than {HEAVIEST_LINK:g} times, more than a "
                        "shaft, a hub or a lumped generator rotor add. Check its units (g for "
                        "kg, kg·cm² or g·mm² for kg·m²)"
                    )))  # fmt: skip
        return notes

    def _joint_axis(self, joint_id: int) -> np.ndarray:
        # The joint's type fixes its axis: found once (the bearing loads ask every block of a run).
        if joint_id not in self._axes:
            if self._neutral_jacobians is None:  # once for every joint: the model has ~80
                self._neutral_jacobians = self.model.createData()
                q = pin.neutral(self.model)
                pin.computeJointJacobians(self.model, self._neutral_jacobians, q)
            data = self._neutral_jacobians
            # Pinocchio hands a one-column matrix to numpy as a vector: keep it (6, nv).
            jac = np.reshape(pin.getJointJacobian(self.model, data, joint_id, pin.LOCAL), (6, -1))
            col = jac[:, self.model.joints[joint_id].idx_v]
            if np.linalg.norm(col[3:]) == 0.0:  # a compliant bearing's slide: its direction
                self._axes[joint_id] = col[:3] / np.linalg.norm(col[:3])
            else:
                self._axes[joint_id] = col[3:] / np.linalg.norm(col[3:])
        return self._axes[joint_id].copy()

    def _mesh(
        self, name: str, gear_a: str, gear_b: str, compliance: MeshCompliance | None = None
    ) -> Mesh:
        where = f'<mesh name="{name}">'
        a, b = self.gears[gear_a], self.gears[gear_b]
        fixed = [g for g in (a, b) if self.model.names[g.joint_id] in self.locked_joints]
        if len(fixed) == 2:
            raise InvalidMount(
                self.path,
                where,
                f'gears "{gear_a}" and "{gear_b}" are both on fixed mounts (welded to the ground): '
                "the mesh could carry any force and pinwind could not tell which. Mount one of "
                "them on a bearing (a revolute or continuous joint)",
            )
        if a.joint_id == b.joint_id:
            body = self.model.names[a.joint_id] if a.joint_id else self.source.root_link
            raise InvalidMount(
                self.path,
                where,
                f'gears "{gear_a}" (link "{a.spec.link}") and "{gear_b}" (link "{b.spec.link}") '
                f'are on one rigid body (the links are welded together on bearing "{body}"): '
                "they cannot turn against each other, so the mesh would carry no force. Mount "
                "one of them on its own bearing (a revolute or continuous joint)",
            )
        data = self.model.createData()
        pin.forwardKinematics(self.model, data, pin.neutral(self.model))
        centre_a = data.oMi[a.joint_id].act(a.centre_in_joint)
        centre_b = data.oMi[b.joint_id].act(b.centre_in_joint)
        axis_a = data.oMi[a.joint_id].rotation @ a.axis_in_joint
        axis_b = data.oMi[b.joint_id].rotation @ b.axis_in_joint
        angle = _angle_between(axis_a, axis_b)
        if angle > AXIS_PARALLEL_TOL:
            raise NonParallelAxes(
                self.path,
                where,
                f'axes of "{gear_a}" {np.round(axis_a, 6)} and "{gear_b}" {np.round(axis_b, 6)} '
                f"are {math.degrees(angle):.4g}° apart; pinwind meshes parallel-axis gears only",
            )
        self._check_carried_axes(where, (gear_a, a), (gear_b, b), axis_a, data)
        d = centre_b - centre_a
        d_perp = d - (d @ axis_a) * axis_a
        actual = float(np.linalg.norm(d_perp))
        sa, sb = a.spec, b.spec
        pair = GearPair.from_gears(sa, sb)
        try:
            geo = pair.geometry
        except ValueError as err:
            raise InvalidGearGeometry(
                self.path,
                where,
                f'gears "{gear_a}" ({sa.teeth} teeth, profile shift {sa.profile_shift:g}) and '
                f'"{gear_b}" ({sb.teeth} teeth, profile shift {sb.profile_shift:g}) cannot mesh: '
                f"{err}",
            ) from err
        tol = CENTRE_DISTANCE_RTOL * geo.centre_distance
        if abs(actual - geo.centre_distance) > tol:
            kind = "internal" if (sa.internal or sb.internal) else "external"
            raise InconsistentCentreDistance(
                self.path,
                where,
                actual,
                geo.centre_distance,
                tol,
                f"an {kind} pair of {sa.teeth} and {sb.teeth} teeth, module "
                f"{sa.module * 1e3:g} mm, profile shifts {sa.profile_shift:g} and "
                f"{sb.profile_shift:g}; move the bearings or correct the gear data",
            )
        if sb.internal:
            pitch_fraction = -sa.teeth / (sb.teeth - sa.teeth)
            line_sign = -1.0
        elif sa.internal:
            pitch_fraction = sa.teeth / (sa.teeth - sb.teeth)
            line_sign = 1.0
        else:
            pitch_fraction = sa.teeth / (sa.teeth + sb.teeth)
            line_sign = 1.0
        # The teeth work at the centre distance of the bearings, not the nominal one: rigid
        # involutes on the same base circles roll at cos α′ = (r_b,B ± r_b,A) / a′.
        base_sum = geo.centre_distance * math.cos(geo.working_pressure_angle)
        working_angle = math.acos(min(1.0, base_sum / actual))
        signed_sum = abs(
            (-sb.teeth if sb.internal else sb.teeth) + (-sa.teeth if sa.internal else sa.teeth)
        )
        path = self._path(where, pair, compliance is not None)
        return Mesh(
            name=name,
            gear_a=a,
            gear_b=b,
            working_pressure_angle=working_angle,
            centre_distance=actual,
            pitch_fraction=pitch_fraction,
            line_sign=line_sign,
            radial_sign=-1.0 if sa.internal else 1.0,
            working_radius_a=actual * sa.teeth / signed_sum,
            working_radius_b=actual * sb.teeth / signed_sum,
            base_radius_a=geo.base_radius_1,
            base_radius_b=geo.base_radius_2,
            helix_angle=sa.helix_angle,
            path=path,
            compliance=compliance,
        )

    def _path(self, where: str, pair: GearPair, compliant: bool) -> PathOfContact | None:
        """The pair's path of contact; for a rigid mesh a failure only warns (outputs NaN)."""
        try:
            return pair.path_of_contact()
        except PinwindError as err:
            if compliant:
                raise InvalidGearGeometry(self.path, where, str(err)) from err
            warnings.warn(
                f"{self.path}: {where}: {err}; the mesh runs rigid, without contact position "
                "or single-tooth force",
                PinwindWarning,
                stacklevel=3,
            )
            return None

    def _tooth_phases(self) -> dict[str, float]:
        """Tooth phase of every gear at the reference pose [rad] (``phasing.tooth_phases``)."""
        data = self.model.createData()
        pin.forwardKinematics(self.model, data, self.neutral())
        points = []
        for m in self.meshes:
            a, b = m.gear_a, m.gear_b
            pose_a, pose_b = data.oMi[a.joint_id], data.oMi[b.joint_id]
            points.append(
                mesh_point(
                    a.name,
                    b.name,
                    centre_a=pose_a.act(a.centre_in_joint),
                    centre_b=pose_b.act(b.centre_in_joint),
                    world_from_a=pose_a.rotation,
                    world_from_b=pose_b.rotation,
                    axis_a=a.axis_in_joint,
                    axis_b=b.axis_in_joint,
                    pitch_fraction=m.pitch_fraction,
                )
            )
        radii = {n: r for n in self.gears if (r := _flank_radius(self.meshes, n)) is not None}
        return tooth_phases(points, {n: g.spec for n, g in self.gears.items()}, radii)

    def _spring(self, spec: SpringSpec) -> TorsionalSpring:
        where = f'<torsional_spring name="{spec.name}">'
        if spec.joint_2 is None and spec.name == f"{spec.joint_1}_torsion":
            where = f'<bearing joint="{spec.joint_1}">'
        ids = []
        for j in (spec.joint_1, spec.joint_2):
            if j is None:
                continue
            if not self.model.existJointName(j) or j in self.support_slides:
                raise MalformedModel(self.path, where, f'joint "{j}" is fixed; it cannot twist')
            ids.append(self.model.getJointId(j))
        data = self.model.createData()
        pin.forwardKinematics(self.model, data, pin.neutral(self.model))
        axes = [data.oMi[j].rotation @ self._joint_axis(j) for j in ids]
        if len(axes) == 2 and np.linalg.norm(np.cross(axes[0], axes[1])) > AXIS_PARALLEL_TOL:
            raise NonParallelAxes(
                self.path, where, f"joint axes {axes[0]} and {axes[1]} are not parallel"
            )
        return TorsionalSpring(
            name=spec.name,
            joint_1=spec.joint_1,
            joint_2=spec.joint_2,
            v_index_1=self.model.joints[ids[0]].idx_v,
            v_index_2=self.model.joints[ids[1]].idx_v if len(ids) == 2 else None,
            stiffness=spec.stiffness,
            damping=spec.damping,
            preload_angle=spec.preload_angle,
        )


def _angle_between(axis: np.ndarray, other: np.ndarray) -> float:
    """The angle [rad] between two unit axes' lines, 0 to π/2: asin |axis × other|."""
    return math.asin(min(1.0, float(np.linalg.norm(np.cross(axis, other)))))


def _default_down(shaft: np.ndarray) -> np.ndarray:
    """The default direction of gravity for a shaft axis (world), unit.

    −y made normal to the shaft, or −z when the shaft lies along y.
    """
    down = np.array([0.0, -1.0, 0.0])
    if abs(shaft @ down) > 0.9:
        down = np.array([0.0, 0.0, -1.0])
    down = down - (down @ shaft) * shaft
    return down / np.linalg.norm(down)


def _support_chain(source: ModelFile) -> tuple[np.ndarray, list[SupportSlide]]:
    """The housing's rotation at rest (world from housing) and the support's slides.

    The tower's vertical is against the file's gravity, or against the default gravity of the
    support's shaft axis, expressed in the housing's frame.
    """
    root = ET.fromstring(source.text)
    world_from_housing = np.eye(3)
    if source.support is None:
        return world_from_housing, []
    link = source.support.housing
    while link != source.root_link:  # read_model_file checked: fixed joints up to the root
        name = _parent_joint(source, link)
        origin = root.find(f"joint[@name='{name}']/origin")
        rpy = origin.get("rpy", "0 0 0") if origin is not None else "0 0 0"
        world_from_housing = pin.rpy.rpyToMatrix(*map(float, rpy.split())) @ world_from_housing
        link = source.joints[name]["parent"]
    gravity = source.gravity
    if gravity is None or np.linalg.norm(gravity) == 0.0:
        down = _default_down(world_from_housing @ source.support.shaft_axis)
    else:
        down = gravity / np.linalg.norm(gravity)
    up = -(world_from_housing.T @ down)
    _check_tower_vertical(source, up)
    return world_from_housing, source.support.slides(up)


def _check_tower_vertical(source: ModelFile, up: np.ndarray) -> None:
    """Refuse a vertical or side-side tower mode on a support whose shaft axis is along gravity.

    Those directions are normal to the shaft axis (the vertical is ``up`` made normal to it):
    a shaft along gravity leaves them undefined (NaN axes, which urdfdom refused with noise).

    Raises:
        InvalidSupport: naming the shaft axis, the gravity and the modes.
    """
    support = cast(Support, source.support)
    modes = [m.direction for m in support.tower_modes if m.direction != "fore_aft"]
    across = up - (up @ support.shaft_axis) * support.shaft_axis
    if not modes or np.linalg.norm(across) > 1e-6:
        return
    angle = math.degrees(math.acos(min(1.0, abs(float(up @ support.shaft_axis)))))
    axis = " ".join(f"{v:g}" for v in support.shaft_axis)
    raise InvalidSupport(
        support.housing,
        "shaft_axis",
        angle,
        f'shaft_axis="{axis}" is along gravity ({angle:.2g}° from it), but the tower modes '
        f"{', '.join(modes)} act normal to the shaft axis (the vertical is gravity's part "
        "normal to it), which a shaft along gravity leaves undefined; give the main shaft's "
        "axis (a wind turbine's is within a few degrees of horizontal), or a gravity across it",
        path=source.path,
    )


def _parent_joint(source: ModelFile, link: str) -> str:
    """The joint whose child is ``link`` (not the root link)."""
    return next(n for n, j in source.joints.items() if j["child"] == link)


def _add_support(source: ModelFile, text: str, slides: list[SupportSlide]) -> str:
    """Put the support's slides between the housing and its parent (or a new ground link).

    The first slide takes the origin of the housing's fixed joint (which it replaces), the others
    sit at the one before, and a fixed joint ``support_housing`` welds the housing to the last
    one: at rest the housing is where the file puts it. A tower slide's link carries its share of
    the modal masses (a point mass at the slide's origin).

    Raises:
        MalformedModel: a slide's name is taken by a joint or link of the file.
    """
    support = cast(Support, source.support)
    root = ET.fromstring(text)
    names = [s.name for s in slides] + [f"{s.name}_link" for s in slides] + ["support_housing"]
    if support.housing == source.root_link:
        names.append("support_ground")
    for taken in names:
        if taken in source.joints or taken in source.links:
            raise MalformedModel(
                source.path,
                f'<support housing="{support.housing}">',
                f'the support needs the name "{taken}", which the file already uses; rename that '
                "element",
            )
    if support.housing == source.root_link:
        ET.SubElement(root, "link", name="support_ground")
        parent, origin = "support_ground", None
    else:
        name = _parent_joint(source, support.housing)
        fixed = cast(ET.Element, root.find(f"joint[@name='{name}']"))
        parent, origin = source.joints[name]["parent"], fixed.find("origin")
        root.remove(fixed)
    for slide in slides:
        child = f"{slide.name}_link"
        el = ET.SubElement(root, "joint", name=slide.name, type=slide.kind)
        if origin is not None:
            el.append(origin)
            origin = None
        ET.SubElement(el, "parent", link=parent)
        ET.SubElement(el, "child", link=child)
        ET.SubElement(el, "axis", xyz=" ".join(repr(float(x)) for x in slide.axis))
        ET.SubElement(el, "limit", lower="-1e30", upper="1e30", effort="0", velocity="0")
        ET.SubElement(el, "dynamics", damping=repr(slide.damping))
        link = ET.SubElement(root, "link", name=child)
        if slide.mass > 0.0:
            inertial = ET.SubElement(link, "inertial")
            ET.SubElement(inertial, "mass", value=repr(slide.mass))
            ET.SubElement(inertial, "inertia", ixx="0", iyy="0", izz="0", ixy="0", ixz="0", iyz="0")
        parent = child
    weld = ET.SubElement(root, "joint", name="support_housing", type="fixed")
    ET.SubElement(weld, "parent", link=parent)
    ET.SubElement(weld, "child", link=support.housing)
    return ET.tostring(root, encoding="unicode")


def _flank_radius(meshes: list[Mesh], name: str) -> float | None:
    """Working pitch radius of a gear's first mesh, in file order, where it is A, else B [m]."""
    for which in ("a", "b"):
        for m in meshes:
            if getattr(m, f"gear_{which}").name == name:
                return getattr(m, f"working_radius_{which}")
    return None


def _pinocchio_urdf(source: ModelFile) -> tuple[str, list[str], dict[str, dict[str, str]]]:
    """The URDF text Pinocchio builds from, the joints to lock and the compliant bearings' slides.

    Continuous joints become revolute (one angle coordinate, unwrapped, instead of cos/sin), and a
    fixed joint whose child carries a gear and whose parent stands still (the ground, or a body
    welded to it) becomes a revolute joint about the gear axis that the simulation locks, so the
    mount reaction of a ring gear is a bearing reaction like any other. A gear on a link welded to
    a moving body (a gear shrunk onto a shaft link) keeps its weld: it turns with that body, as if
    it were on that body's link. A compliant or floating bearing gets its slides before its
    revolute joint (``_add_slides``).
    """
    root = ET.fromstring(source.text)
    geared_links = {g.link: g for g in source.gears.values()}
    moving = _moving_links(source)
    # A gear's fixed mount held in torsion by a spring of its own (a ring on a torsional
    # support) turns on that spring instead of being locked.
    sprung = {s.joint_1 for s in source.springs if s.joint_2 is None}
    locked: list[str] = []
    for joint in root.findall("joint"):
        # read_model_file checked every joint's name, type, parent and child in this text.
        name = cast(str, joint.get("name"))
        jtype = joint.get("type")
        child, parent = source.joints[name]["child"], source.joints[name]["parent"]
        if jtype == "fixed" and child in geared_links and parent not in moving:
            gear = geared_links[child]
            axis = gear.axis_in_link if gear.axis_in_link is not None else np.array([0, 0, 1.0])
            joint.set("type", "revolute")
            for old in joint.findall("axis"):
                joint.remove(old)
            ET.SubElement(joint, "axis", xyz=" ".join(repr(float(x)) for x in axis))
            if name not in sprung:
                locked.append(name)
            jtype = "revolute"
        if jtype in ("revolute", "continuous"):
            joint.set("type", "revolute")
            for old in joint.findall("limit"):
                joint.remove(old)
            ET.SubElement(joint, "limit", lower="-1e30", upper="1e30", effort="0", velocity="0")
    slides = {
        name: _add_slides(source, root, name, compliance)
        for name, compliance in source.compliant_bearings.items()
    }
    for box in root.findall("gearbox"):
        root.remove(box)
    return ET.tostring(root, encoding="unicode"), locked, slides


def slide_link(slide: str) -> str:
    """The name of the massless link a compliant bearing's slide ``slide`` moves."""
    return f"{slide}_link"


def _add_slides(
    source: ModelFile, root: ET.Element, name: str, compliance: BearingCompliance
) -> dict[str, str]:
    """Put a compliant bearing's slides between its parent and its revolute joint ``name``.

    The first slide takes the joint's origin, the others and the joint itself sit at the one
    before (identity origins), so at zero displacement the body is where the ideal bearing puts
    it; massless links join them. Returns slide → joint name (``<joint>_<slide>``).

    Raises:
        MalformedModel: a slide's name is taken by a joint or link of the file.
    """
    joint = next(j for j in root.findall("joint") if j.get("name") == name)
    axis = np.asarray(source.joints[name]["axis"], dtype=float)
    k = axis / np.linalg.norm(axis)
    u, w = _radial_axes(k, compliance.radial_axis)
    directions = {"radial_x": u, "radial_y": w, "axial": k, "tilt_x": u, "tilt_y": w}
    parent = cast(ET.Element, joint.find("parent"))
    origin = joint.find("origin")
    out = {}
    for slide in compliance.slides:
        slide_name = f"{name}_{slide}"
        link_name = slide_link(slide_name)
        for taken, kind in ((slide_name, "joint"), (link_name, "link")):
            if taken in source.joints or taken in source.links:
                raise MalformedModel(
                    source.path,
                    f'<bearing joint="{name}">',
                    f'the compliant bearing\'s {slide} slide needs the {kind} name "{taken}", '
                    "which the file already uses; rename that element",
                )
        kind = "revolute" if slide.startswith("tilt") else "prismatic"
        el = ET.SubElement(root, "joint", name=slide_name, type=kind)
        if origin is not None:
            el.append(origin)
            joint.remove(origin)
            origin = None
        ET.SubElement(el, "parent", link=cast(str, parent.get("link")))
        ET.SubElement(el, "child", link=link_name)
        ET.SubElement(el, "axis", xyz=" ".join(repr(float(x)) for x in directions[slide]))
        ET.SubElement(el, "limit", lower="-1e30", upper="1e30", effort="0", velocity="0")
        # The radial damper acts in contact only: the bearing's element carries it; rows that
        # are the bearing's springs carry every damper (cpp/bearing_rows.hpp).
        rows = row_springs(compliance, source.bearing_rows.get(name, []))
        damping = 0.0 if slide.startswith("radial") or rows else compliance.damping(slide)
        ET.SubElement(el, "dynamics", damping=repr(damping))
        ET.SubElement(root, "link", name=link_name)
        parent.set("link", link_name)
        out[slide] = slide_name
    return out


def _radial_axes(
    axis: np.ndarray, radial_axis: tuple[float, float, float] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Two unit radial axes u, w of a bearing of unit axis k, with u × w = k.

    u is the bearing's ``radial_axis`` (``BearingCompliance``), else the joint frame's x axis
    (or its y axis when k lies along x), made normal to k.
    """
    if radial_axis is not None:
        seed = np.asarray(radial_axis, dtype=float)
    elif abs(axis[0]) < 0.9:
        seed = np.array([1.0, 0.0, 0.0])
    else:
        seed = np.array([0.0, 1.0, 0.0])
    u = seed - (seed @ axis) * axis
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)


def _moving_links(source: ModelFile) -> set[str]:
    """Links that a revolute or continuous joint lies between and the ground."""
    children: dict[str, list[tuple[str, str]]] = {}
    for joint in source.joints.values():
        children.setdefault(joint["parent"], []).append((joint["child"], joint["type"]))
    moving: set[str] = set()
    stack = [(source.root_link, False)]
    while stack:
        link, turns = stack.pop()
        if turns:
            moving.add(link)
        for child, jtype in children.get(link, []):
            stack.append((child, turns or jtype != "fixed"))
    return moving


#: Where ``ImplausibleGear`` warnings were shown (``warnings.warn_explicit``'s registry): under
#: Python's default filter each is shown once per process, however often the model is loaded
#: (a command loads it for its scenario, its run and its log).
_SHOWN: dict[Any, Any] = {}


def _warn_implausible(gearbox: Gearbox) -> None:
    """Each ``ImplausibleGear`` note as a warning at the model file's line of its link."""
    text = gearbox.source_text
    for link, note in gearbox.warnings:
        at = text.find(f'<link name="{link}"')
        line = text.count("\n", 0, at) + 1 if at >= 0 else 0
        warnings.warn_explicit(
            note, ImplausibleGear, str(gearbox.path), line, module="pinwind", registry=_SHOWN
        )


def load(path: str | Path) -> Gearbox:
    """Load a gearbox model file (URDF with a ``<gearbox>`` extension; docs/model_format.md).

    Raises:
        ModelError: malformed file or inconsistent gear data; the message names the file, the
            element and the numbers.
    """
    gearbox = Gearbox(read_model_file(str(path)))
    _warn_implausible(gearbox)
    return gearbox


def loads(text: str, path: str = "<string>") -> Gearbox:
    """Build a gearbox from model-file text (``path`` only names it in messages)."""
    gearbox = Gearbox(read_model_file(path, text))
    _warn_implausible(gearbox)
    return gearbox
