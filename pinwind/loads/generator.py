"""Generator laws on the output shaft, run inside the compiled step loop (``cpp/generator.hpp``).

Each law gives the generator torque T_gen [N·m] (positive when generating, i.e. braking the
shaft) from the shaft speed ω [rad/s]; the shaft gets −T_gen. The joint's recorded torque
(``res.joint(name).torque``) includes it.

- ``ConstantTorque``: T_gen = T₀.
- ``LinearSlip``: T_gen = k (ω − ω_sync), the linearisation of an induction generator near
  synchronous speed.
- ``VariableSpeed``: T_gen = K ω² below rated, P_rated / ω above (constant power) or a
  constant torque T_r above rated speed (ROSCO's default; ``VariableSpeed`` docstring); with
  K = ½ ρ π R⁵ C_p,max / (λ_opt³ N³) the rotor tracks λ_opt (``dynamics/elements.optimal_gain``).
- ``InductionMachine``: the steady-state torque–slip curve of the per-phase equivalent circuit
  (R_s + jX_ls in series with jX_M ∥ (R_r'/s + jX_lr')), star-connected on a grid of line
  voltage V and frequency f, p pole pairs: ω_sync = 2π f / p, s = (ω_sync − ω) / ω_sync; with
  ``dynamic=True`` Krause's dq model with its fluxes as states (IFToMM 2018,
  ``cpp/generator.hpp``), whose steady state is the same curve. ``InductionMachine.cart600()``
  is IFToMM 2018's machine (Table 1: 3-phase, 60 Hz, 575 V, 4 poles, R_s 0.00053 Ω, R_r' 0.00048 Ω,
  L_ls 0.0365 mH, L_lr' 0.052 mH, L_M 1.97 mH).

``LAWS`` names them (``constant``, ``linear-slip``, ``variable-speed``, ``induction``,
``induction-dq``) with their input parameters and presets: the one table that flags, scenario
files and the log read.

The laws of the shaft speed are taken linearly implicit in the step (``cpp/joint_torque.hpp``),
so a steep curve (IFToMM 2018's machine: ≈ 2e4 N·m per rad/s near synchronous speed) is stable
at the step the mechanics use; the dq machine's fluxes are integrated exactly over that step with
the rotor speed held at mid-step (the flux equations are linear: closed-form e^{Ah}), so its 60 Hz
transient keeps its phase at 1 ms.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field, fields
from typing import Any

from pinwind.errors import InputError


@dataclass(frozen=True)
class ConstantTorque:
    """T_gen = torque [N·m]."""

    torque: float


@dataclass(frozen=True)
class LinearSlip:
    """T_gen = slope · (ω − sync_speed); slope [N·m·s/rad], sync_speed [rad/s]."""

    slope: float
    sync_speed: float

    def __post_init__(self):
        if not self.slope >= 0.0:
            raise InputError(
                f"linear-slip generator: slope {self.slope!r} N·m·s/rad is not ≥ 0 (a negative "
                "slope's torque falls as the shaft speeds up past the synchronous speed and runs "
                "it away); give the slope of the torque-speed curve at synchronous speed, "
                "rated torque / (slip · synchronous speed)"
            )


@dataclass(frozen=True)
class VariableSpeed:
    """T_gen = gain · ω² up to rated, then constant power or constant torque (SI units).

    Region 3 at constant power (``rated_power`` [W]): T_gen = rated_power / ω where K ω³ exceeds
    it; ``rated_power = 0`` leaves the K ω² law unlimited. A constant power is a negative damper
    (dT_gen/dω = −P/ω²) on the drivetrain's torsion.

    Region 3 at constant torque (``rated_torque`` T_r [N·m] > 0, ROSCO's ``VS_ConstPower = 0``;
    Abbas et al. 2022): T_gen = T_r from ``rated_speed`` ω_r [rad/s] up, reached from the K ω²
    curve along Jonkman et al. 2009's region 2½ line (§7.2, DISCON's 10 % slip ``VS_SlPc``):

        T_gen = min(max(K ω², T_r (ω − ω_s)/(ω_r − ω_s)), T_r),   ω_s = ω_r / (1 + slip)

    which damps (slope ≥ 0) everywhere. The NREL 5 MW on its generator shaft: K = 2.332287
    N·m·s², T_r = 43 093.55 N·m (ROSCO's VS_RtTq: 5.2966 MW at 1173.7 rpm), ω_r = 121.6805 rad/s
    (DISCON's VS_RtGnSp, 1162 rpm, 99 % of rated), slip 0.1.

    Raises:
        InputError: both region-3 limits, a rated torque without a rated speed or with a
            slip ≤ 0, or a region 2½ line that does not reach the K ω² curve.
    """

    gain: float
    rated_power: float = 0.0
    rated_torque: float = 0.0
    rated_speed: float = 0.0
    slip: float = 0.1

    def __post_init__(self):
        if self.rated_torque == 0.0:
            return
        if self.rated_power != 0.0:
            raise InputError(
                f"variable-speed generator: rated_power {self.rated_power!r} W and rated_torque "
                f"{self.rated_torque!r} N·m both set; region 3 is at constant power or at "
                "constant torque: give one"
            )
        if not (self.rated_torque > 0 and self.rated_speed > 0 and self.slip > 0):
            raise InputError(
                f"variable-speed generator at rated torque {self.rated_torque!r} N·m: give "
                f"rated_speed > 0 (rated_rpm; got {self.rated_speed!r} rad/s) and slip > 0 "
                f"(got {self.slip!r})"
            )
        sync = self.rated_speed / (1.0 + self.slip)
        slope = self.rated_torque / (self.rated_speed - sync)
        if slope < 4.0 * self.gain * sync:  # K ω² = slope (ω − ω_s) has no real root
            raise InputError(
                f"variable-speed generator: the region 2½ line to {self.rated_torque!r} N·m at "
                f"{self.rated_speed!r} rad/s does not meet K ω² (K = {self.gain!r} N·m·s²); "
                "lower the gain or the slip, or raise the rated torque"
            )


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
    def sync_speed(self) -> float:
        """Synchronous shaft speed 2π f / p [rad/s]."""
        return 2.0 * math.pi * self.frequency / (self.poles // 2)

    @classmethod
    def cart600(cls, **changes: Any) -> InductionMachine:
        """IFToMM 2018 Table 1's generator (CART 600 kW)."""
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


GeneratorLaw = ConstantTorque | LinearSlip | VariableSpeed | InductionMachine


@dataclass(frozen=True)
class LawKind:
    """A generator law as runs name it: in flags, scenario files and the log.

    Attributes:
        name: the law's name (``linear-slip``).
        cls: the class that computes it.
        parameters: input key → (keyword of ``cls``, unit of the input: values in "rpm" are
            turned into rad/s at the edge, every other unit is SI as given).
        fixed: keywords the name implies (``induction-dq``: ``dynamic=True``).
        presets: preset name → the class's constructor of it, taking keyword changes.
    """

    name: str
    cls: type
    parameters: Mapping[str, tuple[str, str]]
    fixed: Mapping[str, Any] = field(default_factory=dict)
    presets: Mapping[str, Callable[..., GeneratorLaw]] = field(default_factory=dict)

    @property
    def keys(self) -> tuple[str, ...]:
        """The input keys: ``preset`` (if the law has presets), then the parameters."""
        return ("preset",) * bool(self.presets) + tuple(self.parameters)

    @property
    def usage(self) -> str:
        """The flag form, e.g. ``linear-slip(slope=, sync_rpm=)``."""
        if self.presets:
            return f"{self.name}(preset={next(iter(self.presets))}, ...)"
        return f"{self.name}({', '.join(f'{key}=' for key in self.parameters)})"

    def field_type(self, keyword: str) -> str:
        """The annotation of a keyword of ``cls`` (``"float"``, ``"int"``, ``"bool"``)."""
        return str(next(f.type for f in fields(self.cls) if f.name == keyword))

    def build(self, preset: str | None = None, **kwargs: Any) -> GeneratorLaw:
        """The law from SI keyword arguments, from a preset if one is named."""
        make = self.presets[preset] if preset is not None else self.cls
        return make(**self.fixed, **kwargs)

    def named(self, law: GeneratorLaw) -> bool:
        """Whether ``law`` is of this kind (its class and the keywords the name implies)."""
        return type(law) is self.cls and all(getattr(law, k) == v for k, v in self.fixed.items())


_INDUCTION = {
    key: (key, unit)
    for key, unit in (
        ("stator_resistance", "Ω"), ("rotor_resistance", "Ω"), ("stator_leakage", "H"),
        ("rotor_leakage", "H"), ("magnetizing", "H"), ("voltage", "V"), ("frequency", "Hz"),
        ("poles", "-"), ("steady_start", "-"),
    )
}  # fmt: skip

#: Every generator law by its name: the one table that flags, scenario files, the log's
#: ``generators`` metadata (``describe``) and the help texts read.
LAWS: dict[str, LawKind] = {
    kind.name: kind
    for kind in (
        LawKind("constant", ConstantTorque, {"torque": ("torque", "N·m")}),
        LawKind(
            "linear-slip",
            LinearSlip,
            {"slope": ("slope", "N·m·s/rad"), "sync_rpm": ("sync_speed", "rpm")},
        ),
        LawKind(
            "variable-speed",
            VariableSpeed,
            {
                "gain": ("gain", "N·m·s²"),
                "rated_power": ("rated_power", "W"),
                "rated_torque": ("rated_torque", "N·m"),
                "rated_rpm": ("rated_speed", "rpm"),
                "slip": ("slip", "-"),
            },
        ),
        LawKind(
            "induction",
            InductionMachine,
            _INDUCTION,
            fixed={"dynamic": False},
            presets={"cart600": InductionMachine.cart600},
        ),
        LawKind(
            "induction-dq",
            InductionMachine,
            _INDUCTION,
            fixed={"dynamic": True},
            presets={"cart600": InductionMachine.cart600},
        ),
    )
}


def kind_of(law: GeneratorLaw) -> LawKind:
    """The entry of ``LAWS`` that names ``law``."""
    return next(kind for kind in LAWS.values() if kind.named(law))


def describe(law: GeneratorLaw) -> dict[str, Any]:
    """The law as plain values for the log: ``{"law": name, **parameters in SI}``."""
    return {"law": kind_of(law).name, **asdict(law)}
