"""A gear pair to rate and the load on it: the common input of the ISO 6336 and AGMA 2001 ratings.

Gear 1 is the pinion: the external gear with fewer teeth (ISO 6336 and AGMA both number it so);
gear 2 is the wheel, possibly internal. `GearPair.from_mesh` orders a model's mesh that way.
SI units, angles in radians, ISO 21771 sign of profile shift (`pinwind.gears.involute`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from pinwind.errors import InvalidGearTrain
from pinwind.gears.contact import PathOfContact, path_of_contact
from pinwind.gears.involute import PairGeometry, pair_geometry, transverse_pressure_angle
from pinwind.gears.materials import DEFAULT_MATERIAL, Material, material


@dataclass(frozen=True)
class GearPair:
    """Geometry and materials of a spur or helical pair, pinion first.

    Attributes:
        teeth_1: pinion tooth count (external).
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

    def __post_init__(self) -> None:
        if self.teeth_1 <= 0 or self.teeth_2 <= 0:
            raise InvalidGearTrain(
                f"tooth counts must be positive ({self.teeth_1}, {self.teeth_2})"
            )
        if self.module <= 0 or self.face_width <= 0:
            raise InvalidGearTrain(
                f"module ({self.module} m) and face width ({self.face_width} m) must be positive"
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
            internal_2=b.internal,
            material_1=chosen.get(a.name, DEFAULT_MATERIAL),
            material_2=chosen.get(b.name, DEFAULT_MATERIAL),
            names=(a.name, b.name),
        )

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
            internal_2=self.internal_2,
        )

    @cached_property
    def path(self) -> PathOfContact:
        """Path of contact (contact ratios) from `contact.path_of_contact`."""
        return path_of_contact(
            self.teeth_1,
            self.teeth_2,
            module=self.module,
            pressure_angle=self.pressure_angle,
            profile_shift_1=self.profile_shift_1,
            profile_shift_2=self.profile_shift_2,
            helix_angle=self.helix_angle,
            internal_2=self.internal_2,
            addendum_coefficient=self.addendum_coefficient,
            face_width=self.face_width,
        )

    @property
    def transverse_pressure_angle(self) -> float:
        """α_t [rad]."""
        return transverse_pressure_angle(self.pressure_angle, self.helix_angle)

    @property
    def base_helix_angle(self) -> float:
        """β_b = atan(tan β cos α_t) [rad]."""
        return math.atan(math.tan(self.helix_angle) * math.cos(self.transverse_pressure_angle))

    @property
    def transverse_module(self) -> float:
        """m_t = m_n / cos β [m]."""
        return self.module / math.cos(self.helix_angle)

    @property
    def reference_diameter_1(self) -> float:
        """d1 = z1 m_t [m]."""
        return self.teeth_1 * self.transverse_module

    @property
    def reference_diameter_2(self) -> float:
        """d2 = z2 m_t [m] (positive also for an internal wheel)."""
        return self.teeth_2 * self.transverse_module

    @property
    def gear_ratio(self) -> float:
        """U = z2/z1, negative for an internal wheel (ISO 6336-2) [-]."""
        return (-self.teeth_2 if self.internal_2 else self.teeth_2) / self.teeth_1

    def tip_diameter(self, gear: int) -> float:
        """Tip diameter without tip shortening [m]; the inner diameter of an internal wheel."""
        z, x = (
            (self.teeth_1, self.profile_shift_1)
            if gear == 1
            else (self.teeth_2, self.profile_shift_2)
        )
        d = z * self.transverse_module
        addendum = 2.0 * self.module * (self.addendum_coefficient + x)
        return d - addendum if (gear == 2 and self.internal_2) else d + addendum

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
