"""The torsional natural modes of the NREL 5 MW gearbox and the Saleh 2017 drivetrain, recoded
from the model files alone, and compared with ``pinwind modes``.

Copies (``ideal_copy``): each model with every ``<bearing>`` element removed, so every bearing is
ideal (docs/model_format.md: a bearing without ``radial_stiffness`` is "ideal (rigid)"; its rows
and ratings only carry ISO 281 data, which the modes do not use). Kept: the joints, the torsional
springs (``rotor_coupling``, ``generator_coupling``) and every mesh, compliant (``pinwind modes
MODEL`` takes every mesh compliant by default). The machine is then torsional: one rotation per
continuous joint, the rings on fixed joints (locked).

Recoding (the URDF read with ``xml.etree``, nothing of pinwind's but the compared command):

- Coordinates q: the continuous joints' angles, each about its parent's frame (a planet's
  relative to its carrier, as the model's joints are). Every axis is the world z (checked), so
  a body's small motion is u(X) = Σ_j q_j ẑ × (X − o_j) over the joints j from the ground to it
  (o_j the joint's world origin at the reference pose) and its rotation Σ_j q_j.
- M: Σ over links of m J_vᵀ J_v + I_zz J_ωᵀ J_ω, J_v the rows ẑ × (c − o_j) of its centre of
  mass c and J_ω the ones of its chain; I_zz about the centre of mass (the inertial frames are
  unrotated, checked). For a shaft on its own axis this is its I_zz on its joint; for a planet on
  a carrier at radius r_c it is m r_c² on the carrier's angle and its own I_zz on the carrier's
  angle plus its joint's, the coupling M_cp = I_zz written out (the planet turns at
  θ̇_c + θ̇_p absolutely).
- K: each torsional spring k (e₁ − e₂)(e₁ − e₂)ᵀ (docs/model_format.md: torque −k (θ₁ − θ₂) on
  joint 1); each mesh k_mean g gᵀ, g the gradient of its overlap along the transverse line of
  action, δ = n · (u_A(P) − u_B(P)) at the pitch point P (any point of the line gives the same),
  n the line of action (unit, tangent to both base circles: n = cos α_w t + sin α_w r̂ with
  r̂ the unit vector from A's centre to P, t = ẑ × r̂, cos α_w = (r_b,A ± r_b,B)/a at the
  bearings' centre distance a); so g_j = ±((P − o_j) × n)_z, + for the joints of A's chain, − for
  B's. A gear's own joint contributes ±r_b (its transverse base radius r_b = z m_n cos α_t /
  (2 cos β)); a planet's carrier joint contributes the moment arm of the line about the carrier
  axis: r_b,sun on a sun mesh (the line is tangent to the sun's base circle, centred on that
  axis), r_b,ring on a ring mesh. This is Lin & Parker's (1999) torsional mesh deflection:
  δ_sn = u_s + u_n − η_n cos α_s and δ_rn = u_r − u_n + η_n cos α_r (u = r_b θ with θ absolute,
  η_n = r_c θ_c the planet centre's tangential motion with rigid planet bearings; the signs as
  gfsReboucas/Drivetrain ``Lin_Parker_99.m`` codes their D_s2 and D_r2 blocks), which with
  θ_n = θ_c + θ_p and r_c cos α_s = r_b,s + r_b,p, r_c cos α_r = r_b,r − r_b,p becomes
  δ_sn = r_b,s (θ_s − θ_c) + r_b,p θ_p and δ_rn = −(r_b,r θ_c + r_b,p θ_p) with the ring fixed:
  ``lin_parker_check`` asserts that the geometric gradient is this on every planet mesh. The
  line of action's direction (the flank) only flips g's sign, so K does not depend on it.
- k_mean: ISO 6336-1 method B's c_γα b recoded in benchmarks/independent_mesh_stiffness.py (an
  independent recoding of it: the pinion as ISO's gear 1, a ring as a rack, z_n2 = ∞, which
  docs/validation.md says pinwind takes; the same file prints the other reading).
- The generalized eigenproblem K φ = ω² M φ (``scipy.linalg.eigh``), f = √ω²/2π.

Planar (Lin & Parker 1999's planar model): a copy whose bearings are radial only
(``planar_copy``: ``<bearing joint radial_stiffness>``, axially and in tilt rigid), each such
joint two slides x, y on springs k before its rotation; u(X) gains the slides' directions, so a
mesh's row gains n on its gears' slides, and n's direction now depends on the flank:
n = s cos α_w t + ε sin α_w r̂ (docs/model_format.md, "Mesh sign convention"; ε = −1 when A is
internal), s the flank ``pinwind modes`` names for each unloaded mesh ("X turning forward drives
Y", ``unloaded_flanks``). The NREL 5 MW gearbox with each bearing's own ``radial_stiffness`` (its
rows' isotropic equivalent), the Saleh drivetrain with assumed stiffnesses (``SALEH_RADIAL``).

Compared (every mode, sorted): ``python -m pinwind modes COPY --json``; the NREL 5 MW copy also
with ``--hold generator`` (its row and column struck out of M and K); the Saleh drivetrain also
from its scenario (scenarios/saleh2017_drivetrain.toml, the model without bearings as shipped)
with the rotor's inertia the command prints added on the carrier joint (the rotor preset on the
carrier; the generator law's slope is a damper, which leaves the undamped frequencies alone).

Run:  python benchmarks/independent_modes.py [--all]      (every mode of the large cases with
--all; about 8 s)
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))

from independent_mesh_stiffness import gears_of, recode  # noqa: E402  (ISO 6336-1 c_γα b)

#: Radial stiffness [N/m] of the Saleh drivetrain's bearings in the planar case (assumed: the
#: model file has none; values of the order of the NREL 5 MW gearbox's planet rows).
SALEH_RADIAL = {
    "carrier": 2e9,
    "sun": 1e9,
    "planet1": 1.5e9,
    "planet2": 1.5e9,
    "planet3": 1.5e9,
    "stage1_pinion": 3e9,
    "stage2_pinion": 2.5e9,
}
NREL = REPO / "models" / "nrel5mw_gearbox.urdf"
SALEH = REPO / "models" / "saleh2017_drivetrain.urdf"
SALEH_SCENARIO = REPO / "scenarios" / "saleh2017_drivetrain.toml"


def ideal_copy(model: Path, out: Path) -> Path:
    """``model`` without its ``<bearing>`` elements (every bearing ideal), written to ``out``."""
    tree = ET.parse(model)
    box = tree.getroot().find("gearbox")
    assert box is not None
    for b in box.findall("bearing"):
        box.remove(b)
    tree.write(out, encoding="unicode")
    return out


def planar_copy(model: Path, out: Path, radial: dict[str, float]) -> Path:
    """``model`` with its ``<bearing>`` elements replaced by ``<bearing joint=J
    radial_stiffness=k/>`` for each of ``radial`` [N/m]: every other bearing ideal, these
    compliant radially only (axially and in tilt rigid: docs/model_format.md), written to
    ``out``."""
    tree = ET.parse(model)
    box = tree.getroot().find("gearbox")
    assert box is not None
    for b in box.findall("bearing"):
        box.remove(b)
    for joint, k in radial.items():
        ET.SubElement(box, "bearing", {"joint": joint, "radial_stiffness": repr(k)})
    tree.write(out, encoding="unicode")
    return out


def file_radial_stiffness(model: Path) -> dict[str, float]:
    """Each ``<bearing>``'s own ``radial_stiffness`` [N/m] in ``model`` (for a bearing with rows,
    the rows' equivalent isotropic bearing, docs/model_format.md "Bearing rows")."""
    box = ET.parse(model).getroot().find("gearbox")
    assert box is not None
    return {
        b.attrib["joint"]: float(b.attrib["radial_stiffness"])
        for b in box.findall("bearing")
        if "radial_stiffness" in b.attrib
    }


