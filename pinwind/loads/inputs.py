"""Joint torque inputs and prescribed-speed drivers.

A load is given per joint name as a number or a callable of time t [s]: torques in N·m about the
joint axis (on the child body, reacted by the parent), speeds in rad/s (joint speed relative to
the parent). They are checked before any stepping: unknown joint names and non-finite values give
a clear error naming the joint.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from pinwind.errors import InputError, NonFiniteInput, UnknownJoint

Signal = float | Callable[[float], float]


@dataclass(frozen=True)
class JointLoad:
    """A torque or speed signal on one joint.

    Attributes:
        joint: joint name.
        v_index: index in the velocity vector.
        signal: value or callable of time.
        description: human-readable description for logs (``"1e+06"`` or the callable's name).
    """

    joint: str
    v_index: int
    signal: Signal

    def __call__(self, t: float) -> float:
        """The signal's value at time t [s]."""
        value = self.signal(t) if callable(self.signal) else self.signal
        return float(value)

    @property
    def description(self) -> str:
        """The value, or the callable's ``description`` attribute or name, for logs."""
        if callable(self.signal):
            description = getattr(self.signal, "description", None)
            if description:
                return description
            return getattr(self.signal, "__name__", repr(self.signal))
        return repr(float(self.signal))


def joint_loads(
    spec: Mapping[str, Signal] | None,
    *,
    where: str,
    joint_index: Mapping[str, int],
    unit: str,
    probe_times: tuple[float, ...] = (0.0,),
) -> list[JointLoad]:
    """Check a {joint: signal} mapping and turn it into JointLoads.

    Args:
        spec: joint name → number or callable(t).
        where: the argument's name, for messages (``"torques"``, ``"--speed"``).
        joint_index: joint name → velocity index of every bearing that may be loaded.
        unit: unit of the values, for messages.
        probe_times: times [s] at which callables are evaluated to check they return finite numbers.
    """
    out = []
    for name, signal in (spec or {}).items():
        if name not in joint_index:
            raise UnknownJoint(name, where, joint_index)
        for t in probe_times if callable(signal) else (0.0,):
            try:
                value = signal(t) if callable(signal) else signal
                value = float(value)
            except (TypeError, ValueError) as err:
                raise InputError(
                    f'{where}["{name}"] must be a number or a function of time returning a number'
                    f" [{unit}]; got {signal!r}"
                ) from err
            if not math.isfinite(value):
                raise NonFiniteInput(
                    f'{where}["{name}"] is {value} {unit} at t = {t:g} s; give a finite value'
                )
        out.append(JointLoad(name, joint_index[name], signal))
    return out
