"""Step rate and mesh-force accuracy of pinwind against MuJoCo on the same gearbox.

For each model (default: saleh2017_planetary and saleh2017_drivetrain):

1. pinwind: wall time of ``pinwind.simulate(gb, duration=steps*dt, dt=dt, torques=...)`` with an
   unbalanced torque, carrier +1.2e6 N·m against −1e6 N·m referred to the carrier on the output
   shaft (−1e6/6 N·m on the sun, or −1e6/(6·i_parallel) N·m on the last pinion of the
   drivetrain), so the train accelerates uniformly from rest.
2. MuJoCo, the same model: an MJCF built from the ``pinwind.Gearbox`` (``mjcf_from_gearbox``), one
   body per Pinocchio joint with a hinge about the same axis, the same inertia, the locked ring
   welded to the world, each gear mesh a fixed tendon whose coefficients are pinwind's
   constraint row and a tendon equality holding it at length 0. Integrator: MuJoCo's default
   ``Euler`` (semi-implicit: v⁺ = v + a dt, q⁺ = q + v⁺ dt, the same family as pinwind's).
   Run with the default constraint softness (solref 0.02 1) and with the stiffest that MuJoCo's
   ``refsafe`` allows (solref 2·dt 1); the mesh forces are read from ``efc_force`` every step.
3. The closed-form tooth forces of the uniformly accelerating one-DoF train, from the URDF text
   alone (``closed_form``), and each simulator's relative error on the sun–planet normal force.

4. State-dependent loads in the compiled loop (``loads_cost``): the same model with the
   calibrated 1.4 MW rotor on the carrier in a Kaimal wind and Krause's dq induction machine on
   the output shaft (001's circuit with the pole count whose synchronous speed is nearest the rated
   output speed), against the rigid step (with the rotor's inertia) under the rated torques held
   constant, and fed the same loads as torque tables; step loop only, best of 3 each, in the same
   run. Goal: ≤ 1.2×.

Run:  python benchmarks/step_rate.py [--steps N] [--dt S] [--models A B] [--profile]
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import pstats
import sys
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

import pinwind
from pinwind.dynamics.mesh import MeshSet
from pinwind.loads.generator import InductionMachine
from pinwind.loads.rotor import Rotor
from pinwind.loads.signals import Table
from pinwind.loads.wind import KaimalWind
from pinwind.units import rpm_to_rad_s

MODELS_DIR = Path(__file__).resolve().parents[1] / "models"
DEFAULT_MODELS = ("saleh2017_planetary", "saleh2017_drivetrain")
#: Torque on the carrier [N·m].
CARRIER_TORQUE = 1.2e6
#: Output torque referred to the carrier [N·m]: the train accelerates under the difference.
OUTPUT_TORQUE_AT_CARRIER = -1.0e6
#: Samples skipped at the start before the maximum error is taken.
SKIP = 5
#: MuJoCo's default solimp (d0, dwidth, width, midpoint, power).
DEFAULT_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)


# --- closed form ------------------------------------------------------------------------------


@dataclass(frozen=True)
class ClosedForm:
    """Uniform acceleration of a planetary stage (ring fixed, carrier input) and parallel stages.

    Attributes:
        torques: joint name → applied torque [N·m] (the load case).
        carrier_acceleration: α_c [rad/s²].
        speed_ratio: joint name → absolute speed / carrier speed (planets: absolute spin).
        equivalent_inertia: J_eq about the carrier axis [kg·m²].
        normal_force: mesh name → tooth normal force |F_t|/cos α_w [N].
        sun_planet_meshes: names of the sun–planet meshes.
        sun_joint: the joint of the sun shaft.
        carrier_joint: the joint of the carrier.
    """

    torques: dict[str, float]
    carrier_acceleration: float
    speed_ratio: dict[str, float]
    equivalent_inertia: float
    normal_force: dict[str, float]
    sun_planet_meshes: list[str]
    sun_joint: str
    carrier_joint: str


def _floats(text: str | None, n: int, default: float = 0.0) -> np.ndarray:
    if text is None:
        return np.full(n, default)
    return np.array([float(x) for x in text.split()])


def closed_form(path: Path) -> ClosedForm:
    """Closed-form tooth forces of the uniformly accelerating train, from the URDF text alone.

    Read independently of pinwind and Pinocchio: inertias come from the ``<inertial>`` tags
    (fixed links such as the planet pins are added to their parent shaft by hand), radii from
    teeth × module / 2. Assumes what the Saleh models satisfy and raises otherwise: every joint
    with rpy = 0 and axis z, unshifted gears (working = nominal pressure angle), spur gears.

    Kinematics (pitch radii r, ring fixed, carrier speed ω_c = 1): planet absolute spin
    1 − z_r/z_p, sun 1 + z_r/z_s, each parallel stage ω_pinion = −(z_wheel/z_pinion) ω_wheel.
    J_eq = I_c + Σ_pins (I_zz + m a²) + Σ_planets (m a² + I_p ω_p²) + Σ_shafts I ω²;
    α_c = Σ T_j ω_j / J_eq, α_j = ω_j α_c.

    Forces, torque balance shaft by shaft from the output end. For an external pair A–B
    (ω_B = −(r_A/r_B) ω_A) the mesh torque on A is (r_A/r_B) times that on B. Last pinion:
    τ_mesh = I α − T; each intermediate shaft: τ_pinion = I α − T − τ_wheel(next stage).
    Sun: N r_s f = I_s α_s − T_s − τ_wheel(stage 1), f the tangential force of one planet on the
    sun along the sun's positive tangent. Planet about its own centre: I_p α_p = r_p (f + g), so
    the ring force g = I_p α_p / r_p − f. F_n = |F_t| / cos α_w.
    """
    root = ET.parse(path).getroot()
    links = {}
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            links[link.get("name")] = (0.0, np.zeros(3), 0.0)
            continue
        origin = inertial.find("origin")
        com = _floats(origin.get("xyz") if origin is not None else None, 3)
        rpy = _floats(origin.get("rpy") if origin is not None else None, 3)
        inertia = inertial.find("inertia")
        if np.any(rpy != 0.0) or any(float(inertia.get(k, 0)) != 0.0 for k in ("ixz", "iyz")):
            raise ValueError(f"{path}: link {link.get('name')}: rotated inertia not supported")
        mass = float(inertial.find("mass").get("value"))
        links[link.get("name")] = (mass, com, float(inertia.get("izz")))
    joints = {}
    parent_joint_of = {}
    for joint in root.findall("joint"):
        origin = joint.find("origin")
        xyz = _floats(origin.get("xyz") if origin is not None else None, 3)
        rpy = _floats(origin.get("rpy") if origin is not None else None, 3)
        axis_el = joint.find("axis")
        axis = _floats(axis_el.get("xyz") if axis_el is not None else None, 3)
        jtype = joint.get("type")
        if np.any(rpy != 0.0) or (jtype != "fixed" and not np.allclose(axis, [0, 0, 1])):
            raise ValueError(f"{path}: joint {joint.get('name')}: only rpy 0, axis z supported")
        child = joint.find("child").get("link")
        joints[joint.get("name")] = dict(
            type=jtype, parent=joint.find("parent").get("link"), child=child, xyz=xyz
        )
        parent_joint_of[child] = joint.get("name")

    def owner(link: str) -> tuple[str | None, np.ndarray]:
        """Moving joint that carries a link (None: the ground), and the link origin in it."""
        offset = np.zeros(3)
        while link in parent_joint_of:
            j = joints[parent_joint_of[link]]
            if j["type"] != "fixed":
                return parent_joint_of[link], offset
            offset = offset + j["xyz"]
            link = j["parent"]
        return None, offset

    # Rigid groups: izz about the owner's axis, mass, and CoM in the owner's frame.
    groups: dict[str | None, list] = {}
    for name, (mass, com, izz) in links.items():
        j, offset = owner(name)
        c = offset + com
        groups.setdefault(j, []).append((mass, c, izz + mass * (c[0] ** 2 + c[1] ** 2)))
    axis_inertia = {j: sum(g[2] for g in members) for j, members in groups.items()}
    group_mass = {j: sum(g[0] for g in members) for j, members in groups.items()}
    group_com = {
        j: sum(g[0] * g[1] for g in members) / max(group_mass[j], 1e-300)
        for j, members in groups.items()
    }

    box = root.find("gearbox")
    gears = {}
    for g in box.findall("gear"):
        if float(g.get("profile_shift", 0)) != 0.0 or float(g.get("helix_angle_deg", 0)) != 0.0:
            raise ValueError(f"{path}: gear {g.get('name')}: only unshifted spur gears supported")
        link = g.get("link")
        j, offset = owner(link)
        gears[g.get("name")] = dict(
            joint=j,
            teeth=int(g.get("teeth")),
            radius=0.5 * int(g.get("teeth")) * float(g.get("module_mm")) * 1e-3,
            alpha=math.radians(float(g.get("pressure_angle_deg"))),
            internal=g.get("internal", "false").lower() == "true",
        )
    meshes = [(m.get("name"), m.get("gear1"), m.get("gear2")) for m in box.findall("mesh")]

    ring = next((n for n, g in gears.items() if g["internal"] and g["joint"] is None), None)
    if ring is None:
        raise ValueError(f"{path}: the closed form needs a planetary stage with a fixed ring gear")
    planet_meshes = {}
    for name, a, b in meshes:
        if ring in (a, b):
            planet_meshes[a if b == ring else b] = name
    planets = sorted(planet_meshes)
    sun_meshes = {}
    for name, a, b in meshes:
        for p in planets:
            if p in (a, b) and ring not in (a, b):
                sun_meshes[p] = (name, b if a == p else a)
    suns = {s for _, s in sun_meshes.values()}
    if len(suns) != 1:
        raise ValueError(f"{path}: expected one sun meshing with all planets, found {suns}")
    sun = suns.pop()
    planet_joints = [gears[p]["joint"] for p in planets]
    carrier_link = joints[planet_joints[0]]["parent"]
    carrier, _ = owner(carrier_link) if carrier_link in parent_joint_of else (None, None)
    for pj in planet_joints:
        j = joints[pj]
        if owner(j["parent"])[0] != carrier or np.linalg.norm(group_com[pj][:2]) > 1e-9:
            raise ValueError(f"{path}: planet {pj} not on the carrier or CoM off its axis")
    z_r, z_s = gears[ring]["teeth"], gears[sun]["teeth"]
    z_p = gears[planets[0]]["teeth"]
    r_s, r_p = gears[sun]["radius"], gears[planets[0]]["radius"]
    alpha = gears[sun]["alpha"]

    # Parallel stages: follow the meshes from the sun shaft.
    used = set(planet_meshes.values()) | {n for n, _ in sun_meshes.values()}
    shafts = [gears[sun]["joint"]]
    stages = []  # (mesh, wheel gear, pinion gear)
    while True:
        nxt = [
            (n, a, b)
            for n, a, b in meshes
            if n not in used and shafts[-1] in (gears[a]["joint"], gears[b]["joint"])
        ]
        if not nxt:
            break
        n, a, b = nxt[0]
        wheel, pinion = (a, b) if gears[a]["joint"] == shafts[-1] else (b, a)
        used.add(n)
        stages.append((n, wheel, pinion))
        shafts.append(gears[pinion]["joint"])

    speed = {carrier: 1.0, shafts[0]: 1.0 + z_r / z_s}
    for pj in planet_joints:
        speed[pj] = 1.0 - z_r / z_p
    for (_, wheel, pinion), shaft in zip(stages, shafts[1:], strict=True):
        ratio = gears[wheel]["teeth"] / gears[pinion]["teeth"]
        speed[shaft] = -ratio * speed[gears[wheel]["joint"]]

    # Load case: carrier input, the output torque on the last shaft referred to the carrier.
    out = shafts[-1]
    torques = {carrier: CARRIER_TORQUE, out: OUTPUT_TORQUE_AT_CARRIER / speed[out]}

    j_eq = axis_inertia[carrier]
    for pj in planet_joints:
        a = np.linalg.norm(joints[pj]["xyz"][:2])
        j_eq += group_mass[pj] * a**2 + axis_inertia[pj] * speed[pj] ** 2
    for shaft in shafts:
        j_eq += axis_inertia[shaft] * speed[shaft] ** 2
    alpha_c = sum(t * speed[j] for j, t in torques.items()) / j_eq
    acc = {j: s * alpha_c for j, s in speed.items()}

    forces = {}
    torque_on_next_wheel = 0.0
    for (mesh, wheel, pinion), shaft in reversed(list(zip(stages, shafts[1:], strict=True))):
        on_pinion = axis_inertia[shaft] * acc[shaft] - torques.get(shaft, 0.0)
        on_pinion -= torque_on_next_wheel
        forces[mesh] = abs(on_pinion / gears[pinion]["radius"]) / math.cos(gears[pinion]["alpha"])
        torque_on_next_wheel = gears[wheel]["teeth"] / gears[pinion]["teeth"] * on_pinion
    s = shafts[0]
    f_sun = (axis_inertia[s] * acc[s] - torques.get(s, 0.0) - torque_on_next_wheel) / (
        len(planets) * r_s
    )
    for p, pj in zip(planets, planet_joints, strict=True):
        g_ring = axis_inertia[pj] * acc[pj] / r_p - f_sun
        forces[sun_meshes[p][0]] = abs(f_sun) / math.cos(alpha)
        forces[planet_meshes[p]] = abs(g_ring) / math.cos(gears[ring]["alpha"])
    return ClosedForm(
        torques=torques,
        carrier_acceleration=alpha_c,
        speed_ratio=speed,
        equivalent_inertia=j_eq,
        normal_force=forces,
        sun_planet_meshes=[sun_meshes[p][0] for p in planets],
        sun_joint=s,
        carrier_joint=carrier,
    )


# --- MuJoCo model -----------------------------------------------------------------------------


def mesh_rows(gb: pinwind.Gearbox) -> np.ndarray:
    """pinwind's mesh constraint rows J (meshes, nv) at the reference pose, flank +1."""
    model = gb.model
    q0 = gb.neutral()
    v0 = np.zeros(model.nv)
    data = model.createData()
    pin.computeJointJacobiansTimeVariation(model, data, q0, v0)
    ms = MeshSet(gb)
    ms.set_velocity(v0)
    rows = ms.evaluate(model, data)
    jac, _ = ms.combine(rows, np.ones(ms.count))
    return jac


