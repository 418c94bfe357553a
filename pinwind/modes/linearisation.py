"""A drivetrain linearised at its reference pose: M, K, C and the rigid rows, and its modes.

The machine is the one a run steps (``dynamics/drivetrain.py``): the gearbox with the run's rotors,
generator laws, speed drivers, loads and mesh choice. The joint-space inertia M is Pinocchio's
(CRBA at the neutral pose) plus the rotors' inertias on their joints; the stiffness and damping are
those of the linear elements a run has: each compliant mesh a spring of its mean mesh stiffness
(``compliant.mean_mesh_stiffness``: c_γα b for the ISO shape, the mean of a pair table) and its
dashpot along the row of the flank the static load presses (``dynamics/loaded_flanks.py``: the line
of action of ``cpp/mesh_rows.hpp``, the same the step uses; whichever order the mesh's gears are
written in), each torsional spring k (e₁ − e₂), each damped bearing c on its joint, each compliant
bearing's and support slide its spring and damper (``linear_model.bearing_elements``), and each
generator rotor law's slope as a damper on its joint (c = dT_gen/dω, −∂T_aero/∂ω at the operating
speed and the wind at t = 0; ``Drivetrain.law_damping``). The rigid meshes (on their loaded
flanks), the held joints (speed drivers: a driver holds its joint) and the locked bearings are
rows; a floating bearing that nothing holds is refused. These are the run's own
(``dynamics/linear_model.py``, which a run uses for its mass, flanks and checks);
``dynamics/normal_modes.py``'s ``natural_modes`` solves the eigenproblem.

The linearisation is about the reference pose at an operating speed v₀ (the given joints' speeds,
the others through the gear ratios). The speed enters through the velocity terms of the equations
of motion, C(q, v) v: linearised about v₀ they give a gyroscopic matrix G = ∂(C v)/∂v and a
centrifugal stiffness K_Ω = ∂(C v)/∂q (Pinocchio's RNEA derivatives; G is not Pinocchio's
Coriolis matrix C(q, v₀): the two differ by (∂C/∂v) v₀). On torsional coordinates both vanish
exactly: every body turns about its own axis of symmetry, fixed or carried at a fixed radius by the
carrier, so the kinetic energy ½ vᵀ M v has an M that does not depend on q and every Christoffel
symbol is zero; the modes are those at rest at every speed. A body that spins while it tilts in a
compliant bearing feels its polar inertia's gyroscopic moment (G ≠ 0): its modes at speed solve
the quadratic eigenproblem (M λ² + (C + G) λ + K + K_Ω) φ = 0 (``gyroscopic_modes.py``), the
others the symmetric one (``dynamics/normal_modes.py``), exact and faster, whenever the velocity
terms would move no frequency by ``SPEED_TERMS_TOLERANCE``.

Modes at speed need equations whose coefficients stay constant while the train turns at v₀. They
do not when M or a mesh row depends on the angle of a turning joint: a body whose centre of mass
or inertia is off its axis (M changes as it turns), or a body translating on slides fixed to the
ground that meshes with planets the carrier carries round (the line of action turns). The
equations are then periodic in time, which no modal analysis covers, and such a linearisation is
refused (``SpeedOutOfRange``, ``TURNING_TOLERANCE``).
The mean stiffness stands for its variation along the path, and there is no backlash (the teeth
in contact on the loaded flank; a mesh no static load presses on the flank ``loaded_flanks``
states).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, fields, replace

import numpy as np
import pinocchio as pin

from pinwind.dynamics.coordinates import Coordinate, coordinates
from pinwind.dynamics.drivetrain import Drivetrain, drivetrain
from pinwind.dynamics.linear_model import LinearModel, check_held, linear_model, mesh_rows_at
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.normal_modes import Mode, natural_modes, repeated_groups
from pinwind.dynamics.ratios import train_speeds
from pinwind.errors import SpeedOutOfRange, UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox
from pinwind.modes.gyroscopic_modes import WhirlPair, gyroscopic_modes, whirl
from pinwind.modes.planetary_modes import PlanetaryStage, mode_kinds, planetary_stages
from pinwind.units import rad_s_to_rpm

#: Fastest joint speed a linearisation is asked at [rad/s]: ``simulate``'s plausibility bound,
#: beyond which a run is called diverged (≈ 955 000 rpm; a 10 mm pinion's pitch-line speed would
#: be 1000 m/s).
MAX_SPEED = 1e5
#: Velocity terms that would move the natural frequencies by less than this fraction are left out
#: (the modes are printed to 5 digits, and the symmetric solve takes them): K_Ω against |K|, G
#: against √(|K| |M|) (G ω against K at the train's frequency scale ω = √(|K|/|M|)); with no
#: stiffness at all (every mesh rigid), any term above rounding (10⁻⁹ of |M| Ω and |M| Ω²) counts.
SPEED_TERMS_TOLERANCE = 1e-6
#: Change of M (against |M|) or of a mesh row (against its largest entry) per radian a turning
#: joint turns above which the linearisation at speed is refused (module docstring).
TURNING_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Linearisation(LinearModel):
    """M q̈ + C q̇ + K q = 0 under J q̇ = 0 on the joint coordinates (module docstring).

    The run's linear model at rest (``LinearModel``: M, K, C, J, the springs, the loaded flanks,
    the added inertias and the laws' slopes), with what the modes add at an operating speed.

    Attributes:
        coordinates: each coordinate's kind (rotation, translation) and axis.
        stages: the planetary stages, whose modes are classified (``planetary_modes.py``).
        speed: v₀ (nv,), the operating joint speeds [rad/s].
        gyroscopic: G = ∂(C(q, v) v)/∂v at v₀ [N·m·s/rad], (nv, nv); zero on torsional models.
        centrifugal: ∂(C(q, v) v)/∂q at v₀ [N·m/rad], (nv, nv); zero on torsional models.
        whirl_pairs: the compliant bearings' radial and tilt pairs and their bodies' spin at v₀,
            whose orbits give a mode's whirl (``gyroscopic_modes.py``).
    """

    coordinates: list[Coordinate]
    stages: list[PlanetaryStage]
    speed: np.ndarray
    gyroscopic: np.ndarray
    centrifugal: np.ndarray
    whirl_pairs: list[WhirlPair]

    def modes(self) -> list[Mode]:
        """The natural modes, lowest first (rigid ones at 0 Hz), each with its class and whirl.

        The symmetric solve when the velocity terms move no frequency, the quadratic one at
        speed otherwise (module docstring).
        """
        if self.speed_terms_act():
            found = gyroscopic_modes(
                self.mass,
                self.stiffness,
                self.damping,
                self.constraints,
                gyroscopic=self.gyroscopic,
                centrifugal=self.centrifugal,
                joint_names=self.joint_names,
                elements=self.elements,
            )
            single = [g[0] for g in repeated_groups(found) if len(g) == 1]
            found = [
                replace(m, whirl=whirl(m, self.whirl_pairs)) if any(m is x for x in single) else m
                for m in found
            ]
        else:
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

    def speed_terms_act(self) -> bool:
        """G or K_Ω would move a frequency by ``SPEED_TERMS_TOLERANCE`` or more."""
        omega = float(np.abs(self.speed).max(initial=0.0))
        inertia = float(np.abs(self.mass).max(initial=0.0))
        stiffness = float(np.abs(self.stiffness).max(initial=0.0))
        if stiffness > 0.0:
            g_scale, k_scale = math.sqrt(stiffness * inertia), stiffness
        else:
            g_scale, k_scale = 1e-3 * inertia * omega, 1e-3 * inertia * omega**2
        g = float(np.abs(self.gyroscopic).max(initial=0.0)) / (g_scale or 1.0)
        k = float(np.abs(self.centrifugal).max(initial=0.0)) / (k_scale or 1.0)
        return max(g, k) > SPEED_TERMS_TOLERANCE

    def at_speed_scale(self, factor: float) -> Linearisation:
        """The same linearisation at ``factor`` times the operating speed (factor ≥ 0).

        G = ∂(C v)/∂v is linear in v₀ and K_Ω = ∂(C v)/∂q quadratic (C(q, v) v is quadratic in
        v), and nothing else depends on the speed: a Campbell diagram linearises once.
        """
        return replace(
            self,
            speed=factor * self.speed,
            gyroscopic=factor * self.gyroscopic,
            centrifugal=factor**2 * self.centrifugal,
            whirl_pairs=[replace(p, spin=factor * p.spin) for p in self.whirl_pairs],
        )


def linearise(
    machine: Gearbox | Drivetrain,
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    speeds: Mapping[str, float] | None = None,
) -> Linearisation:
    """The machine's linearisation at its reference pose and an operating speed (module docstring).

    Args:
        machine: the drivetrain a run steps (``drivetrain.drivetrain``: the rotors' inertias,
            the generator and rotor laws' slopes as dampers, the speed drivers held, the static
            loads that choose the flanks), or a gearbox alone (no rotor, no law, no load).
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a ``MeshCompliance``,
            as ``simulate`` takes it, replacing the machine's choice; default the model file's
            (a gearbox) or the drivetrain's.
        held: joints held at their speed besides the drivetrain's drivers (a speed driver, a
            stiff grid-connected generator).
        speeds: joint name → operating speed [rad/s] (≥ 0), the other joints at the speeds the
            gear ratios and springs give them: the velocity terms G and K_Ω are taken there, and
            the laws' slopes and static loads at it. Default: the velocity terms at rest, the
            laws at the drivetrain's start speeds (``Drivetrain.operating_speed``).

    A gearbox alone is linearised unloaded (no torque, no weight): every mesh on the flank
    ``loaded_flanks`` takes without load, stated in ``Linearisation.flanks.notes()``.

    Raises:
        UnknownJoint: a held joint or speed on a joint the model does not have.
        SpeedOutOfRange: a speed negative or not finite, a joint beyond ``MAX_SPEED``, or
            equations whose coefficients change as the train turns (module docstring).
        UnheldMember: a floating bearing that nothing holds.
    """
    if isinstance(machine, Drivetrain):
        train = machine
    else:  # the gearbox alone: no load presses a flank, not even its weight
        train = drivetrain(machine, meshes=meshes, gravity=np.zeros(3))
    if isinstance(machine, Drivetrain) and meshes is not None:
        train = train.with_meshes(meshes)
    gearbox = train.gearbox
    names = list(gearbox.joint_names)
    held = list(held)
    for name in held:
        if name not in names:
            raise UnknownJoint(name, "held joints", names)
    if held:
        train = replace(train, held=(*train.held, *held))
    for name in speeds or {}:
        if name not in names:
            raise UnknownJoint(name, "the operating speeds", names)
    speed = operating_speed(gearbox, speeds or {})
    at = speed if speeds else train.operating_speed()
    base = linear_model(train, at=at)
    _check_turning(gearbox, base.mesh_set, speed, base.mass, base.mesh_rows, base.flanks.flank)
    gyroscopic, centrifugal = speed_terms(gearbox, speed)
    coords = coordinates(gearbox)
    out = Linearisation(
        **{f.name: getattr(base, f.name) for f in fields(LinearModel)},
        coordinates=coords,
        stages=planetary_stages(gearbox, coords),
        speed=speed,
        gyroscopic=gyroscopic,
        centrifugal=centrifugal,
        whirl_pairs=whirl_pairs(gearbox, coords, speed),
    )
    check_held(gearbox, base)
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


def _mass(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """The bodies' joint-space inertia M(q) (CRBA, its upper triangle mirrored)."""
    mass = pin.crba(model, data, q)
    return np.triu(mass) + np.triu(mass, 1).T


