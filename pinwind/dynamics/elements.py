"""Generator and rotor laws (``loads/``) as the compiled step loop takes them.

``load_elements`` checks the joint names and the laws, and gives the compiled specs
(``_native.GeneratorSpec``, ``_native.RotorSpec``, from ``generator_spec`` and ``rotor_spec``),
the rotor inertias to add to their joints, and the per-sample input columns the rotors read (one
wind-speed column). The compiled laws can also be evaluated alone (``induction_torque``,
``rotor_torque``, ``rotor_power_coefficient``, ``rotor_thrust``, ``optimal_gain``): the numbers the
step loop uses. ``LoadElements.add_rotor_hubs`` places a rotor's thrust, weight and shear moment
on its hub's body.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from pinwind.dynamics import _native
from pinwind.errors import InputError, NonFiniteInput, UnknownJoint
from pinwind.loads.generator import (
    ConstantTorque,
    GeneratorLaw,
    InductionMachine,
    LinearSlip,
    VariableSpeed,
    describe,
)
from pinwind.loads.hub_loads import COMPONENTS, HubFrame, HubLoad
from pinwind.loads.rotor import CpTable, Rotor, hub_weight, shear_arm
from pinwind.loads.signal_text import signal_from_spec
from pinwind.loads.signals import Signal


@dataclass
class LoadElements:
    """The compiled generator and rotor specs of a run.

    Attributes:
        generators, rotors: compiled specs.
        generator_names, rotor_names: their joints, in the same order.
        rotor_laws: joint name → ``Rotor``.
        added_inertia: velocity index → inertia added to the joint [kg·m²] (rotors).
        input_columns: per-sample inputs: the wind speed [m/s] with rotors (column 0), then
            six per hub load (its F_x, F_y, F_z [N], M_x, M_y, M_z [N·m]).
        wind: the wind-speed signal [m/s], or None.
        hub_loads: the hub loads (``loads/hub_loads.py``) and hub_load_specs their compiled
            specs (``dynamics/hub_load_specs.py``), in the same order.
        metadata: the laws as plain values, for the log.
    """

    generators: list[_native.GeneratorSpec] = field(default_factory=list)
    rotors: list[_native.RotorSpec] = field(default_factory=list)
    generator_names: list[str] = field(default_factory=list)
    rotor_names: list[str] = field(default_factory=list)
    rotor_laws: dict[str, Rotor] = field(default_factory=dict)
    added_inertia: dict[int, float] = field(default_factory=dict)
    input_columns: int = 0
    wind: Signal | None = None
    hub_loads: list[HubLoad] = field(default_factory=list)
    hub_load_specs: list[_native.HubLoadSpec] = field(default_factory=list)
    metadata: dict[str, Any] = field(default_factory=dict)

    def add_hub_loads(self, loads: Sequence[HubLoad], gearbox: Any, gravity: np.ndarray) -> None:
        """Add hub loads, their inputs after the others' (``dynamics/hub_load_specs.py``).

        Raises:
            InputError: a load that is not a ``HubLoad``, or one the model cannot take.
        """
        from pinwind.dynamics.hub_load_specs import hub_load_specs

        for load in loads:
            if not isinstance(load, HubLoad):
                raise InputError(
                    f"hub_loads holds {load!r}; give pinwind.loads.hub_loads.HubLoad objects "
                    "(constant_hub_load, hub_load_from_openfast)"
                )
        self.hub_load_specs += hub_load_specs(loads, gearbox, gravity, self.input_columns)
        self.hub_loads += list(loads)
        self.input_columns += 6 * len(loads)
        self.metadata["hub_loads"] = [load.describe() for load in self.hub_loads]

    def add_rotor_hubs(self, gearbox: Any, gravity: np.ndarray) -> None:
        """Give each rotor with a hub its loads on the hub's body (``loads/rotor.py``).

        The hub's fixed frame is a fixed ``HubLoad``'s (``dynamics/hub_load_specs.py``); the
        weight is the model's gravity in it, turned by the shaft tilt (``hub_weight``).

        Raises:
            InputError: a hub on a body the model cannot load (as a hub load's), or a rotor mass
                with no gravity to weigh it.
        """
        from pinwind.dynamics.hub_load_specs import fixed_axes_at_rest, hub_load_specs

        for spec, name in zip(self.rotors, self.rotor_names, strict=True):
            rotor = self.rotor_laws[name]
            if rotor.hub is None:
                continue
            where = HubLoad(rotor.hub.body, (0.0,) * 6, HubFrame.FIXED, rotor.hub.point,
                            rotor.hub.up)  # fmt: skip
            try:
                (placement,) = hub_load_specs([where], gearbox, gravity, 0)
            except InputError as err:
                raise InputError(f'rotor on "{name}": its hub_body: {err}') from err
            if rotor.mass and not np.any(gravity):
                raise InputError(
                    f'rotor on "{name}": its mass {rotor.mass} kg has no weight: the model has '
                    "no gravity; give the model gravity, or mass=0"
                )
            spec.hub = True
            spec.hub_load = placement
            gravity_in_hub = fixed_axes_at_rest(placement, gearbox).T @ gravity
            spec.weight = hub_weight(rotor.mass, rotor.shaft_tilt, gravity_in_hub)
            spec.shear_arm = shear_arm(rotor.radius, rotor.hub_height, rotor.shear_exponent)

    def inputs(self, times: np.ndarray) -> np.ndarray | None:
        """The per-sample inputs at ``times`` [s], (len(times), input_columns), or None.

        Values are as the signals give them, finite or not: the run checks them step by step
        (``input_names`` names each column).
        """
        if not self.input_columns:
            return None
        columns = []
        if self.wind is not None:
            columns.append(np.asarray(self.wind.values(times), dtype=float).reshape(-1, 1))
        columns += [load.values(times, check=False) for load in self.hub_loads]
        return np.ascontiguousarray(np.hstack(columns))

    @property
    def input_names(self) -> list[tuple[str, str]]:
        """(name, unit) of each input column, as messages name them."""
        names = [("wind", "m/s")] if self.wind is not None else []
        for load in self.hub_loads:
            names += [
                (f'hub load on "{load.body}": {c}', "N" if c.startswith("force") else "N·m")
                for c in COMPONENTS
            ]
        return names


_GENERATORS = GeneratorLaw.__args__  # type: ignore[attr-defined]


def load_elements(
    generators: Mapping[str, GeneratorLaw] | None,
    rotors: Mapping[str, Rotor] | None,
    wind: Signal | float | None,
    *,
    joint_index: Mapping[str, int],
) -> LoadElements:
    """Check generator and rotor laws and build their compiled specs.

    Args:
        generators: joint name → generator law (``loads/generator.py``).
        rotors: joint name → ``Rotor``.
        wind: wind speed [m/s] at the rotors: a number or a ``Signal``; needed with rotors.
        joint_index: joint name → velocity index of every joint that may carry them.

    Raises:
        UnknownJoint, InputError, NonFiniteInput: a bad joint, law or wind.
    """
    out = LoadElements()
    for name, law in (generators or {}).items():
        if name not in joint_index:
            raise UnknownJoint(name, "generators", joint_index)
        if not isinstance(law, _GENERATORS):
            raise InputError(
                f'generators["{name}"] is {law!r}; give a ConstantTorque, LinearSlip, '
                "VariableSpeed or InductionMachine (pinwind.loads.generator)"
            )
        _check_finite(law, f'generators["{name}"]')
        if isinstance(law, InductionMachine):
            positive = ("rotor_resistance", "magnetizing", "voltage", "frequency", "poles")
            for key in positive:
                if not getattr(law, key) > 0:
                    raise InputError(f'generators["{name}"].{key} must be positive')
            if law.poles % 2:
                raise InputError(f'generators["{name}"].poles = {law.poles} must be even')
        out.generators.append(generator_spec(law, joint_index[name]))
        out.generator_names.append(name)
        out.metadata.setdefault("generators", {})[name] = describe(law)
    if rotors:
        if wind is None:
            raise InputError("rotors need a wind speed: give wind= (m/s, a number or a signal)")
        out.wind = signal_from_spec(wind, where="wind") if not isinstance(wind, Signal) else wind
        out.input_columns = 1
        out.metadata["wind"] = out.wind.spec()
    for name, rotor in (rotors or {}).items():
        if name not in joint_index:
            raise UnknownJoint(name, "rotors", joint_index)
        if not isinstance(rotor, Rotor):
            raise InputError(f'rotors["{name}"] is {rotor!r}; give a pinwind.loads.rotor.Rotor')
        index = joint_index[name]
        out.rotors.append(rotor_spec(rotor, index, 0))
        out.rotor_names.append(name)
        out.rotor_laws[name] = rotor
        if rotor.inertia:
            out.added_inertia[index] = out.added_inertia.get(index, 0.0) + rotor.inertia
        out.metadata.setdefault("rotors", {})[name] = rotor.describe()
    return out


def _check_finite(law: Any, where: str) -> None:
    for f in fields(law):
        value = getattr(law, f.name)
        if isinstance(value, float) and not math.isfinite(value):
            raise NonFiniteInput(f"{where}.{f.name} is {value}; give a finite value")


# --- compiled specs ------------------------------------------------------------------------------


def _constant_torque_spec(law: ConstantTorque, index: int) -> _native.GeneratorSpec:
    """The compiled spec on velocity index ``index``."""
    g = _native.GeneratorSpec()
    g.index, g.law, g.torque = index, _native.GeneratorLaw.constant, float(law.torque)
    return g


def _linear_slip_spec(law: LinearSlip, index: int) -> _native.GeneratorSpec:
    """The compiled spec on velocity index ``index``."""
    g = _native.GeneratorSpec()
    g.index, g.law = index, _native.GeneratorLaw.linear_slip
    g.slope, g.sync_speed = float(law.slope), float(law.sync_speed)
    return g


def _variable_speed_spec(law: VariableSpeed, index: int) -> _native.GeneratorSpec:
    """The compiled spec on velocity index ``index``."""
    g = _native.GeneratorSpec()
    g.index, g.law = index, _native.GeneratorLaw.variable_speed
    g.gain, g.rated_power = float(law.gain), float(law.rated_power)
    g.rated_torque, g.rated_speed, g.slip = (
        float(law.rated_torque),
        float(law.rated_speed),
        float(law.slip),
    )
    return g


def _induction_machine_spec(machine: InductionMachine, index: int) -> _native.GeneratorSpec:
    """The compiled spec on velocity index ``index``."""
    g = _native.GeneratorSpec()
    g.index = index
    g.law = _native.GeneratorLaw.induction_dq if machine.dynamic else _native.GeneratorLaw.induction
    g.stator_resistance = float(machine.stator_resistance)
    g.rotor_resistance = float(machine.rotor_resistance)
    g.stator_leakage = float(machine.stator_leakage)
    g.rotor_leakage = float(machine.rotor_leakage)
    g.magnetizing = float(machine.magnetizing)
    g.voltage = float(machine.voltage)
    g.frequency = float(machine.frequency)
    g.pole_pairs = int(machine.poles) // 2
    g.steady_start = bool(machine.steady_start)
    return g


#: Generator law → the builder of its compiled spec.
_GENERATOR_SPECS: dict[type, Callable[[Any, int], _native.GeneratorSpec]] = {
    ConstantTorque: _constant_torque_spec,
    LinearSlip: _linear_slip_spec,
    VariableSpeed: _variable_speed_spec,
    InductionMachine: _induction_machine_spec,
}


def generator_spec(law: GeneratorLaw, index: int) -> _native.GeneratorSpec:
    """The compiled spec of a generator law on velocity index ``index``."""
    return _GENERATOR_SPECS[type(law)](law, index)


def rotor_spec(rotor: Rotor, index: int, wind_column: int) -> _native.RotorSpec:
    """The compiled spec on velocity index ``index``, wind from input ``wind_column``."""
    r = _native.RotorSpec()
    r.index, r.wind_column = index, wind_column
    r.radius, r.air_density, r.pitch = float(rotor.radius), float(rotor.air_density), rotor.pitch
    if rotor.pitch_control is not None:
        c, control = r.pitch_control, rotor.pitch_control
        c.enabled, c.speed_set, c.kp, c.ki = True, control.speed_set, control.kp, control.ki
        c.gain_angle, c.corner, c.rate = control.gain_angle, control.corner, control.rate
        c.pitch_min, c.pitch_max = control.pitch_min, control.pitch_max
        r.pitch_control = c
    if isinstance(rotor.cp, CpTable):
        r.cp_model = _native.CpModel.table
        r.table_tsr = [float(x) for x in rotor.cp.tsr]
        r.table_pitch = [float(x) for x in rotor.cp.pitch]
        r.table_cp = [float(c) for row in rotor.cp.cp for c in row]
    else:
        r.cp_model = _native.CpModel.heier
        r.cp_scale = float(rotor.cp.scale)
    if rotor.ct is not None:
        r.ct_model = _native.ThrustModel.table
        r.ct_tsr = [float(x) for x in rotor.ct.tsr]
        r.ct_pitch = [float(x) for x in rotor.ct.pitch]
        r.ct_values = [float(c) for row in rotor.ct.ct for c in row]
    else:
        r.ct_model = _native.ThrustModel.momentum
    return r


# --- the compiled laws, evaluated alone ----------------------------------------------------------


def induction_torque(machine: InductionMachine, speed: float) -> float:
    """Steady-state generator torque T_gen [N·m] at shaft speed [rad/s] (compiled law)."""
    return -_native.induction_torque(_induction_machine_spec(machine, 0), float(speed))


def rotor_torque(rotor: Rotor, speed: float, wind: float) -> float:
    """Aerodynamic torque [N·m] at rotor speed [rad/s] in wind [m/s] (the compiled law)."""
    return _native.rotor_torque(rotor_spec(rotor, 0, 0), float(speed), float(wind))


def rotor_power_coefficient(rotor: Rotor, tsr: float) -> float:
    """C_p at tip-speed ratio λ (the compiled law)."""
    return _native.rotor_cp(rotor_spec(rotor, 0, 0), float(tsr))


def rotor_thrust_coefficient(rotor: Rotor, tsr: float) -> float:
    """C_t at tip-speed ratio λ (the compiled law: its table, or momentum theory from C_p)."""
    return _native.rotor_ct(rotor_spec(rotor, 0, 0), float(tsr))


def rotor_thrust(rotor: Rotor, speed: float, wind: float) -> float:
    """Aerodynamic thrust [N] at rotor speed [rad/s] in wind [m/s] (the compiled law)."""
    return _native.rotor_thrust(rotor_spec(rotor, 0, 0), float(speed), float(wind))


def rotor_optimum(rotor: Rotor) -> tuple[float, float]:
    """(λ_opt, C_p,max): the tip-speed ratio of the highest power coefficient."""
    from scipy.optimize import minimize_scalar

    best = minimize_scalar(
        lambda x: -rotor_power_coefficient(rotor, x), bounds=(1.0, 20.0), method="bounded",
        options={"xatol": 1e-10},
    )  # fmt: skip
    return float(best.x), -float(best.fun)


def optimal_gain(rotor: Rotor, ratio: float = 1.0) -> float:
    """K of ``VariableSpeed`` that holds λ_opt, for a generator turning ratio × the rotor.

    K = ½ ρ π R⁵ C_p,max / λ_opt³ / ratio³ [N·m·s²].
    """
    tsr, cp = rotor_optimum(rotor)
    return 0.5 * rotor.air_density * math.pi * rotor.radius**5 * cp / tsr**3 / ratio**3