def _joint_axis(model: pin.Model, data: pin.Data, j: int) -> np.ndarray:
    """Axis of 1-DoF revolute joint j in its own frame (from its local Jacobian column)."""
    col = pin.getJointJacobian(model, data, j, pin.LOCAL)[:, model.joints[j].idx_v]
    if np.linalg.norm(col[:3]) > 1e-12:
        raise ValueError(f'joint "{model.names[j]}" is not a revolute joint about its origin')
    return col[3:] / np.linalg.norm(col[3:])


def _fmt(x) -> str:
    return " ".join(repr(float(v)) for v in np.ravel(x))


def mjcf_from_gearbox(
    gb: pinwind.Gearbox,
    *,
    dt: float,
    solref: tuple[float, float] = (0.02, 1.0),
    solimp: tuple[float, ...] = DEFAULT_SOLIMP,
) -> str:
    """MJCF text of a pinwind gearbox: bodies, hinges, inertias, meshes as tendon equalities.

    One body per Pinocchio joint, nested as in the Pinocchio tree, placed at the joint placement
    (pos, quat) with a hinge at its origin about the joint axis, so that body frame = Pinocchio
    joint frame for every q. The inertial is ``model.inertias[j]``: mass, CoM (lever) and the
    full inertia about the CoM in the joint frame. A locked joint (the ring) becomes a body
    without a joint, welded to its parent. Mesh i is a fixed tendon Σ_k J[i, k] q_k with J
    pinwind's row (units m/rad, so the tendon force is the tooth normal force in N) and a tendon
    equality holding its length at 0; columns of locked joints are dropped (their speed is 0).
    """
    model = gb.model
    data = model.createData()
    pin.computeJointJacobians(model, data, gb.neutral())
    jac = mesh_rows(gb)
    locked = set(gb.locked_joints)
    children: dict[int, list[int]] = {}
    for j in range(1, model.njoints):
        children.setdefault(model.parents[j], []).append(j)

    def body(j: int, indent: str) -> list[str]:
        name = model.names[j]
        placement = model.jointPlacements[j]
        quat = pin.Quaternion(placement.rotation).coeffs()  # x y z w
        inertia = model.inertias[j]
        i_c = inertia.inertia
        lines = [
            f'{indent}<body name="{name}" pos="{_fmt(placement.translation)}" '
            f'quat="{_fmt([quat[3], quat[0], quat[1], quat[2]])}">'
        ]
        if name not in locked:
            lines.append(
                f'{indent}  <joint name="{name}" type="hinge" pos="0 0 0" '
                f'axis="{_fmt(_joint_axis(model, data, j))}"/>'
            )
        full = [i_c[0, 0], i_c[1, 1], i_c[2, 2], i_c[0, 1], i_c[0, 2], i_c[1, 2]]
        lines.append(
            f'{indent}  <inertial pos="{_fmt(inertia.lever)}" mass="{float(inertia.mass)!r}" '
            f'fullinertia="{_fmt(full)}"/>'
        )
        for c in children.get(j, []):
            lines += body(c, indent + "  ")
        lines.append(f"{indent}</body>")
        return lines

    world = [line for j in children.get(0, []) for line in body(j, "    ")]
    tendons, equalities = [], []
    scale = np.abs(jac).max()
    for i, mesh in enumerate(gb.meshes):
        terms = [
            f'      <joint joint="{name}" coef="{float(jac[i, gb.v_index(name)])!r}"/>'
            for name in gb.joint_names
            if name not in locked and abs(jac[i, gb.v_index(name)]) > 1e-14 * scale
        ]
        tendons += [f'    <fixed name="{mesh.name}">', *terms, "    </fixed>"]
        equalities.append(
            f'    <tendon name="{mesh.name}" tendon1="{mesh.name}" '
            f'solref="{_fmt(solref)}" solimp="{_fmt(solimp)}"/>'
        )
    return "\n".join(
        [
            f'<mujoco model="{gb.name}">',
            '  <compiler angle="radian" autolimits="true"/>',
            f'  <option timestep="{dt!r}" gravity="{_fmt(gb.gravity)}" integrator="Euler"/>',
            "  <worldbody>",
            *world,
            "  </worldbody>",
            "  <tendon>",
            *tendons,
            "  </tendon>",
            "  <equality>",
            *equalities,
            "  </equality>",
            "</mujoco>",
        ]
    )


