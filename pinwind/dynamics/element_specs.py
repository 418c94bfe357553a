"""Each kind of element and constraint of the compiled step, as its specs: one builder per kind.

The compiled step loop holds lists of elements (forces) and constraints (rows), each built by the
factory of its kind (``cpp/element_kind.hpp``; the kinds are listed in ``cpp/element_kinds.hpp``,
each in a header of its own that holds its spec, checks, binding and factory). A kind reads one
field of ``_native.StepperSpec``; ``SPEC_BUILDERS`` maps each field to the function that builds
its specs from the run (``RunElements``), and ``fill_kinds`` fills every field the compiled module
lists (``_native.kind_fields``). A test checks that the two lists agree, so a new kind is its
C++ header, its line in ``element_kinds.hpp`` and its builder here.

The kinds, in the compiled order (the order the elements' forces are summed in, then the order
of the constraints' rows):

- ``springs``: the torsional spring-dampers (``<torsional_spring>``; ``cpp/torsional_spring.hpp``);
- ``bearing_damping``: each joint's viscous damping c [N·m·s/rad or N·s/m] (``<dynamics
  damping>``; ``cpp/bearing_damping.hpp``);
- ``bearing_springs``: the compliant bearings' springs (``dynamics/bearing_springs.py``) and the
  support's slides' (``dynamics/support_springs.py``), one law (``cpp/bearing_spring.hpp``);
- ``bearing_rows``: the rows of the compliant bearings whose rows are their springs, each a
  linear spring-damper at its position (``model/bearing_rows.py``; ``cpp/bearing_rows.hpp``),
  in the order of ``Gearbox.row_names``;
- ``compliant_meshes``: the compliant meshes (``dynamics/compliant.py``;
  ``cpp/compliant_mesh.hpp``);
- ``generators``, ``rotors``: the generator and rotor laws (``dynamics/elements.py``;
  ``cpp/generator.hpp``, ``cpp/rotor.hpp``);
- ``hub_loads``: six load components on a body (``dynamics/hub_load_specs.py``;
  ``cpp/hub_loads.hpp``);
- ``bearing_friction``: each rolling bearing's frictional moment on its joint, Palmgren's
  M0 + M1 as ISO/TR 14179-2 gives it (``losses/bearing_friction.py``;
  ``cpp/bearing_friction.hpp``);
- ``rigid_meshes``: the meshes that are constraint rows, in row order (``cpp/rigid_meshes.hpp``);
- ``driver_index``: the velocity index of each speed driver and lock, in row order
  (``cpp/speed_drivers.hpp``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.dynamics import _native
from pinwind.dynamics.bearing_springs import bearing_law, row_specs
from pinwind.dynamics.compliant import MeshSetup
from pinwind.dynamics.elements import LoadElements
from pinwind.losses.bearing_friction import (
    LOAD_RULES,
    PALMGREN_FACTORS,
    STICK_SPEED,
    load_moment,
    no_load_moment_coefficients,
)
from pinwind.model.bearing_frictions import bearing_frictions
from pinwind.model.gearbox import Gearbox


@dataclass(frozen=True)
class RunElements:
    """What the kinds' specs are built from.

    Attributes:
        gearbox: the model (its springs, damping, compliant bearings and support).
        meshes: the run's rigid and compliant meshes (``dynamics/compliant.py``).
        loads: the generator and rotor elements (``dynamics/elements.py``), or None.
        driver_index: velocity index of each speed driver and locked bearing, in row order.
    """

    gearbox: Gearbox
    meshes: MeshSetup
    loads: LoadElements | None
    driver_index: list[int]


def torsional_springs(run: RunElements) -> list[_native.TorsionalSpringSpec]:
    """A spec per torsional spring; index_2 = −1: the spring acts across joint 1 alone."""
    out = []
    for s in run.gearbox.springs:
        spec = _native.TorsionalSpringSpec()
        spec.index_1 = s.v_index_1
        spec.index_2 = -1 if s.v_index_2 is None else s.v_index_2
        spec.stiffness, spec.damping, spec.preload_angle = s.stiffness, s.damping, s.preload_angle
        out.append(spec)
    return out


def bearing_damping(run: RunElements) -> np.ndarray:
    """Each velocity's viscous damping c (the model's ``damping``) [N·m·s/rad or N·s/m]."""
    return np.array(run.gearbox.model.damping, dtype=float).copy()


def compliant_bearing_springs(gearbox: Any) -> list[_native.BearingSpringSpec]:
    """The compiled springs of the gearbox's compliant bearings (floating ones have none)."""
    out = []
    for bearing in gearbox.compliant_bearings.values():
        c, index = bearing.compliance, bearing.v_index
        if bearing.rows or (c.floating and "axial" not in index and "tilt_x" not in index):
            continue  # rows: their own kind (bearing_rows)
        spec = bearing_law(c)
        if not c.floating:
            spec.index_x, spec.index_y = index["radial_x"], index["radial_y"]
        if "axial" in index:
            spec.index_axial = index["axial"]
        if "tilt_x" in index:
            spec.index_tilt_x, spec.index_tilt_y = index["tilt_x"], index["tilt_y"]
        out.append(spec)
    return out


