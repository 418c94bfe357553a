"""Rotor aerodynamics on the rotor joint, run inside the compiled step loop (``cpp/rotor.hpp``).

The rotor puts on its joint the torque of its power coefficient C_p(λ, β) at the sample's wind
speed v:

    τ = P / ω = ½ ρ π R² v³ C_p(λ, β) / ω,   λ = ω R / v

with C_p from Heier's analytical fit (``HeierCp``, the one of MATLAB's wind-turbine block and of
Slootweg et al. 2003; λ_opt = 8.1, C_p,max = 0.48 at β = 0) times a calibration scale, or from a
table (``CpTable``, bilinear). The rotor's inertia is added to the joint (Pinocchio armature):
it turns with the hub, so the bearing reactions and the hub torque into the gearbox are those of
the shaft, after the rotor's own inertia.

Calibration for Saleh 2017's 1.4 MW turbine (``Rotor.saleh2017``): 3 blades of 41 m
on a 3.7 m hub give R = 41 + 3.7/2 = 42.85 m; at 14.2 rpm in 10 m/s, λ = 6.37. Heier's fit at
β = 0 gives C_p(6.37) = 0.409 there, 0.972 MN·m with ρ = 1.225 kg/m³; 000 (§4, Figs. 5-6) gives
1 MN·m, C_p = 0.421. We keep Heier's shape and scale it by ``SALEH2017_CP_SCALE`` = 1.0292
(``calibrated_scale``), the one number fitted. 000 does not give the rotor's inertia: we take
the NREL 5 MW rotor's 3.8e7 kg·m² (61.5 m blades) scaled by (41 / 61.5)⁵ (mass ∝ L³, inertia
∝ m L²): 5.0e6 kg·m².

Jørgensen 2014's 500 kW turbine (``Rotor.jorgensen2014``): 003 names it (500 kW, 41 m
rotor, stall-regulated, FLEX5 for its aerodynamics) but gives neither its C_p nor its power
curve. We take R = 41 / 2 = 20.5 m, the fixed speed 27.1 rpm of 41 m, 500 kW stall rotors, and
an ASSUMED power curve typical of such machines (``JORGENSEN2014_POWER_CURVE``: C_p,max 0.36 near
8 m/s, 500 kW reached at 16 m/s, a stall plateau to 19 m/s, falling to 440 kW at 25 m/s), turned
into a C_p(λ) table at 27.1 rpm (C_p = P / (½ ρ π R² v³), λ = ω R / v): a rotor held at that
speed by its generator gives that power curve in steady wind. It is not a fitted or measured
curve; the damage it gives is the trend, not 003's numbers (docs/fatigue.md). Inertia: the NREL
5 MW rotor's 3.8e7 kg·m² scaled by (20.5 / 63)⁵ (as for 000's rotor): 1.4e5 kg·m².
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.errors import InputError
from pinwind.units import rpm_to_rad_s

#: 000's rotor: 41 m blades on a 3.7 m hub [m].
SALEH2017_RADIUS = 41.0 + 3.7 / 2
#: 000's rated point: 1 MN·m at 14.2 rpm in a steady 10 m/s wind.
SALEH2017_RATED = {"torque": 1e6, "speed": rpm_to_rad_s(14.2), "wind": 10.0}
#: Rotor inertia [kg·m²]: NREL 5 MW rotor (3.8e7 kg·m², R 63 m, blades 61.5 m) × (41/61.5)⁵.
SALEH2017_INERTIA = round(3.8e7 * (41.0 / 61.5) ** 5, -5)


#: 003's rotor radius [m] (41 m diameter) and its fixed speed [rad/s] (module docstring).
JORGENSEN2014_RADIUS = 41.0 / 2
JORGENSEN2014_SPEED = rpm_to_rad_s(27.1)
#: Assumed power curve of a 500 kW, 41 m stall-regulated rotor at 27.1 rpm: wind speed [m/s],
#: aerodynamic power [kW] (module docstring; not from 003, which gives none).
JORGENSEN2014_POWER_CURVE = (
    (4.0, 8.0), (5.0, 30.0), (6.0, 60.0), (7.0, 100.0), (8.0, 150.0), (9.0, 205.0),
    (10.0, 265.0), (11.0, 325.0), (12.0, 380.0), (13.0, 425.0), (14.0, 460.0), (15.0, 485.0),
    (16.0, 500.0), (17.0, 505.0), (18.0, 505.0), (19.0, 500.0), (20.0, 490.0), (22.0, 470.0),
    (25.0, 440.0),
)  # fmt: skip
#: Rotor inertia [kg·m²]: NREL 5 MW rotor (3.8e7 kg·m², R 63 m) × (20.5/63)⁵.
JORGENSEN2014_INERTIA = round(3.8e7 * (JORGENSEN2014_RADIUS / 63.0) ** 5, -4)


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


def power_curve_cp(
    curve: tuple[tuple[float, float], ...], *, radius: float, speed: float, air_density: float
) -> CpTable:
    """C_p(λ) of a fixed-speed rotor from its power curve (wind [m/s], power [kW]).

    C_p = P / (½ ρ π R² v³) at λ = ω R / v: the table that gives back the power curve when the
    rotor turns at ``speed`` [rad/s] in a steady wind.
    """
    wind = np.array([v for v, _ in curve], dtype=float)
    power = np.array([p for _, p in curve], dtype=float) * 1e3
    cp = power / (0.5 * air_density * math.pi * radius**2 * wind**3)
    order = np.argsort(speed * radius / wind)
    tsr = speed * radius / wind
    return CpTable(
        tsr=tuple(float(x) for x in tsr[order]), cp=tuple((float(c),) for c in cp[order])
    )


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
        """Saleh 2017's 1.4 MW rotor, calibrated (module docstring)."""
        values = dict(
            radius=SALEH2017_RADIUS,
            inertia=SALEH2017_INERTIA,
            air_density=1.225,
            cp=HeierCp(SALEH2017_CP_SCALE),
        )
        return cls(**{**values, **changes})

    @classmethod
    def jorgensen2014(cls, **changes: Any) -> Rotor:
        """Jørgensen 2014's 500 kW, 41 m stall rotor, assumed (module docstring)."""
        values = dict(
            radius=JORGENSEN2014_RADIUS,
            inertia=JORGENSEN2014_INERTIA,
            air_density=1.225,
            cp=power_curve_cp(
                JORGENSEN2014_POWER_CURVE,
                radius=JORGENSEN2014_RADIUS,
                speed=JORGENSEN2014_SPEED,
                air_density=1.225,
            ),
        )
        return cls(**{**values, **changes})

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
