"""Involute gear geometry, path of contact, ISO 6336 mesh stiffness, checks and ratings."""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.gears.checks import (
        Finding,
        check_gear,
        check_pair,
        check_planetary,
        min_profile_shift,
        stage_pairs,
        tip_thickness,
        trochoid_clearance,
    )
    from pinwind.gears.contact import (
        ContactRatioBelowOne,
        InvoluteInterference,
        PathOfContact,
        TipInsideBaseCircle,
        pairs_in_contact,
        path_of_contact,
    )
    from pinwind.gears.gear_pair import GearPair, MeshLoad
    from pinwind.gears.hertz import HertzAlongPath, hertz_along_path, hertz_pressure
    from pinwind.gears.involute import (
        PairGeometry,
        base_helix_angle,
        base_radius,
        half_tooth_angle,
        inverse_involute,
        involute,
        pair_geometry,
        pitch_radius,
        tip_radius,
        transverse_pressure_angle,
        virtual_teeth,
    )
    from pinwind.gears.materials import MATERIALS, Material
    from pinwind.gears.mesh_stiffness import (
        contact_line_pair_stiffness,
        mesh_stiffness,
        pair_stiffness_along_path,
        single_pair_stiffness,
    )
    from pinwind.gears.rating_agma import AgmaFactors, AgmaRating, ResolvedAgmaFactors, agma_rating
    from pinwind.gears.rating_iso import IsoFactors, IsoRating, ResolvedIsoFactors, iso_rating
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = [
    "MATERIALS",
    "AgmaFactors",
    "AgmaRating",
    "ContactRatioBelowOne",
    "Finding",
    "GearPair",
    "HertzAlongPath",
    "InvoluteInterference",
    "IsoFactors",
    "IsoRating",
    "Material",
    "MeshLoad",
    "PairGeometry",
    "PathOfContact",
    "ResolvedAgmaFactors",
    "ResolvedIsoFactors",
    "TipInsideBaseCircle",
    "agma_rating",
    "base_helix_angle",
    "base_radius",
    "check_gear",
    "check_pair",
    "check_planetary",
    "contact_line_pair_stiffness",
    "half_tooth_angle",
    "hertz_along_path",
    "hertz_pressure",
    "inverse_involute",
    "involute",
    "iso_rating",
    "mesh_stiffness",
    "min_profile_shift",
    "pair_geometry",
    "pair_stiffness_along_path",
    "pairs_in_contact",
    "path_of_contact",
    "pitch_radius",
    "single_pair_stiffness",
    "stage_pairs",
    "tip_radius",
    "tip_thickness",
    "transverse_pressure_angle",
    "trochoid_clearance",
    "virtual_teeth",
]
