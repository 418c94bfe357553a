"""A gear pair and the load on it: the one description of a pair that every gear function takes.

The path of contact (`contact.path_of_contact`), the geometry checks (`checks.check_pair`), the
ISO 6336-1 mesh stiffness (`mesh_stiffness`), Hertz stress (`hertz.hertz_along_path`) and the
ISO 6336 and AGMA 2001 ratings all take a `GearPair`; the derived geometry they share (working
geometry, base radii, tip radii, base helix angle, path of contact) lives here, computed once.

For the ratings gear 1 is the pinion: the external gear with fewer teeth (ISO 6336 and AGMA both
number it so); gear 2 is the wheel, possibly internal. `GearPair.from_mesh` orders a model's
mesh that way. The geometry (path of contact, checks) also takes gear 1 internal
(``internal_1``), the order of a model's mesh (`GearPair.from_gears`).
SI units, angles in radians, ISO 21771 sign of profile shift (`pinwind.gears.involute`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import cast

from pinwind.errors import InvalidGearTrain
from pinwind.gears.contact import PathOfContact, path_of_contact
from pinwind.gears.involute import (
    PairGeometry,
    base_helix_angle,
    pair_geometry,
    tip_radius,
    transverse_pressure_angle,
    virtual_teeth,
)
from pinwind.gears.materials import DEFAULT_MATERIAL, Material, material


@dataclass(frozen=True)
class GearPair:
    """Geometry and materials of a spur or helical pair, pinion first.

    Attributes:
        teeth_1: pinion tooth count (positive, also when internal).
        teeth_2: wheel tooth count (positive, also when internal).
        module: normal module m_n [m].
        pressure_angle: normal pressure angle α_n [rad].
        face_width: common face width b [m].
        profile_shift_1, profile_shift_2: x1, x2 [-] (ISO sign).
        helix_angle: β [rad].
        internal_2: the wheel is an internal (ring) gear.
        material_1, material_2: `Material` or a key of `materials.MATERIALS`.
        names: names of the pinion and the wheel (for tables and messages).
        addendum_coefficient: h_aP* of the basic rack [-].
        dedendum_coefficient: h_fP* of the basic rack [-] (ISO 53 profile A: 1.25).
        root_radius_coefficient: ρ_fP* of the basic rack [-] (ISO 53 profile A: 0.38).
        internal_1: gear 1 is an internal (ring) gear: a model's mesh in its own order
            (`from_gears`); the ratings and the ISO stiffness want it as gear 2 (`from_mesh`).
        tip_alteration_1, tip_alteration_2: tip alteration k·m_n of each gear [m], negative for
            a shortened tip (ISO 21771; `involute.tip_radius`).

    Raises:
        InvalidGearTrain: a non-positive tooth count, module or face width, or two internal
            gears.
    """

    teeth_1: int
    teeth_2: int
    module: float
    pressure_angle: float
    face_width: float
    profile_shift_1: float = 0.0
    profile_shift_2: float = 0.0
    helix_angle: float = 0.0
    internal_2: bool = False
    material_1: Material | str = DEFAULT_MATERIAL
    material_2: Material | str = DEFAULT_MATERIAL
    names: tuple[str, str] = ("pinion", "wheel")
    addendum_coefficient: float = 1.0
    dedendum_coefficient: float = 1.25
    root_radius_coefficient: float = 0.38
    internal_1: bool = False
    tip_alteration_1: float = 0.0
    tip_alteration_2: float = 0.0

    def __post_init__(self) -> None:
        if self.teeth_1 <= 0 or self.teeth_2 <= 0:
            raise InvalidGearTrain(
                f"tooth counts must be positive ({self.teeth_1}, {self.teeth_2}); mark a ring "
                "gear with internal_1/internal_2 rather than a negative tooth count"
            )
        if self.internal_1 and self.internal_2:
            raise InvalidGearTrain(
                "two internal gears cannot mesh; set internal_1 or internal_2, not both"
            )
        label = f"{self.names[0]}–{self.names[1]}"
        for what, value in (
            ("module", self.module),
            ("face width", self.face_width),
            ("profile shift x1", self.profile_shift_1),
            ("profile shift x2", self.profile_shift_2),
            ("helix angle", self.helix_angle),
            ("pressure angle", self.pressure_angle),
            ("tip alteration 1", self.tip_alteration_1),
            ("tip alteration 2", self.tip_alteration_2),
        ):
            if not math.isfinite(value):
                raise InvalidGearTrain(f"{label}: the {what} is {value}; give a finite number")
        if self.module <= 0 or self.face_width <= 0:
            raise InvalidGearTrain(
                f"{label}: module ({self.module} m) and face width ({self.face_width} m) must be "
                "positive"
            )
        if not 0.0 < self.pressure_angle < math.radians(45.0):
            raise InvalidGearTrain(
                f"{label}: the pressure angle is {math.degrees(self.pressure_angle):g}°; it must "
                "lie in (0, 45)° (20° is the ISO 53 standard; Saleh 2017 uses 24.5°)"
            )
        object.__setattr__(self, "material_1", material(self.material_1))
        object.__setattr__(self, "material_2", material(self.material_2))

    @classmethod
    def from_mesh(cls, mesh, materials: dict[str, Material | str] | None = None) -> GearPair:
        """The pair of a model's mesh (``pinwind.model.gearbox.Mesh``), pinion first.

        The pinion is the external gear of the two with fewer teeth. ``materials`` maps gear
        names to materials (default: `materials.DEFAULT_MATERIAL` for every gear).
        """
        a, b = mesh.gear_a.spec, mesh.gear_b.spec
        if a.internal or (not b.internal and b.teeth < a.teeth):
            a, b = b, a
        return cls.from_gears(a, b, materials)

    @classmethod
    def from_gears(cls, a, b, materials: dict[str, Material | str] | None = None) -> GearPair:
        """The pair of two gears of a model (``pinwind.model.gearbox.GearSpec``), in that order.

        Gear 1 is ``a`` (possibly internal), gear 2 ``b``; the module, pressure and helix angles
        are ``a``'s, the face width the smaller one. ``materials`` as in `from_mesh`.
        """
        chosen = materials or {}
        return cls(
            teeth_1=a.teeth,
            teeth_2=b.teeth,
            module=a.module,
            pressure_angle=a.pressure_angle,
            face_width=min(a.face_width, b.face_width),
            profile_shift_1=a.profile_shift,
            profile_shift_2=b.profile_shift,
            helix_angle=abs(a.helix_angle),
            internal_1=a.internal,
            internal_2=b.internal,
            material_1=chosen.get(a.name, DEFAULT_MATERIAL),
            material_2=chosen.get(b.name, DEFAULT_MATERIAL),
            names=(a.name, b.name),
            tip_alteration_1=a.tip_alteration,
            tip_alteration_2=b.tip_alteration,
        )

    def reversed(self) -> GearPair:
        """The same pair with gears 1 and 2 exchanged (teeth, shifts, internal flags, ...)."""
        return replace(
            self,
            teeth_1=self.teeth_2,
            teeth_2=self.teeth_1,
            profile_shift_1=self.profile_shift_2,
            profile_shift_2=self.profile_shift_1,
            internal_1=self.internal_2,
            internal_2=self.internal_1,
            material_1=self.material_2,
            material_2=self.material_1,
            names=(self.names[1], self.names[0]),
            tip_alteration_1=self.tip_alteration_2,
            tip_alteration_2=self.tip_alteration_1,
        )

    def pinion_first(self) -> GearPair:
        """The pair numbered as the ratings number it: the external gear with fewer teeth first.

        An internal gear goes second, as `from_mesh` orders a mesh; the pair itself when it
        already is so numbered.
        """
        swap = self.internal_1 or (not self.internal_2 and self.teeth_2 < self.teeth_1)
        return self.reversed() if swap else self

    def require_external_gear_1(self, method: str) -> None:
        """Raise `InvalidGearTrain` if gear 1 is internal: ``method`` takes the pinion first."""
        if self.internal_1:
            raise InvalidGearTrain(
                f"{method} takes the external gear first, but gear 1 ({self.names[0]}) is "
                "internal; use pair.reversed() or GearPair.from_mesh, which puts it second"
            )

    @property
    def materials(self) -> tuple[Material, Material]:
        """(material_1, material_2), resolved to `Material` by the constructor."""
        return cast(Material, self.material_1), cast(Material, self.material_2)

    # --- derived geometry (ISO 21771) ---------------------------------------------------------

    @cached_property
    def geometry(self) -> PairGeometry:
        """Working centre distance, pressure angle, pitch and base radii."""
        return pair_geometry(
            self.teeth_1,
            self.teeth_2,
            module=self.module,
            pressure_angle=self.pressure_angle,
            profile_shift_1=self.profile_shift_1,
            profile_shift_2=self.profile_shift_2,
            helix_angle=self.helix_angle,
            internal_1=self.internal_1,
            internal_2=self.internal_2,
        )

    @cached_property
    def path(self) -> PathOfContact:
        """Path of contact (contact ratios), tips with their tip alteration (`path_of_contact`)."""
        return self.path_of_contact()

    def path_of_contact(
        self, *, tip_radius_1: float | None = None, tip_radius_2: float | None = None
    ) -> PathOfContact:
        """Path of contact of the pair (`contact.path_of_contact`).

        Args:
            tip_radius_1: tip radius of gear 1 [m]; default `tip_radius` (its tip alteration).
            tip_radius_2: tip radius of gear 2 [m]; the same.

        Raises:
            TipInsideBaseCircle, InvoluteInterference, ContactRatioBelowOne: as
                `contact.path_of_contact`.
        """
        overlap = self.face_width * math.sin(abs(self.helix_angle)) / (math.pi * self.module)
        return path_of_contact(
            self.geometry,
            tip_radius_1=self.tip_radius(1) if tip_radius_1 is None else tip_radius_1,
            tip_radius_2=self.tip_radius(2) if tip_radius_2 is None else tip_radius_2,
            base_pitch=math.pi * self.transverse_module * math.cos(self.transverse_pressure_angle),
            internal_1=self.internal_1,
            internal_2=self.internal_2,
            overlap_ratio=overlap,
        )

    @property
    def tangency_distance(self) -> float:
        """|T1 T2| = a_w sin α_wt, between the base-circle tangency points [m] (ISO 21771)."""
        return self.geometry.tangency_distance

    def flank_radii(self, roll_1):
        """Flank radii of curvature (ρ1, ρ2) at roll distance ``roll_1`` from T1 [m].

        ρ1 = u, ρ2 = |T1T2| − u for an external pair and −(|T1T2| + u) for an internal
        gear 2 (concave flank); for an internal gear 1, whose T1 lies |T1T2| behind T2,
        ρ1 = −u and ρ2 = u − |T1T2|. ``roll_1`` a float or an array
        (Jørgensen 2014 Fig. 10).
        """
        line = self.tangency_distance
        if self.internal_1:
            return -roll_1, roll_1 - line
        return roll_1, (-(line + roll_1) if self.internal_2 else line - roll_1)

    @property
    def transverse_pressure_angle(self) -> float:
        """α_t [rad]."""
        return transverse_pressure_angle(self.pressure_angle, self.helix_angle)

    @property
    def base_helix_angle(self) -> float:
        """β_b = atan(tan β cos α_t) [rad] (`involute.base_helix_angle`)."""
        return base_helix_angle(self.pressure_angle, self.helix_angle)

    @property
    def transverse_module(self) -> float:
        """m_t = m_n / cos β [m]."""
        return self.module / math.cos(self.helix_angle)

    @property
    def reference_diameter_1(self) -> float:
        """d1 = z1 m_t [m]."""
        return self.teeth_1 * self.transverse_module

    @property
    def gear_ratio(self) -> float:
        """U = z2/z1, negative for an internal wheel (ISO 6336-2) [-]."""
        return (-self.teeth_2 if self.internal_2 else self.teeth_2) / self.teeth_1

    def gear(self, gear: int) -> tuple[int, float, bool]:
        """(teeth, profile shift, internal) of gear 1 or 2."""
        if gear == 1:
            return self.teeth_1, self.profile_shift_1, self.internal_1
        if gear == 2:
            return self.teeth_2, self.profile_shift_2, self.internal_2
        raise ValueError(f"a gear pair has gears 1 and 2, not {gear!r}")

    def tip_radius(self, gear: int) -> float:
        """Tip radius with its tip alteration [m] (`involute.tip_radius`); inner one if internal."""
        teeth, shift, internal = self.gear(gear)
        alteration = self.tip_alteration_1 if gear == 1 else self.tip_alteration_2
        return tip_radius(
            teeth, self.module, shift, self.helix_angle, internal, self.addendum_coefficient,
            alteration,
        )  # fmt: skip

    def tip_diameter(self, gear: int) -> float:
        """Tip diameter with the gear's tip alteration, 2 `tip_radius` [m]."""
        return 2.0 * self.tip_radius(gear)

    def virtual_teeth(self, gear: int) -> float:
        """Virtual tooth number z_n of gear 1 or 2 (`involute.virtual_teeth`) [-]."""
        return virtual_teeth(self.gear(gear)[0], self.helix_angle, self.pressure_angle)

    def flank_normal_force(self, transverse_force):
        """F_n = F_bt / cos β_b: the force normal to the flanks from its transverse part [N].

        A run logs a mesh's force along the transverse line of action, F_bt (``mesh_normal``,
        ``mesh_single_tooth_force``); the flanks of a helical pair touch along contact lines
        inclined at β_b, so the force normal to them is F_bt / cos β_b (``cpp/mesh_rows.hpp``
        ``tooth_force_on_b``). The same for a spur pair. A float or an array.
        """
        return transverse_force / math.cos(self.base_helix_angle)

    def tangential_force(self, normal_force: float) -> float:
        """F_t at the reference circle from the normal tooth force: F_n cos β_b cos α_t [N].

        ISO 6336 and AGMA rate on the nominal tangential force at the reference circle,
        F_t = 2 T1/d1. A normal force F_n along the line of action carries the torque
        F_n r_b cos β_b
        (the transverse part F_n cos β_b acts at the base radius r_b = r cos α_t), so
        F_t = F_n cos β_b cos α_t whatever the working pressure angle.
        """
        return (
            normal_force
            * math.cos(self.base_helix_angle)
            * math.cos(self.transverse_pressure_angle)
        )


@dataclass(frozen=True)
class MeshLoad:
    """One load level of a mesh.

    Attributes:
        tangential_force: nominal tangential force at the reference circle F_t [N] (> 0).
        pitch_line_speed: v at the reference circle, relative to the carrier for a planet mesh
            [m/s] (≥ 0).
        normal_force: the normal tooth force the rating started from [N] (for the tables).
    """

    tangential_force: float
    pitch_line_speed: float = 0.0
    normal_force: float = math.nan
