"""The machine a run steps, linear at its reference pose and at rest: M, K, C and the rigid rows.

What a run needs of the linearisation (``dynamics/simulate.py``): the joint-space inertia with the
rotors' (``Drivetrain.mass``), the flank the static load presses on each mesh
(``loaded_flanks.py``), a floating member that nothing holds refused (``check_held``), and the
torsional-spring modes (``torsional_modes.py``). The stiffness and damping are those of the linear
elements a run has: each compliant mesh a spring of its mean mesh stiffness
(``compliant.mean_mesh_stiffness``) and its dashpot along the row of its loaded flank, each
torsional spring k (e₁ − e₂), each damped bearing c on its joint, each compliant bearing's and
support slide its spring and damper (``bearing_elements``), and each generator and rotor law's slope
as a damper on its joint (``Drivetrain.law_damping``). The rigid meshes (on their loaded flanks),
the held joints and the locked bearings are rows.

The modes built on it, at rest and at an operating speed (the velocity terms, the planetary
classes, the whirl), are the ``modes`` package's (``modes/linearisation.py``): the run imports
nothing of it, so that ``modes`` sits above ``dynamics``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinwind.dynamics import _native
from pinwind.dynamics.bearing_springs import row_specs
from pinwind.dynamics.compliant import mean_mesh_stiffness, mesh_setup
from pinwind.dynamics.drivetrain import Drivetrain
from pinwind.dynamics.loaded_flanks import FlankChoice, loaded_flanks
from pinwind.dynamics.mesh import MeshRows, MeshSet
from pinwind.dynamics.normal_modes import SpringElement, element_matrices, natural_modes
from pinwind.errors import UnheldMember
from pinwind.model.bearing_rows import row_name
from pinwind.model.gearbox import CompliantBearing, Gearbox


@dataclass(frozen=True)
class LinearModel:
    """M q̈ + C q̇ + K q = 0 under J q̇ = 0 on the joint coordinates, at rest (module docstring).

    Attributes:
        joint_names: the coordinates, in the order of the velocity vector.
        mass, stiffness, damping: M [kg·m²], K [N·m/rad], C [N·m·s/rad], (nv, nv) (kg, N/m
            and N·s/m on a compliant bearing's slides).
        constraints: J (r, nv): rigid meshes, held joints, locked bearings.
        elements: the springs K is made of (meshes, torsional springs, bearing slides).
        flanks: the flank each mesh is taken on, the one the static load presses
            (``loaded_flanks.py``), and the meshes no load presses.
        added_inertia: joint name → inertia in M besides the bodies' [kg·m²] (the rotors').
        law_damping: joint name → the generator and rotor laws' slope in C [N·m·s/rad]
            (``Drivetrain.law_damping``).
        mesh_set: the meshes whose rows ``mesh_rows`` holds.
        mesh_rows: each mesh's row on its loaded flank (meshes, nv) [m/rad].
    """

    joint_names: list[str]
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    constraints: np.ndarray
    elements: list[SpringElement]
    flanks: FlankChoice
    added_inertia: dict[str, float]
    law_damping: dict[str, float]
    mesh_set: MeshSet
    mesh_rows: np.ndarray


def linear_model(train: Drivetrain, *, at: np.ndarray) -> LinearModel:
    """The drivetrain's linear model at its reference pose (module docstring).

    Args:
        train: the drivetrain a run steps; its held joints (speed drivers and ``held``) are rows.
        at: v₀ (nv,) [rad/s], the joint speeds at which the laws' slopes and the static load
            that chooses the flanks are taken.
    """
    gearbox = train.gearbox
    names = list(gearbox.joint_names)
    model = gearbox.model
    nv = model.nv
    driver_index = [gearbox.v_index(j) for j in train.held_joints]
    holds = np.eye(nv)[driver_index].reshape(-1, nv)
    data = model.createData()
    q = gearbox.neutral()
    mesh_set = MeshSet(gearbox, train.meshes)
    rows = mesh_rows_at(mesh_set, model, data, q)
    mass = train.mass(q)
    others = [*spring_elements(gearbox), *bearing_elements(gearbox)]
    other_stiffness, other_damping = element_matrices(others, nv)
    static = train.static_load(at)
    flanks = loaded_flanks(
        gearbox,
        train.meshes,
        rows,
        mesh_stiffness={
            i: mean_mesh_stiffness(m) for i, m in enumerate(train.meshes) if m.compliance
        },
        other_stiffness=other_stiffness,
        holds=holds,
        mass=mass,
        load=static.load,
        gross=static.gross,
    )
    jac, _ = mesh_set.combine(rows, flanks.flank)
    setup = mesh_setup(
        gearbox, train.meshes, driver_index=driver_index, dt=None, mass=mass, flank=flanks.flank
    )
    constraints = [*(jac[i] for i in setup.rigid), *holds]
    elements = [
        SpringElement(
            train.meshes[s.mesh].name, "mesh", s.stiffness, s.damping, np.array(jac[s.mesh])
        )
        for s in setup.compliant
    ]
    elements += others
    stiffness, damping = element_matrices(elements, nv)
    # The joints' viscous damping, but the slides': their bearings' elements carry it.
    bearing_damping = np.asarray(model.damping, dtype=float).copy()
    bearing_damping[[gearbox.v_index(s) for s in gearbox.slide_joints]] = 0.0
    damping += np.diag(bearing_damping)
    law_damping = train.law_damping(at)
    for name, value in law_damping.items():
        damping[gearbox.v_index(name), gearbox.v_index(name)] += value
    return LinearModel(
        sorted(names, key=gearbox.v_index),
        mass,
        stiffness,
        damping,
        np.array(constraints).reshape(-1, nv),
        elements,
        flanks,
        train.added_inertia,
        law_damping,
        mesh_set,
        jac,
    )


def spring_elements(gearbox: Gearbox) -> list[SpringElement]:
    """The torsional springs: k (e₁ − e₂), one element each (k e₁ e₁ᵀ to the ground)."""
    out = []
    for spring in gearbox.springs:
        row = spring.twist_row(gearbox.model.nv)
        out.append(SpringElement(spring.name, "spring", spring.stiffness, spring.damping, row))
    return out


def mesh_rows_at(mesh_set: MeshSet, model: pin.Model, data: pin.Data, q: np.ndarray) -> MeshRows:
    """The meshes' rows at pose ``q``, at rest."""
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
    return mesh_set.evaluate(model, data)


