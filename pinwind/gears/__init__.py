"""Involute gear geometry, path of contact and ISO 6336 mesh stiffness."""

from pinwind.gears.contact import (
    ContactRatioBelowOne,
    InvoluteInterference,
    PathOfContact,
    TipInsideBaseCircle,
    pairs_in_contact,
    path_of_contact,
)
from pinwind.gears.involute import (
    PairGeometry,
    base_radius,
    inverse_involute,
    involute,
    pair_geometry,
    pitch_radius,
    transverse_pressure_angle,
)
from pinwind.gears.mesh_stiffness import (
    mesh_stiffness,
    pair_stiffness_along_path,
    single_pair_stiffness,
)

__all__ = [
    "ContactRatioBelowOne",
    "InvoluteInterference",
    "PairGeometry",
    "PathOfContact",
    "TipInsideBaseCircle",
    "base_radius",
    "inverse_involute",
    "involute",
    "mesh_stiffness",
    "pair_geometry",
    "pair_stiffness_along_path",
    "pairs_in_contact",
    "path_of_contact",
    "pitch_radius",
    "single_pair_stiffness",
    "transverse_pressure_angle",
]
