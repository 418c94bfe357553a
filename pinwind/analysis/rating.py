"""Rating of every mesh of a run: ISO 6336, AGMA 2001 and Hertz from pinwind's own mesh forces.

    rating = rate(gearbox, result)              # one load level per mesh, taken from the run
    rating.meshes[0].iso.S_H, rating.meshes[0].agma.S_F, rating.gears["sun"].min_S_H_iso

The load of a mesh is its line-of-action force at one sample (``at="last"``, the default, for a
run that has settled; ``"max"`` for the largest value; ``"mean"``). A run reports it in the
transverse plane (``MeshForces.normal``, docs/model_format.md), so the force normal to the tooth
flank is F_n = normal / cos β_b (the same for spur gears), and the nominal tangential force at the
reference circle is F_t = F_n cos β_b cos α_t (`GearPair.tangential_force`). The
pitch-line speed v for the dynamic factors (ISO K_v, AGMA K_v) is the mesh's speed at the
reference circle in the carrier's frame, as KISSsoft's ISO 6336:2006 method B takes it for a
planetary stage: its report of the NREL 5 MW stage 1 (Rebouças 2020, docs/references.md) gives
v = 1.60 m/s "(Planet)" at sun 47.8 rpm and carrier 12.1 rpm, π d_sun (n_sun − n_carrier)/60 =
π 0.855 m · 35.7/60 s, not the sun's absolute 2.14 m/s, and resonance ratios N = n/n_E1 of the
speeds relative to the carrier (0.016 = 35.7/2266 for the sun, 0.028 = 39.9/1435 for the
planet on the ring); stage 2 likewise (4.88 m/s, not 5.83). ISO 6336-1's own text was not
available to quote. For a mesh with a planet v = r |ω| of the planet (`gear_roles`), r its
reference radius and ω its joint speed relative to its parent, the carrier, at that sample;
the sun's and the ring's speeds relative to the carrier give the same v (r_s |ω_s − ω_c| =
r_p |ω_p|, the tooth counts' ratio). For any other mesh (fixed axes) it is the larger of r |ω|
of the two gears, each gear's joint speed.

ISO's face and transverse load factors K_Hβ and K_Hα take ISO 6336-1's empirical forms unless
the rating is asked to take pinwind's own (``face_load``, ``transverse_load``;
`pinwind.analysis.load_factors`): the run's computed K_Hβ (``mesh_face_load_factor`` of a
sliced compliant mesh) and K_Hα from the quasi-static loaded contact of the pair with its flank
modifications. Each mesh's rating says where each came from (``MeshRating.factor_sources``);
K_Fβ follows from the K_Hβ taken (K_Hβ^N_F, ISO 6336-1), K_Fα = K_Hα. AGMA's factors stay
AGMA 2001's.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from pinwind.analysis.load_factors import (
    FACE_LOAD_SOURCES,
    TRANSVERSE_LOAD_SOURCES,
    loaded_contact_transverse_factor,
    run_face_load_factor,
)
from pinwind.errors import (
    ConflictingInputs,
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
from pinwind.model.gear_roles import gearbox_planetary_gears

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
        factor_sources: where ISO's load factors came from, ``"K_Hbeta"`` and ``"K_Halpha"``
            → a line such as ``"ISO 6336-1 method C (F_βy = 10 µm)"`` or ``"run:
            mesh_face_load_factor max"`` (`iso_factor_sources`).
    """

    mesh: str
    pair: GearPair
    normal_force: float
    load: MeshLoad
    iso: IsoRating
    agma: AgmaRating
    hertz_p_max: float
    hertz_von_mises: float
    factor_sources: dict[str, str] = field(default_factory=dict)

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
                    "factor_sources": m.factor_sources,
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
    factor_sources: Mapping[str, str] | None = None,
) -> MeshRating:
    """Rate one pair at a normal tooth force F_n [N] by both methods and Hertz.

    ``factor_sources`` names where ``iso``'s K_Hβ and K_Hα came from when the caller computed
    them; by default `iso_factor_sources` of ``iso``.
    """
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
        factor_sources=dict(factor_sources or iso_factor_sources(iso or IsoFactors())),
    )


def iso_factor_sources(iso: IsoFactors) -> dict[str, str]:
    """Where `iso_rating` takes K_Hβ and K_Hα from with these factors (``"given"``: by you)."""
    if iso.K_Hbeta is not None:
        face = "given"
    else:
        face = f"ISO 6336-1 method C (F_βy = {iso.misalignment * 1e6:g} µm)"
    if iso.K_Halpha is not None:
        transverse = "given"
    elif iso.base_pitch_deviation is None:
        transverse = "ISO 6336-1: 1 (no f_pb given)"
    else:
        transverse = f"ISO 6336-1 method B (f_pb = {iso.base_pitch_deviation * 1e6:g} µm)"
    return {"K_Hbeta": face, "K_Halpha": transverse}