def unloaded_flanks(stderr: str, model: Path) -> dict[str, float]:
    """Each mesh's flank s that ``pinwind modes`` says it linearised an unloaded mesh on ("X
    turning forward drives Y"). s = +1 is the flank on which gear1 (A) turning forward drives
    gear2 (B) (docs/model_format.md, "Mesh sign convention"): at the pitch point A's tooth moves
    along t, an external B's along −t and an internal B's along +t when each turns forward, so
    B turning forward presses the same flank as A does when external, the other when internal."""
    gears, meshes = gears_of(model)
    pair = {name: (a, b) for name, a, b in meshes}
    found = re.findall(r"(\w+) \((\w+) turning forward drives (\w+)\)", stderr)
    flank = {}
    for mesh, driver, _ in found:
        a, b = pair[mesh]
        internal = gears[a]["internal"] or gears[b]["internal"]
        flank[mesh] = 1.0 if driver == a or not internal else -1.0
    return flank


def _xyz(el: ET.Element | None, name: str = "xyz") -> np.ndarray:
    if el is None:
        return np.zeros(3)
    return np.array([float(v) for v in el.attrib.get(name, "0 0 0").split()])


def _joints_from_ground(link: str, parent_joint: dict) -> list[tuple[ET.Element, np.ndarray]]:
    """The joints from the ground to ``link``, each with its origin in the world [m].

    Every frame is unrotated (``_check_unrotated``), so a joint's world origin is the sum of its
    and its ancestors' origins.
    """
    up = []  # (joint, its origin in the parent frame), from the link to the ground
    while link in parent_joint:
        j = parent_joint[link]
        origin = j.find("origin")
        _check_unrotated(origin, f"joint {j.attrib['name']}")
        up.append((j, _xyz(origin)))
        link = j.find("parent").attrib["link"]  # type: ignore[union-attr]
    chain, at = [], np.zeros(3)
    for j, origin in reversed(up):
        at = at + origin
        chain.append((j, at))
    return chain


