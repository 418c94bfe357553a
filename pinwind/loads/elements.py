"""Generator and rotor laws of one run as the compiled step loop takes them.

``load_elements`` checks the joint names and the laws, and gives the compiled specs
(``_native.GeneratorSpec``, ``_native.RotorSpec``), the rotor inertias to add to their joints,
and the per-sample input columns the rotors read (one wind-speed column).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any

from pinwind.dynamics import _native
from pinwind.errors import InputError, NonFiniteInput, UnknownJoint
from pinwind.loads.generator import GeneratorLaw, InductionMachine, describe
from pinwind.loads.rotor import Rotor
from pinwind.loads.signal_text import signal_from_spec
from pinwind.loads.signals import Signal


@dataclass
class LoadElements:
    """The compiled generator and rotor specs of a run.

    Attributes:
        generators, rotors: compiled specs.
        generator_names, rotor_names: their joints, in the same order.
        added_inertia: velocity index → inertia added to the joint [kg·m²] (rotors).
        input_columns: per-sample inputs (1 with rotors: the wind speed [m/s], else 0).
        wind: the wind-speed signal [m/s], or None.
        metadata: the laws as plain values, for the log.
    """

    generators: list[_native.GeneratorSpec] = field(default_factory=list)
    rotors: list[_native.RotorSpec] = field(default_factory=list)
    generator_names: list[str] = field(default_factory=list)
    rotor_names: list[str] = field(default_factory=list)
    added_inertia: dict[int, float] = field(default_factory=dict)
    input_columns: int = 0
    wind: Signal | None = None
    metadata: dict[str, Any] = field(default_factory=dict)


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
        out.generators.append(law.native(joint_index[name]))
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
        out.rotors.append(rotor.native(index, 0))
        out.rotor_names.append(name)
        if rotor.inertia:
            out.added_inertia[index] = out.added_inertia.get(index, 0.0) + rotor.inertia
        out.metadata.setdefault("rotors", {})[name] = rotor.describe()
    return out


def _check_finite(law: Any, where: str) -> None:
    for f in fields(law):
        value = getattr(law, f.name)
        if isinstance(value, float) and not math.isfinite(value):
            raise NonFiniteInput(f"{where}.{f.name} is {value}; give a finite value")