def bearing_elements(gearbox: Gearbox) -> list[SpringElement]:
    """The compliant bearings' and the support's springs and dampers, one per slide.

    A compliant bearing's slides are ``<joint>_<slide>``, the support's ``support_tower_<dir>``
    and ``support_mount_<axis>`` (``model/support.py``).

    A linear bearing with a radial clearance counts as loaded (the clearance taken up, stiffness
    k); a floating bearing's radial slides have none. A roller-sum bearing is linearised about
    its static deflection under the model's weight (``roller_sum_elements``).
    """
    nv = gearbox.model.nv
    out: list[SpringElement] = []
    gravity = None
    for joint, bearing in gearbox.compliant_bearings.items():
        c = bearing.compliance
        if bearing.rows:
            out += row_elements(joint, bearing, nv)
            continue
        for slide, name in bearing.slides.items():
            if c.law == "roller_sum" and slide.startswith("radial"):
                if slide == "radial_x":
                    if gravity is None:
                        data = gearbox.model.createData()
                        gravity = pin.computeGeneralizedGravity(
                            gearbox.model, data, gearbox.neutral()
                        )
                    out += roller_sum_elements(bearing, gravity, nv)
                continue
            k, damping = c.stiffness(slide), c.damping(slide)
            if k == 0.0 and damping == 0.0:
                continue
            row = np.zeros(nv)
            row[bearing.v_index[slide]] = 1.0
            out.append(SpringElement(name, "bearing", k, damping, row))
    for name, support in gearbox.support_slides.items():
        row = np.zeros(nv)
        row[gearbox.v_index(name)] = 1.0
        out.append(SpringElement(name, "support", support.stiffness, support.damping, row))
    return out