@dataclass
class MujocoRun:
    """One MuJoCo run: wall time, mesh forces (steps, meshes) [N] and speeds (steps, nv)."""

    seconds: float
    seconds_step_only: float
    forces: np.ndarray
    speeds: np.ndarray


def mujoco_dof(mj: mujoco.MjModel, gb: pinwind.Gearbox) -> dict[str, int]:
    """pinwind joint name → MuJoCo dof address (unlocked joints)."""
    return {
        name: int(mj.jnt_dofadr[mj.joint(name).id])
        for name in gb.joint_names
        if name not in gb.locked_joints
    }


def run_mujoco(
    mj: mujoco.MjModel, gb: pinwind.Gearbox, steps: int, torques: dict[str, float]
) -> MujocoRun:
    """Steps from rest with constant joint torques; reads the tendon-equality forces every step.

    After ``mj_step`` the constraint forces are those of the state at the start of the step, so
    row k holds the forces at t = k·dt, like pinwind's sample k.
    """
    dof = mujoco_dof(mj, gb)
    eq_type = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    # Equality id → mesh index (the equalities are written in mesh order; map by name anyway).
    eq_to_mesh = np.array(
        [[m.name for m in gb.meshes].index(mj.equality(e).name) for e in range(mj.neq)]
    )
    tau = np.zeros(mj.nv)
    for name, value in torques.items():
        tau[dof[name]] = value
    forces = np.zeros((steps, len(gb.meshes)))
    speeds = np.zeros((steps, mj.nv))

    d = mujoco.MjData(mj)
    started = time.perf_counter()
    for k in range(steps):
        d.qfrc_applied[:] = tau
        mujoco.mj_step(mj, d)
        n = d.nefc
        rows = d.efc_type[:n] == eq_type
        forces[k, eq_to_mesh[d.efc_id[:n][rows]]] = d.efc_force[:n][rows]
        speeds[k] = d.qvel
    seconds = time.perf_counter() - started

    d = mujoco.MjData(mj)
    started = time.perf_counter()
    for _ in range(steps):
        d.qfrc_applied[:] = tau
        mujoco.mj_step(mj, d)
    seconds_step_only = time.perf_counter() - started
    return MujocoRun(seconds, seconds_step_only, forces, speeds)


