"""A gear train linearised at its reference pose: M, K, C and the rigid rows, and its modes.

The joint-space inertia M is Pinocchio's (CRBA at the neutral pose, with the rotors' inertia when
given); the stiffness and damping are those of the linear elements a run has: each compliant
mesh a spring of its mean mesh stiffness (``compliant.mean_mesh_stiffness``: c_γα b for the ISO
shape, the mean of a pair table) and its dashpot along the front flank's row (the line of action
of ``cpp/mesh_rows.hpp``, the same the step uses), each torsional spring k (e₁ − e₂), each damped
bearing c on its joint. The rigid meshes, the held joints (speed drivers) and the locked bearings
are rows. ``normal_modes.natural_modes`` solves the eigenproblem.

The linearisation is torsional about the reference pose: no gyroscopic terms (the gears turn
about fixed or carrier-borne axes), the mean stiffness instead of its variation along the path,
no backlash (the teeth in contact on the front flank).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace

import numpy as np
import pinocchio as pin

from pinwind.dynamics.compliant import mesh_choices, mesh_setup
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.normal_modes import Mode, SpringElement, element_matrices, natural_modes
from pinwind.dynamics.planetary_modes import (
    Coordinate,
    PlanetaryStage,
    coordinates,
    mode_kinds,
    planetary_stages,
)
from pinwind.errors import UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox


@dataclass(frozen=True)
class Linearisation:
    """M q̈ + C q̇ + K q = 0 under J q̇ = 0 on the joint coordinates (module docstring).

    Attributes:
        joint_names: the coordinates, in the order of the velocity vector.
        mass, stiffness, damping: M [kg·m²], K [N·m/rad], C [N·m·s/rad], (nv, nv).
        constraints: J (r, nv): rigid meshes, held joints, locked bearings.
        elements: the springs K is made of (meshes, torsional springs).
        coordinates: each coordinate's kind (rotation, translation) and axis.
        stages: the planetary stages, whose modes are classified (``planetary_modes.py``).
    """

    joint_names: list[str]
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    constraints: np.ndarray
    elements: list[SpringElement]
    coordinates: list[Coordinate] = field(default_factory=list)
    stages: list[PlanetaryStage] = field(default_factory=list)

    def modes(self) -> list[Mode]:
        """The natural modes, lowest first (rigid ones at 0 Hz), each with its class."""
        found = natural_modes(
            self.mass,
            self.stiffness,
            self.damping,
            self.constraints,
            joint_names=self.joint_names,
            elements=self.elements,
        )
        kinds = mode_kinds(
            self.stages,
            self.coordinates,
            [m.shape for m in found],
            self.mass,
            self.stiffness,
            self.damping,
            self.constraints,
        )
        return [replace(m, kind=k) for m, k in zip(found, kinds, strict=True)]


def linearise(
    gearbox: Gearbox,
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    added_inertia: Mapping[str, float] | None = None,
) -> Linearisation:
    """The train's linearisation at its reference pose (module docstring).

    Args:
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a ``MeshCompliance``,
            as ``simulate`` takes it; default the model file's choice.
        held: joints held at their speed (a speed driver, a stiff grid-connected generator).
        added_inertia: joint name → inertia added to it [kg·m²] (a rotor).

    Raises:
        UnknownJoint: a held joint or inertia on a joint the model does not have.
    """
    names = list(gearbox.joint_names)
    for name in [*held, *(added_inertia or {})]:
        if name not in names:
            raise UnknownJoint(name, "held joints or added inertia", names)
    model = gearbox.model
    nv = model.nv
    driver_index = [gearbox.v_index(j) for j in held]
    driver_index += [gearbox.v_index(j) for j in gearbox.locked_joints]
    choices = mesh_choices(gearbox, meshes)
    setup = mesh_setup(gearbox, choices, driver_index=driver_index, dt=None)
    data = model.createData()
    q = gearbox.neutral()
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(nv))
    rows = MeshSet(gearbox, choices).evaluate(model, data)
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    for name, inertia in (added_inertia or {}).items():
        mass[gearbox.v_index(name), gearbox.v_index(name)] += inertia
    constraints = [rows.row_front[i] for i in setup.rigid]
    for j in driver_index:
        constraints.append(np.eye(nv)[j])
    elements = [
        SpringElement(
            choices[s.mesh].name, "mesh", s.stiffness, s.damping, np.array(rows.row_front[s.mesh])
        )
        for s in setup.compliant
    ]
    for spring in gearbox.springs:
        row = np.zeros(nv)
        row[spring.v_index_1], row[spring.v_index_2] = 1.0, -1.0
        elements.append(SpringElement(spring.name, "spring", spring.stiffness, spring.damping, row))
    stiffness, damping = element_matrices(elements, nv)
    damping += np.diag(np.asarray(model.damping, dtype=float))
    order = sorted(names, key=gearbox.v_index)
    return Linearisation(
        order,
        mass,
        stiffness,
        damping,
        np.array(constraints).reshape(-1, nv),
        elements,
        coordinates(gearbox),
        planetary_stages(gearbox),
    )