def _torsional_springs(box: ET.Element, index: dict[str, int]) -> np.ndarray:
    """K of the model's torsional springs over the coordinates ``index``: k (e₁ − e₂)(e₁ − e₂)ᵀ
    (a spring to the ground when it has no joint2)."""
    K = np.zeros((len(index), len(index)))
    for spring in box.findall("torsional_spring"):
        e = np.zeros(len(index))
        e[index[spring.attrib["joint1"]]] += 1.0
        if "joint2" in spring.attrib:
            e[index[spring.attrib["joint2"]]] -= 1.0
        K += float(spring.attrib["stiffness"]) * np.outer(e, e)
    return K


def _z_axis(joint: ET.Element) -> np.ndarray:
    """A revolute joint's unit axis, which the recoding takes along ±z."""
    axis = _xyz(joint.find("axis"))
    axis = axis / np.linalg.norm(axis)
    if abs(abs(axis[2]) - 1.0) > 1e-12:
        raise ValueError(f"joint {joint.attrib['name']}: axis {axis} is not along z")
    return axis


def _check_unrotated(el: ET.Element | None, what: str) -> None:
    if el is not None and any(float(v) != 0.0 for v in el.attrib.get("rpy", "0 0 0").split()):
        raise ValueError(f"{what}: a rotated frame; this recoding takes unrotated frames only")


@dataclass
class Torsional:
    """A torsional model: joint names (the coordinates), M [kg·m²], K [N·m/rad], the meshes'
    k_mean [N/m] and gradients g [m/rad]."""

    joints: list[str]
    M: np.ndarray
    K: np.ndarray
    k_mean: dict[str, float]
    gradient: dict[str, np.ndarray]

    def frequencies_hz(
        self, hold: tuple[str, ...] = (), extra_inertia: dict[str, float] | None = None
    ) -> np.ndarray:
        """Sorted natural frequencies [Hz] with the ``hold`` joints held (struck out) and
        ``extra_inertia`` [kg·m²] added on joints."""
        M = self.M.copy()
        for j, inertia in (extra_inertia or {}).items():
            i = self.joints.index(j)
            M[i, i] += inertia
        keep = [i for i, j in enumerate(self.joints) if j not in hold]
        lam = scipy.linalg.eigh(
            self.K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True
        )
        return np.sqrt(np.clip(lam, 0.0, None)) / (2 * math.pi)