def check_mujoco_model(mj: mujoco.MjModel, gb: pinwind.Gearbox) -> tuple[float, float]:
    """Largest relative differences MuJoCo − pinwind at the reference pose: mass matrix, rows."""
    dof = mujoco_dof(mj, gb)
    names = list(dof)
    pv = [gb.v_index(n) for n in names]
    mv = [dof[n] for n in names]
    d = mujoco.MjData(mj)
    mujoco.mj_forward(mj, d)
    full = np.zeros((mj.nv, mj.nv))
    mujoco.mj_fullM(mj, d, full)
    data = gb.model.createData()
    m_pin = pin.crba(gb.model, data, gb.neutral())
    m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
    mass_err = np.abs(full[np.ix_(mv, mv)] - m_pin[np.ix_(pv, pv)]).max() / np.abs(m_pin).max()
    # Tendon Jacobian column by column from ten_velocity (ten_J's layout is sparse in MuJoCo 4).
    ten_j = np.zeros((mj.ntendon, mj.nv))
    for k in range(mj.nv):
        d.qvel[:] = 0.0
        d.qvel[k] = 1.0
        mujoco.mj_forward(mj, d)
        ten_j[:, k] = d.ten_velocity
    jac = mesh_rows(gb)
    row_err = np.abs(ten_j[:, mv] - jac[:, pv]).max() / np.abs(jac).max()
    return float(mass_err), float(row_err)


