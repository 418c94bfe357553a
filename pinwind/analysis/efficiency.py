"""Power losses and efficiency of a run, from its series, by ISO/TR 14179-2's load-dependent losses.

After a run, each rolling bearing's and each mesh's loss is computed sample by sample from the
loads the run gives it (``losses/``):

- **bearings**: Palmgren's M0 + M1 (``losses/bearing_friction.py``) of every row that is a
  compliant bearing's spring (its load from the row series, ``analysis/bearing_rows.py``) and of
  every ideal ``<bearing>`` with a ``type`` and ``size_mm`` and no rows (its load from the
  ``bearing_radial`` and ``bearing_axial`` series), at the joint's relative speed ω:
  P = (M0(ω) + M1(P1)) |ω|, P1 = ``friction_load(type, F_r, F_a)``. The factors are the model's
  ``friction_f0``/``friction_f1`` or the type's, the oil the bearing's (``lubricant_vg``,
  ``temperature_C``, ...). This is an estimate from the loads of the run (``source`` =
  "estimate"; a run with friction in the step reads its own losses instead, below).
- **meshes**: P_VZP = P_mesh μ_mz H_V (``losses/mesh_friction.py``) with P_mesh = F_bt v_t
  cos α_wt the power the mesh passes (F_bt the run's transverse normal force, v_t the pitch-line
  speed relative to the carrier: the planet's joint speed for a planet's meshes, else gear A's)
  and μ_mz from F_bt, v_Σc, ρ_redC, the oil's η, the flanks' Ra and X_L.

The input power is P_in = Σ_j max(τ_j ω_j, 0) over the joints, τ the torque from outside the
train (``Result.torque``: applied, drivers, generator, rotor); the efficiency over the run is
η = 1 − Σ losses / P_in and its mean 1 − mean(Σ losses) / mean(P_in). Not counted: the gears'
churning and windage, seals, the oil pumps (ISO/TR 14179-2's no-load losses), so η is an upper
bound.

**From the run's own losses.** When the run had friction in the step (a compliant mesh with
``friction_coefficient`` > 0 or a bearing with a ``friction_model``), ``efficiency`` reads what
the step took instead of estimating it: ``mesh_friction_power`` of every mesh and
``bearing_friction_power`` of every bearing (the heat each gives to the oil; a bearing's rows
summed), ``Efficiency.source`` = "run". The ledger's ``friction_loss`` is the time integral of
their sum. Without friction in the step ``source`` = "estimate" (the formulas above).

**Stages** (``train_stages``): a planetary stage per ring with planets (``model/gear_roles.py``):
its meshes are those of its planets, its members the suns' and the ring's shafts and the
carrier (the planets' parent joint, past a compliant bearing's slides); every other mesh is a
parallel stage of its two shafts. A bearing belongs to its planet's stage, else to the last
stage (in power-flow order) that its shaft is a member of: the stage that shaft drives (the main
shaft to stage 1, the intermediate shaft that carries stage 2's sun and stage 3's wheel to stage
3), the output shaft to the last stage; a bearing on no stage's shaft (a rotor or generator
joint) is counted in the total only. The stages are ordered from the input: by their fastest
member's mean speed, ascending when the input joint (the largest mean τ ω > 0) turns slower
than the output joint (the most negative), descending otherwise. Stage i receives the input power
less the losses of the stages before it, P_i = P_in − Σ_{j<i} L_j, and η_i = 1 − L_i / P_i.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.analysis.bearing_rows import row_loads
from pinwind.errors import InvalidLossInput
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
from pinwind.model.bearing_frictions import bearing_frictions
from pinwind.model.gear_roles import gearbox_planetary_gears

#: Mean arithmetic roughness Ra of ground wind-turbine gear flanks [m] when not given.
DEFAULT_ROUGHNESS = 0.5e-6


@dataclass(frozen=True)
class ComponentLoss:
    """One bearing's or mesh's power loss over a run.

    Attributes:
        name: the row (``INP-A``), bearing (its joint) or mesh.
        kind: "bearing" or "mesh".
        power: the power it takes [W], (n,), ≥ 0: the heat it gives to the oil.
        moment: a bearing's friction moment [N·m] (n,); a mesh's μ_mz [-] (n,) in an estimate,
            its friction force [N] (n,) from the run.
        joint: a bearing's (or row's) joint; "" for a mesh.
    """

    name: str
    kind: str
    power: np.ndarray
    moment: np.ndarray
    joint: str = ""

    @property
    def mean_power(self) -> float:
        """The mean loss over the run [W]."""
        return float(np.mean(self.power))


@dataclass(frozen=True)
class Stage:
    """One stage of a train (module docstring, "Stages").

    Attributes:
        name: "stage 1", "stage 2", ... from the input.
        kind: "planetary" or "parallel".
        meshes: its meshes.
        members: the joints of its shafts (suns, ring, carrier; a parallel stage's two gears).
        bearings: the bearings (joints) whose losses it takes.
    """

    name: str
    kind: str
    meshes: tuple[str, ...]
    members: tuple[str, ...]
    bearings: tuple[str, ...]


def efficiency_of(loss: np.ndarray, input_power: np.ndarray) -> np.ndarray:
    """η(t) = 1 − L(t) / P(t) [-] of a loss and the power it is taken from (NaN where P ≤ 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(input_power > 0.0, 1.0 - loss / input_power, np.nan)


def mean_efficiency_of(loss: np.ndarray, input_power: np.ndarray) -> float:
    """1 − mean(L) / mean(P) [-]: the efficiency of the energies over the run."""
    return 1.0 - float(np.mean(loss)) / float(np.mean(input_power))


@dataclass(frozen=True)
class StageLoss:
    """A stage's losses over a run.

    Attributes:
        stage: the stage.
        mesh_loss: its meshes' loss [W], (n,).
        bearing_loss: its bearings' loss [W], (n,).
        input_power: the power it receives, P_in less the losses of the stages before [W], (n,).
    """

    stage: Stage
    mesh_loss: np.ndarray
    bearing_loss: np.ndarray
    input_power: np.ndarray

    @property
    def loss(self) -> np.ndarray:
        """Its loss [W], (n,)."""
        return self.mesh_loss + self.bearing_loss

    @property
    def efficiency(self) -> np.ndarray:
        """η_i(t) = 1 − L_i / P_i [-], (n,) (NaN without input power)."""
        return efficiency_of(self.loss, self.input_power)

    @property
    def mean_efficiency(self) -> float:
        """1 − mean(L_i) / mean(P_i) [-]."""
        return mean_efficiency_of(self.loss, self.input_power)


@dataclass(frozen=True)
class Efficiency:
    """The losses and efficiency of a run (module docstring).

    Attributes:
        time: sample times [s], (n,).
        input_power: P_in [W], (n,).
        components: every bearing's and mesh's loss.
        source: "run" (the losses the step took, its friction series) or "estimate"
            (ISO/TR 14179-2's formulas at the run's loads, after the run).
        output_power: P_out = Σ max(−τ_j ω_j, 0) [W], (n,), the power the train gives out.
        stages: each stage's losses and efficiency (``train_stages``), from the input.
    """

    time: np.ndarray
    input_power: np.ndarray
    components: tuple[ComponentLoss, ...]
    source: str = "estimate"
    output_power: np.ndarray | None = None
    stages: tuple[StageLoss, ...] = ()

    @property
    def loss(self) -> np.ndarray:
        """Σ losses [W], (n,)."""
        return np.sum([c.power for c in self.components], axis=0)

    @property
    def efficiency(self) -> np.ndarray:
        """η(t) = 1 − Σ losses / P_in [-], (n,) (NaN without input power)."""
        return efficiency_of(self.loss, self.input_power)

    @property
    def mean_efficiency(self) -> float:
        """1 − mean(Σ losses) / mean(P_in) [-]."""
        return mean_efficiency_of(self.loss, self.input_power)


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
            out.append(ComponentLoss(name, "bearing", moment * np.abs(omega), moment, joint))
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
        result: the run.
        gearbox: its model.
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


def friction_in_step(gearbox: Any) -> bool:
    """True if a run of ``gearbox`` has friction in the step.

    A compliant mesh with μ > 0 or a bearing (or row) with a friction model
    (``model.bearing_frictions.bearing_frictions``).
    """
    meshes = any(m.compliance is not None and m.compliance.has_friction for m in gearbox.meshes)
    return meshes or bool(bearing_frictions(gearbox))


def run_losses(result: Any) -> list[ComponentLoss]:
    """Every mesh's and bearing's loss as the step took it.

    The series ``mesh_friction_power`` and ``bearing_friction_power`` [W] (a bearing's rows
    summed), with ``mesh_friction_force`` [N] and ``bearing_friction_moment`` [N·m] as the
    moment.
    """
    out = []
    for i, name in enumerate(result.mesh_names):
        out.append(
            ComponentLoss(
                name, "mesh", np.asarray(result.mesh_friction_power[:, i], dtype=float),
                np.asarray(result.mesh_friction_force[:, i], dtype=float),
            )
        )  # fmt: skip
    for i, name in enumerate(result.bearing_names):
        out.append(
            ComponentLoss(
                name, "bearing", np.asarray(result.bearing_friction_power[:, i], dtype=float),
                np.asarray(result.bearing_friction_moment[:, i], dtype=float), name,
            )
        )  # fmt: skip
    return out


def _shaft(gearbox: Any, joint_id: int) -> str | None:
    """The joint that turns a body: past a compliant bearing's slides; None for the ground."""
    model = gearbox.model
    slides = set(gearbox.slide_joints)
    while joint_id > 0 and model.names[joint_id] in slides:
        joint_id = int(model.parents[joint_id])
    return None if joint_id <= 0 else str(model.names[joint_id])


def train_stages(gearbox: Any, speed: Any = None, power: Any = None) -> list[Stage]:
    """The stages of ``gearbox``'s train, from its input (module docstring, "Stages").

    Args:
        gearbox: the model.
        speed: joint name → its mean |ω| [rad/s] (the order), or None: the model's order.
        power: joint name → its mean τ ω [W] (which end is the input), or None.
    """
    gears = gearbox.gears
    joint_of = {name: _shaft(gearbox, g.joint_id) for name, g in gears.items()}
    found: list[tuple[str, list[str], set[str], set[str]]] = []
    taken: set[str] = set()
    for stage in gearbox_planetary_gears(gearbox):
        planets = set(stage.planets)
        meshes = [
            m.name for m in gearbox.meshes if m.gear_a.name in planets or m.gear_b.name in planets
        ]
        carriers = [_shaft(gearbox, int(gearbox.model.parents[gears[p].joint_id])) for p in planets]
        joints = [joint_of[g] for g in (*stage.suns, stage.ring)] + carriers
        planet_joints = {j for p in planets if (j := joint_of[p])}
        found.append(("planetary", meshes, {j for j in joints if j}, planet_joints))
        taken |= set(meshes)
    for m in gearbox.meshes:
        if m.name not in taken:
            joints = [joint_of[m.gear_a.name], joint_of[m.gear_b.name]]
            found.append(("parallel", [m.name], {j for j in joints if j}, set()))
    if speed is not None:
        fastest = [max((speed.get(j, 0.0) for j in f[2]), default=0.0) for f in found]
        order = sorted(range(len(found)), key=lambda i: fastest[i])
        if power is not None and power:
            inlet = max(power, key=lambda j: power[j])
            outlet = min(power, key=lambda j: power[j])
            if speed.get(inlet, 0.0) > speed.get(outlet, 0.0):
                order.reverse()
        found = [found[i] for i in order]
    owner: dict[str, int] = {}
    for i, (_, _, members, _) in enumerate(found):
        for j in members:
            owner[j] = i  # the last stage the shaft is a member of
    for i, (_, _, _, planet_joints) in enumerate(found):
        for j in planet_joints:
            owner[j] = i
    return [
        Stage(
            f"stage {i + 1}", kind, tuple(meshes), tuple(sorted(members)),
            tuple(b for b in gearbox.bearing_names if owner.get(b) == i),
        )
        for i, (kind, meshes, members, _) in enumerate(found)
    ]  # fmt: skip


def stage_losses(
    stages: list[Stage], components: tuple[ComponentLoss, ...], input_power: np.ndarray
) -> tuple[StageLoss, ...]:
    """Each stage's mesh and bearing losses and the power it receives (module docstring)."""
    zero = np.zeros_like(input_power)
    out = []
    received = input_power.copy()
    for stage in stages:
        meshes = sum(
            (c.power for c in components if c.kind == "mesh" and c.name in stage.meshes), zero
        )
        bearings = sum(
            (c.power for c in components if c.kind == "bearing" and c.joint in stage.bearings), zero
        )
        out.append(StageLoss(stage, meshes, bearings, received))
        received = received - meshes - bearings
    return tuple(out)


def mesh_friction_coefficients(
    result: Any,
    gearbox: Any,
    *,
    oil: Lubricant,
    roughness: float = DEFAULT_ROUGHNESS,
    lubricant_factor: float = 1.0,
    start: float = 0.0,
) -> dict[str, float]:
    """Each mesh's μ_mz at a run's operating point: its mean over the samples from ``start`` [s].

    ISO/TR 14179-2's μ_mz (``mesh_losses``) at the run's transverse force and pitch-line
    speed, sample by sample, averaged: the constant μ to give the mesh's flank friction in a
    run at the same point (``MeshCompliance(friction_coefficient=μ)``, or
    ``friction_coefficient`` in the model file). Samples where the mesh does not turn are left
    out; a mesh that never turns gets 0.
    """
    keep = np.asarray(result.time) >= start
    out = {}
    for c in mesh_losses(
        result, gearbox, oil=oil, roughness=roughness, lubricant_factor=lubricant_factor
    ):
        mu = c.moment[keep]
        turning = mu[mu > 0.0]
        out[c.name] = float(np.mean(turning)) if turning.size else 0.0
    return out


def efficiency(
    result: Any,
    gearbox: Any,
    *,
    oil: Lubricant,
    roughness: float = DEFAULT_ROUGHNESS,
    lubricant_factor: float = 1.0,
    source: str = "auto",
) -> Efficiency:
    """The run's losses per bearing, mesh and stage, and its efficiency (module docstring).

    Args:
        result: the run.
        gearbox: its model.
        oil: the estimate's oil.
        roughness: the estimate's flank roughness Ra [m].
        lubricant_factor: the estimate's lubricant factor X_L [-].
        source: "run" (the step's friction series), "estimate" (the formulas after the run),
            or "auto": "run" when the run had friction in the step (``friction_in_step``).
    """
    if source == "auto":
        source = "run" if friction_in_step(gearbox) else "estimate"
    if source not in ("run", "estimate"):
        raise InvalidLossInput("source", source, 'give "run", "estimate" or "auto"')
    torque = np.asarray(result.torque, dtype=float)
    speed = np.asarray(result.speed, dtype=float)
    input_power = np.sum(np.maximum(torque * speed, 0.0), axis=1)
    output_power = np.sum(np.maximum(-torque * speed, 0.0), axis=1)
    if source == "run":
        components = tuple(run_losses(result))
    else:
        components = (
            *bearing_losses(result, gearbox),
            *mesh_losses(
                result, gearbox, oil=oil, roughness=roughness, lubricant_factor=lubricant_factor
            ),
        )
    names = list(result.joint_names)
    mean_speed = dict(zip(names, np.mean(np.abs(speed), axis=0), strict=True))
    mean_power = dict(zip(names, np.mean(torque * speed, axis=0), strict=True))
    stages = stage_losses(train_stages(gearbox, mean_speed, mean_power), components, input_power)
    return Efficiency(
        np.asarray(result.time), input_power, tuple(components), source, output_power, stages
    )