def torsional_model(
    model: Path, pinion_first: bool = True, flank: dict[str, float] | None = None
) -> Torsional:
    """M and K of ``model`` (read as XML) in its joints' coordinates: each continuous joint's
    angle, and before it, for a joint whose ``<bearing>`` has ``radial_stiffness`` k, two slides
    along the world x and y (the bearing's translations relative to the joint's parent, each on
    a spring k; isotropic, so the slides' axes do not change the modes) — Lin & Parker's (1999)
    planar model. ``pinion_first=False`` takes each mesh's ``gear1`` as ISO 6336-1's gear 1
    instead of the pinion; ``flank`` gives each mesh's loaded flank s = ±1 (docs/model_format.md,
    "Mesh sign convention": +1 when gear1 turning positively drives gear2), which only a model
    with translations needs (default +1)."""
    root = ET.parse(model).getroot()
    box = root.find("gearbox")
    assert box is not None
    joints = {j.attrib["name"]: j for j in root.findall("joint")}
    parent_joint = {j.find("child").attrib["link"]: j for j in joints.values()}  # type: ignore[union-attr]
    radial = {
        b.attrib["joint"]: float(b.attrib["radial_stiffness"])
        for b in box.findall("bearing")
        if "radial_stiffness" in b.attrib
    }
    dofs: list[str] = []
    for name, j in joints.items():
        if j.attrib["type"] in ("continuous", "revolute"):
            if name in radial:
                dofs += [f"{name}_x", f"{name}_y"]
            dofs.append(name)
    index = {n: i for i, n in enumerate(dofs)}

    Link = tuple[int, np.ndarray, float, np.ndarray | None]

    def chain(link: str) -> tuple[np.ndarray, list[Link]]:
        """The link frame's world origin and its chain: (dof index, joint origin, axis sign,
        None) for a rotation, (dof index, _, _, direction) for a slide."""
        acc, world = np.zeros(3), []
        for j, acc in _joints_from_ground(link, parent_joint):
            name = j.attrib["name"]
            if j.attrib["type"] in ("continuous", "revolute"):
                axis = _z_axis(j)
                if name in radial:
                    world.append((index[f"{name}_x"], acc.copy(), 0.0, np.array([1.0, 0.0, 0.0])))
                    world.append((index[f"{name}_y"], acc.copy(), 0.0, np.array([0.0, 1.0, 0.0])))
                world.append((index[name], acc.copy(), float(np.sign(axis[2])), None))
        return acc, world

    def displacement_rows(x: np.ndarray, ch: list[Link]) -> tuple[np.ndarray, np.ndarray]:
        """∂u(x)/∂q (3, n) and ∂ω/∂q (n) of a point x on a body with chain ``ch``."""
        jv, jw = np.zeros((3, n)), np.zeros(n)
        for i, o, s, direction in ch:
            if direction is None:
                jv[:, i] += s * np.cross(z, x - o)
                jw[i] += s
            else:
                jv[:, i] += direction
        return jv, jw

    n = len(dofs)
    z = np.array([0.0, 0.0, 1.0])
    M = np.zeros((n, n))
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        origin = inertial.find("origin")
        _check_unrotated(origin, f"link {link.attrib['name']} inertial")
        m = float(inertial.find("mass").attrib["value"])  # type: ignore[union-attr]
        izz = float(inertial.find("inertia").attrib["izz"])  # type: ignore[union-attr]
        pos, ch = chain(link.attrib["name"])
        Jv, Jw = displacement_rows(pos + _xyz(origin), ch)
        M += m * Jv.T @ Jv + izz * np.outer(Jw, Jw)

    K = np.zeros((n, n))
    for joint, k in radial.items():
        for axis in "xy":
            K[index[f"{joint}_{axis}"], index[f"{joint}_{axis}"]] += k
    K += _torsional_springs(box, index)

    gears, meshes = gears_of(model)
    gear_el = {g.attrib["name"]: g for g in box.findall("gear")}
    k_mean, gradient = {}, {}
    for name, a, b in meshes:
        ga, gb = gears[a], gears[b]
        k = recode(ga, gb, ring_as_rack=True, pinion_first=pinion_first)["kmean"]
        (ca, cha), (cb, chb) = (
            (
                chain(gear_el[g].attrib["link"])[0] + _xyz(gear_el[g]),
                chain(gear_el[g].attrib["link"])[1],
            )
            for g in (a, b)
        )
        rb = [
            g["z"]
            * g["m"]
            * math.cos(math.atan(math.tan(g["alpha"]) / math.cos(g["beta"])))
            / (2 * math.cos(g["beta"]))
            for g in (ga, gb)
        ]
        d = (cb - ca)[:2]
        dist = float(np.linalg.norm(d))
        # r̂ from A's centre to the pitch point P; ε = −1 when A is the internal gear
        if gb["internal"]:  # B the ring around A: P beyond A's centre, away from B's
            r_hat, cos_aw, eps = -d / dist, (rb[1] - rb[0]) / dist, 1.0
        elif ga["internal"]:  # A the ring around B: P beyond B's centre, from A's
            r_hat, cos_aw, eps = d / dist, (rb[0] - rb[1]) / dist, -1.0
        else:
            r_hat, cos_aw, eps = d / dist, (rb[0] + rb[1]) / dist, 1.0
        sin_aw = math.sqrt(1.0 - cos_aw**2)
        t_hat = np.array([-r_hat[1], r_hat[0]])
        s = (flank or {}).get(name, 1.0)
        nvec = np.append(s * cos_aw * t_hat + eps * sin_aw * r_hat, 0.0)
        P = ca + rb[0] / cos_aw * np.append(r_hat, 0.0)
        P[2] = 0.0
        # δ = n · (u_A(P) − u_B(P)): the force on B is along n (docs/model_format.md)
        ja, _ = displacement_rows(P, [(i, o * [1, 1, 0], sg, dr) for i, o, sg, dr in cha])
        jb, _ = displacement_rows(P, [(i, o * [1, 1, 0], sg, dr) for i, o, sg, dr in chb])
        g = nvec @ (ja - jb)
        K += k * np.outer(g, g)
        k_mean[name], gradient[name] = k, g
    return Torsional(dofs, M, K, k_mean, gradient)