# --- the benchmark ----------------------------------------------------------------------------


@dataclass
class Errors:
    """Relative error of the sun–planet normal force (worst planet) at given samples."""

    at_0: float
    at_10: float
    at_50: float
    at_100: float
    max_after_skip: float
    all_meshes_max: float

    @classmethod
    def of(cls, forces: np.ndarray, cf: ClosedForm, names: list[str]) -> Errors:
        """forces: (samples, meshes) normal forces [N], signed or not."""
        exact = np.array([cf.normal_force[n] for n in names])
        rel = np.abs(np.abs(forces) - exact) / exact
        sp = rel[:, [names.index(n) for n in cf.sun_planet_meshes]].max(axis=1)
        n = len(sp)
        return cls(
            at_0=float(sp[0]),
            at_10=float(sp[int(0.1 * n)]),
            at_50=float(sp[int(0.5 * n)]),
            at_100=float(sp[n - 1]),
            max_after_skip=float(sp[SKIP:].max()),
            all_meshes_max=float(rel[SKIP:].max()),
        )


def resolve(model: str) -> Path:
    path = Path(model)
    if path.suffix != ".urdf":
        path = MODELS_DIR / f"{model}.urdf"
    if not path.exists():
        known = ", ".join(sorted(p.stem for p in MODELS_DIR.glob("*.urdf")))
        raise SystemExit(f"model {model!r}: no file {path}; models in {MODELS_DIR}: {known}")
    return path