def rate(
    gearbox: Gearbox,
    result: Result,
    *,
    at: str = "last",
    materials: Mapping[str, Material | str] | None = None,
    iso: IsoFactors | None = None,
    agma: AgmaFactors | None = None,
    face_load: str = "iso",
    transverse_load: str = "iso",
) -> GearboxRating:
    """Rate every mesh of ``gearbox`` with the mesh forces of ``result`` (a `Result`).

    Args:
        gearbox: the model (``pinwind.load``).
        result: a run of that model (``pinwind.simulate`` or ``pinwind.read_log``).
        at: which load: ``"last"`` sample, ``"max"`` or ``"mean"`` of the normal force.
        materials: gear name → material (default 18CrNiMo7-6 for every gear).
        iso: ISO factor overrides, the same for every mesh.
        agma: AGMA factor overrides, the same for every mesh.
        face_load: ISO's K_Hβ from ``"iso"`` (ISO 6336-1's closed form), ``"run-max"`` (the
            largest ``mesh_face_load_factor`` of the run) or ``"run-at"`` (at the rated
            sample; its mean for ``at="mean"``): `pinwind.analysis.load_factors`.
        transverse_load: ISO's K_Hα and K_Fα from ``"iso"`` (ISO 6336-1 method B, 1 without
            f_pb) or ``"loaded-contact"`` (the quasi-static loaded contact at the rated force
            with the gears' flank modifications).

    Raises:
        InputError: an unknown ``at``, ``face_load`` or ``transverse_load``, or a mesh that
            carries no load.
        FactorNotInRun: K_Hβ asked from a run whose mesh has no slices.
        ConflictingInputs: a factor both given in ``iso`` and asked from the run.
    """
    if at not in ("last", "max", "mean"):
        raise InputError(f'at = "{at}"; choose "last", "max" or "mean"')
    if face_load not in FACE_LOAD_SOURCES:
        raise InputError(f'face_load = "{face_load}"; choose {", ".join(FACE_LOAD_SOURCES)}')
    if transverse_load not in TRANSVERSE_LOAD_SOURCES:
        raise InputError(
            f'transverse_load = "{transverse_load}"; choose {", ".join(TRANSVERSE_LOAD_SOURCES)}'
        )
    given = iso or IsoFactors()
    for name, value, source, option in (
        ("K_Hbeta", given.K_Hbeta, face_load, "face_load"),
        ("K_Halpha", given.K_Halpha, transverse_load, "transverse_load"),
        ("K_Falpha", given.K_Falpha, transverse_load, "transverse_load"),
    ):
        if value is not None and source != "iso":
            raise ConflictingInputs(
                f'IsoFactors({name}={value:g}) and {option}="{source}" both set {name}; '
                f'drop one (the given value, or {option}="iso")'
            )
    _warn_if_not_steady(gearbox, result, at)
    planets = frozenset(p for stage in gearbox_planetary_gears(gearbox) for p in stage.planets)
    ratings = []
    for mesh in gearbox.meshes:
        normal = result.mesh(mesh.name).normal
        k = len(normal) - 1 if at != "max" else int(np.argmax(normal))
        transverse = float(np.mean(normal)) if at == "mean" else float(normal[k])
        pair = GearPair.from_mesh(mesh, dict(materials or {}))
        force = pair.flank_normal_force(transverse)
        speed = _pitch_line_speed(gearbox, result, mesh, k, planets)
        factors, sources = given, iso_factor_sources(given)
        if face_load != "iso":
            k_hb, sources["K_Hbeta"] = run_face_load_factor(
                result, mesh.name, face_load, sample=None if at == "mean" else k
            )
            factors = replace(factors, K_Hbeta=k_hb)
        if transverse_load == "loaded-contact" and transverse > 0.0:
            specs = {g.name: g.spec for g in (mesh.gear_a, mesh.gear_b)}
            k_ha = loaded_contact_transverse_factor(
                pair,
                transverse,
                gear_1=specs[pair.names[0]].modification,
                gear_2=specs[pair.names[1]].modification,
            )
            factors = replace(factors, K_Halpha=k_ha, K_Falpha=k_ha)
            sources["K_Halpha"] = "loaded contact: max pair load / ideal's"
        ratings.append(
            rate_pair(
                pair,
                force,
                pitch_line_speed=speed,
                iso=factors,
                agma=agma,
                mesh=mesh.name,
                factor_sources=sources,
            )
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


def _pitch_line_speed(
    gearbox: Gearbox, result: Result, mesh: Mesh, k: int, planets: frozenset[str]
) -> float:
    """Pitch-line speed v in the carrier's frame at sample k [m/s] (module docstring).

    r |ω_joint| of the mesh's planet (its joint turns relative to the carrier), or the larger
    over the two gears for a mesh with no planet.
    """
    speeds = []
    gears = [g for g in (mesh.gear_a, mesh.gear_b) if g.name in planets]
    for gear in gears or (mesh.gear_a, mesh.gear_b):
        joint = gearbox.model.names[gear.joint_id]
        if joint in result.joint_names:
            omega = float(result.joint(joint).speed[k])
        else:
            omega = 0.0
        radius = pitch_radius(gear.spec.teeth, gear.spec.module, gear.spec.helix_angle)
        speeds.append(abs(omega) * radius)
    return max(speeds)