def spatial_model(model: Path, flank: dict[str, float], thrust: float = 1.0) -> Torsional:
    """M and K of ``model`` as shipped, its compliant bearings with their rows
    (docs/model_format.md, "Compliant bearings" and "Bearing rows"): before each continuous
    joint whose ``<bearing>`` has ``radial_stiffness``, slides along u and w (u the
    ``radial_axis``, default the joint's x, w = k × u), along k with ``axial_stiffness``, and
    hinges about u and w through the joint's origin with ``tilt_stiffness``. Each row at a along
    k holds them with its five springs along δ = (z, x + a θ_w, y − a θ_u, θ_u, θ_w) (K_x, K_y,
    K_z, K_β, K_γ); a bearing without rows its own isotropic springs. A body moves by u(X) = Σ
    θ_j a_j × (X − o_j) + Σ q_j d_j and turns by Σ θ_j a_j, so M = Σ m J_vᵀ J_v + J_ωᵀ I J_ω
    with the full inertia tensor. A mesh's overlap δ = f · (u_A(P) − u_B(P)) at the pitch point
    P in the gears' plane, f = n − s tan β_b,A k_A: the transverse line of action n
    (``torsional_model``) and, for a helical pair, the axial part of the tooth force
    (docs/model_format.md, "Mesh sign convention": the force on B gains −s F_n tan β_b,A k_A; an
    axial shift dz of A moves its flank as a turn of −dz tan β_w / r_w, the overlap by −s dz tan
    β_b); ``thrust=0`` leaves that axial part out, as pinwind's mesh row did before it carried the
    thrust. All axes along z,
    frames unrotated (checked)."""
    root = ET.parse(model).getroot()
    box = root.find("gearbox")
    assert box is not None
    joints = {j.attrib["name"]: j for j in root.findall("joint")}
    parent_joint = {j.find("child").attrib["link"]: j for j in joints.values()}  # type: ignore[union-attr]
    bearings = {
        b.attrib["joint"]: b for b in box.findall("bearing") if "radial_stiffness" in b.attrib
    }
    k_hat = np.array([0.0, 0.0, 1.0])
    dofs: list[str] = []
    frames: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for name, j in joints.items():
        if j.attrib["type"] not in ("continuous", "revolute"):
            continue
        if name in bearings:
            b = bearings[name]
            u = _xyz(b, "radial_axis") if "radial_axis" in b.attrib else np.array([1.0, 0, 0])
            u = u - (u @ k_hat) * k_hat
            u = u / np.linalg.norm(u)
            frames[name] = (u, np.cross(k_hat, u))
            dofs += [f"{name}_radial_x", f"{name}_radial_y"]
            if "axial_stiffness" in b.attrib:
                dofs.append(f"{name}_axial")
            if "tilt_stiffness" in b.attrib:
                dofs += [f"{name}_tilt_x", f"{name}_tilt_y"]
        dofs.append(name)
    index = {n: i for i, n in enumerate(dofs)}
    n = len(dofs)

    Entry = tuple[int, np.ndarray, np.ndarray, bool]  # (dof, point, axis or direction, rotation?)

    def chain(link: str) -> tuple[np.ndarray, list[Entry]]:
        acc, out = np.zeros(3), []
        for j, acc in _joints_from_ground(link, parent_joint):
            name = j.attrib["name"]
            if j.attrib["type"] not in ("continuous", "revolute"):
                continue
            axis = _z_axis(j)
            if name in frames:
                u, w = frames[name]
                out.append((index[f"{name}_radial_x"], acc.copy(), u, False))
                out.append((index[f"{name}_radial_y"], acc.copy(), w, False))
                if f"{name}_axial" in index:
                    out.append((index[f"{name}_axial"], acc.copy(), k_hat, False))
                if f"{name}_tilt_x" in index:
                    out.append((index[f"{name}_tilt_x"], acc.copy(), u, True))
                    out.append((index[f"{name}_tilt_y"], acc.copy(), w, True))
            out.append((index[name], acc.copy(), axis, True))
        return acc, out

    def rows(x: np.ndarray, ch: list[Entry]) -> tuple[np.ndarray, np.ndarray]:
        jv, jw = np.zeros((3, n)), np.zeros((3, n))
        for i, o, a, rotation in ch:
            if rotation:
                jv[:, i] += np.cross(a, x - o)
                jw[:, i] += a
            else:
                jv[:, i] += a
        return jv, jw

    M = np.zeros((n, n))
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        origin = inertial.find("origin")
        _check_unrotated(origin, f"link {link.attrib['name']} inertial")
        m = float(inertial.find("mass").attrib["value"])  # type: ignore[union-attr]
        ia = inertial.find("inertia").attrib  # type: ignore[union-attr]
        inertia = np.array(
            [
                [float(ia["ixx"]), float(ia["ixy"]), float(ia["ixz"])],
                [float(ia["ixy"]), float(ia["iyy"]), float(ia["iyz"])],
                [float(ia["ixz"]), float(ia["iyz"]), float(ia["izz"])],
            ]
        )
        pos, ch = chain(link.attrib["name"])
        jv, jw = rows(pos + _xyz(origin), ch)
        M += m * jv.T @ jv + jw.T @ inertia @ jw

    K = np.zeros((n, n))
    for joint, b in bearings.items():
        row_els = b.findall("row")
        stiff = [
            (
                float(r.attrib.get("position_mm", "0")) * 1e-3,
                [float(v) for v in r.attrib["stiffness"].split()],
            )
            for r in row_els
            if "stiffness" in r.attrib
        ]
        if not stiff:  # the bearing's own isotropic springs
            kr = float(b.attrib["radial_stiffness"])
            ka = float(b.attrib.get("axial_stiffness", "0"))
            kt = float(b.attrib.get("tilt_stiffness", "0"))
            stiff = [(0.0, [ka, kr, kr, kt, kt])]
        e = {
            key: np.eye(n)[index[f"{joint}_{key}"]] if f"{joint}_{key}" in index else np.zeros(n)
            for key in ("radial_x", "radial_y", "axial", "tilt_x", "tilt_y")
        }
        for a, kk in stiff:
            deltas = (
                e["axial"],
                e["radial_x"] + a * e["tilt_y"],
                e["radial_y"] - a * e["tilt_x"],
                e["tilt_x"],
                e["tilt_y"],
            )
            for kj, dj in zip(kk, deltas, strict=True):
                K += kj * np.outer(dj, dj)
    K += _torsional_springs(box, index)

    gears, meshes = gears_of(model)
    gear_el = {g.attrib["name"]: g for g in box.findall("gear")}
    k_mean, gradient = {}, {}
    for name, a_name, b_name in meshes:
        ga, gb = gears[a_name], gears[b_name]
        k = recode(ga, gb, ring_as_rack=True)["kmean"]
        (ca, cha), (cb, chb) = (
            (
                chain(gear_el[g].attrib["link"])[0] + _xyz(gear_el[g]),
                chain(gear_el[g].attrib["link"])[1],
            )
            for g in (a_name, b_name)
        )
        at = [math.atan(math.tan(g["alpha"]) / math.cos(g["beta"])) for g in (ga, gb)]
        rb = [
            g["z"] * g["m"] * math.cos(t) / (2 * math.cos(g["beta"]))
            for g, t in zip((ga, gb), at, strict=True)
        ]
        d = (cb - ca)[:2]
        dist = float(np.linalg.norm(d))
        if gb["internal"]:
            r_hat, cos_aw, eps = -d / dist, (rb[1] - rb[0]) / dist, 1.0
        elif ga["internal"]:
            r_hat, cos_aw, eps = d / dist, (rb[0] - rb[1]) / dist, -1.0
        else:
            r_hat, cos_aw, eps = d / dist, (rb[0] + rb[1]) / dist, 1.0
        sin_aw = math.sqrt(1.0 - cos_aw**2)
        t_hat = np.array([-r_hat[1], r_hat[0]])
        s = flank.get(name, 1.0)
        nvec = np.append(s * cos_aw * t_hat + eps * sin_aw * r_hat, 0.0)
        tan_bb = math.tan(ga["beta"]) * math.cos(at[0])  # signed by A's hand
        f = nvec - thrust * s * tan_bb * k_hat
        P = ca + rb[0] / cos_aw * np.append(r_hat, 0.0)
        ja, _ = rows(P, cha)
        jb, _ = rows(P, chb)
        g = f @ (ja - jb)
        K += k * np.outer(g, g)
        k_mean[name], gradient[name] = k, g
    return Torsional(dofs, M, K, k_mean, gradient)