def bearing_rows(run: RunElements) -> list[_native.BearingRowSpec]:
    """A spec per row of the bearings whose rows are their springs (``Gearbox.row_names``).

    Each row's slides (−1: the bearing lacks it), its position a along the bearing axis from
    the bearing centre [m] and its five stiffnesses and dampers in the model file's order
    (axial, along u, along w, about u, about w; ``model/bearing_rows.py``).
    """
    return [spec for b in run.gearbox.compliant_bearings.values() for spec in row_specs(b)]


def support_springs(gearbox: Any) -> list[_native.BearingSpringSpec]:
    """The linear springs F = −k q of the support's slides, one spec per slide (axial law)."""
    out = []
    for name, slide in gearbox.support_slides.items():
        spec = _native.BearingSpringSpec()
        spec.index_axial, spec.axial_stiffness = gearbox.v_index(name), float(slide.stiffness)
        out.append(spec)
    return out


def bearing_springs(run: RunElements) -> list[_native.BearingSpringSpec]:
    """The compliant bearings' springs, then the support's."""
    return [*compliant_bearing_springs(run.gearbox), *support_springs(run.gearbox)]


def _compliant_meshes(run: RunElements) -> list[_native.CompliantMeshSpec]:
    return list(run.meshes.compliant)


def _generators(run: RunElements) -> list[_native.GeneratorSpec]:
    return list(run.loads.generators) if run.loads is not None else []


def _rotors(run: RunElements) -> list[_native.RotorSpec]:
    return list(run.loads.rotors) if run.loads is not None else []


def _hub_loads(run: RunElements) -> list[_native.HubLoadSpec]:
    return list(run.loads.hub_load_specs) if run.loads is not None else []


def bearing_friction(run: RunElements) -> list[_native.BearingFrictionSpec]:
    """A spec per rolling bearing with a friction model (``losses.bearing_friction``).

    Its joint's velocity index, its column of the bearing series (−1 if none), c0 and M0_min of
    M0 = max(c0 |ω|^(2/3), M0_min), the regularising speed ``STICK_SPEED`` and M1 = f1 P1 d_m:
    at the model's ``friction_load_kN`` when given, else with P1 following the load of the
    step before (``follow_load``): the row's force for a row that is its compliant bearing's
    spring, the bearing's reaction (axis k, joint frame) otherwise, by the type's rule
    (``LOAD_RULES``, ``friction_load``). A row of an ideal bearing has no force of its own in
    the step: without ``friction_load_kN`` it takes its bearing's whole reaction (an upper
    bound; docs/losses.md).
    """
    gearbox = run.gearbox
    columns = {name: i for i, name in enumerate(gearbox.bearing_names)}
    out = []
    for b in bearing_frictions(gearbox):
        spec = _native.BearingFrictionSpec()
        spec.index = gearbox.v_index(b.joint)
        spec.bearing = columns.get(b.joint, -1)
        spec.no_load_coefficient, spec.no_load_minimum = no_load_moment_coefficients(
            b.f0, b.viscosity, b.mean_diameter
        )
        spec.stick_speed = STICK_SPEED
        if b.load is not None:
            spec.load_moment = float(load_moment(b.f1, b.load, b.mean_diameter))
        else:
            factors = PALMGREN_FACTORS[b.kind]
            spec.follow_load = True
            spec.row = -1 if b.row is None else b.row
            spec.load_coefficient = b.f1 * b.mean_diameter
            spec.load_rule = LOAD_RULES[factors.axial]
            spec.contact_cot = (
                1.0 / math.tan(factors.contact_angle) if factors.contact_angle > 0.0 else 0.0
            )
            spec.axis = np.asarray(gearbox.joint_axis(b.joint), dtype=float)
        out.append(spec)
    return out


def _rigid_meshes(run: RunElements) -> list[int]:
    return list(run.meshes.rigid)


def _driver_index(run: RunElements) -> list[int]:
    return list(run.driver_index)


#: ``_native.StepperSpec`` field of each compiled kind → the builder of its specs.
SPEC_BUILDERS: dict[str, Callable[[RunElements], Any]] = {
    "springs": torsional_springs,
    "bearing_damping": bearing_damping,
    "bearing_springs": bearing_springs,
    "bearing_rows": bearing_rows,
    "compliant_meshes": _compliant_meshes,
    "generators": _generators,
    "rotors": _rotors,
    "hub_loads": _hub_loads,
    "bearing_friction": bearing_friction,
    "rigid_meshes": _rigid_meshes,
    "driver_index": _driver_index,
}


def fill_kinds(spec: _native.StepperSpec, run: RunElements) -> None:
    """Set every kind's field of ``spec`` (``_native.kind_fields``) from its builder."""
    for field in _native.kind_fields():
        setattr(spec, field, SPEC_BUILDERS[field](run))