def _check_turning(
    gearbox: Gearbox,
    mesh_set: MeshSet,
    speed: np.ndarray,
    mass: np.ndarray,
    mesh_rows: np.ndarray,
    flank: np.ndarray,
) -> None:
    """Refuse a linearisation at ``speed`` whose M or mesh rows change as a turning joint turns.

    Each joint turning at v₀ is turned 1 rad alone: M against |M| and the mesh rows against
    their largest entry (module docstring). A finite turn, as M may be at an extremum at the
    reference pose (a centre of mass off the axis, radially outward: ∂M/∂q = 0 there).

    Raises:
        SpeedOutOfRange: names the joints whose turning changes the equations.
    """
    # Joints the ratios leave at a rounding's speed (a fixed ring's 1e-13 rad/s) do not turn.
    turning = np.flatnonzero(np.abs(speed) > 1e-9 * float(np.abs(speed).max(initial=0.0)))
    if turning.size == 0:
        return
    model, data = gearbox.model, gearbox.model.createData()
    q = gearbox.neutral()
    mass_scale = float(np.abs(mass).max())
    row_scale = float(np.abs(mesh_rows).max(initial=0.0))
    names = sorted(gearbox.joint_names, key=gearbox.v_index)
    changing = []
    for j in turning:
        unit = np.zeros(model.nv)
        unit[j] = 1.0
        turned = pin.integrate(model, q, unit)
        # The added inertias (rotors) are constant: M's change is the bodies'.
        change = np.abs(_mass(model, data, turned) - _mass(model, data, q)).max()
        changed = change > TURNING_TOLERANCE * mass_scale
        if row_scale > 0.0 and not changed:
            turned_rows, _ = mesh_set.combine(mesh_rows_at(mesh_set, model, data, turned), flank)
            changed = np.abs(turned_rows - mesh_rows).max() > TURNING_TOLERANCE * row_scale
        if changed:
            changing.append(names[j])
    if changing:
        listed = ", ".join(changing)
        raise SpeedOutOfRange(
            f"at the operating speed (fastest joint {np.abs(speed).max():.4g} rad/s) the "
            f"velocity terms act on {listed} with coefficients that change as "
            f"{'it turns' if len(changing) == 1 else 'they turn'} (a centre of mass or inertia "
            "off the joint axis, or slides fixed to the ground under meshes that a carrier "
            "carries round): the linear equations are periodic in time and have no modes at "
            "speed; balance the body, or linearise at speed 0"
        )


def whirl_pairs(gearbox: Gearbox, coords: list[Coordinate], speed: np.ndarray) -> list[WhirlPair]:
    """Each compliant bearing's radial and tilt pairs with its body's spin at ``speed``.

    The spin is the body's angular velocity (Pinocchio's, at the bearing's revolute joint, world
    axes) along k = u × w of the pair's coordinates.
    """
    model, data = gearbox.model, gearbox.model.createData()
    pin.forwardKinematics(model, data, gearbox.neutral(), speed)
    out = []
    for bearing in gearbox.compliant_bearings.values():
        jid = model.getJointId(bearing.joint)
        angular = pin.getVelocity(model, data, jid, pin.LOCAL_WORLD_ALIGNED).angular
        for u, w in (("radial_x", "radial_y"), ("tilt_x", "tilt_y")):
            if u not in bearing.v_index:
                continue
            iu, iw = bearing.v_index[u], bearing.v_index[w]
            k = np.cross(coords[iu].axis, coords[iw].axis)
            out.append(WhirlPair(bearing.joint, (iu, iw), float(angular @ k)))
    return out


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
