"""Involute gear geometry."""

from pinwind.gears.involute import (
    PairGeometry,
    base_radius,
    inverse_involute,
    involute,
    pair_geometry,
    pitch_radius,
    transverse_pressure_angle,
)

__all__ = [
    "PairGeometry",
    "base_radius",
    "inverse_involute",
    "involute",
    "pair_geometry",
    "pitch_radius",
    "transverse_pressure_angle",
]
