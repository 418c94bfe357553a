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
β = 0 gives C_p(6.37) = 0.409 there, 0.972 MN·m with ρ = 1.225 kg/m³; Saleh 2017 (§4,
Figs. 5-6) gives 1 MN·m, C_p = 0.421. We keep Heier's shape and scale it by
``SALEH2017_CP_SCALE`` = 1.0292 (``calibrated_scale``), the one number fitted. Saleh 2017 does
not give the rotor's inertia: we take the NREL 5 MW rotor's 3.8e7 kg·m² (61.5 m blades) scaled
by (41 / 61.5)⁵ (mass ∝ L³, inertia ∝ m L²): 5.0e6 kg·m².

Jørgensen 2014's 500 kW turbine (``Rotor.jorgensen2014``): the paper names it (500 kW, 41 m
rotor, stall-regulated, FLEX5 for its aerodynamics) but gives neither its C_p nor its power
curve. We take R = 41 / 2 = 20.5 m, the fixed speed 27.1 rpm of 41 m, 500 kW stall rotors, and
an ASSUMED power curve typical of such machines (``JORGENSEN2014_POWER_CURVE``: C_p,max 0.36 near
8 m/s, 500 kW reached at 16 m/s, a stall plateau to 19 m/s, falling to 440 kW at 25 m/s), turned
into a C_p(λ) table at 27.1 rpm (C_p = P / (½ ρ π R² v³), λ = ω R / v): a rotor held at that
speed by its generator gives that power curve in steady wind. It is not a fitted or measured
curve; the damage it gives is the trend, not Jørgensen 2014's numbers (docs/fatigue.md).
Inertia: the NREL 5 MW rotor's 3.8e7 kg·m² scaled by (20.5 / 63)⁵ (as for Saleh 2017's rotor):
1.4e5 kg·m².

The rotor's non-torque loads (Keller et al. 2018 found them to change planet-bearing loads by up
to 46 %): with a ``RotorHub`` the rotor also loads the body it sits on (the main shaft) at the
rotor centre, in the hub's fixed frame (``loads/hub_loads.py``: x along the shaft, downwind; z up):

- the thrust T = ½ ρ π R² v² C_t(λ, β) along x, with C_t from a ``CtTable`` or, for a rotor
  known only by its C_p, from actuator-disc momentum theory, C_p = 4a(1 − a)², C_t = 4a(1 − a)
  (Burton et al. 2011, Wind Energy Handbook §3.2; an ideal rotor's thrust for its power, below a
  real rotor's: the NREL 5 MW rotor's table gives C_t 0.77 at its C_p,max 0.482, momentum 0.59);
- its weight m g at the rotor centre, with the shaft tilted by τ (rotor end up): the model's
  gravity g in the hub axes turned by τ about y, (m g sin τ, 0, −m g cos τ) for a model whose
  shaft is level (``hub_weight``);
- the wind-shear moment: in a power-law profile v(z) = v_hub (1 + z/H)^α over the disc (z from
  the hub, H the hub height), a local thrust ∝ v(z)² with the hub's C_t puts the thrust's centre
  ℓ above the hub, M_y = ℓ T with ℓ = (1/πR²) ∫ z (1 + z/H)^{2α} dA over the disc
  (``shear_arm``); for small α, ℓ ≈ α R²/(2H). The moment pushes the upper half downwind: +y.

``Rotor.nrel5mw`` is the NREL 5 MW reference rotor (Jonkman et al. 2009 Table 1-1: R 63 m, hub
height 90 m, 110 t, shaft tilt 5°) with the C_p and C_t tables of NREL's ROSCO toolbox
(``data/nrel5mw_cp_ct_cq.txt``, Abbas et al. 2022; computed with CCBlade from the rotor's blade
data) and the IEC 61400-1 normal wind profile's α = 0.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.errors import InputError
from pinwind.loads.pitch_control import PitchControl
from pinwind.loads.rotor_performance import NREL5MW_PERFORMANCE, read_performance
from pinwind.units import rpm_to_rad_s

