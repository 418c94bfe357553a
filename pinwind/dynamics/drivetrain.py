"""The drivetrain: the gearbox with what a run puts on it, the one machine runs and modes take.

A model file describes the gearbox; a run adds to it the rotor on its shaft (an inertia and an
aerodynamic torque), the generator's law on the output, speed drivers that hold their joints, the
applied torques and gravity, and the run's choice of rigid or compliant meshes. ``drivetrain``
checks those inputs once (an error names the argument, as ``simulate``'s always did) and builds a
``Drivetrain``; ``simulate`` steps it and ``linearisation.linearise`` linearises it, so the modes,
the run's highest mesh mode and the dt advice are those of the machine the run steps:

- bodies: the gearbox's, plus the rotors' inertias on their joints (``added_inertia``, the
  compiled loop's armature);
- elements: meshes, torsional springs, bearings and support from the gearbox, with the run's
  mesh choice (``meshes``); generator and rotor laws (``loads``);
- rows: rigid meshes, speed drivers (a driver holds its joint: fixed in the modes), locked
  bearings;
- loads at the operating point: applied torques at t = 0, gravity, the generator torque and the
  rotor's aerodynamic torque at the operating speed (``static_load``), and the laws' slopes
  dT/dω, dampers in the linearisation (``law_damping``).

The operating point is the run's start: the initial speeds and the speed drivers at t = 0, the
other joints through the gear ratios and the torsional springs (the mean running speeds of
spring-coupled shafts), and the wind at t = 0.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pinwind.dynamics.compliant import mesh_choices
from pinwind.dynamics.ratios import train_speeds
from pinwind.errors import (
    ConflictingConstraints,
    ConflictingInputs,
    InputError,
    NonFiniteInput,
    UnknownJoint,
)
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox, Mesh

if TYPE_CHECKING:
    # The laws' modules are imported where a drivetrain has laws or loads: `pinwind modes
    # MODEL`, the gearbox alone, starts without them (tests/test_lazy_exports.py).
    from pinwind.dynamics.elements import LoadElements
    from pinwind.loads.generator import GeneratorLaw
    from pinwind.loads.hub_loads import HubLoad
    from pinwind.loads.inputs import JointLoad, Signal
    from pinwind.loads.rotor import Rotor
    from pinwind.loads.signals import Signal as TimeSignal

#: Relative step of the central differences that give the slope dT/dω of a law without a closed
#: form (the induction machine's curve, the rotor's C_p): h = STEP · max(|ω|, 1 rad/s). The
#: laws are smooth; the truncation error O(h²) is ~1e-10 of the slope, rounding ~1e-16/h.
SLOPE_STEP = 1e-5


@dataclass(frozen=True)
class Drivetrain:
    """A gearbox with a run's rotor, generator, drivers, loads and mesh choice (module docstring).

    Attributes:
        gearbox: the model.
        meshes: the gearbox's meshes with the run's rigid/compliant choice
            (``compliant.mesh_choices``).
        torques: applied joint torques (``loads/inputs.py``), numbers or signals [N·m].
        drivers: speed drivers, each holding its joint at its speed [rad/s].
        initial_speeds: given initial speeds [rad/s].
        loads: the generator and rotor laws compiled, with the rotors' inertias
            (``LoadElements.added_inertia``) and the wind; None without laws.
        generators: joint name → generator law (``loads/generator.py``).
        rotors: joint name → ``Rotor`` (``loads/rotor.py``).
        gravity: gravity in world [m/s²].
        held: joints held besides the drivers and the locked bearings (a stiff grid-connected
            generator held at its speed in the modes: ``pinwind modes --hold``).
    """

    gearbox: Gearbox
    meshes: list[Mesh]
    torques: list[JointLoad] = field(default_factory=list)
    drivers: list[JointLoad] = field(default_factory=list)
    initial_speeds: list[JointLoad] = field(default_factory=list)
    loads: LoadElements | None = None
    generators: Mapping[str, GeneratorLaw] = field(default_factory=dict)
    rotors: Mapping[str, Rotor] = field(default_factory=dict)
    gravity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    held: tuple[str, ...] = ()

    @property
    def rows(self) -> list[JointLoad]:
        """The joints held by rows after the meshes: the speed drivers, then the locked bearings.

        A locked bearing is a row at zero speed; the order is the compiled loop's.
        """
        from pinwind.loads.inputs import JointLoad

        locks = [JointLoad(j, self.gearbox.v_index(j), 0.0) for j in self.gearbox.locked_joints]
        return [*self.drivers, *locks]

    @property
    def held_joints(self) -> list[str]:
        """Every joint a linearisation holds: the drivers, ``held`` and the locked bearings."""
        names = [d.joint for d in self.drivers] + list(self.held)
        names += [j for j in self.gearbox.locked_joints if j not in names]
        return list(dict.fromkeys(names))

    @property
    def added_inertia(self) -> dict[str, float]:
        """Joint name → inertia the run adds to it [kg·m²] (the rotors')."""
        names = sorted(self.gearbox.joint_names, key=self.gearbox.v_index)
        added = self.loads.added_inertia if self.loads is not None else {}
        return {names[i]: inertia for i, inertia in added.items()}

    def mass(self, q: np.ndarray | None = None) -> np.ndarray:
        """M(q) [kg·m² and kg]: the bodies' (CRBA, symmetric) plus the added inertias.

        At the reference pose by default.
        """
        model = self.gearbox.model
        q = self.gearbox.neutral() if q is None else q
        mass = pin.crba(model, model.createData(), q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        for index, inertia in (self.loads.added_inertia if self.loads is not None else {}).items():
            mass[index, index] += inertia
        return mass

    def with_meshes(self, meshes: Mapping[str, str | MeshCompliance]) -> Drivetrain:
        """The same drivetrain with the gearbox's meshes chosen afresh (``mesh_choices``)."""
        return replace(self, meshes=mesh_choices(self.gearbox, meshes))

    def operating_speed(self) -> np.ndarray:
        """v₀ (nv,) [rad/s]: the run's start speeds (module docstring); zero when none given.

        Speeds given on both sides of a torsional spring that twist it at the start are taken as
        given, the springs left out of the ratios.
        """
        given = {ld.joint: ld(0.0) for ld in [*self.initial_speeds, *self.drivers]}
        if not given:
            return np.zeros(self.gearbox.model.nv)
        try:
            v = train_speeds(self.gearbox, given, through_springs=True)
        except ConflictingConstraints:
            v = train_speeds(self.gearbox, given)
        return np.asarray(v, dtype=float)

    def wind_at_start(self) -> float:
        """The wind speed at t = 0 [m/s] (0 without rotors)."""
        if self.loads is None or self.loads.wind is None:
            return 0.0
        return float(np.asarray(self.loads.wind.values(np.zeros(1)), dtype=float)[0])

    def static_load(self, speed: np.ndarray) -> StaticLoad:
        """The generalised static load at the reference pose and ``speed`` (``StaticLoad``).

        The applied torques at t = 0, the bodies' weights (``gravity``), each generator's
        −T_gen(ω) and each rotor's aerodynamic torque at ω and the wind at t = 0. The speed
        drivers' torques are their rows' multipliers, not loads.
        """
        gearbox = self.gearbox
        nv = gearbox.model.nv
        load, gross = np.zeros(nv), np.zeros(nv)
        for ld in self.torques:
            load[ld.v_index] += ld(0.0)
            gross[ld.v_index] += abs(ld(0.0))
        for weight in _weights(gearbox, self.gravity):
            load += weight
            gross += np.abs(weight)
        wind = self.wind_at_start()
        torques: list[tuple[str, float]] = []
        for name, law in self.generators.items():
            j = gearbox.v_index(name)
            torques.append((name, -generator_torque(law, float(speed[j]))))
        if self.rotors:
            from pinwind.dynamics.elements import rotor_torque

            for name, rotor in self.rotors.items():
                j = gearbox.v_index(name)
                torques.append((name, rotor_torque(rotor, float(speed[j]), wind)))
        for name, value in torques:
            load[gearbox.v_index(name)] += value
            gross[gearbox.v_index(name)] += abs(value)
        return StaticLoad(load, gross)

    def law_damping(self, speed: np.ndarray) -> dict[str, float]:
        """Joint name → the laws' damping c = −d(torque on the joint)/dω at ``speed`` [N·m·s/rad].

        A generator brakes its shaft with T_gen(ω): c = dT_gen/dω (``generator_slope``); a rotor
        drives its shaft with T_aero(ω, v): c = −∂T_aero/∂ω at the wind at t = 0 (aerodynamic
        damping, ``rotor_slope``). Negative where the torque grows with the speed (a constant
        power law above rated).
        """
        out: dict[str, float] = {}
        for name, law in self.generators.items():
            j = self.gearbox.v_index(name)
            out[name] = out.get(name, 0.0) + generator_slope(law, float(speed[j]))
        wind = self.wind_at_start()
        for name, rotor in self.rotors.items():
            j = self.gearbox.v_index(name)
            out[name] = out.get(name, 0.0) - rotor_slope(rotor, float(speed[j]), wind)
        return out


@dataclass(frozen=True)
class StaticLoad:
    """A generalised static load on the joint coordinates.

    Attributes:
        load: F (nv,) [N·m on rotations, N on slides].
        gross: the sum of the magnitudes of its contributions (nv,): each torque, law and body
            weight taken by its size, so that loads that cancel (the weights of equally spaced
            planets on the carrier) are told apart from no load.
    """

    load: np.ndarray
    gross: np.ndarray


def _weights(gearbox: Gearbox, gravity: np.ndarray) -> list[np.ndarray]:
    """Each body's weight m g at its centre of mass as a generalised force (nv,) at q₀.

    J_c(q₀)ᵀ m g, J_c the linear Jacobian of the body's centre of mass (world axes); their sum
    is −g(q₀), Pinocchio's generalised gravity with this gravity vector.
    """
    g = np.asarray(gravity, dtype=float)
    if not np.any(g):
        return []
    model = gearbox.model
    data = model.createData()
    pin.computeJointJacobians(model, data, gearbox.neutral())
    out = []
    for joint in range(1, model.njoints):
        inertia = model.inertias[joint]
        if inertia.mass <= 0.0:
            continue
        jac = pin.getJointJacobian(model, data, joint, pin.LOCAL_WORLD_ALIGNED)
        arm = data.oMi[joint].rotation @ inertia.lever
        linear = jac[:3] - pin.skew(arm) @ jac[3:]
        out.append(linear.T @ (inertia.mass * g))
    return out


def drivetrain(
    gearbox: Gearbox,
    *,
    torques: Mapping[str, Signal] | None = None,
    speeds: Mapping[str, Signal] | None = None,
    initial_speeds: Mapping[str, float] | None = None,
    generators: Mapping[str, GeneratorLaw] | None = None,
    rotors: Mapping[str, Rotor] | None = None,
    wind: float | TimeSignal | None = None,
    hub_loads: Sequence[HubLoad] | None = None,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    gravity: np.ndarray | Sequence[float] | None = None,
    held: Iterable[str] = (),
) -> Drivetrain:
    """Check a run's inputs and build its ``Drivetrain`` (``simulate``'s arguments, same names).

    Args:
        torques: joint name → torque [N·m], number or callable(t).
        speeds: joint name → prescribed speed [rad/s], number or callable(t) (speed drivers).
        initial_speeds: joint name → initial speed [rad/s].
        generators: joint name → generator law; rotors: joint name → ``Rotor``.
        wind: wind speed at the rotors [m/s], a number or a signal; needed with rotors.
        hub_loads: loads of six components on bodies (``loads/hub_loads.py``).
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a ``MeshCompliance``.
        gravity: gravity in world [m/s²]; default the model's.
        held: joints the linearisation holds besides the drivers (``Drivetrain.held``).

    Raises:
        InputError: unknown joint names, non-finite values, a torque or speed on a fixed mount,
            bad laws; ConflictingInputs: a joint given both a torque and a speed.
    """
    index = {name: gearbox.v_index(name) for name in gearbox.joint_names}
    free = {k: i for k, i in index.items() if k not in gearbox.locked_joints}
    probe = (0.0,)  # later failures are caught in the run, which logs the samples before them
    if torques or speeds or initial_speeds:
        from pinwind.loads.inputs import joint_loads
    torque_loads = (
        []
        if not torques
        else joint_loads(torques, where="torques", joint_index=index, unit="N·m", probe_times=probe)
    )
    for name in torques or {}:
        if name in gearbox.locked_joints:
            raise InputError(
                f'joint "{name}" is a fixed mount (a gear on a fixed joint, held at zero speed); '
                "a torque on it would vanish into the lock. Load one of: " + ", ".join(free)
            )
    for name in torques or {}:
        if name in (speeds or {}):
            raise ConflictingInputs(
                f'joint "{name}" is given both torques["{name}"] and speeds["{name}"]; the speed '
                "driver would absorb the torque, which then loads no gear (every mesh force 0): "
                "give the joint either a torque or a speed"
            )
    for name in list(speeds or {}) + list(initial_speeds or {}):
        if name in gearbox.locked_joints:
            raise InputError(
                f'joint "{name}" is a fixed mount (a gear on a fixed joint, held at zero speed); '
                "it cannot be driven or given a speed. Drive one of: " + ", ".join(free)
            )
    speed_loads = (
        []
        if not speeds
        else joint_loads(speeds, where="speeds", joint_index=free, unit="rad/s", probe_times=probe)
    )
    init = (
        []
        if not initial_speeds
        else joint_loads(initial_speeds, where="initial_speeds", joint_index=free, unit="rad/s")
    )
    slides = set(gearbox.slide_joints)
    for load in init:
        start = float(load(0.0))
        if load.joint in slides and start != 0.0:
            # The start speeds hold every slide at rest (train_speeds); a speed given one was
            # reported as speed drivers conflicting with the gear meshes.
            turning = [name for name in free if name not in slides]
            raise InputError(
                f'initial_speeds["{load.joint}"] = {start:g}: "{load.joint}" is a slide of a '
                "compliant bearing or of the support, which starts at rest (at its static "
                'deflection, or undeflected with initial_deflection="none"); its speed is not '
                "an input. Give initial speeds to the turning joints: " + ", ".join(turning)
            )
    held = tuple(held)
    for name in held:
        if name not in index:
            raise UnknownJoint(name, "held joints", list(index))
    if gravity is not None:
        g = np.asarray(gravity, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise NonFiniteInput(f"gravity must be three finite numbers [m/s²]; got {gravity!r}")
    else:
        g = np.asarray(gearbox.gravity, dtype=float)
    if wind is not None and not rotors:
        # It was ignored, even a NaN wind (--wind nan ran without a word).
        raise InputError(
            f"wind {wind!r} m/s is given but the run has no rotor, the one element that takes "
            "it; give a rotor (--rotor JOINT=PRESET, [rotor.JOINT], rotors=...) or leave out "
            "the wind"
        )
    laws = _laws(generators, rotors, wind, free)
    if laws is not None and any(rotor.hub is not None for rotor in (rotors or {}).values()):
        laws.add_rotor_hubs(gearbox, g)
    if hub_loads:
        from pinwind.dynamics.elements import LoadElements

        laws = laws if laws is not None else LoadElements()
        laws.add_hub_loads(list(hub_loads), gearbox, g)
    return Drivetrain(
        gearbox=gearbox,
        meshes=mesh_choices(gearbox, meshes),
        torques=torque_loads,
        drivers=speed_loads,
        initial_speeds=init,
        loads=laws,
        generators=dict(generators or {}),
        rotors=dict(rotors or {}),
        gravity=g,
        held=held,
    )


def _laws(
    generators: Mapping[str, GeneratorLaw] | None,
    rotors: Mapping[str, Rotor] | None,
    wind: float | TimeSignal | None,
    free: Mapping[str, int],
) -> LoadElements | None:
    """The laws compiled and checked (``elements.load_elements``); None without any."""
    if not (generators or rotors):
        return None
    from pinwind.dynamics.elements import load_elements

    return load_elements(generators, rotors, wind, joint_index=free)


def generator_torque(law: GeneratorLaw, speed: float) -> float:
    """T_gen [N·m] of a law at shaft speed ω [rad/s], positive generating (``loads/generator.py``).

    The dq machine's is its steady-state curve, the torque its fluxes settle to at ω.
    """
    from pinwind.dynamics.elements import induction_torque
    from pinwind.loads.generator import (
        ConstantTorque,
        InductionMachine,
        LinearSlip,
        VariableSpeed,
    )

    if isinstance(law, ConstantTorque):
        return float(law.torque)
    if isinstance(law, LinearSlip):
        return law.slope * (speed - law.sync_speed)
    if isinstance(law, VariableSpeed) and law.rated_torque > 0.0:  # the compiled law
        from pinwind.dynamics import _native
        from pinwind.dynamics.elements import generator_spec

        return -_native.shaft_speed_torque(generator_spec(law, 0), float(speed))
    if isinstance(law, VariableSpeed):
        below = law.gain * speed * abs(speed)
        if law.rated_power > 0.0 and abs(below * speed) > law.rated_power:
            return math.copysign(law.rated_power / abs(speed), speed)
        return below
    if isinstance(law, InductionMachine):
        return induction_torque(law, speed)
    raise InputError(f"{law!r} is not a generator law (pinwind.loads.generator)")


def generator_slope(law: GeneratorLaw, speed: float) -> float:
    """dT_gen/dω [N·m·s/rad] at ω [rad/s]: the damping the law adds to its shaft.

    Closed forms: 0 (constant), k (linear slip), 2 K |ω| below rated and −P/ω² above (variable
    speed at constant power); the variable-speed law at constant torque and the induction
    machine's curve by central differences (``SLOPE_STEP``), the dq
    machine's steady-state curve (its flux dynamics are left out of the modes).
    """
    from pinwind.loads.generator import ConstantTorque, LinearSlip, VariableSpeed

    if isinstance(law, ConstantTorque):
        return 0.0
    if isinstance(law, LinearSlip):
        return float(law.slope)
    if isinstance(law, VariableSpeed) and law.rated_torque == 0.0:
        below = law.gain * speed * abs(speed)
        if law.rated_power > 0.0 and abs(below * speed) > law.rated_power:
            return -law.rated_power / speed**2
        return 2.0 * law.gain * abs(speed)
    h = SLOPE_STEP * max(abs(speed), 1.0)
    return (generator_torque(law, speed + h) - generator_torque(law, speed - h)) / (2.0 * h)


def rotor_slope(rotor: Rotor, speed: float, wind: float) -> float:
    """∂T_aero/∂ω [N·m·s/rad] at rotor speed ω [rad/s] and wind v [m/s].

    The central difference the compiled rotor takes its implicit slope from (``cpp/rotor.hpp``:
    h = 10⁻⁶ (|ω| + max(v, 1 m/s)/R)). Zero without wind (the rotor then puts no torque on its
    shaft).
    """
    if wind <= 0.0:
        return 0.0
    from pinwind.dynamics.elements import rotor_torque

    h = 1e-6 * (abs(speed) + max(wind, 1.0) / rotor.radius)
    return (rotor_torque(rotor, speed + h, wind) - rotor_torque(rotor, speed - h, wind)) / (2.0 * h)
