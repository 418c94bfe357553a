"""Compliant bearings in a run: their compiled springs and their two output series.

A compliant bearing's body moves on massless slides in the bearing (``model/bearing_compliance.py``
derives the model); the compiled element ``cpp/bearing_spring.hpp`` holds the slides (radial law,
linear or Harris's roller sum, with clearance and its damper, in contact only; linear axial and
tilt springs), and the axial and
tilt slides' own viscous damping is their damper. ``bearing_law`` gives a bearing's laws as the
compiled spec takes them (``dynamics/element_specs.py`` puts them on the slides). The bearing's
reaction stays the RNEA one of its revolute joint (``bearing_force_local``); two series add

- ``bearing_displacement``: the body's displacement in the bearing, u x + w y + k z [m] in the
  bearing's joint frame (the orbit is its radial part); 0 for an ideal bearing;
- ``bearing_elastic_force``: the bearing springs' force on the body, the radial law's
  (``BearingCompliance.radial_force``: −k max(|r| − c, 0) r̂ or the roller sum) radially and
  −k_a z axially [N], same frame; 0 for an ideal or a floating bearing.

Both are ``derive`` functions of the schema (``dynamics/series.py``): (block, gearbox) → array
(samples, bearings, 3), from the block's joint coordinates (the slides' ``angle`` [m]), computed
by ``_native.bearing_slide_series`` (``cpp/bearing_spring.hpp``): numpy's products of
(samples, 3) by (3, 3) per bearing took as long as a tenth of the step.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pinwind.dynamics import _native


def bearing_law(compliance: Any) -> _native.BearingSpringSpec:
    """A compiled spec holding the bearing's laws (radial, axial and tilt), without its slides."""
    c = compliance
    spec = _native.BearingSpringSpec()
    if not c.floating:
        spec.radial_stiffness, spec.clearance = float(c.radial_stiffness), float(c.clearance)
        spec.radial_damping = float(c.radial_damping)
        if c.law == "roller_sum":
            spec.law = _native.BearingLaw.roller_sum
            spec.rollers, spec.load_exponent = c.rollers, float(c.load_exponent)
            spec.contact_stiffness = float(c.contact_stiffness)
    spec.axial_stiffness = float(c.axial_stiffness or 0.0)
    spec.tilt_stiffness = float(c.tilt_stiffness or 0.0)
    return spec


def row_law(row: Any) -> _native.BearingRowSpec:
    """A compiled spec holding a bearing row's position and laws, without its slides.

    Its position a along the bearing axis from the bearing centre [m], its five stiffnesses
    and dampers in the model file's order (axial, along u, along w, about u, about w;
    ``model/bearing_rows.py``, ``cpp/bearing_rows.hpp``) and its radial clearance c [m]
    (negative: a preload), when it has one.
    """
    spec = _native.BearingRowSpec()
    spec.position = float(row.position)
    spec.stiffness = np.array(row.stiffness, dtype=float)
    spec.damping = np.array(row.damping, dtype=float)
    if row.clearance != 0.0:
        # its radial_clearance_mm (negative: a preload): each radial direction between two
        # sides (cpp/bearing_rows.hpp); none keeps the linear law as it was.
        spec.has_clearance, spec.clearance = True, float(row.clearance)
    return spec


def row_specs(bearing: Any) -> list[_native.BearingRowSpec]:
    """The compiled specs of a ``CompliantBearing``'s rows on its slides (−1: a slide it lacks)."""
    index = bearing.v_index
    out = []
    for row in bearing.rows:
        spec = row_law(row)
        spec.index_x, spec.index_y = index["radial_x"], index["radial_y"]
        spec.index_axial = index.get("axial", -1)
        spec.index_tilt_x, spec.index_tilt_y = index.get("tilt_x", -1), index.get("tilt_y", -1)
        out.append(spec)
    return out


def _slides(block: Any, gearbox: Any) -> list[_native.BearingSlides]:
    """The compiled description of each compliant bearing of the block.

    Its column, its slides' joint columns, their axes in the joint frame and its laws.
    """
    out = []
    for name, bearing in gearbox.compliant_bearings.items():
        if name not in block.bearing_names:
            continue
        slides = _native.BearingSlides()
        slides.bearing = block.bearing_names.index(name)
        for coordinate, slide in (
            ("x", "radial_x"), ("y", "radial_y"), ("z", "axial"), ("tilt_x", "tilt_x"),
            ("tilt_y", "tilt_y"),
        ):  # fmt: skip
            if slide in bearing.slides:
                setattr(slides, coordinate, block.joint_names.index(bearing.slides[slide]))
        slides.axes = np.asarray(bearing.axes_in_joint, dtype=float)
        slides.spring = bearing_law(bearing.compliance)
        slides.rows = [row_law(row) for row in bearing.rows]
        out.append(slides)
    return out


def _series(block: Any, gearbox: Any, elastic: bool) -> np.ndarray:
    """Displacement [m] or elastic force [N] of each bearing, (samples, bearings, 3), joint frame.

    ``cpp/bearing_spring.hpp`` over the block's slide coordinates (the slides' ``angle`` [m]).
    """
    out = np.zeros((len(block.time), len(block.bearing_names), 3))
    if gearbox.compliant_bearings and out.size:
        angle = np.ascontiguousarray(block.angle, dtype=float)
        slides = _slides(block, gearbox)
        if elastic:
            _native.bearing_slide_series(angle, slides, None, out)
        else:
            _native.bearing_slide_series(angle, slides, out)
    return out


def displacement(block: Any, gearbox: Any) -> np.ndarray:
    """The body's displacement in each bearing [m], (samples, bearings, 3), joint frame.

    u x + w y + k z from its slides' coordinates; 0 for an ideal bearing.
    """
    return _series(block, gearbox, elastic=False)


def elastic_force(block: Any, gearbox: Any) -> np.ndarray:
    """The bearing springs' force on each body [N], (samples, bearings, 3), joint frame.

    The radial law (``BearingCompliance.radial_force``) at the slides' (x, y) and −k_a z
    axially; 0 for an ideal bearing and radially for a floating one. A bearing whose rows are
    its springs: the sum of the rows' spring forces (``cpp/bearing_rows.hpp``).
    """
    return _series(block, gearbox, elastic=True)
