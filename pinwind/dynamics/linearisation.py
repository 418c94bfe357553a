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

The linearisation is about the reference pose at an operating speed v₀ (the given joints' speeds,
the others through the gear ratios). The speed enters through the velocity terms of the equations
of motion, C(q, v) v: linearised about v₀ they give a gyroscopic matrix G = ∂(C v)/∂v and a
centrifugal stiffness ∂(C v)/∂q (Pinocchio's RNEA derivatives). On today's coordinates both vanish
exactly: every body turns about its own axis of symmetry, fixed or carried at a fixed radius by the
carrier, so the kinetic energy ½ vᵀ M v has an M that does not depend on q and every Christoffel
symbol is zero; the modes are those at rest at every speed. Translational coordinates (a planet
moving in its bearing on the turning carrier) would feel Coriolis and centripetal terms; their
modes at speed (a quadratic eigenproblem with a gyroscopic G) are pending, and a linearisation at
a speed where these terms would move the frequencies (``SPEED_TERMS_TOLERANCE``) is refused
(``SpeedOutOfRange``) rather than solved without them. (G is ∂(C v)/∂v, not Pinocchio's Coriolis
matrix C(q, v₀): the two differ by (∂C/∂v) v₀.)
The mean stiffness stands for its variation along the path, and there is no backlash (the teeth
in contact on the front flank).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from pinwind.dynamics.compliant import mesh_choices, mesh_setup
from pinwind.dynamics.coordinates import Coordinate, coordinates
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.normal_modes import Mode, SpringElement, element_matrices, natural_modes
from pinwind.dynamics.planetary_modes import PlanetaryStage, mode_kinds, planetary_stages
from pinwind.dynamics.ratios import train_speeds
from pinwind.errors import SpeedOutOfRange, UnheldMember, UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import CompliantBearing, Gearbox
from pinwind.units import rad_s_to_rpm

#: Fastest joint speed a linearisation is asked at [rad/s]: ``simulate``'s plausibility bound,
#: beyond which a run is called diverged (≈ 955 000 rpm; a 10 mm pinion's pitch-line speed would
#: be 1000 m/s).
MAX_SPEED = 1e5
#: Velocity terms that would move the natural frequencies by less than this fraction are left out
#: (the modes are printed to 5 digits): K_Ω against |K|, G against √(|K| |M|) (G ω against K at
#: the train's frequency scale ω = √(|K|/|M|)); with no stiffness at all (every mesh rigid), any
#: term above rounding (10⁻⁹ of |M| Ω and |M| Ω²) counts.
SPEED_TERMS_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Linearisation:
    """M q̈ + C q̇ + K q = 0 under J q̇ = 0 on the joint coordinates (module docstring).

    Attributes:
        joint_names: the coordinates, in the order of the velocity vector.
        mass, stiffness, damping: M [kg·m²], K [N·m/rad], C [N·m·s/rad], (nv, nv) (kg, N/m
            and N·s/m on a compliant bearing's slides).
        constraints: J (r, nv): rigid meshes, held joints, locked bearings.
        elements: the springs K is made of (meshes, torsional springs, bearing slides).
        coordinates: each coordinate's kind (rotation, translation) and axis.
        stages: the planetary stages, whose modes are classified (``planetary_modes.py``).
        speed: v₀ (nv,), the operating joint speeds [rad/s].
        gyroscopic: G = ∂(C(q, v) v)/∂v at v₀ [N·m·s/rad], (nv, nv); zero on torsional models.
        centrifugal: ∂(C(q, v) v)/∂q at v₀ [N·m/rad], (nv, nv); zero on torsional models.
    """

    joint_names: list[str]
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    constraints: np.ndarray
    elements: list[SpringElement]
    coordinates: list[Coordinate]
    stages: list[PlanetaryStage]
    speed: np.ndarray
    gyroscopic: np.ndarray
    centrifugal: np.ndarray

    def modes(self) -> list[Mode]:
        """The natural modes, lowest first (rigid ones at 0 Hz), each with its class.

        Raises:
            SpeedOutOfRange: the velocity terms act at this speed (module docstring).
        """
        self._check_speed_terms()
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

    def _check_speed_terms(self) -> None:
        omega = float(np.abs(self.speed).max(initial=0.0))
        inertia = float(np.abs(self.mass).max(initial=0.0))
        stiffness = float(np.abs(self.stiffness).max(initial=0.0))
        if stiffness > 0.0:
            g_scale, k_scale = math.sqrt(stiffness * inertia), stiffness
        else:
            g_scale, k_scale = 1e-3 * inertia * omega, 1e-3 * inertia * omega**2
        g = np.abs(self.gyroscopic).max(axis=0, initial=0.0) / (g_scale or 1.0)
        k = np.abs(self.centrifugal).max(axis=0, initial=0.0) / (k_scale or 1.0)
        acted = np.flatnonzero(np.maximum(g, k) > SPEED_TERMS_TOLERANCE)
        if acted.size:
            names = ", ".join(self.joint_names[j] for j in acted)
            raise SpeedOutOfRange(
                f"at the operating speed (fastest joint {omega:.4g} rad/s) gyroscopic and "
                f"centrifugal terms act on {names}; modes at speed with them are pending "
                "(issue 24): linearise at speed 0"
            )


def linearise(
    gearbox: Gearbox,
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    added_inertia: Mapping[str, float] | None = None,
    speeds: Mapping[str, float] | None = None,
) -> Linearisation:
    """The train's linearisation at its reference pose and an operating speed (module docstring).

    Args:
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a ``MeshCompliance``,
            as ``simulate`` takes it; default the model file's choice.
        held: joints held at their speed (a speed driver, a stiff grid-connected generator).
        added_inertia: joint name → inertia added to it [kg·m²] (a rotor).
        speeds: joint name → operating speed [rad/s] (≥ 0), the other joints at the speeds the
            gear ratios and springs give them; default at rest.

    Raises:
        UnknownJoint: a held joint, inertia or speed on a joint the model does not have.
        SpeedOutOfRange: a speed negative or not finite, or a joint beyond ``MAX_SPEED``.
    """
    names = list(gearbox.joint_names)
    for name in [*held, *(added_inertia or {})]:
        if name not in names:
            raise UnknownJoint(name, "held joints or added inertia", names)
    for name in speeds or {}:
        if name not in names:
            raise UnknownJoint(name, "the operating speeds", names)
    speed = operating_speed(gearbox, speeds or {})
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
    gyroscopic, centrifugal = speed_terms(gearbox, speed)
    coords = coordinates(gearbox)
    order = sorted(names, key=gearbox.v_index)
    out = Linearisation(
        order,
        mass,
        stiffness,
        damping,
        np.array(constraints).reshape(-1, nv),
        elements,
        coords,
        planetary_stages(gearbox, coords),
        speed,
        gyroscopic,
        centrifugal,
    )
    _check_held(gearbox, out)
    return out


def operating_speed(gearbox: Gearbox, speeds: Mapping[str, float]) -> np.ndarray:
    """v₀ (nv,) [rad/s]: the given joint speeds and the others through the ratios and springs.

    Raises:
        SpeedOutOfRange: a given speed negative or not finite, or a joint beyond ``MAX_SPEED``.
    """
    for name, value in speeds.items():
        if not (math.isfinite(value) and value >= 0.0):
            raise SpeedOutOfRange(
                f'speed {value:g} rad/s ({rad_s_to_rpm(value):g} rpm) of "{name}": give 0 or more '
                "(the modes do not depend on the direction of turning)"
            )
    if not speeds:
        return np.zeros(gearbox.model.nv)
    v = np.asarray(train_speeds(gearbox, speeds, through_springs=True), dtype=float)
    fastest = int(np.argmax(np.abs(v)))
    if abs(v[fastest]) > MAX_SPEED:
        given = ", ".join(f"{n} {rad_s_to_rpm(x):g} rpm" for n, x in speeds.items())
        raise SpeedOutOfRange(
            f'at {given}, joint "{sorted(gearbox.joint_names, key=gearbox.v_index)[fastest]}" '
            f"turns at {abs(v[fastest]):.4g} rad/s ({rad_s_to_rpm(abs(v[fastest])):.4g} rpm), "
            f"beyond the {MAX_SPEED:.0e} rad/s a gear can turn at (a run beyond it is "
            "diverged); give a lower speed"
        )
    return v


def speed_terms(gearbox: Gearbox, speed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """G = ∂(C v)/∂v and K_Ω = ∂(C v)/∂q at the reference pose and ``speed`` (module docstring).

    Pinocchio's RNEA derivatives at (q₀, v₀, 0) less those at (q₀, 0, 0): gravity drops out.
    """
    model, data = gearbox.model, gearbox.model.createData()
    q, zero = gearbox.neutral(), np.zeros(model.nv)
    if not np.any(speed):
        return np.zeros((model.nv, model.nv)), np.zeros((model.nv, model.nv))
    pin.computeRNEADerivatives(model, data, q, zero, zero)
    at_rest = np.array(data.dtau_dq)
    pin.computeRNEADerivatives(model, data, q, speed, zero)
    return np.array(data.dtau_dv), np.array(data.dtau_dq) - at_rest


def bearing_elements(gearbox: Gearbox) -> list[SpringElement]:
    """The compliant bearings' springs and dampers, one per slide (``<joint>_<slide>``).

    A linear bearing with a radial clearance counts as loaded (the clearance taken up, stiffness
    k); a floating bearing's radial slides have none. A roller-sum bearing is linearised about
    its static deflection under the model's weight (``roller_sum_elements``).
    """
    nv = gearbox.model.nv
    out: list[SpringElement] = []
    gravity = None
    for bearing in gearbox.compliant_bearings.values():
        c = bearing.compliance
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
