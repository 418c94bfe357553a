"""Generator laws on the output shaft, run inside the compiled step loop (``cpp/generator.hpp``).

Each law gives the generator torque T_gen [N·m] (positive when generating, i.e. braking the
shaft) from the shaft speed ω [rad/s]; the shaft gets −T_gen. The joint's recorded torque
(``res.joint(name).torque``) includes it.

- ``ConstantTorque``: T_gen = T₀.
- ``LinearSlip``: T_gen = k (ω − ω_sync), the linearisation of an induction generator near
  synchronous speed.
- ``VariableSpeed``: T_gen = K ω² below rated, P_rated / ω above (constant power); with
  K = ½ ρ π R⁵ C_p,max / (λ_opt³ N³) the rotor tracks λ_opt (``Rotor.optimal_gain``).
- ``InductionMachine``: the steady-state torque–slip curve of the per-phase equivalent circuit
  (R_s + jX_ls in series with jX_M ∥ (R_r'/s + jX_lr')), star-connected on a grid of line
  voltage V and frequency f, p pole pairs: ω_sync = 2π f / p, s = (ω_sync − ω) / ω_sync; with
  ``dynamic=True`` Krause's dq model with its fluxes as states (001_2d0e0f624d8db633.txt,
  ``cpp/generator.hpp``), whose steady state is the same curve. ``InductionMachine.cart600()``
  is 001's machine (Table 1: 3-phase, 60 Hz, 575 V, 4 poles, R_s 0.00053 Ω, R_r' 0.00048 Ω,
  L_ls 0.0365 mH, L_lr' 0.052 mH, L_M 1.97 mH).

The laws of the shaft speed are taken linearly implicit in the step (``cpp/joint_torque.hpp``),
so a steep curve (001's machine: ≈ 2e4 N·m per rad/s near synchronous speed) is stable at the
step the mechanics use; the dq machine's fluxes are integrated exactly over that step with the
rotor speed held at mid-step (the flux equations are linear: closed-form e^{Ah}), so its 60 Hz
transient keeps its phase at 1 ms.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from pinwind.dynamics import _native


@dataclass(frozen=True)
class ConstantTorque:
    """T_gen = torque [N·m]."""

    torque: float

    law = "constant"

    def native(self, index: int) -> _native.GeneratorSpec:
        """The compiled spec on velocity index ``index``."""
        g = _native.GeneratorSpec()
        g.index, g.law, g.torque = index, _native.GeneratorLaw.constant, float(self.torque)
        return g


@dataclass(frozen=True)
class LinearSlip:
    """T_gen = slope · (ω − sync_speed); slope [N·m·s/rad], sync_speed [rad/s]."""

    slope: float
    sync_speed: float

    law = "linear-slip"

    def native(self, index: int) -> _native.GeneratorSpec:
        """The compiled spec on velocity index ``index``."""
        g = _native.GeneratorSpec()
        g.index, g.law = index, _native.GeneratorLaw.linear_slip
        g.slope, g.sync_speed = float(self.slope), float(self.sync_speed)
        return g


@dataclass(frozen=True)
class VariableSpeed:
    """T_gen = gain · ω² up to rated_power, then rated_power / ω; gain [N·m·s²], power [W].

    ``rated_power = 0`` leaves the K ω² law unlimited.
    """

    gain: float
    rated_power: float = 0.0

    law = "variable-speed"

    def native(self, index: int) -> _native.GeneratorSpec:
        """The compiled spec on velocity index ``index``."""
        g = _native.GeneratorSpec()
        g.index, g.law = index, _native.GeneratorLaw.variable_speed
        g.gain, g.rated_power = float(self.gain), float(self.rated_power)
        return g


@dataclass(frozen=True)
class InductionMachine:
    """A squirrel-cage induction machine from its per-phase equivalent circuit (SI units).

    Attributes:
        stator_resistance, rotor_resistance: R_s, R_r' [Ω].
        stator_leakage, rotor_leakage, magnetizing: L_ls, L_lr', L_M [H].
        voltage: line-to-line RMS voltage [V] (star connection: V / √3 per phase).
        frequency: grid frequency [Hz].
        poles: number of poles (2 p).
        dynamic: Krause's dq model with flux states instead of the steady-state curve.
        steady_start: (dynamic) start with the steady-state fluxes of the initial speed instead
            of zero flux (a machine switched on at t = 0).
    """

    stator_resistance: float
    rotor_resistance: float
    stator_leakage: float
    rotor_leakage: float
    magnetizing: float
    voltage: float
    frequency: float
    poles: int
    dynamic: bool = False
    steady_start: bool = False

    @property
    def law(self) -> str:  # type: ignore[override]
        """``"induction"`` or ``"induction-dq"``."""
        return "induction-dq" if self.dynamic else "induction"

    @property
    def sync_speed(self) -> float:
        """Synchronous shaft speed 2π f / p [rad/s]."""
        return 2.0 * math.pi * self.frequency / (self.poles // 2)

    @classmethod
    def cart600(cls, **changes: Any) -> InductionMachine:
        """001_2d0e0f624d8db633.txt Table 1's generator (CART 600 kW)."""
        values = dict(
            stator_resistance=0.00053,
            rotor_resistance=0.00048,
            stator_leakage=0.0365e-3,
            rotor_leakage=0.052e-3,
            magnetizing=1.97e-3,
            voltage=575.0,
            frequency=60.0,
            poles=4,
        )
        return cls(**{**values, **changes})

    def native(self, index: int) -> _native.GeneratorSpec:
        """The compiled spec on velocity index ``index``."""
        g = _native.GeneratorSpec()
        g.index = index
        g.law = (
            _native.GeneratorLaw.induction_dq if self.dynamic else _native.GeneratorLaw.induction
        )
        g.stator_resistance = float(self.stator_resistance)
        g.rotor_resistance = float(self.rotor_resistance)
        g.stator_leakage = float(self.stator_leakage)
        g.rotor_leakage = float(self.rotor_leakage)
        g.magnetizing = float(self.magnetizing)
        g.voltage = float(self.voltage)
        g.frequency = float(self.frequency)
        g.pole_pairs = int(self.poles) // 2
        g.steady_start = bool(self.steady_start)
        return g

    def torque(self, speed: float) -> float:
        """Steady-state generator torque T_gen [N·m] at shaft speed [rad/s] (compiled law)."""
        return -_native.induction_torque(self.native(0), float(speed))


GeneratorLaw = ConstantTorque | LinearSlip | VariableSpeed | InductionMachine


def describe(law: GeneratorLaw) -> dict[str, Any]:
    """The law as plain values for the log: ``{"law": name, **parameters in SI}``."""
    return {"law": law.law, **asdict(law)}