#: Saleh 2017's rotor: 41 m blades on a 3.7 m hub [m].
SALEH2017_RADIUS = 41.0 + 3.7 / 2
#: Saleh 2017's rated point: 1 MN·m at 14.2 rpm in a steady 10 m/s wind.
SALEH2017_RATED = {"torque": 1e6, "speed": rpm_to_rad_s(14.2), "wind": 10.0}
#: Rotor inertia [kg·m²]: NREL 5 MW rotor (3.8e7 kg·m², R 63 m, blades 61.5 m) × (41/61.5)⁵.
SALEH2017_INERTIA = round(3.8e7 * (41.0 / 61.5) ** 5, -5)


#: Jørgensen 2014's rotor radius [m] (41 m diameter) and its fixed speed [rad/s] (module docstring).
JORGENSEN2014_RADIUS = 41.0 / 2
JORGENSEN2014_SPEED = rpm_to_rad_s(27.1)
#: Assumed power curve of a 500 kW, 41 m stall-regulated rotor at 27.1 rpm: wind speed [m/s],
#: aerodynamic power [kW] (module docstring; not from Jørgensen 2014, which gives none).
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


#: Heier's C_p scaled to Saleh 2017's rated point (module docstring).
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


def _grid_values(
    name: str, values: Any, tsr: tuple[float, ...], pitch: tuple[float, ...]
) -> tuple[tuple[float, ...], ...]:
    """A table's values as rows per tip-speed ratio, checked against its grid.

    Raises:
        InputError: a shape that is not (ratios, pitch angles), fewer than two ratios, a grid
            that does not increase strictly, or a value that is not finite.
    """
    grid = np.asarray(values, dtype=float)
    if grid.ndim == 1:
        grid = grid[:, None]
    ratios, angles = np.asarray(tsr, dtype=float), np.asarray(pitch, dtype=float)
    if grid.shape != (ratios.size, angles.size) or ratios.size < 2:
        raise InputError(
            f"{name} table: {grid.shape} values for {ratios.size} tip-speed ratios × "
            f"{angles.size} pitch angles; give one value per pair and at least two ratios"
        )
    if not (np.all(np.diff(ratios) > 0) and np.all(np.diff(angles) > 0)):
        raise InputError(f"{name} table: tip-speed ratios and pitch angles must increase strictly")
    if not np.all(np.isfinite(grid)):
        raise InputError(f"{name} table: every value must be finite")
    return tuple(tuple(float(x) for x in row) for row in grid)


@dataclass(frozen=True)
class CpTable:
    """C_p on a grid: ``cp[i][j]`` at tip-speed ratio ``tsr[i]`` and pitch ``pitch[j]`` [rad].

    Bilinear between grid points, held at the edges. One pitch value: C_p(λ) only.
    """

    tsr: tuple[float, ...]
    cp: tuple[tuple[float, ...], ...]
    pitch: tuple[float, ...] = (0.0,)

    def __post_init__(self):
        object.__setattr__(self, "cp", _grid_values("Cp", self.cp, self.tsr, self.pitch))


@dataclass(frozen=True)
class CtTable:
    """C_t on a grid: ``ct[i][j]`` at tip-speed ratio ``tsr[i]`` and pitch ``pitch[j]`` [rad].

    Bilinear between grid points, held at the edges, as ``CpTable``.
    """

    tsr: tuple[float, ...]
    ct: tuple[tuple[float, ...], ...]
    pitch: tuple[float, ...] = (0.0,)

    def __post_init__(self):
        object.__setattr__(self, "ct", _grid_values("Ct", self.ct, self.tsr, self.pitch))


