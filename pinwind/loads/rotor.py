"""Rotor aerodynamics on the rotor joint, run inside the compiled step loop (``cpp/rotor.hpp``).

The rotor puts on its joint the torque of its power coefficient C_p(λ, β) at the sample's wind
speed v:

    τ = P / ω = ½ ρ π R² v³ C_p(λ, β) / ω,   λ = ω R / v

with C_p from Heier's analytical fit (``HeierCp``, the one of MATLAB's wind-turbine block and of
Slootweg et al. 2003; λ_opt = 8.1, C_p,max = 0.48 at β = 0) times a calibration scale, or from a
table (``CpTable``, bilinear). The rotor's inertia is added to the joint (Pinocchio armature):
it turns with the hub, so the bearing reactions and the hub torque into the gearbox are those of
the shaft, after the rotor's own inertia.

Calibration for 000_3b7c4a8fe52a6eee.txt's 1.4 MW turbine (``Rotor.saleh2017``): 3 blades of 41 m
on a 3.7 m hub give R = 41 + 3.7/2 = 42.85 m; at 14.2 rpm in 10 m/s, λ = 6.37. Heier's fit at
β = 0 gives C_p(6.37) = 0.409 there, 0.972 MN·m with ρ = 1.225 kg/m³; 000 (§4, Figs. 5-6) gives
1 MN·m, C_p = 0.421. We keep Heier's shape and scale it by ``SALEH2017_CP_SCALE`` = 1.0292
(``calibrated_scale``), the one number fitted. 000 does not give the rotor's inertia: we take
the NREL 5 MW rotor's 3.8e7 kg·m² (61.5 m blades) scaled by (41 / 61.5)⁵ (mass ∝ L³, inertia
∝ m L²): 5.0e6 kg·m².
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.dynamics import _native
from pinwind.errors import InputError

#: 000's rotor: 41 m blades on a 3.7 m hub [m].
SALEH2017_RADIUS = 41.0 + 3.7 / 2
#: 000's rated point: 1 MN·m at 14.2 rpm in a steady 10 m/s wind.
SALEH2017_RATED = {"torque": 1e6, "speed": 14.2 * 2 * math.pi / 60, "wind": 10.0}
#: Rotor inertia [kg·m²]: NREL 5 MW rotor (3.8e7 kg·m², R 63 m, blades 61.5 m) × (41/61.5)⁵.
SALEH2017_INERTIA = round(3.8e7 * (41.0 / 61.5) ** 5, -5)


def heier_cp(tsr, pitch: float = 0.0, scale: float = 1.0):
    """Heier's C_p(λ, β) (β in radians here; the fit itself is in degrees)."""
    beta = math.degrees(pitch)
    inv = 1.0 / (np.asarray(tsr, dtype=float) + 0.08 * beta) - 0.035 / (beta**3 + 1.0)
    return scale * (0.5176 * (116.0 * inv - 0.4 * beta - 5.0) * np.exp(-21.0 * inv) + 0.0068 * tsr)


def calibrated_scale(
    *, radius: float, air_density: float, wind: float, speed: float, torque: float
) -> float:
    """Scale s on Heier's C_p so that the rotor gives ``torque`` at ``speed`` in ``wind``."""
    tsr = speed * radius / wind
    unscaled = 0.5 * air_density * math.pi * radius**3 * wind**2 * heier_cp(tsr) / tsr
    return torque / float(unscaled)


#: Heier's C_p scaled to 000's rated point (module docstring).
SALEH2017_CP_SCALE = round(
    calibrated_scale(radius=SALEH2017_RADIUS, air_density=1.225, **SALEH2017_RATED), 6
)


@dataclass(frozen=True)
class HeierCp:
    """Heier's analytical C_p(λ, β) times ``scale``."""

    scale: float = 1.0

    def __call__(self, tsr, pitch: float = 0.0):
        """C_p at tip-speed ratio λ and pitch β [rad]."""
        return heier_cp(tsr, pitch, self.scale)