def lin_parker_check(
    model: Path, t: Torsional, carrier: str, sun: str, planets: dict[str, str], rings: set[str]
) -> float:
    """Largest |g − g_LP| / r_b over the planet meshes of the stage whose carrier joint, sun joint
    and planet joints are given (``planets``: planet gear name → its joint), g_LP Lin & Parker's
    torsional deflection in joint coordinates (module docstring), up to the flank's sign."""
    gears, meshes = gears_of(model)
    worst = 0.0

    def rbase(g: dict[str, float]) -> float:
        at = math.atan(math.tan(g["alpha"]) / math.cos(g["beta"]))
        return g["z"] * g["m"] * math.cos(at) / (2 * math.cos(g["beta"]))

    ic = t.joints.index(carrier)
    for name, a, b in meshes:
        if b not in planets or a in planets:
            if not (a in planets and b in rings):
                continue
        lp = np.zeros(len(t.joints))
        if a in planets and b in rings:  # δ_rn = −(r_b,r θ_c + r_b,p θ_p)
            lp[ic] = rbase(gears[b])
            lp[t.joints.index(planets[a])] = rbase(gears[a])
            scale = rbase(gears[b])
        else:  # sun–planet: δ_sn = r_b,s (θ_s − θ_c) + r_b,p θ_p
            lp[t.joints.index(sun)] = rbase(gears[a])
            lp[ic] = -rbase(gears[a])
            lp[t.joints.index(planets[b])] = rbase(gears[b])
            scale = rbase(gears[a])
        g = t.gradient[name]
        worst = max(worst, min(np.max(np.abs(g - lp)), np.max(np.abs(g + lp))) / scale)
    return worst


def pinwind_modes(path: Path, *args: str) -> tuple[np.ndarray, str]:
    """Frequencies [Hz] of ``pinwind modes PATH --json ARGS`` (sorted) and its stderr."""
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "modes", str(path), "--json", *args],
        capture_output=True,
        text=True,
        check=True,
        cwd=REPO,
        env={"PYTHONPATH": str(REPO), "PATH": "/usr/bin:/bin"},
    )
    modes = json.loads(out.stdout)
    if isinstance(modes, dict):
        modes = modes["modes"]
    return np.sort(np.array([m["frequency_hz"] for m in modes])), out.stderr


def compare(label: str, pinwind_hz: np.ndarray, recoded_hz: np.ndarray) -> float:
    """Print one row per mode (with ``--all``, or up to 13 modes; else the lowest five, the
    highest two and the largest difference); return the largest relative difference of the
    flexible modes."""
    if len(pinwind_hz) != len(recoded_hz):
        raise AssertionError(
            f"{label}: pinwind has {len(pinwind_hz)} modes, the recoding {len(recoded_hz)}"
        )
    rigid = recoded_hz < 1e-6 * recoded_hz[-1]
    rel = np.where(rigid, 0.0, pinwind_hz / np.where(rigid, 1.0, recoded_hz) - 1)
    worst = int(np.argmax(np.abs(rel)))
    n = len(recoded_hz)
    shown = set(range(n)) if n <= 13 or "--all" in sys.argv else {*range(5), n - 2, n - 1, worst}
    print(f"\n{label}: {n} modes")
    print(f"{'#':>3s} {'pinwind [Hz]':>14s} {'recoded [Hz]':>14s} {'rel. diff':>10s}")
    for i in sorted(shown):
        if i > 0 and i - 1 not in shown:
            print("  ⋮")
        p, r = pinwind_hz[i], recoded_hz[i]
        if rigid[i]:
            print(f"{i + 1:3d} {p:14.6g} {r:14.6g} {'rigid':>10s}")
        else:
            print(f"{i + 1:3d} {p:14.8g} {r:14.8g} {rel[i]:+10.1e}")
    return float(np.abs(rel[worst]))