def performance_tables(path: Any) -> tuple[CpTable, CtTable]:
    """The C_p and C_t tables of a ROSCO rotor performance file (``loads/rotor_performance.py``).

    Raises:
        InputError: a file that cannot be read or is not in ROSCO's format.
    """
    grid = read_performance(path)
    return (
        CpTable(tsr=grid.tsr, cp=tuple(map(tuple, grid.cp)), pitch=grid.pitch),
        CtTable(tsr=grid.tsr, ct=tuple(map(tuple, grid.ct)), pitch=grid.pitch),
    )


@dataclass(frozen=True)
class RotorHub:
    """Where the rotor's thrust, weight and wind-shear moment load the drivetrain.

    Attributes:
        body: the body the rotor sits on (URDF link), e.g. the main shaft.
        point: the rotor centre in the body's frame [m].
        up: the hub's z in the model's world frame, or None: against the model's gravity
            (``loads/hub_loads.py``, ``HubLoad.up``).
    """

    body: str
    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] | None = None

    def __post_init__(self):
        for name in ("point", "up"):
            vector = getattr(self, name)
            if vector is None:
                continue
            if len(vector) != 3 or not all(math.isfinite(float(x)) for x in vector):
                raise InputError(
                    f'rotor hub on "{self.body}": {name} {vector} must be three finite numbers [m]'
                )
            object.__setattr__(self, name, tuple(float(x) for x in vector))


def shear_arm(radius: float, hub_height: float, exponent: float) -> float:
    """ℓ [m]: the height of the thrust's centre above the hub in a power-law wind shear.

    ℓ = (1/πR²) ∫ z (1 + z/H)^{2α} dA over the rotor disc (module docstring): over horizontal
    strips at z = ±R sin θ, ∫ z (1 + z/H)^{2α} 2√(R² − z²) dz = ∫ 2R³ sin θ cos² θ ((1 + u)^{2α}
    − (1 − u)^{2α}) dθ from 0 to π/2, u = R sin θ / H, by quadrature (the difference by expm1
    and log1p, exact where it is small). 0 without shear (α = 0 or H infinite).

    Raises:
        InputError: a hub lower than the radius (the disc would reach below the ground).
    """
    if exponent == 0.0 or math.isinf(hub_height):
        return 0.0
    if not hub_height > radius:
        raise InputError(
            f"rotor hub height {hub_height} m is not above its radius {radius} m: the rotor "
            "disc would reach the ground; give hub_height in metres above the ground"
        )
    from scipy.integrate import quad

    def strips(theta: float) -> float:  # the strips at z = ±R sin θ, their moment per unit v²
        s, c = math.sin(theta), math.cos(theta)
        u, p = radius * s / hub_height, 2.0 * exponent
        above_less_below = math.expm1(p * math.log1p(u)) - math.expm1(p * math.log1p(-u))
        return 2.0 * radius**3 * s * c * c * above_less_below

    moment, _ = quad(strips, 0.0, math.pi / 2, epsabs=0.0, epsrel=1e-13)
    return moment / (math.pi * radius**2)


