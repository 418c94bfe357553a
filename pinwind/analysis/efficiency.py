"""Power losses and efficiency of a run, from its series, by ISO/TR 14179-2's load-dependent losses.

After a run, each rolling bearing's and each mesh's loss is computed sample by sample from the
loads the run gives it (``losses/``):

- **bearings**: Palmgren's M0 + M1 (``losses/bearing_friction.py``) of every row that is a
  compliant bearing's spring (its load from the row series, ``analysis/bearing_rows.py``) and of
  every ideal ``<bearing>`` with a ``type`` and ``size_mm`` and no rows (its load from the
  ``bearing_radial`` and ``bearing_axial`` series), at the joint's relative speed ω:
  P = (M0(ω) + M1(P1)) |ω|, P1 = ``friction_load(type, F_r, F_a)``. The factors are the model's
  ``friction_f0``/``friction_f1`` or the type's, the oil the bearing's (``lubricant_vg``,
  ``temperature_C``, ...). This is an estimate from the loads of the run, whether or not the
  bearing's friction acted in the step (``friction_model``; there its P1 is a number).
- **meshes**: P_VZP = P_mesh μ_mz H_V (``losses/mesh_friction.py``) with P_mesh = F_bt v_t
  cos α_wt the power the mesh passes (F_bt the run's transverse normal force, v_t the pitch-line
  speed relative to the carrier: the planet's joint speed for a planet's meshes, else gear A's)
  and μ_mz from F_bt, v_Σc, ρ_redC, the oil's η, the flanks' Ra and X_L.

The input power is P_in = Σ_j max(τ_j ω_j, 0) over the joints, τ the torque from outside the
train (``Result.torque``: applied, drivers, generator, rotor); the efficiency over the run is
η = 1 − Σ losses / P_in and its mean 1 − mean(Σ losses) / mean(P_in). Not counted: the gears'
churning and windage, seals, the oil pumps (ISO/TR 14179-2's no-load losses), so η is an upper
bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.analysis.bearing_rows import row_loads
from pinwind.gears.gear_pair import GearPair
from pinwind.losses.bearing_friction import (
    PALMGREN_FACTORS,
    friction_load,
    load_moment,
    lubricant_viscosity,
    no_load_moment,
)
from pinwind.losses.mesh_friction import pair_friction_coefficient, tooth_loss_factor
from pinwind.losses.oil import Lubricant
from pinwind.model.bearing_friction_data import BearingFrictionData
from pinwind.model.gear_roles import gearbox_planetary_gears

#: Mean arithmetic roughness Ra of ground wind-turbine gear flanks [m] when not given.
DEFAULT_ROUGHNESS = 0.5e-6


@dataclass(frozen=True)
class ComponentLoss:
    """One bearing's or mesh's power loss over a run.

    Attributes:
        name: the row (``INP-A``), bearing (its joint) or mesh.
        kind: "bearing" or "mesh".
        power: the power it takes [W], (n,), ≥ 0.
        moment: a bearing's friction moment [N·m] (n,), or a mesh's μ_mz [-] (n,).
    """

    name: str
    kind: str
    power: np.ndarray
    moment: np.ndarray

    @property
    def mean_power(self) -> float:
        """The mean loss over the run [W]."""
        return float(np.mean(self.power))


@dataclass(frozen=True)
class Efficiency:
    """The losses and efficiency of a run (module docstring).

    Attributes:
        time: sample times [s], (n,).
        input_power: P_in [W], (n,).
        components: every bearing's and mesh's loss.
    """

    time: np.ndarray
    input_power: np.ndarray
    components: tuple[ComponentLoss, ...]

    @property
    def loss(self) -> np.ndarray:
        """Σ losses [W], (n,)."""
        return np.sum([c.power for c in self.components], axis=0)

    @property
    def efficiency(self) -> np.ndarray:
        """η(t) = 1 − Σ losses / P_in [-], (n,) (NaN without input power)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.input_power > 0.0, 1.0 - self.loss / self.input_power, np.nan)

    @property
    def mean_efficiency(self) -> float:
        """1 − mean(Σ losses) / mean(P_in) [-]."""
        return 1.0 - float(np.mean(self.loss)) / float(np.mean(self.input_power))


def _speed(result: Any, joint: str) -> np.ndarray:
    return np.asarray(result.joint(joint).speed, dtype=float)