def pinwind_mesh_stiffness(model: Path) -> dict[str, float]:
    """The stiffness [N/m] of each mesh element ``pinwind.modes.linearisation.linearise`` takes
    with every mesh compliant (compared with the recoded k_mean, not used by the recoding)."""
    import pinwind
    from pinwind.modes.linearisation import linearise

    lin = linearise(pinwind.load(model), meshes={"all": "compliant"})
    return {e.name: float(e.stiffness) for e in lin.elements if e.kind == "mesh"}


def izz_of(model: Path, link: str) -> float:
    """I_zz [kg·m²] of ``link`` in ``model``'s XML."""
    for el in ET.parse(model).getroot().findall("link"):
        if el.attrib["name"] == link:
            return float(el.find("inertial/inertia").attrib["izz"])  # type: ignore[union-attr]
    raise KeyError(link)


def scenario_rotor(stderr: str) -> tuple[str, float]:
    """The joint and inertia [kg·m²] of the rotor ``pinwind modes SCENARIO`` says it took."""
    found = re.search(r"rotor inertia on (\w+): ([0-9.e+-]+) kg", stderr)
    if found is None:
        raise AssertionError(f"no rotor inertia line in: {stderr}")
    return found.group(1), float(found.group(2))


def main() -> None:
    start = time.perf_counter()
    worst: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        nrel = ideal_copy(NREL, Path(tmp) / "nrel5mw_ideal_bearings.urdf")
        saleh = ideal_copy(SALEH, Path(tmp) / "saleh2017_ideal_bearings.urdf")
        tn, ts = torsional_model(nrel), torsional_model(saleh)
        lp = max(
            lin_parker_check(nrel, tn, "lss", "iss", planets(1), {"stage1_ring"}),
            lin_parker_check(nrel, tn, "iss", "ims", planets(2), {"stage2_ring"}),
            lin_parker_check(saleh, ts, "carrier", "sun", planets(0), {"ring"}),
        )
        print(f"planet meshes' gradients against Lin & Parker's deflections: {lp:.1e} of r_b")
        print("\nk_mean = c_γα b [N/m], recoded, and pinwind's mesh element over it − 1:")
        for model, t in ((nrel, tn), (saleh, ts)):
            theirs = pinwind_mesh_stiffness(model)
            for name, k in t.k_mean.items():
                if name[-1] in "23" or name.endswith(("2_ring", "3_ring")):
                    continue  # the other planets' meshes are the same pairs
                print(f"  {name:20s} {k:.6e}  {theirs[name] / k - 1:+.1e}")
            worst["k_mean"] = max(
                worst.get("k_mean", 0.0), *(abs(theirs[n] / k - 1) for n, k in t.k_mean.items())
            )

        p, _ = pinwind_modes(nrel)
        worst["nrel"] = compare("NREL 5 MW gearbox, ideal bearings, free", p, tn.frequencies_hz())
        p, _ = pinwind_modes(nrel, "--hold", "generator")
        worst["nrel_held"] = compare(
            "NREL 5 MW gearbox, ideal bearings, generator held (--hold generator)",
            p,
            tn.frequencies_hz(hold=("generator",)),
        )
        keep = [i for i, j in enumerate(tn.joints) if j != "generator"]
        mu = scipy.linalg.eigh(
            tn.M[np.ix_(keep, keep)], tn.K[np.ix_(keep, keep)], eigvals_only=True
        )
        flex = 1 / math.sqrt(mu[-1]) / (2 * math.pi)
        mine = tn.frequencies_hz(hold=("generator",))[0]
        eps_rel = np.finfo(float).eps * (p[-1] / p[0]) ** 2
        print(
            f"mode 1 from the flexibility form, eigh(M, K): {flex:.12g} Hz; pinwind "
            f"{p[0] / flex - 1:+.1e}, the recoding {mine / flex - 1:+.1e} (eigh(K, M) resolves "
            f"ω² to about ε λ_max, {eps_rel:.0e} of this mode's)"
        )
        p, _ = pinwind_modes(saleh)
        worst["saleh"] = compare(
            "Saleh 2017 drivetrain (no bearings), free", p, ts.frequencies_hz()
        )
        p, err = pinwind_modes(SALEH_SCENARIO)
        joint, inertia = scenario_rotor(err)
        rec = ts.frequencies_hz(extra_inertia={joint: inertia})
        worst["saleh_rotor"] = compare(
            f"Saleh 2017 drivetrain scenario: its rotor, {inertia:.3g} kg·m² on {joint}", p, rec
        )
        print("\nplanet modes in closed form, f = √((k_sp + k_rp) r_b,p² / I_p)/2π (the central")
        print("members still, N − 1 = 2 of them), against pinwind's nearest two:")
        for model, t, stage in ((nrel, tn, 1), (nrel, tn, 2), (saleh, ts, 0)):
            gear = next(iter(planets(stage)))
            g = gears_of(model)[0][gear]
            at = math.atan(math.tan(g["alpha"]) / math.cos(g["beta"]))
            rbp = g["z"] * g["m"] * math.cos(at) / (2 * math.cos(g["beta"]))
            izz = izz_of(model, gear)
            prefix = gear[: -len("planet1")]
            k = t.k_mean[f"{prefix}sun_planet1"] + t.k_mean[f"{gear}_ring"]
            f = math.sqrt(k * rbp**2 / izz) / (2 * math.pi)
            theirs, _ = pinwind_modes(model)
            near = theirs[np.argsort(np.abs(theirs - f))[:2]]
            worst["planet"] = max(worst.get("planet", 0.0), *np.abs(near / f - 1))
            print(f"  {gear:16s} {f:.8g} Hz: {near[0] / f - 1:+.1e}, {near[1] / f - 1:+.1e}")
        # Lin & Parker's planar model: the bearings compliant radially (two slides each)
        cases = (
            ("NREL 5 MW gearbox, each bearing its rows' isotropic radial stiffness", NREL,
             file_radial_stiffness(NREL)),
            ("Saleh 2017 drivetrain, radial bearings (assumed stiffnesses)", SALEH, SALEH_RADIAL),
        )  # fmt: skip
        for label, source, radial in cases:
            copy = planar_copy(source, Path(tmp) / f"planar_{source.name}", radial)
            p, err = pinwind_modes(copy)
            flank = unloaded_flanks(err, copy)
            key = f"planar {source.stem}"
            worst[key] = compare(
                f"{label}, planar", p, torsional_model(copy, flank=flank).frequencies_hz()
            )
            # the flanks matter once members translate: each mesh's flipped alone
            moved = 0.0
            for mesh in flank:
                flipped = torsional_model(copy, flank={**flank, mesh: -flank[mesh]})
                moved = max(moved, float(np.max(np.abs(flipped.frequencies_hz()[1:] / p[1:] - 1))))
            print(f"one mesh on its other flank moves a mode by up to {moved:.1e}")
        # the shipped NREL 5 MW gearbox: its rows at their positions, K_y ≠ K_z, axial and tilt
        p, err = pinwind_modes(NREL)
        flank = unloaded_flanks(err, NREL)
        shipped = spatial_model(NREL, flank)
        worst["shipped"] = compare(
            "NREL 5 MW gearbox as shipped (each row's five springs at its position), stage 3's "
            "helical thrust in its mesh row",
            p,
            shipped.frequencies_hz(),
        )
        p, _ = pinwind_modes(NREL, "--hold", "generator")
        mine = shipped.frequencies_hz(hold=("generator",))
        worst["shipped_held"] = float(np.max(np.abs(p / mine - 1)))
        print(
            f"with the generator held: {len(p)} modes, the first {p[0]:.6g} Hz (recoded "
            f"{mine[0]:.6g} Hz), largest |rel. diff| {worst['shipped_held']:.1e}"
        )
        thrust = shipped.frequencies_hz()
        free = spatial_model(NREL, flank, thrust=0.0).frequencies_hz()
        flexible = free > 1e-3 * free[-1]
        moved = np.abs(thrust[flexible] / free[flexible] - 1)
        worst_at = int(np.argmax(moved))
        print(
            "with stage 3's axial thrust left out of its row (f = n): modes move by up to "
            f"{moved[worst_at]:.1e} ({thrust[flexible][worst_at]:.2f} Hz with it, "
            f"{free[flexible][worst_at]:.2f} Hz without)"
        )
        old = torsional_model(saleh, pinion_first=False)
        print(
            "\nwith each mesh's gear1 as ISO 6336-1's gear 1 (the numbering before the pinion was "
            f"taken first): {old.frequencies_hz()[1]:.2f} Hz free, "
            f"{old.frequencies_hz(extra_inertia={joint: inertia})[1]:.2f} Hz with the rotor"
        )
    print(
        f"\nlargest |rel. diff|: k_mean {worst.pop('k_mean'):.1e}, flexible modes "
        f"{max(worst.values()):.1e}; {time.perf_counter() - start:.1f} s wall"
    )


def planets(stage: int) -> dict[str, str]:
    """Planet gear → planet joint of a stage (0: the Saleh stage's ``planet{i}``)."""
    prefix = f"stage{stage}_" if stage else ""
    return {f"{prefix}planet{i}": f"{prefix}planet{i}" for i in (1, 2, 3)}


if __name__ == "__main__":
    main()