@dataclass(frozen=True)
class CpTable:
    """C_p on a grid: ``cp[i][j]`` at tip-speed ratio ``tsr[i]`` and pitch ``pitch[j]`` [rad].

    Bilinear between grid points, held at the edges. One pitch value: C_p(λ) only.
    """

    tsr: tuple[float, ...]
    cp: tuple[tuple[float, ...], ...]
    pitch: tuple[float, ...] = (0.0,)

    def __post_init__(self):
        cp = np.asarray(self.cp, dtype=float)
        if cp.ndim == 1:
            cp = cp[:, None]
            object.__setattr__(self, "cp", tuple((float(c),) for c in cp[:, 0]))
        tsr = np.asarray(self.tsr, dtype=float)
        pitch = np.asarray(self.pitch, dtype=float)
        if cp.shape != (tsr.size, pitch.size) or tsr.size < 2:
            raise InputError(
                f"Cp table: {cp.shape} values for {tsr.size} tip-speed ratios × {pitch.size} "
                "pitch angles; give one value per pair and at least two ratios"
            )
        if not (np.all(np.diff(tsr) > 0) and np.all(np.diff(pitch) > 0)):
            raise InputError("Cp table: tip-speed ratios and pitch angles must increase strictly")
        if not np.all(np.isfinite(cp)):
            raise InputError("Cp table: every value must be finite")


@dataclass(frozen=True)
class Rotor:
    """A wind-turbine rotor on one joint.

    Attributes:
        radius: R [m], blade tip to axis.
        inertia: rotor inertia about the shaft [kg·m²], added to the joint.
        air_density: ρ [kg/m³].
        pitch: blade pitch β [rad].
        cp: ``HeierCp`` (default) or ``CpTable``.
    """

    radius: float
    inertia: float = 0.0
    air_density: float = 1.225
    pitch: float = 0.0
    cp: HeierCp | CpTable = field(default_factory=HeierCp)

    def __post_init__(self):
        for name in ("radius", "air_density"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise InputError(f"rotor {name} is {value!r}; it must be a positive number")
        if not (math.isfinite(self.inertia) and self.inertia >= 0):
            raise InputError(f"rotor inertia is {self.inertia!r} kg·m²; it must be ≥ 0")

    @classmethod
    def saleh2017(cls, **changes: Any) -> Rotor:
        """000_3b7c4a8fe52a6eee.txt's 1.4 MW rotor, calibrated (module docstring)."""
        values = dict(
            radius=SALEH2017_RADIUS,
            inertia=SALEH2017_INERTIA,
            air_density=1.225,
            cp=HeierCp(SALEH2017_CP_SCALE),
        )
        return cls(**{**values, **changes})

    def native(self, index: int, wind_column: int) -> _native.RotorSpec:
        """The compiled spec on velocity index ``index``, wind from input ``wind_column``."""
        r = _native.RotorSpec()
        r.index, r.wind_column = index, wind_column
        r.radius, r.air_density, r.pitch = float(self.radius), float(self.air_density), self.pitch
        if isinstance(self.cp, CpTable):
            r.cp_model = _native.CpModel.table
            r.table_tsr = [float(x) for x in self.cp.tsr]
            r.table_pitch = [float(x) for x in self.cp.pitch]
            r.table_cp = [float(c) for row in self.cp.cp for c in row]
        else:
            r.cp_model = _native.CpModel.heier
            r.cp_scale = float(self.cp.scale)
        return r

    def torque(self, speed: float, wind: float) -> float:
        """Aerodynamic torque [N·m] at rotor speed [rad/s] in wind [m/s] (the compiled law)."""
        return _native.rotor_torque(self.native(0, 0), float(speed), float(wind))

    def power_coefficient(self, tsr: float) -> float:
        """C_p at tip-speed ratio λ (the compiled law)."""
        return _native.rotor_cp(self.native(0, 0), float(tsr))

    def optimum(self) -> tuple[float, float]:
        """(λ_opt, C_p,max): the tip-speed ratio of the highest power coefficient."""
        from scipy.optimize import minimize_scalar

        best = minimize_scalar(
            lambda x: -self.power_coefficient(x), bounds=(1.0, 20.0), method="bounded",
            options={"xatol": 1e-10},
        )  # fmt: skip
        return float(best.x), -float(best.fun)

    def optimal_gain(self, ratio: float = 1.0) -> float:
        """K of ``VariableSpeed`` that holds λ_opt, for a generator turning ratio × the rotor.

        K = ½ ρ π R⁵ C_p,max / λ_opt³ / ratio³ [N·m·s²].
        """
        tsr, cp = self.optimum()
        return 0.5 * self.air_density * math.pi * self.radius**5 * cp / tsr**3 / ratio**3

    def describe(self) -> dict[str, Any]:
        """Plain values for the log (SI)."""
        out: dict[str, Any] = {
            "radius": self.radius,
            "inertia": self.inertia,
            "air_density": self.air_density,
            "pitch": self.pitch,
        }
        if isinstance(self.cp, CpTable):
            out["cp_table"] = {"tsr": list(self.cp.tsr), "pitch": list(self.cp.pitch),
                               "cp": [list(r) for r in self.cp.cp]}  # fmt: skip
        else:
            out["cp_scale"] = self.cp.scale
        return out