def bearing_losses(result: Any, gearbox: Any) -> list[ComponentLoss]:
    """Every typed and sized bearing's (or row's) friction loss over the run (module docstring)."""
    source = gearbox.source
    out = []
    by_row = {(r.bearing, r.name): r for r in row_loads(result, gearbox)}
    for joint, friction in source.bearing_friction.items():
        rows = source.bearing_rows.get(joint, [])
        omega = _speed(result, joint)
        parts: list[tuple[str, str | None, Any, Any, BearingFrictionData, Any, Any]] = []
        if rows:
            for row, data in zip(rows, source.row_friction[joint], strict=True):
                load = by_row.get((joint, row.name))
                if load is None:
                    continue  # a rated row with no load series: not a spring of the step
                life = row.life or source.bearing_life[joint]
                parts.append(
                    (row.name, row.kind, row.size or life.size, life, data,
                     load.radial_magnitude, load.axial)
                )  # fmt: skip
        else:
            rating = source.bearings.get(joint)
            life = source.bearing_life[joint]
            series = result.bearing(joint)
            parts.append(
                (joint, rating.kind if rating else None, life.size, life, friction,
                 series.radial, series.axial)
            )  # fmt: skip
        for name, kind, size, life, data, radial, axial in parts:
            if kind not in PALMGREN_FACTORS or size is None:
                continue
            factors = PALMGREN_FACTORS[kind]
            f0 = factors.f0 if data.f0 is None else data.f0
            f1 = factors.f1 if data.f1 is None else data.f1
            d_m = 0.5 * (size[0] + size[1])
            nu = lubricant_viscosity(
                life.grade, life.temperature, life.viscosity_100, life.viscosity
            )
            moment = np.asarray(
                no_load_moment(f0, nu, omega, d_m)
                + load_moment(f1, friction_load(kind, radial, axial), d_m)
            )
            out.append(ComponentLoss(name, "bearing", moment * np.abs(omega), moment))
    return out


def mesh_losses(
    result: Any,
    gearbox: Any,
    *,
    oil: Lubricant,
    roughness: float = DEFAULT_ROUGHNESS,
    lubricant_factor: float = 1.0,
) -> list[ComponentLoss]:
    """Every mesh's load-dependent loss P_mesh μ_mz H_V over the run (module docstring).

    Args:
        result: the run; gearbox: its model.
        oil: the gear oil at its temperature (its dynamic viscosity).
        roughness: Ra = (Ra1 + Ra2)/2 of the flanks [m].
        lubricant_factor: X_L (``losses.mesh_friction.LUBRICANT_FACTORS``).
    """
    planets = {p for stage in gearbox_planetary_gears(gearbox) for p in stage.planets}
    out = []
    for mesh in gearbox.meshes:
        pair = GearPair.from_mesh(mesh)
        h_v = tooth_loss_factor(pair)
        gear = mesh.gear_b if mesh.gear_b.name in planets else mesh.gear_a
        omega = _speed(result, gearbox.model.names[gear.joint_id])
        g = pair.geometry
        a, b = mesh.gear_a.spec, mesh.gear_b.spec
        a_first = not (a.internal or (not b.internal and b.teeth < a.teeth))  # as from_mesh
        first = a_first == (gear is mesh.gear_a)
        radius = g.working_radius_1 if first else g.working_radius_2
        v_t = np.abs(omega) * radius
        force = np.abs(np.asarray(result.mesh(mesh.name).normal, dtype=float))
        moving = v_t > 0.0
        mu = np.zeros_like(v_t)
        if np.any(moving):
            mu[moving] = pair_friction_coefficient(
                pair, transverse_force=force[moving], pitch_line_speed=v_t[moving], oil=oil,
                roughness=roughness, lubricant_factor=lubricant_factor,
            )  # fmt: skip
        power = force * v_t * math.cos(float(g.working_pressure_angle))
        out.append(ComponentLoss(mesh.name, "mesh", power * mu * h_v, mu))
    return out


def efficiency(
    result: Any,
    gearbox: Any,
    *,
    oil: Lubricant,
    roughness: float = DEFAULT_ROUGHNESS,
    lubricant_factor: float = 1.0,
) -> Efficiency:
    """The run's losses per bearing and mesh, and its efficiency (module docstring)."""
    torque = np.asarray(result.torque, dtype=float)
    speed = np.asarray(result.speed, dtype=float)
    input_power = np.sum(np.maximum(torque * speed, 0.0), axis=1)
    components = (
        *bearing_losses(result, gearbox),
        *mesh_losses(
            result, gearbox, oil=oil, roughness=roughness, lubricant_factor=lubricant_factor
        ),
    )
    return Efficiency(np.asarray(result.time), input_power, tuple(components))
