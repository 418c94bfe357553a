"""A gear train linearised at its reference pose: M, K, C and the rigid rows, and its modes.

The joint-space inertia M is Pinocchio's (CRBA at the neutral pose, with the rotors' inertia when
given); the stiffness and damping are those of the linear elements a run has: each compliant
mesh a spring of its mean mesh stiffness (``compliant.mean_mesh_stiffness``: c_γα b for the ISO
shape, the mean of a pair table) and its dashpot along the front flank's row (the line of action
of ``cpp/mesh_rows.hpp``, the same the step uses), each torsional spring k (e₁ − e₂), each damped
bearing c on its joint, each compliant bearing's slide its spring and damper
(``bearing_elements``). The rigid meshes, the held joints (speed drivers) and the locked bearings
are rows; a floating bearing that nothing holds is refused. ``normal_modes.natural_modes``
solves the eigenproblem.

The linearisation is about the reference pose: no gyroscopic terms (the gears turn
about fixed or carrier-borne axes), the mean stiffness instead of its variation along the path,
no backlash (the teeth in contact on the front flank).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinwind.dynamics.compliant import mesh_choices, mesh_setup
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.normal_modes import Mode, SpringElement, element_matrices, natural_modes
from pinwind.errors import UnheldMember, UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox


@dataclass(frozen=True)
class Linearisation:
    """M q̈ + C q̇ + K q = 0 under J q̇ = 0 on the joint coordinates (module docstring).

    Attributes:
        joint_names: the coordinates, in the order of the velocity vector.
        mass, stiffness, damping: M [kg·m²], K [N·m/rad], C [N·m·s/rad], (nv, nv) (kg, N/m
            and N·s/m on a compliant bearing's slides).
        constraints: J (r, nv): rigid meshes, held joints, locked bearings.
        elements: the springs K is made of (meshes, torsional springs, bearing slides).
    """

    joint_names: list[str]
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    constraints: np.ndarray
    elements: list[SpringElement]

    def modes(self) -> list[Mode]:
        """The natural modes, lowest first (rigid ones at 0 Hz)."""
        return natural_modes(
            self.mass,
            self.stiffness,
            self.damping,
            self.constraints,
            joint_names=self.joint_names,
            elements=self.elements,
        )


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
    elements += bearing_elements(gearbox)
    stiffness, damping = element_matrices(elements, nv)
    # The joints' viscous damping, but the slides': their bearings' elements carry it.
    bearing_damping = np.asarray(model.damping, dtype=float).copy()
    bearing_damping[[gearbox.v_index(s) for s in gearbox.slide_joints]] = 0.0
    damping += np.diag(bearing_damping)
    order = sorted(names, key=gearbox.v_index)
    out = Linearisation(
        order, mass, stiffness, damping, np.array(constraints).reshape(-1, nv), elements
    )
    _check_held(gearbox, out)
    return out


def bearing_elements(gearbox: Gearbox) -> list[SpringElement]:
    """The compliant bearings' springs and dampers, one per slide (``<joint>_<slide>``).

    A bearing with a radial clearance counts as loaded (the clearance taken up, stiffness k);
    a floating bearing's radial slides have none.
    """
    nv = gearbox.model.nv
    out = []
    for bearing in gearbox.compliant_bearings.values():
        c = bearing.compliance
        for slide, name in bearing.slides.items():
            k, damping = c.stiffness(slide), c.damping(slide)
            if k == 0.0 and damping == 0.0:
                continue
            row = np.zeros(nv)
            row[bearing.v_index[slide]] = 1.0
            out.append(SpringElement(name, "bearing", k, damping, row))
    return out


#: Share of a rigid mode's motion on a floating bearing's slides above which that bearing is
#: unheld (a whole-train rotation has none).
UNHELD_SHARE = 1e-6


def _check_held(gearbox: Gearbox, lin: Linearisation) -> None:
    """Refuse a floating bearing whose body a motion no mesh, spring or row resists moves.

    Raises:
        UnheldMember: names the bearing and the free motion (its largest joint coordinates).
    """
    floating = [b for b in gearbox.compliant_bearings.values() if b.compliance.floating]
    if not floating:
        return
    for mode in lin.modes():
        if not mode.rigid:
            continue
        for bearing in floating:
            radial = mode.shape[[bearing.v_index[s] for s in ("radial_x", "radial_y")]]
            if float(radial @ radial) <= UNHELD_SHARE * float(mode.shape @ mode.shape):
                continue
            unit = mode.shape / np.linalg.norm(mode.shape)
            motion = {
                lin.joint_names[i]: float(unit[i])
                for i in np.argsort(-np.abs(unit))
                if abs(unit[i]) > 1e-3
            }
            text = ", ".join(f"{name} {value:+.3g}" for name, value in list(motion.items())[:6])
            raise UnheldMember(
                bearing.joint,
                motion,
                f'the floating bearing "{bearing.joint}" lets its body move freely: no mesh, '
                f"spring or row resists the motion ({text}; joint coordinates, m and rad, "
                "unit length). Give the bearing a radial_stiffness, or meshes that centre it "
                "(a sun between three or more planets)",
                path=str(gearbox.path),
            )
