"""Collective blade-pitch control of a rotor, run inside the compiled step loop (``cpp/rotor.hpp``).

Above rated wind a variable-speed rotor is held at its rated speed by pitching its blades to
feather: the pitch β lowers C_p(λ, β) until the rotor's torque matches the generator's. The
controller is Jonkman et al. 2009's baseline (NREL/TP-500-38060 §7: the speed filter of §7.1,
the pitch controller of §7.3, the actuator limits of §7.4), as Jonkman's DISCON routine computes
it (OpenFAST, ``reg_tests/5MW_Baseline/ServoData/Source/DISCON.f90``):

- the rotor speed through a recursive single-pole low-pass, ω_f ← (1 − α) ω + α ω_f,
  α = e^{−ω_c h}, corner ω_c = 2π · 0.25 Hz (a quarter of the blades' first edgewise mode);
- a PI law on the filtered speed error e = ω_f − Ω_ref, β_c = GK(β) (K_P e + K_I ∫e dt), with the
  gain schedule GK(β) = 1/(1 + β/θ_K) (the rotor's −∂P/∂β grows about linearly with β and
  doubles at θ_K), the integral held to [β_min/K_I, β_max/K_I] (anti-windup: below rated wind it
  stays at β_min/K_I instead of winding up, so the pitch leaves β_min as soon as the speed
  exceeds its set point, through K_P);
- the command held to [β_min, β_max] and the pitch moved toward it at most β̇_max per second.

It runs once per time step, at the step's end, and the pitch is held over the next step.

``PitchControl.nrel5mw()`` holds DISCON's constants, restated on the rotor (low-speed) shaft.
DISCON acts on the generator speed, ratio N = 97 above the rotor's: the speed set point
PC_RefSpd = 122.9096 rad/s (1173.7 rpm) is 12.1 rpm of the rotor, and the gains on the generator
speed error, PC_KP = 0.01882681 s and PC_KI = 0.008068634 (rad of pitch per rad/s, per rad),
multiply a rotor speed error N times smaller, so on the rotor speed they are N K: 1.826201 s and
0.7826575. θ_K = PC_KK = 0.1099965 rad (6.302336°), β 0 to 90° (PC_MinPit, PC_MaxPit),
β̇_max = PC_MaxRat = 0.1396263 rad/s (8°/s; §7.4), ω_c = CornerFreq = 1.570796 rad/s. Jonkman
chose K_P and K_I for a closed-loop rotor-speed response of ω_n = 0.6 rad/s and ζ = 0.7 at
β = 0 (§7.3, the values summarised in §7.5: ∂P/∂β = −25.52 MW/rad there, the drivetrain's
inertia on the rotor shaft I = 38 759 236 + 97² × 534.116 kg·m², rotor and generator of Table
5-1): K_P = 2 I Ω_ref ζ ω_n / (N (−∂P/∂β)), K_I = I Ω_ref ω_n² / (N (−∂P/∂β)), which gives back
DISCON's gains to 3e-5.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from pinwind.errors import InputError
from pinwind.units import rpm_to_rad_s

#: The NREL 5 MW's gearbox ratio (Jonkman et al. 2009 Table 1-1): generator speed / rotor speed.
NREL5MW_GEAR_RATIO = 97.0
#: DISCON's constants on the generator shaft (the module docstring): the speed set point
#: [rad/s], K_P [s] and K_I [-] on the generator speed error, θ_K [rad], the pitch rate limit
#: [rad/s], the filter's corner [rad/s].
DISCON_REFERENCE_SPEED = 122.9096
DISCON_KP = 0.01882681
DISCON_KI = 0.008068634
DISCON_GAIN_ANGLE = 0.1099965
DISCON_PITCH_RATE = 0.1396263
DISCON_CORNER = 1.570796


@dataclass(frozen=True)
class PitchControl:
    """A gain-scheduled PI pitch controller on a rotor's speed (module docstring). SI units.

    Attributes:
        speed_set: Ω_ref, the rotor speed set point [rad/s].
        kp: K_P(0), proportional gain on the rotor speed error at β = 0 [s] (rad of pitch per
            rad/s of error).
        ki: K_I(0), integral gain at β = 0 [-] (rad of pitch per rad of integrated error).
        gain_angle: θ_K, the pitch at which the gains are halved [rad].
        corner: ω_c, the corner frequency of the speed's low-pass filter [rad/s].
        pitch_min, pitch_max: the pitch limits [rad].
        rate: β̇_max, the largest pitch rate [rad/s].
    """

    speed_set: float
    kp: float
    ki: float
    gain_angle: float
    corner: float
    pitch_min: float = 0.0
    pitch_max: float = math.pi / 2
    rate: float = DISCON_PITCH_RATE

    def __post_init__(self):
        for name in ("speed_set", "ki", "gain_angle", "corner", "rate"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise InputError(
                    f"rotor pitch_control {name} is {value!r}; it must be a positive number "
                    "(SI: rad/s, s, rad; scenario files take speed_rpm, gain_angle_deg, "
                    "corner_hz, rate_deg_s)"
                )
        if not (math.isfinite(self.kp) and self.kp >= 0):
            raise InputError(f"rotor pitch_control kp is {self.kp!r} s; it must be ≥ 0")
        if not (
            math.isfinite(self.pitch_min)
            and math.isfinite(self.pitch_max)
            and self.pitch_min < self.pitch_max
        ):
            raise InputError(
                f"rotor pitch_control limits {self.pitch_min!r} to {self.pitch_max!r} rad: give "
                "finite limits with pitch_min below pitch_max (pitch_min_deg, pitch_max_deg)"
            )

    @classmethod
    def nrel5mw(cls, **changes: Any) -> PitchControl:
        """Jonkman et al. 2009's baseline controller of the NREL 5 MW, on the rotor shaft."""
        n = NREL5MW_GEAR_RATIO
        values = dict(
            speed_set=rpm_to_rad_s(12.1),  # PC_RefSpd / 97: 122.9096 rad/s is 1173.7 rpm
            kp=n * DISCON_KP,
            ki=n * DISCON_KI,
            gain_angle=DISCON_GAIN_ANGLE,
            corner=DISCON_CORNER,
            pitch_min=0.0,
            pitch_max=math.pi / 2,
            rate=DISCON_PITCH_RATE,
        )
        return cls(**{**values, **changes})

    def gain_factor(self, pitch: float) -> float:
        """GK(β) = 1/(1 + β/θ_K) [-]."""
        return 1.0 / (1.0 + pitch / self.gain_angle)

    def describe(self) -> dict[str, Any]:
        """Plain values for the log (SI)."""
        return asdict(self)


#: Pitch controllers by preset name (scenario ``pitch_control = "nrel5mw"``).
PITCH_PRESETS = {"nrel5mw": PitchControl.nrel5mw}