def bench_model(path: Path, steps: int, dt: float, profile: bool) -> list[dict]:
    gb = pinwind.load(path)
    cf = closed_form(path)
    names = [m.name for m in gb.meshes]
    pw_torques = dict(cf.torques)

    pinwind.simulate(gb, duration=10 * dt, dt=dt, torques=pw_torques, progress=False)  # warm-up
    started = time.perf_counter()
    res = pinwind.simulate(gb, duration=steps * dt, dt=dt, torques=pw_torques, progress=False)
    pw_seconds = time.perf_counter() - started
    pw_loop = res.metadata["wall_time_s"]
    pw_forces = res.mesh_normal[:steps]
    pw_err = Errors.of(pw_forces, cf, names)
    end = res.speed[steps - 1]
    pw_ratio = end[gb.v_index(cf.sun_joint)] / end[gb.v_index(cf.carrier_joint)]

    print(f"\n== {gb.name} ({path})")
    print(
        f"closed form: J_eq = {cf.equivalent_inertia:.6g} kg·m², α_c = "
        f"{cf.carrier_acceleration:.6g} rad/s², torques {cf.torques} N·m"
    )
    print("  F_n [N]: " + ", ".join(f"{n} {cf.normal_force[n]:.6g}" for n in names))
    pw_alpha = res.acceleration[steps // 2, gb.v_index(cf.carrier_joint)]
    print(
        f"pinwind: α_c = {pw_alpha:.9g} rad/s² (closed form rel. err. "
        f"{abs(pw_alpha / cf.carrier_acceleration - 1):.1e}), ω_sun/ω_c at the end "
        f"{pw_ratio:.9g}, simulate() {pw_seconds:.2f} s, of which step loop {pw_loop:.2f} s"
    )

    rows = []
    dt_limited = 2.0 * dt
    settings = [
        ("default (solref 0.02 1)", (0.02, 1.0), DEFAULT_SOLIMP),
        (f"stiff (solref {dt_limited:g} 1)", (dt_limited, 1.0), DEFAULT_SOLIMP),
        (
            f"stiff (solref {dt_limited:g} 1, solimp .99 .999)",
            (dt_limited, 1.0),
            (0.99, 0.999, 0.001, 0.5, 2.0),
        ),
    ]
    for label, solref, solimp in settings:
        xml = mjcf_from_gearbox(gb, dt=dt, solref=solref, solimp=solimp)
        mj = mujoco.MjModel.from_xml_string(xml)
        mass_err, row_err = check_mujoco_model(mj, gb)
        run_mujoco(mj, gb, min(steps, 100), cf.torques)  # warm-up
        best = None
        for _ in range(3):
            run = run_mujoco(mj, gb, steps, cf.torques)
            if best is None or run.seconds < best.seconds:
                best = run
        dof = mujoco_dof(mj, gb)
        end = best.speeds[-1]
        mj_ratio = end[dof[cf.sun_joint]] / end[dof[cf.carrier_joint]]
        mj_err = Errors.of(best.forces, cf, names)
        flank = res.mesh_flank[:steps]
        signs_agree = bool(np.all(np.sign(best.forces[SKIP:]) == flank[SKIP:]))
        print(
            f"mujoco {label}: nv {mj.nv}, tendons {mj.ntendon}; vs pinwind at q0: mass matrix "
            f"rel. diff {mass_err:.1e}, tendon rows {row_err:.1e}; ω_sun/ω_c at the end "
            f"{mj_ratio:.9g}; force signs = pinwind's loaded flank: {signs_agree}; "
            f"step only {best.seconds_step_only / steps * 1e6:.2f} µs/step"
        )
        rows.append(
            dict(
                model=gb.name,
                setting=label,
                pw_us=pw_seconds / steps * 1e6,
                pw_loop_us=pw_loop / steps * 1e6,
                mj_us=best.seconds / steps * 1e6,
                mj_step_us=best.seconds_step_only / steps * 1e6,
                pw_err=pw_err,
                mj_err=mj_err,
            )
        )

    if profile:
        profiler = cProfile.Profile()
        profiler.enable()
        pinwind.simulate(gb, duration=steps * dt, dt=dt, torques=pw_torques, progress=False)
        profiler.disable()
        out = io.StringIO()
        pstats.Stats(profiler, stream=out).sort_stats("tottime").print_stats(15)
        print(f"\n-- cProfile of pinwind.simulate on {gb.name}, {steps} steps, top 15 by tottime")
        print(out.getvalue())
    return rows


def loads_cost(path: Path, steps: int, dt: float) -> dict:
    """Step-loop time with rotor + dq generator over the rigid step (module docstring, 4)."""
    gb = pinwind.load(path)
    cf = closed_form(path)
    output = max(cf.speed_ratio, key=lambda j: abs(cf.speed_ratio[j]))
    rated_rpm = 14.2 * abs(cf.speed_ratio[output])
    poles = 2 * max(1, round(3600.0 / rated_rpm))  # 60 Hz: n_sync = 7200 / poles rpm
    machine = InductionMachine.cart600(poles=poles, dynamic=True, steady_start=True)
    wind = KaimalWind(mean=10.0, turbulence_intensity=0.1, seed=1,
                      duration=max(600.0, steps * dt))  # fmt: skip
    loaded = dict(rotors={cf.carrier_joint: Rotor.saleh2017()}, wind=wind,
                  generators={output: machine},
                  initial_speeds={cf.carrier_joint: rpm_to_rad_s(14.2)})  # fmt: skip

    def best(**kwargs) -> float:
        pinwind.simulate(gb, duration=10 * dt, dt=dt, progress=False, **kwargs)  # warm-up
        times = []
        for _ in range(3):
            res = pinwind.simulate(gb, duration=steps * dt, dt=dt, progress=False, **kwargs)
            times.append(res.metadata["wall_time_s"])
        return min(times) / steps * 1e6

    # Baselines with the same inertia: the rotor's added to the carrier by a rotor in no wind
    # (its torque is 0 without any evaluation of C_p).
    inertia = dict(rotors={cf.carrier_joint: Rotor.saleh2017()}, wind=0.0,
                   initial_speeds=loaded["initial_speeds"])  # fmt: skip
    rated = {cf.carrier_joint: 1e6, output: -1e6 / cf.speed_ratio[output]}
    rigid = best(torques=rated, **inertia)
    with_loads = best(**loaded)
    # The same loads fed to the rigid step as tables (recorded joint torques of a loaded run):
    # the QP then sees the same changing forces, without the elements.
    res = pinwind.simulate(gb, duration=steps * dt, dt=dt, progress=False, **loaded)
    fed = {j: Table(res.time, res.joint(j).torque) for j in (cf.carrier_joint, output)}
    table_fed = best(torques=fed, **inertia)
    return dict(model=gb.name, output=output, poles=poles, rigid_us=rigid, loads_us=with_loads,
                table_us=table_fed)  # fmt: skip


def print_tables(rows: list[dict], steps: int, dt: float) -> None:
    print(f"\n{steps} steps of dt = {dt:g} s; error = relative error of the sun–planet normal")
    print(f"force (worst planet) against the closed form, max over samples {SKIP}..{steps - 1}\n")
    head = (
        f"{'model':<22} {'MuJoCo setting':<45} {'pinwind':>8} {'MuJoCo':>7} {'ratio':>6} "
        f"{'pw err':>8} {'MJ err':>8} {'MJ step':>8} {'ratio':>6}"
    )
    print(head)
    units = (
        f"{'µs/step':>8} {'µs/step':>7} {'pw/MJ':>6} {'':>8} {'':>8} {'only µs':>8} {'pw/MJs':>6}"
    )
    print(f"{'':<22} {'':<45} {units}")
    print("-" * len(head))
    for r in rows:
        print(
            f"{r['model']:<22} {r['setting']:<45} {r['pw_us']:8.2f} {r['mj_us']:7.2f} "
            f"{r['pw_us'] / r['mj_us']:6.2f} {r['pw_err'].max_after_skip:8.1e} "
            f"{r['mj_err'].max_after_skip:8.1e} {r['mj_step_us']:8.2f} "
            f"{r['pw_us'] / r['mj_step_us']:6.2f}"
        )
    print(
        "\nsun–planet error at the first sample (k = 0), at 10 % / 50 % / 100 % of the run, max"
        f" over k ≥ {SKIP};\nall meshes = max over every mesh (ring and parallel stages too), "
        f"k ≥ {SKIP}"
    )
    print(
        f"{'model':<22} {'simulator':<52} {'k = 0':>8} {'10 %':>8} {'50 %':>8} {'100 %':>8} "
        f"{'max':>8} {'all':>8}"
    )
    done = set()
    for r in rows:
        entries = [(f"mujoco {r['setting']}", r["mj_err"])]
        if r["model"] not in done:
            entries.insert(0, ("pinwind", r["pw_err"]))
            done.add(r["model"])
        for label, e in entries:
            print(
                f"{r['model']:<22} {label:<52} {e.at_0:8.1e} {e.at_10:8.1e} {e.at_50:8.1e} "
                f"{e.at_100:8.1e} {e.max_after_skip:8.1e} {e.all_meshes_max:8.1e}"
            )
    print(
        "\npinwind µs/step is the whole simulate() call over steps (set-up, recording, bearing "
        "reactions, poses);\nstep loop only: "
        + ", ".join(
            f"{m} {us:.1f}" for m, us in {r["model"]: r["pw_loop_us"] for r in rows}.items()
        )
        + ".\nMuJoCo µs/step includes setting qfrc_applied, mj_step, and reading efc_force and "
        "qvel every step (best of 3);\nMJ step only: setting qfrc_applied and mj_step; pw/MJs = "
        "pinwind µs/step over it."
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=10_000, help="time steps per run")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument(
        "--models",
        nargs="+",
        default=list(DEFAULT_MODELS),
        help="model names in models/ or paths to .urdf files",
    )
    parser.add_argument(
        "--profile", action="store_true", help="print a cProfile top 15 of each pinwind run"
    )
    args = parser.parse_args(argv)
    if args.steps < 20:
        parser.error("--steps must be at least 20")
    if not (args.dt > 0 and math.isfinite(args.dt)):
        parser.error("--dt must be a positive number of seconds")
    print(
        f"pinwind {pinwind.__version__}, pinocchio {pin.__version__}, mujoco {mujoco.__version__}, "
        f"numpy {np.__version__}, python {sys.version.split()[0]}"
    )
    rows = []
    costs = []
    for model in args.models:
        path = resolve(model)
        try:
            closed_form(path)
        except ValueError as err:
            raise SystemExit(f"model {model!r}: {err}") from err
        rows += bench_model(path, args.steps, args.dt, args.profile)
        costs.append(loads_cost(path, args.steps, args.dt))
    print_tables(rows, args.steps, args.dt)
    print(
        "\nstate-dependent loads in the compiled loop: rotor (Kaimal wind) on the carrier + dq "
        "induction machine on the\noutput shaft; rigid: the rigid step under the rated torques, "
        "constant; fed: the rigid step fed the same loads\nas torque tables (the QP sees the same "
        "changing forces); both with the rotor's inertia; step loop only, best of 3;\ngoal <= "
        "1.20x"
    )
    print(
        f"{'model':<22} {'generator on':<24} {'rigid':>7} {'fed':>7} {'+ loads':>8} "
        f"{'/rigid':>7} {'/fed':>6}"
    )
    for c in costs:
        where = f"{c['output']} ({c['poles']} poles)"
        print(
            f"{c['model']:<22} {where:<24} {c['rigid_us']:7.2f} {c['table_us']:7.2f} "
            f"{c['loads_us']:8.2f} {c['loads_us'] / c['rigid_us']:7.2f} "
            f"{c['loads_us'] / c['table_us']:6.2f}"
        )
    print("(µs per step)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
