"""Compliant bearings in a run: their compiled springs and their two output series.

A compliant bearing's body moves on massless slides in the bearing (``model/bearing_compliance.py``
derives the model); the compiled element ``cpp/bearing_spring.hpp`` holds the slides (radial law,
linear or Harris's roller sum, with clearance and its damper, in contact only; linear axial and
tilt springs), and the axial and
tilt slides' own viscous damping is their damper. ``bearing_spring_specs`` gives the compiled
specs. The bearing's reaction stays the RNEA one of its revolute joint (``bearing_force_local``);
two series add

- ``bearing_displacement``: the body's displacement in the bearing, u x + w y + k z [m] in the
  bearing's joint frame (the orbit is its radial part); 0 for an ideal bearing;
- ``bearing_elastic_force``: the bearing springs' force on the body, the radial law's
  (``BearingCompliance.radial_force``: −k max(|r| − c, 0) r̂ or the roller sum) radially and
  −k_a z axially [N], same frame; 0 for an ideal or a floating bearing.

Both are ``derive`` functions of the schema (``dynamics/series.py``): (block, gearbox) → array
(samples, bearings, 3), from the block's joint coordinates (the slides' ``angle`` [m]).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pinwind.dynamics import _native


def bearing_spring_specs(gearbox: Any) -> list[_native.BearingSpringSpec]:
    """The compiled springs of the gearbox's compliant bearings (floating ones have none)."""
    out = []
    for bearing in gearbox.compliant_bearings.values():
        c, index = bearing.compliance, bearing.v_index
        if c.floating and "axial" not in index and "tilt_x" not in index:
            continue
        spec = _native.BearingSpringSpec()
        if not c.floating:
            spec.index_x, spec.index_y = index["radial_x"], index["radial_y"]
            spec.radial_stiffness, spec.clearance = float(c.radial_stiffness), float(c.clearance)
            spec.radial_damping = float(c.radial_damping)
            if c.law == "roller_sum":
                spec.law = _native.BearingLaw.roller_sum
                spec.rollers, spec.load_exponent = c.rollers, float(c.load_exponent)
                spec.contact_stiffness = float(c.contact_stiffness)
        if "axial" in index:
            spec.index_axial, spec.axial_stiffness = index["axial"], float(c.axial_stiffness)
        if "tilt_x" in index:
            spec.index_tilt_x, spec.index_tilt_y = index["tilt_x"], index["tilt_y"]
            spec.tilt_stiffness = float(c.tilt_stiffness)
        out.append(spec)
    return out


def _coordinates(block: Any, bearing: Any) -> np.ndarray:
    """The slides' (x, y, z) of a bearing over the block [m], (samples, 3) (z 0 without)."""
    out = np.zeros((len(block.time), 3))
    for column, slide in enumerate(("radial_x", "radial_y", "axial")):
        if slide in bearing.slides:
            out[:, column] = block.angle[:, block.joint_names.index(bearing.slides[slide])]
    return out


def displacement(block: Any, gearbox: Any) -> np.ndarray:
    """The body's displacement in each bearing [m], (samples, bearings, 3), joint frame."""
    out = np.zeros((len(block.time), len(block.bearing_names), 3))
    for name, bearing in gearbox.compliant_bearings.items():
        if name in block.bearing_names:
            out[:, block.bearing_names.index(name)] = (
                _coordinates(block, bearing) @ bearing.axes_in_joint
            )
    return out


def elastic_force(block: Any, gearbox: Any) -> np.ndarray:
    """The bearing springs' force on each body [N], (samples, bearings, 3), joint frame."""
    out = np.zeros((len(block.time), len(block.bearing_names), 3))
    for name, bearing in gearbox.compliant_bearings.items():
        if name not in block.bearing_names:
            continue
        c = bearing.compliance
        xyz = _coordinates(block, bearing)
        force = np.zeros_like(xyz)
        force[:, :2] = c.radial_force(xyz[:, :2])
        force[:, 2] = -(c.axial_stiffness or 0.0) * xyz[:, 2]
        out[:, block.bearing_names.index(name)] = force @ bearing.axes_in_joint
    return out