#: The springs of a bearing row, in the order of its stiffness (``cpp/bearing_rows.hpp``).
ROW_SPRINGS = ("axial", "radial_u", "radial_w", "tilt_u", "tilt_w")


def row_elements(joint: str, bearing: CompliantBearing, nv: int) -> list[SpringElement]:
    """A bearing's rows as springs: each row's five, ``<joint>.<row>_<spring>`` (``ROW_SPRINGS``).

    Spring j of a row acts along its deflection δ_j = B_j q (``_native.bearing_row_map``: the
    row's radial springs at its position a see x + a θ_w and y − a θ_u), with the row's k_j and
    c_j (``model/bearing_rows.py``): a row with a clearance as loaded (one side, k_j), a
    preloaded one as at its centre (both sides, 2 k_j).
    """
    out = []
    for row, spec in zip(bearing.rows, row_specs(bearing), strict=True):
        b = _native.bearing_row_map(spec, nv)
        for j, spring in enumerate(ROW_SPRINGS):
            k, c = row.stiffness[j], row.damping[j]
            if row.clearance < 0.0 and spring.startswith("radial"):
                k = 2.0 * k  # a preloaded row's two sides press at the centre (2 K_j)
            if (k == 0.0 and c == 0.0) or not np.any(b[j]):
                continue
            name = f"{row_name(joint, row.name)}_{spring}"
            out.append(SpringElement(name, "bearing", k, c, np.array(b[j], dtype=float)))
    return out


def roller_sum_elements(
    bearing: CompliantBearing, gravity: np.ndarray, nv: int
) -> list[SpringElement]:
    """A roller-sum bearing's radial law linearised about its loaded position: two springs.

    The position is the static deflection r under the model's weight, F(r) = g on the radial
    slides (g the generalised gravity at the reference pose; the loads of a run's torques are
    not in it), and the tangent K(r) (``model/roller_sum.py``) splits into springs along its
    principal directions, named ``<joint>_radial_x`` for the one nearer the slide x and
    ``<joint>_radial_y``, each with the radial damper (in contact: a loaded bearing).
    """
    c = bearing.compliance
    index = [bearing.v_index["radial_x"], bearing.v_index["radial_y"]]
    tangent = c.radial_tangent(c.static_deflection(-gravity[index]))
    values, vectors = np.linalg.eigh(tangent)
    values = np.maximum(values, 0.0)  # K is positive semi-definite: rounding only
    damping = c.radial_damping if np.any(tangent) else 0.0
    order = np.argsort(-np.abs(vectors[0]), kind="stable")
    out = []
    for column, name in zip(order, ("radial_x", "radial_y"), strict=True):
        row = np.zeros(nv)
        row[index] = vectors[:, column]
        out.append(SpringElement(bearing.slides[name], "bearing", values[column], damping, row))
    return out


#: Share of a rigid mode's motion on a floating bearing's slides above which that bearing is
#: unheld (a whole-train rotation has none).
UNHELD_SHARE = 1e-6


def check_held(gearbox: Gearbox, lin: LinearModel) -> None:
    """Refuse a floating bearing whose body a motion no mesh, spring or row resists moves.

    Raises:
        UnheldMember: names the bearing and the free motion (its largest joint coordinates).
    """
    floating = [b for b in gearbox.compliant_bearings.values() if b.compliance.floating]
    if not floating:
        return
    # Which motion no spring resists does not depend on the speed: the modes at rest tell.
    at_rest = natural_modes(lin.mass, lin.stiffness, lin.damping, lin.constraints)
    for mode in at_rest:
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
