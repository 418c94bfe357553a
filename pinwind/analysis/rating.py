"""Rating of every mesh of a run: ISO 6336, AGMA 2001 and Hertz from pinwind's own mesh forces.

    rating = rate(gearbox, result)              # one load level per mesh, taken from the run
    rating.meshes[0].iso.S_H, rating.meshes[0].agma.S_F, rating.gears["sun"].min_S_H_iso

The load of a mesh is its line-of-action force at one sample (``at="last"``, the default, for a
run that has settled; ``"max"`` for the largest value; ``"mean"``). A run reports it in the
transverse plane (``MeshForces.normal``, docs/model_format.md), so the force normal to the tooth
flank is F_n = normal / cos β_b (the same for spur gears), and the nominal tangential force at the
reference circle is F_t = F_n cos β_b cos α_t (`GearPair.tangential_force`). The
pitch-line speed for the dynamic factors is the larger of r |ω| of the two gears, with ω each
gear's joint speed relative to its parent body at that sample: exact for fixed axes and for a
planet's meshes (the planet's joint speed is relative to the carrier), a little high for the sun
(whose speed relative to the housing includes the carrier's).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pinwind.errors import (
    InputError,
    PointedTeeth,
    RatingAtZeroSpeed,
    RatingOfTransient,
    UndercutGear,
)
from pinwind.gears.checks import check_pair as check_gear_pair
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.hertz import hertz_along_path
from pinwind.gears.involute import pitch_radius
from pinwind.gears.materials import Material
from pinwind.gears.rating_agma import AgmaFactors, AgmaRating, agma_rating
from pinwind.gears.rating_iso import IsoFactors, IsoRating, iso_rating

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.model.gearbox import Gearbox, Mesh


@dataclass(frozen=True)
class MeshRating:
    """Ratings of one mesh at one load.

    Attributes:
        mesh: mesh name from the model file.
        pair: the pair rated, pinion first (``pair.names``).
        normal_force: F_n the rating started from [N].
        load: F_t at the reference circle and pitch-line speed.
        iso: ISO 6336-2/-3 rating.
        agma: AGMA 2001 rating.
        hertz_p_max: largest Hertz pressure along the path of contact [Pa] (Jørgensen 2014
            eqs. 20-22).
        hertz_von_mises: 0.65 of it [Pa].
    """

    mesh: str
    pair: GearPair
    normal_force: float
    load: MeshLoad
    iso: IsoRating
    agma: AgmaRating
    hertz_p_max: float
    hertz_von_mises: float

    @property
    def passes(self) -> bool:
        """Both methods pass."""
        return self.iso.passes and self.agma.passes


@dataclass(frozen=True)
class GearSummary:
    """Smallest safety factors of one gear over the meshes it takes part in."""

    gear: str
    meshes: list[str]
    S_H_iso: float
    S_F_iso: float
    S_H_agma: float
    S_F_agma: float
    hertz_p_max: float

    @property
    def passes(self) -> bool:
        """All four safety factors at least 1."""
        return min(self.S_H_iso, self.S_F_iso, self.S_H_agma, self.S_F_agma) >= 1.0


@dataclass(frozen=True)
class GearboxRating:
    """Ratings of every mesh and the summary per gear."""

    meshes: list[MeshRating]
    gears: dict[str, GearSummary] = field(default_factory=dict)

    @property
    def passes(self) -> bool:
        """Every mesh passes both methods."""
        return all(m.passes for m in self.meshes)

    def as_dict(self) -> dict:
        """Plain numbers (SI units) for JSON."""
        return {
            "meshes": [
                {
                    "mesh": m.mesh,
                    "pinion": m.pair.names[0],
                    "wheel": m.pair.names[1],
                    "normal_force_N": m.normal_force,
                    "tangential_force_N": m.load.tangential_force,
                    "pitch_line_speed_m_s": m.load.pitch_line_speed,
                    "iso": m.iso.as_dict(),
                    "agma": m.agma.as_dict(),
                    "hertz_p_max_Pa": m.hertz_p_max,
                    "hertz_von_mises_Pa": m.hertz_von_mises,
                    "passes": m.passes,
                }
                for m in self.meshes
            ],
            "gears": {
                name: {
                    "meshes": g.meshes,
                    "S_H_iso": g.S_H_iso,
                    "S_F_iso": g.S_F_iso,
                    "S_H_agma": g.S_H_agma,
                    "S_F_agma": g.S_F_agma,
                    "hertz_p_max_Pa": g.hertz_p_max,
                    "passes": g.passes,
                }
                for name, g in self.gears.items()
            },
            "passes": self.passes,
        }


def rate_pair(
    pair: GearPair,
    normal_force: float,
    *,
    pitch_line_speed: float = 0.0,
    iso: IsoFactors | None = None,
    agma: AgmaFactors | None = None,
    mesh: str = "",
) -> MeshRating:
    """Rate one pair at a normal tooth force F_n [N] by both methods and Hertz."""
    if not (math.isfinite(normal_force) and normal_force > 0.0):
        raise InputError(
            f"mesh {mesh or pair.names}: the normal force is {normal_force} N; a rating needs a "
            "loaded mesh (apply torques so that the teeth carry load)"
        )
    _check_geometry(pair, mesh or "–".join(pair.names))
    load = MeshLoad(pair.tangential_force(normal_force), pitch_line_speed, normal_force)
    hertz = hertz_along_path(pair, normal_force)
    return MeshRating(
        mesh=mesh,
        pair=pair,
        normal_force=normal_force,
        load=load,
        iso=iso_rating(pair, load, iso),
        agma=agma_rating(pair, load, agma),
        hertz_p_max=hertz.largest,
        hertz_von_mises=float(np.max(hertz.von_mises)),
    )


def rate(
    gearbox: Gearbox,
    result: Result,
    *,
    at: str = "last",
    materials: Mapping[str, Material | str] | None = None,
    iso: IsoFactors | None = None,
    agma: AgmaFactors | None = None,
) -> GearboxRating:
    """Rate every mesh of ``gearbox`` with the mesh forces of ``result`` (a `Result`).

    Args:
        gearbox: the model (``pinwind.load``).
        result: a run of that model (``pinwind.simulate`` or ``pinwind.read_log``).
        at: which load: ``"last"`` sample, ``"max"`` or ``"mean"`` of the normal force.
        materials: gear name → material (default 18CrNiMo7-6 for every gear).
        iso: ISO factor overrides, the same for every mesh.
        agma: AGMA factor overrides, the same for every mesh.

    Raises:
        InputError: an unknown ``at``, or a mesh that carries no load.
    """
    if at not in ("last", "max", "mean"):
        raise InputError(f'at = "{at}"; choose "last", "max" or "mean"')
    _warn_if_not_steady(gearbox, result, at)
    ratings = []
    for mesh in gearbox.meshes:
        normal = result.mesh(mesh.name).normal
        k = len(normal) - 1 if at != "max" else int(np.argmax(normal))
        transverse = float(np.mean(normal)) if at == "mean" else float(normal[k])
        pair = GearPair.from_mesh(mesh, dict(materials or {}))
        force = pair.flank_normal_force(transverse)
        speed = _pitch_line_speed(gearbox, result, mesh, k)
        ratings.append(
            rate_pair(pair, force, pitch_line_speed=speed, iso=iso, agma=agma, mesh=mesh.name)
        )
    fastest = max((r.load.pitch_line_speed for r in ratings), default=math.inf)
    if fastest < STANDSTILL_SPEED:
        # The bound the speeds are below, a power of ten from 1 µm/s up: a run started at rest
        # under torques balanced to a few digits creeps at µm/s.
        bound = 10.0 ** max(0, math.floor(math.log10(max(fastest * 1e6, 1e-300))) + 1)
        warnings.warn(
            RatingAtZeroSpeed(
                "the run stands still at the rated sample: every pitch-line speed is below "
                f"{bound:g} µm/s, so "
                "the dynamic factors (ISO K_v, AGMA K_v) are ≈ 1, their static value, and the "
                "rating leaves out the dynamic load of the operating speed; start the run at "
                "that speed (initial_speeds, --initial-speed carrier=14.2)"
            ),
            stacklevel=2,
        )
    return GearboxRating(ratings, summarise(ratings))


#: Pitch-line speed [m/s] below which a rating is at standstill: its dynamic factors are 1 to
#: within 0.5 % (AGMA K_v − 1 ∝ √v: 0.0045 at 1 mm/s, 0.18 at Saleh's rated 1.6 m/s; ISO's is
#: linear in v), whereas a run started at rest under torques balanced to a few digits
#: (``--torque sun=-166666.7``) creeps at µm/s.
STANDSTILL_SPEED = 1e-3

#: A rated sample whose net torque along the train exceeds this fraction of the largest torque
#: on it is a transient (``_warn_if_not_steady``).
STEADY_TOLERANCE = 0.05


def _warn_if_not_steady(gearbox: Gearbox, result: Result, at: str) -> None:
    """Warn when the train accelerates at the rated sample (the mean of the run for "mean").

    The net torques from outside the train (``Result.torque``: applied, drivers, generators,
    rotors) less the bearing damping leave J_eq dω/dt along each mode of the train
    (``dynamics/torque_balance.py``); a steady load leaves nothing.
    """
    from pinwind.dynamics.torque_balance import imbalances

    if not len(result):
        return
    torque = result.torque.mean(axis=0) if at == "mean" else result.torque[-1]
    speed = result.speed.mean(axis=0) if at == "mean" else result.speed[-1]
    net = {
        name: float(torque[i] - gearbox.model.damping[gearbox.v_index(name)] * speed[i])
        for i, name in enumerate(result.joint_names)
        if name in gearbox.joint_names
    }
    when = "on average over the run" if at == "mean" else f"at t = {result.time[-1]:g} s"
    for found in imbalances(gearbox, net, tolerance=STEADY_TOLERANCE):
        warnings.warn(
            RatingOfTransient(
                f"the train accelerates {when}: the torques on it leave {found.net_torque:.4g} "
                f'N·m at joint "{found.joint}" (referred through the gear ratios), so the rated '
                "mesh forces and pitch-line speeds are those of a transient, not of a steady "
                "load; rate a run whose torques balance (simulate warns when they do not)"
            ),
            stacklevel=3,
        )


def _check_geometry(pair: GearPair, label: str) -> None:
    """Refuse pointed teeth and warn of an undercut gear (``gears.checks.check_pair``).

    Raises:
        PointedTeeth: a gear's tip thickness is not positive.
    """
    for finding in check_gear_pair(pair):
        if finding.check == "tip_thickness" and finding.severity == "error":
            raise PointedTeeth(f"mesh {label}: {finding.message}; no rating applies to it")
        if finding.check == "undercut":
            warnings.warn(
                UndercutGear(
                    f"mesh {label}: {finding.message}. The ratings (AGMA 908 J, ISO Y_F) take "
                    "the full involute flank, which an undercut tooth has lost at its root: "
                    "its bending safety factors are too high"
                ),
                stacklevel=4,
            )


def summarise(ratings: list[MeshRating]) -> dict[str, GearSummary]:
    """Smallest safety factors per gear over its meshes."""
    rows: dict[str, dict] = {}
    for r in ratings:
        for i, name in enumerate(r.pair.names):
            row = rows.setdefault(
                name, {"meshes": [], "S_H_iso": [], "S_F_iso": [], "S_H_agma": [], "S_F_agma": []}
            )
            row["meshes"].append(r.mesh)
            row["S_H_iso"].append(r.iso.S_H[i])
            row["S_F_iso"].append(r.iso.S_F[i])
            row["S_H_agma"].append(r.agma.S_H[i])
            row["S_F_agma"].append(r.agma.S_F[i])
            row.setdefault("hertz", []).append(r.hertz_p_max)
    return {
        name: GearSummary(
            gear=name,
            meshes=row["meshes"],
            S_H_iso=min(row["S_H_iso"]),
            S_F_iso=min(row["S_F_iso"]),
            S_H_agma=min(row["S_H_agma"]),
            S_F_agma=min(row["S_F_agma"]),
            hertz_p_max=max(row["hertz"]),
        )
        for name, row in rows.items()
    }


def _pitch_line_speed(gearbox: Gearbox, result: Result, mesh: Mesh, k: int) -> float:
    """Max over the two gears of r |ω_joint| at sample k [m/s] (module docstring)."""
    speeds = []
    for gear in (mesh.gear_a, mesh.gear_b):
        joint = gearbox.model.names[gear.joint_id]
        if joint in result.joint_names:
            omega = float(result.joint(joint).speed[k])
        else:
            omega = 0.0
        radius = pitch_radius(gear.spec.teeth, gear.spec.module, gear.spec.helix_angle)
        speeds.append(abs(omega) * radius)
    return max(speeds)