def hub_weight(mass: float, shaft_tilt: float, gravity_in_hub: np.ndarray) -> np.ndarray:
    """The rotor's weight [N] in the hub's fixed axes, with the shaft tilted by ``shaft_tilt``.

    ``gravity_in_hub`` [m/s²] is the model's gravity in the hub axes of its own (level) shaft;
    the real shaft is turned by τ about the hub's y so that its rotor end rises (module
    docstring): g' = (cos τ g_x − sin τ g_z, g_y, sin τ g_x + cos τ g_z), the weight m g'.
    """
    g = np.asarray(gravity_in_hub, dtype=float)
    c, s = math.cos(shaft_tilt), math.sin(shaft_tilt)
    return mass * np.array([c * g[0] - s * g[2], g[1], s * g[0] + c * g[2]])


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
        pitch: blade pitch β [rad]; with ``pitch_control``, the pitch it starts from.
        pitch_control: a ``PitchControl`` that moves the pitch to hold the rotor's speed
            (``loads/pitch_control.py``), or None: the pitch stays ``pitch``.
        cp: ``HeierCp`` (default) or ``CpTable``.
        ct: ``CtTable``, or None: C_t from C_p by momentum theory (module docstring).
        mass: the rotor's mass (blades and hub) [kg], its weight on the hub.
        shaft_tilt: τ [rad], the shaft's tilt from level, rotor end up (5° on the NREL 5 MW).
        hub_height: H [m] above the ground, for the wind shear.
        shear_exponent: α of the power-law wind profile (0: no shear; IEC 61400-1 NWP 0.2).
        hub: where the thrust, weight and shear moment act, or None: the rotor gives its torque
            only (its thrust is still recorded).
    """

    radius: float
    inertia: float = 0.0
    air_density: float = 1.225
    pitch: float = 0.0
    cp: HeierCp | CpTable = field(default_factory=HeierCp)
    ct: CtTable | None = None
    mass: float = 0.0
    shaft_tilt: float = 0.0
    hub_height: float = math.inf
    shear_exponent: float = 0.0
    hub: RotorHub | None = None
    pitch_control: PitchControl | None = None

    def __post_init__(self):
        for name in ("radius", "air_density", "hub_height"):
            value = getattr(self, name)
            if not (value > 0 and (math.isfinite(value) or name == "hub_height")):
                raise InputError(f"rotor {name} is {value!r}; it must be a positive number")
        for name, unit in (("inertia", "kg·m²"), ("mass", "kg"), ("shear_exponent", "")):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise InputError(f"rotor {name} is {value!r} {unit}; it must be ≥ 0".strip())
        if not (math.isfinite(self.shaft_tilt) and abs(self.shaft_tilt) < math.pi / 2):
            raise InputError(
                f"rotor shaft_tilt is {self.shaft_tilt!r} rad; give the tilt from level in "
                "radians, below π/2 (shaft_tilt_deg in scenario files)"
            )
        shear_arm(self.radius, self.hub_height, self.shear_exponent)  # checks H > R
        control = self.pitch_control
        if control is not None and not control.pitch_min <= self.pitch <= control.pitch_max:
            raise InputError(
                f"rotor pitch {self.pitch!r} rad is outside its controller's limits "
                f"{control.pitch_min!r} to {control.pitch_max!r} rad; start the pitch within them"
            )

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

    @classmethod
    def nrel5mw(cls, **changes: Any) -> Rotor:
        """The NREL 5 MW reference rotor with ROSCO's C_p and C_t tables (module docstring).

        Its inertia is left at 0: the shipped model (``models/nrel5mw_gearbox.urdf``) has the
        rotor as a body of its own; give ``inertia=`` for a model without it (Jonkman et al.
        2009 Table 5-1: 38 759 236 kg·m² about the shaft, blades and hub). Give ``hub=`` for its
        thrust, weight and shear moment to load the main shaft.
        """
        cp, ct = performance_tables(NREL5MW_PERFORMANCE)
        values = dict(
            radius=63.0,
            air_density=1.225,
            cp=cp,
            ct=ct,
            mass=110_000.0,
            shaft_tilt=math.radians(5.0),
            hub_height=90.0,
            shear_exponent=0.2,
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
        if self.ct is not None:
            out["ct_table"] = {"tsr": list(self.ct.tsr), "pitch": list(self.ct.pitch),
                               "ct": [list(r) for r in self.ct.ct]}  # fmt: skip
        out.update(mass=self.mass, shaft_tilt=self.shaft_tilt, shear_exponent=self.shear_exponent,
                   hub_height=None if math.isinf(self.hub_height) else self.hub_height)  # fmt: skip
        if self.pitch_control is not None:
            out["pitch_control"] = self.pitch_control.describe()
        if self.hub is not None:
            out["hub"] = {"body": self.hub.body, "point": list(self.hub.point),
                          "up": None if self.hub.up is None else list(self.hub.up)}  # fmt: skip
        return out
