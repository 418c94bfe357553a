"""The rotor's thrust, weight and wind-shear moment on the NREL 5 MW main shaft, and the bearing
rows that carry them, recoded from the model file and public formulas without pinwind's rotor,
hub-load or bearing-row code.

Runs (``pinwind.runs.scenario``, no log) on ``models/nrel5mw_gearbox.urdf`` as shipped (rigid
meshes, every bearing on its rows, the static start), dt = 1e-4 s:

- **A** (the rotor): the ``nrel5mw`` preset on joint ``rotor`` with its hub on ``lss`` at the
  main shaft's rotor end (``hub_point`` of scenarios/nrel5mw_turbulent.toml), the blades at
  1.3° of pitch, a constant wind of 10 m/s, the generator held at 12.1 rpm · 96.354 (turning
  against the rotor), 0.3 s.
- **A′**: A again with the rotor's ``hub_body`` left out and, instead, a hub load on ``lss`` at
  the same point (fixed frame) whose F_x, F_z, M_y are the recoded ones, sample by sample (a
  ``csv`` signal of A's sample times). A and A′ go through the same states exactly when the
  rotor's hub loads are the recoded ones; the rows' loads of the two runs then agree to rounding.
- **B** (a hub load, standing): no rotor law; the rated rotor torque 3 945 990 N·m on joint
  ``rotor`` against the generator held at standstill, and a constant hub load on ``lss`` at the
  hub, F_x = 8e5, F_y = 1.5e5, F_z = −1.2e6 N, M_y = 2.5e6, M_z = −8e5 N·m (fixed frame), 0.2 s.
  The static start puts it in equilibrium: its statics close to rounding.
- **B rotating**: B with its hub load in the ``rotating`` frame, standing (the shaft angle ψ is
  the coupling's wind-up, 4.3e-4 rad).
- **E**: A in 3 m/s for 30 steps: λ = 26.6, beyond the table (held at its edge, docs/loads.md).
- **S** (a rotor known by its C_p alone): Saleh 2017's rotor (the ``saleh2017`` preset, Heier's
  C_p fit) on ``models/saleh2017_planetary.urdf`` at 14.2 rpm in 10 m/s, 0.05 s at dt = 1 ms;
  its thrust from momentum theory, C_t = 4a(1 − a) for the a ≤ 1/3 of C_p = 4a(1 − a)² (Burton
  et al. 2011 §3.2), with the run's own C_p as the input and ρ = 1.225 kg/m³, R = 42.85 m.
- **C**, **C′** and **C″** (a rotating-frame hub load, turning): B's torque, the generator held
  at 12.1 rpm · 96.354, B's five hub components as a ``rotating`` load, 0.3 s; C′ the same load
  given in the fixed frame as ``csv`` signals, turned by hand with the shaft angle ψ of C's
  samples (docs/loads.md: v_ys = cos ψ v_ya − sin ψ v_za, v_zs = sin ψ v_ya + cos ψ v_za) and
  then with the shaft's tilts θ_u, θ_w of C's samples (a rotating load turns with the body's
  frame, which the bearing tilts; a fixed one keeps the housing's axes); C″ turned by ψ alone.

Recoding (the model file read with ``xml.etree``, the shipped ROSCO table read by its own parser):

- thrust T = ½ ρ π R² v² C_t(λ, β) (Burton et al. 2011, Wind Energy Handbook §3.2: the thrust
  coefficient C_T = T / (½ ρ U² A_D)), λ = ω R / v with ω the rotor joint's speed at the sample,
  C_t bilinear in (λ, β) on ROSCO's table (``pinwind/loads/data/nrel5mw_cp_ct_cq.txt``, Abbas et
  al. 2022); R = 63 m, hub height 90 m, shaft tilt 5°, rotor mass 110 000 kg (Jonkman et al. 2009
  Table 1-1), ρ = 1.225 kg/m³ (Jonkman et al. 2009), β = 1.3° (between the table's columns);
- the wind-shear arm ℓ = (1/πR²) ∫ z (1 + z/H)^{2α} dA over the disc (docs/loads.md; IEC 61400-1's
  normal wind profile v(z) = v_hub (z/z_hub)^α with α = 0.2, the hub at z = H), by Gauss–Legendre
  quadrature on z = R sin t (the chord 2R cos t makes the integrand smooth), beside its small-shear
  limit α R²/(2H);
- the hub's loads in its fixed frame (x along the shaft downwind, z up): F_x = T + m g sin τ,
  F_z = −m g cos τ, M_y = ℓ T;
- the main shaft ``lss`` as a rigid body on its rows: all four rows of its ``<bearing>``, the
  main bearings INP-A, INP-B and the carrier bearings PLC-A, PLC-B (``lss`` is the main shaft and
  stage 1's carrier in one body), on the slides of docs/model_format.md ("Compliant bearings":
  x along u, y along w, z along k, then the tilts θ_u about u and θ_w about the tilted w through
  the bearing centre) with each row's law δ = (z, x + a θ_w, y − a θ_u, θ_u, θ_w), L = −K δ − C δ̇
  ("Bearing rows"). The loads on the shaft: the hub load at its point (force and moment in the
  housing's axes, or turned with the shaft's tilts for a rotating load; the point moves with the
  shaft), the shaft's weight at its centre of mass (the
  model's gravity), and what the gearbox side puts on it. ``lss`` carries the three stage-1
  planets on their compliant bearings, whose reactions do not cancel (the planets' weights and
  the meshes' unequal sharing, as the hub load moves and tilts the carrier against rigid meshes:
  in run B the stage-1 sun meshes carry 729, 940 and 820 kN and the planets push the carrier by
  0.29 MN on 2026-12-08), so they enter as an input: minus
  each planet bearing's reaction (``bearing_force``, ``bearing_moment``, world) at the planet's
  link origin (``body_position``). The rotor torque reaches ``lss`` through the coupling spring on
  the joint's own coordinate, not on the slides. The slides' equilibrium Σ_i B_iᵀ K_i B_i q = Q(q)
  (Q the loads' virtual work through the slides' exact kinematics, which moves with q only by the
  lever arms) is solved by fixed-point iteration; each row's (F_u, F_w, F_k) and (M_u, M_w)
  follow.

Compared with the runs' series: ``rotor("rotor").tip_speed_ratio``, ``thrust_coefficient``,
``thrust``; ``row("lss.<row>").force``, ``moment``; the slides (``joint("lss_radial_x")`` …);
``bearing("lss").displacement``, ``force`` and ``moment``. Run A turns: its planets orbit, their
reactions turn with them, and the shaft vibrates on its lightly damped rows, so the statics hold
there only to that vibration; with the shaft's inertia (its mass matrix on the slides from the
model's mass, centre of mass and I_xx, times the slides' ``acceleration``) and the spin's
gyroscopic moment I_zz Ω θ̇ the equation of motion closes to 1e-7. The rows' law itself is checked
on every sample of A at the step's weighted state (a sample's loads are its step's, at ρ∞ = 1 the
mean of the states at its two ends). C and C′ start from static starts that stop at a residual of
7e-7 (a turning start with loads fixed in space is periodic, not static: docs/limitations.md), a
follower load and a given one leading the solve to points 1e-11 m apart; their rows differ by that
start, 2e-7, at every sample.

Run: ``PYTHONPATH=. python benchmarks/independent_hub_loads.py`` (about 10 s).
"""

from __future__ import annotations

import math
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from pinwind.runs.scenario import load_scenario, run  # noqa: E402

MODEL = REPO / "models" / "nrel5mw_gearbox.urdf"
TABLE = REPO / "pinwind" / "loads" / "data" / "nrel5mw_cp_ct_cq.txt"
DT = 1e-4

# Jonkman et al. 2009 Table 1-1 (ρ: their air density)
RADIUS = 63.0  # m
HUB_HEIGHT = 90.0  # m
TILT = math.radians(5.0)
ROTOR_MASS = 110_000.0  # kg
AIR_DENSITY = 1.225  # kg/m³
SHEAR_EXPONENT = 0.2  # IEC 61400-1 normal wind profile
WIND = 10.0  # m/s
#: run E's wind [m/s]: λ = 26.6 at 12.1 rpm, beyond the table's 14.5
LOW_WIND = 3.0
SALEH_RADIUS = 42.85  # m: 41 m + 3.7 m / 2 (docs/loads.md, Saleh 2017's calibration)
#: run A's blade pitch [deg]: between the table's columns 1.0° and 1.5°
PITCH_DEG = 1.3
ROTOR_RPM = 12.1
RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # from the teeth
HUB_POINT = (0.0, 0.0, -0.88709638554)  # m, in the lss frame: where the rotor joint sits
RATED_TORQUE = 3945990.3245924464  # N·m, 5 MW at 12.1 rpm
#: runs B and C: the hub load F_x, F_y, F_z [N], M_x, M_y, M_z [N·m]
HUB_LOAD = (8.0e5, 1.5e5, -1.2e6, 0.0, 2.5e6, -8.0e5)
COMPONENTS = ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")
SLIDES = ("radial_x", "radial_y", "axial", "tilt_x", "tilt_y")


# --- the rotor --------------------------------------------------------------------------------


def read_performance(path: Path) -> dict[str, np.ndarray]:
    """ROSCO's table: pitch [deg], tsr, and the C_p, C_t matrices (rows λ, columns β)."""
    lines = path.read_text().splitlines()

    def after(title: str) -> int:
        return next(n for n, s in enumerate(lines) if s.startswith("#") and title in s) + 1

    pitch = np.array([float(v) for v in lines[after("Pitch angle vector")].split()])
    tsr = np.array([float(v) for v in lines[after("TSR vector")].split()])

    def matrix(title: str) -> np.ndarray:
        rows = [s for s in lines[after(title) :] if s.strip()][: len(tsr)]
        m = np.array([[float(v) for v in s.split()] for s in rows])
        if m.shape != (len(tsr), len(pitch)):
            raise ValueError(f"{path}: {title} has shape {m.shape}")
        return m

    return {
        "pitch_deg": pitch,
        "tsr": tsr,
        "cp": matrix("Power coefficient"),
        "ct": matrix("Thrust coefficient"),
    }


def bilinear(xs: np.ndarray, ys: np.ndarray, m: np.ndarray, x: float, y: float) -> float:
    """m[i, j] at (xs[i], ys[j]), interpolated bilinearly at (x, y), held at the grid's edges
    outside it (docs/loads.md)."""
    x, y = min(max(x, xs[0]), xs[-1]), min(max(y, ys[0]), ys[-1])
    i = int(np.clip(np.searchsorted(xs, x) - 1, 0, len(xs) - 2))
    j = int(np.clip(np.searchsorted(ys, y) - 1, 0, len(ys) - 2))
    s = (x - xs[i]) / (xs[i + 1] - xs[i])
    t = (y - ys[j]) / (ys[j + 1] - ys[j])
    return float(
        (1 - s) * (1 - t) * m[i, j]
        + s * (1 - t) * m[i + 1, j]
        + (1 - s) * t * m[i, j + 1]
        + s * t * m[i + 1, j + 1]
    )


def thrust_of(omega: np.ndarray, wind: np.ndarray) -> tuple[np.ndarray, ...]:
    """λ, C_t(λ, β) and T = ½ ρ π R² v² C_t [N] at rotor speeds ω [rad/s] and winds v [m/s], at
    the blade pitch ``PITCH_DEG``."""
    table = read_performance(TABLE)
    lam = omega * RADIUS / wind
    ct = np.array(
        [bilinear(table["tsr"], table["pitch_deg"], table["ct"], x, PITCH_DEG) for x in lam]
    )
    return lam, ct, 0.5 * AIR_DENSITY * math.pi * RADIUS**2 * wind**2 * ct


def momentum_ct(cp: float) -> float:
    """C_t = 4a(1 − a) of the axial induction a ≤ 1/3 with C_p = 4a(1 − a)² (actuator-disc
    momentum theory, Burton et al. 2011 §3.2), a by bisection (C_p increases on [0, 1/3])."""
    lo, hi = 0.0, 1.0 / 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if 4 * mid * (1 - mid) ** 2 < cp else (lo, mid)
    a = 0.5 * (lo + hi)
    return 4 * a * (1 - a)


def momentum_run():
    """A rotor known by its C_p alone (Saleh 2017's, Heier's fit): the saleh2017 planetary at
    14.2 rpm in 10 m/s, 50 steps of 1 ms. Returns the Result."""
    text = (
        f'model = "{(REPO / "models" / "saleh2017_planetary.urdf").as_posix()}"\n'
        "dt = 1e-3\nduration = 0.05\nno_log = true\ninitial_speed = { carrier = 14.2 }\n"
        'wind = 10.0\n[speed]\nsun = 85.2\n[rotor.carrier]\npreset = "saleh2017"\n'
    )
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "case.toml"
        path.write_text(text)
        return run(load_scenario(path), progress=False)


def shear_arm(radius: float, hub_height: float, alpha: float, nodes: int = 64) -> float:
    """ℓ = (1/πR²) ∫ z (1 + z/H)^{2α} dA over the disc [m]: with z = R sin t a strip dz has the
    chord 2R cos t, so ℓ = (2R/π) ∫_{−π/2}^{π/2} sin t cos² t (1 + R sin t/H)^{2α} dt."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    t = 0.5 * math.pi * x
    f = np.sin(t) * np.cos(t) ** 2 * (1 + radius * np.sin(t) / hub_height) ** (2 * alpha)
    return float(radius * np.sum(w * f))


def rotor_hub_load(thrust, arm: float, g: float) -> tuple[Any, Any, Any]:
    """F_x, F_z [N] and M_y [N·m] of the rotor on its hub, in the hub's fixed frame."""
    return (
        thrust + ROTOR_MASS * g * math.sin(TILT),
        -ROTOR_MASS * g * math.cos(TILT) + 0 * thrust,
        arm * thrust,
    )


# --- the shaft on its rows --------------------------------------------------------------------


@dataclass
class Shaft:
    """A shaft from the model file: its joint origin in the world [m] (the joint frame has the
    world's axes), mass [kg], centre of mass along k [m], I_xx and I_zz [kg·m²], gravity [m/s²],
    its rows (name, position a [m], K (K_x, K_y, K_z, K_β, K_γ), C alike) and child joints."""

    origin: np.ndarray
    mass: float
    com_a: float
    inertia_xx: float
    inertia_zz: float
    gravity: np.ndarray
    rows: list[tuple[str, float, np.ndarray, np.ndarray]]
    children: list[str]


def _floats(text: str | None) -> list[float]:
    if text is None:
        raise ValueError("missing attribute")
    return [float(v) for v in text.split()]


def _child(e: ET.Element, tag: str) -> ET.Element:
    c = e.find(tag)
    if c is None:
        raise ValueError(f"<{e.tag}> has no <{tag}>")
    return c


def read_shaft(model: Path, joint: str) -> Shaft:
    root = ET.parse(model).getroot()
    j = next(e for e in root.iter("joint") if e.get("name") == joint)
    origin = _child(j, "origin")
    if _floats(origin.get("rpy", "0 0 0")) != [0, 0, 0] or _floats(
        _child(j, "axis").get("xyz")
    ) != [0, 0, 1]:
        raise ValueError("the recoding takes a joint along z with the world's axes")
    link = _child(j, "child").get("link")
    inertial = _child(next(e for e in root.iter("link") if e.get("name") == link), "inertial")
    inertia = _child(inertial, "inertia")
    gearbox = _child(root, "gearbox")
    bearing = next(b for b in gearbox.iter("bearing") if b.get("joint") == joint)
    rows = [
        (
            str(r.get("name")),
            _floats(r.get("position_mm"))[0] / 1000.0,
            np.array(_floats(r.get("stiffness"))),
            np.array(_floats(r.get("damping"))),
        )
        for r in bearing.iter("row")
    ]
    children = [
        str(e.get("name"))
        for e in root.iter("joint")
        if _child(e, "parent").get("link") == link and e.get("type") != "fixed"
    ]
    return Shaft(
        origin=np.array(_floats(origin.get("xyz"))),
        mass=_floats(_child(inertial, "mass").get("value"))[0],
        com_a=_floats(_child(inertial, "origin").get("xyz"))[2],
        inertia_xx=_floats(inertia.get("ixx"))[0],
        inertia_zz=_floats(inertia.get("izz"))[0],
        gravity=np.array(_floats(gearbox.get("gravity"))),
        rows=rows,
        children=children,
    )


def row_map(a: float) -> np.ndarray:
    """B with δ = B q, q = (x, y, z, θ_u, θ_w), δ = (z, x + a θ_w, y − a θ_u, θ_u, θ_w)."""
    b = np.zeros((5, 5))
    b[0, 2] = 1.0
    b[1, 0], b[1, 4] = 1.0, a
    b[2, 1], b[2, 3] = 1.0, -a
    b[3, 3] = 1.0
    b[4, 4] = 1.0
    return b


def row_loads(k: np.ndarray, c: np.ndarray, a: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A row's loads on the shaft, (F_u, F_w, F_k, M_u, M_w): L = −K δ − C δ̇ reordered."""
    b = row_map(a)
    load = -k * (b @ q) - c * (b @ v)  # along (k, u, w, u, w)
    return np.array([load[1], load[2], load[0], load[3], load[4]])


def mass_matrix(shaft: Shaft) -> np.ndarray:
    """The shaft's mass matrix on (x, y, z, θ_u, θ_w) at q = 0: its centre of mass at a_c k moves
    by ẋ u + ẏ w + ż k + a_c θ̇_w u − a_c θ̇_u w; I_xx about its centre for both tilts."""
    m, a, i = shaft.mass, shaft.com_a, shaft.inertia_xx + shaft.mass * shaft.com_a**2
    return np.array(
        [
            [m, 0, 0, 0, m * a],
            [0, m, 0, -m * a, 0],
            [0, 0, m, 0, 0],
            [0, -m * a, 0, i, 0],
            [m * a, 0, 0, 0, i],
        ]
    )


def rot_x(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


@dataclass
class Wrench:
    """A force [N] and moment [N·m] (world axes) at a point: on the shaft's axis at ``a`` [m] from
    the bearing centre (moves with the shaft), or at a world ``point`` [m]. ``tilts``: force and
    moment turn with the shaft's tilts (a load in the shaft's own frame)."""

    force: np.ndarray
    moment: np.ndarray
    a: float | None = None
    point: np.ndarray | None = None
    tilts: bool = False


def hinge_axes(q: np.ndarray) -> np.ndarray:
    """The slides' axes in the world: u, w, k, then the tilt hinges u and R_x(θ_u) w."""
    u, w, k = np.eye(3)
    return np.array([u, w, k, u, rot_x(q[3]) @ w])


def generalised(shaft: Shaft, q: np.ndarray, wrenches: list[Wrench]) -> np.ndarray:
    """The wrenches' virtual work through the slides x, y, z, θ_u, θ_w (exact kinematics)."""
    k = np.array([0.0, 0.0, 1.0])
    centre = shaft.origin + q[:3]
    turn = rot_x(q[3]) @ rot_y(q[4])
    axes = hinge_axes(q)
    out = np.zeros(5)
    for e in wrenches:
        p = centre + turn @ (e.a * k) if e.a is not None else e.point
        f, m = (turn @ e.force, turn @ e.moment) if e.tilts else (e.force, e.moment)
        m = m + np.cross(p - centre, f)
        out += np.concatenate([axes[:3] @ f, axes[3:] @ m])
    return out


def solve_shaft(
    shaft: Shaft, wrenches: list[Wrench], inertia: np.ndarray | None = None
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """q at Σ B_iᵀ K_i B_i q = Q(q) − ``inertia`` (a generalised force, default 0), and each
    row's loads (F_u, F_w, F_k, M_u, M_w) at q, at rest."""
    stiffness = sum(row_map(a).T @ np.diag(k) @ row_map(a) for _, a, k, _ in shaft.rows)
    extra = np.zeros(5) if inertia is None else inertia
    q = np.zeros(5)
    for _ in range(50):
        q_new = np.linalg.solve(stiffness, generalised(shaft, q, wrenches) - extra)
        done = np.max(np.abs(q_new - q)) <= 1e-15 * np.max(np.abs(q_new))
        q = q_new
        if done:
            break
    zero = np.zeros(5)
    return q, {name: row_loads(k, c, a, q, zero) for name, a, k, c in shaft.rows}


def weight(shaft: Shaft) -> Wrench:
    return Wrench(shaft.mass * shaft.gravity, np.zeros(3), a=shaft.com_a)


def hub_wrench(loads, up: np.ndarray, psi: float | None = None) -> Wrench:
    """A hub load (F_x, F_y, F_z, M_x, M_y, M_z) at the hub point, in world axes: x the shaft's
    axis k (downwind), z the vertical ``up`` made normal to it, y = z × x (the fixed frame); with
    ``psi`` [rad] a rotating-frame load at the shaft angle ψ, turned into the fixed frame as
    docs/loads.md writes it, and then with the shaft's tilts (it turns with the shaft's frame)."""
    if psi is not None:
        loads = fixed_from_rotating(loads, np.array([psi]))[0]
    x = np.array([0.0, 0.0, 1.0])
    z = up - (up @ x) * x
    z /= np.linalg.norm(z)
    y = np.cross(z, x)
    f = loads[0] * x + loads[1] * y + loads[2] * z
    m = loads[3] * x + loads[4] * y + loads[5] * z
    return Wrench(f, m, a=HUB_POINT[2], tilts=psi is not None)


def child_wrenches(res, shaft: Shaft, i: int) -> list[Wrench]:
    """Minus each child bearing's reaction (its force on the child at the child's link origin)."""
    positions = res.pose_at_samples("body_position")
    out = []
    for name in shaft.children:
        b = res.bearing(name)
        out.append(
            Wrench(-b.force[i], -b.moment[i], point=positions[i, res.body_names.index(name)])
        )
    return out


def slides_of(res, joint: str, quantity: str = "angle") -> np.ndarray:
    """(n, 5): the shaft's slides x, y, z, θ_u, θ_w at every sample."""
    return np.column_stack([getattr(res.joint(f"{joint}_{s}"), quantity) for s in SLIDES])


# --- runs -------------------------------------------------------------------------------------


def scenario_text(case: str, duration: float, hub=None) -> str:
    """Scenario TOML of run ``case`` ("A", "A'", "B", "C"); each hub component is a number or a
    signal text; ``hub`` None: no hub load."""
    text = f'model = "{MODEL.as_posix()}"\ndt = {DT!r}\nduration = {duration!r}\nno_log = true\n'
    turning = case != "B"
    if turning:
        text += f"initial_speed = {{ rotor = {ROTOR_RPM!r} }}\npose_rate = {1.0 / DT!r}\n"
    if case in ("A", "A'", "E"):
        text += f"wind = {WIND if case != 'E' else LOW_WIND!r}\n"
    else:
        text += f"[torque]\nrotor = {RATED_TORQUE!r}\n"
    text += f"[speed]\ngenerator = {-ROTOR_RPM * RATIO if turning else 0.0!r}\n"
    if case in ("A", "A'", "E"):
        text += f'[rotor.rotor]\npreset = "nrel5mw"\npitch_deg = {PITCH_DEG!r}\n'
        if case == "A":
            text += f'hub_body = "lss"\nhub_point = {list(HUB_POINT)!r}\n'
    if hub is not None:
        frame, values = hub
        text += "[hub_load.lss]\n"
        text += "".join(
            f"{n} = {v!r}\n" if isinstance(v, float) else f"{n} = '{v}'\n"
            for n, v in zip(COMPONENTS, values, strict=True)
        )
        text += f'point = {list(HUB_POINT)!r}\nframe = "{frame}"\n'
    return text


def run_case(case: str, duration: float, hub=None, table: np.ndarray | None = None):
    """Run ``case``. ``table`` (time, columns...) is written as ``hub.csv`` beside the scenario;
    a hub component ``"csv:N"`` reads its column N."""
    with tempfile.TemporaryDirectory() as d:
        if table is not None and hub is not None:
            csv = Path(d) / "hub.csv"
            np.savetxt(csv, table, delimiter=",", fmt="%.17g")
            hub = (
                hub[0],
                tuple(
                    f'csv(file="{csv.as_posix()}", column={v[4:]})' if isinstance(v, str) else v
                    for v in hub[1]
                ),
            )
        path = Path(d) / "case.toml"
        path.write_text(scenario_text(case, duration, hub))
        return run(load_scenario(path), progress=False)


def fixed_from_rotating(loads, psi: np.ndarray) -> np.ndarray:
    """(n, 6) fixed-frame components of a rotating-frame load at shaft angles ψ (docs/loads.md)."""
    c, s = np.cos(psi), np.sin(psi)
    fx, fy, fz, mx, my, mz = loads
    one = np.ones_like(psi)
    return np.column_stack(
        [fx * one, c * fy - s * fz, s * fy + c * fz, mx * one, c * my - s * mz, s * my + c * mz]
    )


# --- comparisons --------------------------------------------------------------------------------

ROW_LABELS = ("F_u", "F_w", "F_k", "M_u", "M_w")


def rel(a, b) -> float:
    """max |a − b| over max |b|."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def fmt(v) -> str:
    v = np.atleast_1d(np.asarray(v, float)) + 0.0  # no "-0"
    return ", ".join(f"{x:.6g}" for x in v) if len(v) > 1 else f"{v[0]:.9g}"


def row_series(res, shaft: Shaft, i) -> dict[str, np.ndarray]:
    """The run's rows' loads (F_u, F_w, F_k, M_u, M_w) at sample(s) i."""
    return {
        name: np.concatenate(
            [res.row(f"lss.{name}").force[i], res.row(f"lss.{name}").moment[i][..., :2]], axis=-1
        )
        for name, *_ in shaft.rows
    }


def statics_table(res, shaft: Shaft, hub: Wrench, label: str) -> list[tuple[str, str, str, float]]:
    """Run ``res``'s last sample against the hand statics: each row's loads, the slides, the
    bearing's displacement, force and moment."""
    i = len(res.time) - 1
    q, loads = solve_shaft(shaft, [hub, weight(shaft), *child_wrenches(res, shaft, i)])
    ran = row_series(res, shaft, i)
    out = []
    for name, *_ in shaft.rows:
        for part, cols in (("F_u, F_w, F_k [N]", slice(0, 3)), ("M_u, M_w [N·m]", slice(3, 5))):
            if np.max(np.abs(loads[name][cols])) > 0:
                out.append(
                    (
                        f"{label} {name} {part}",
                        fmt(ran[name][cols]),
                        fmt(loads[name][cols]),
                        rel(ran[name][cols], loads[name][cols]),
                    )
                )
    q_run = slides_of(res, "lss")[i]
    out.append((f"{label} slides x, y, z [m]", fmt(q_run[:3]), fmt(q[:3]), rel(q_run[:3], q[:3])))
    out.append((f"{label} tilts θ_u, θ_w [rad]", fmt(q_run[3:]), fmt(q[3:]), rel(q_run[3:], q[3:])))
    bearing = res.bearing("lss")
    out.append(
        (
            f"{label} bearing displacement [m]",
            fmt(bearing.displacement[i]),
            fmt(q[:3]),
            rel(bearing.displacement[i], q[:3]),
        )
    )
    force = sum(v[:3] for v in loads.values())
    out.append(
        (
            f"{label} bearing force (world) [N]",
            fmt(bearing.force[i]),
            fmt(force),
            rel(bearing.force[i], force),
        )
    )
    # the bearing's moment on the hinge axes u, R_x(θ_u) w, and the joint's axis: the rows'
    # Σ (M + a k × F), and the torque the coupling carries (the rotor's, standing still)
    k = np.array([0.0, 0.0, 1.0])
    tilting = sum(
        np.array([v[3], v[4], 0.0]) + np.cross(a * k, v[:3])
        for (_, a, *_), v in zip(shaft.rows, loads.values(), strict=True)
    )
    axes = hinge_axes(q)
    axis = rot_x(q[3]) @ rot_y(q[4]) @ k
    ran_m = np.array(
        [axes[3] @ bearing.moment[i], axes[4] @ bearing.moment[i], axis @ bearing.moment[i]]
    )
    rec_m = np.array([tilting[0], tilting[1], RATED_TORQUE])
    out.append(
        (f"{label} bearing moment on u, w′, k′ [N·m]", fmt(ran_m), fmt(rec_m), rel(ran_m, rec_m))
    )
    # radial, axial and tilting: across and along the tilted axis k′; the tilting moment with
    # the torque's part across k′ taken out, from the recoded force and hinge moments
    moment = np.linalg.solve(np.array([axes[3], axes[4], axis]), rec_m)
    ran_s = np.array([bearing.radial[i], bearing.axial[i], bearing.tilting[i]])
    rec_s = np.array(
        [
            np.linalg.norm(force - (force @ axis) * axis),
            force @ axis,
            np.linalg.norm(moment - (moment @ axis) * axis),
        ]
    )
    out.append(
        (
            f"{label} bearing radial, axial [N], tilting [N·m]",
            fmt(ran_s),
            fmt(rec_s),
            rel(ran_s, rec_s),
        )
    )
    return out


def statics_summary(res, shaft: Shaft, hub: Wrench, label: str) -> tuple[str, str, str, float]:
    """The largest difference of any row's force (moment) or the slides at the last sample from
    the hand statics, over that row's largest force (moment), the slides' largest x, y, z or
    tilt."""
    i = len(res.time) - 1
    q, loads = solve_shaft(shaft, [hub, weight(shaft), *child_wrenches(res, shaft, i)])
    ran = row_series(res, shaft, i)
    q_run = slides_of(res, "lss")[i]
    worst = max(rel(q_run[:3], q[:3]), rel(q_run[3:], q[3:]))
    for name in loads:
        for cols in (slice(0, 3), slice(3, 5)):
            if np.max(np.abs(loads[name][cols])) > 0:
                worst = max(worst, rel(ran[name][cols], loads[name][cols]))
    return (f"{label}: every row, the slides", "", "", worst)


def dynamic_residual(res, shaft: Shaft, hubs: list[Wrench], first: int = 100) -> tuple[float, ...]:
    """Over the samples from ``first`` (but the last), each over the rows' largest generalised
    force: the largest statics error Σ rows + Q (no inertia), and the largest residual of the
    shaft's equation of motion Σ rows + Q − M q̈ − G q̇, without and with the gyroscopic term
    G q̇ = I_zz Ω (θ̇_w, −θ̇_u) on the tilts (Euler: the spin's angular momentum I_zz Ω k′ turns
    with the axis k′ ≈ k + θ_w u − θ_u w). Q, q̇ and Ω at the step's mean state, q̈ the run's."""
    mass = mass_matrix(shaft)
    ran = row_series(res, shaft, slice(None))
    q, v = slides_of(res, "lss"), slides_of(res, "lss", "speed")
    acc, spin = slides_of(res, "lss", "acceleration"), res.joint("lss").speed
    worst, scale = np.zeros(3), 0.0
    for i in range(first, len(res.time) - 1):
        ws = [hubs[i], weight(shaft), *child_wrenches(res, shaft, i)]
        q_mid, v_mid = 0.5 * (q[i] + q[i + 1]), 0.5 * (v[i] + v[i + 1])
        gyro = (
            shaft.inertia_zz
            * 0.5
            * (spin[i] + spin[i + 1])
            * np.array([0, 0, 0, v_mid[4], -v_mid[3]])
        )
        q_rows = np.zeros(5)
        for name, a, *_ in shaft.rows:
            load = ran[name][i]
            q_rows += row_map(a).T @ np.array([load[2], load[0], load[1], load[3], load[4]])
        scale = max(scale, float(np.max(np.abs(q_rows))))
        statics = q_rows + generalised(shaft, q_mid, ws)
        for j, r in enumerate((statics, statics - mass @ acc[i], statics - mass @ acc[i] - gyro)):
            worst[j] = max(worst[j], float(np.max(np.abs(r))))
    return tuple(float(w) / scale for w in worst)


def law_check(res, shaft: Shaft) -> float:
    """Every sample's rows against L = −K δ − C δ̇ at the step's mean state, over max |L|."""
    q, v = slides_of(res, "lss"), slides_of(res, "lss", "speed")
    q_mid, v_mid = 0.5 * (q[:-1] + q[1:]), 0.5 * (v[:-1] + v[1:])
    ran = row_series(res, shaft, slice(0, len(q) - 1))
    worst = 0.0
    for name, a, k, c in shaft.rows:
        law = np.array([row_loads(k, c, a, x, y) for x, y in zip(q_mid, v_mid, strict=True)])
        for j in range(5):
            if np.max(np.abs(law[:, j])) > 0:
                worst = max(worst, rel(ran[name][:, j], law[:, j]))
    return worst


def twin_check(res1, res2, shaft: Shaft) -> float:
    """The largest difference of an lss row's force (moment) between two runs, over the largest
    row force (moment) of the second (INP-B's moments are its tilt dampers' alone, 1e-3 N·m)."""
    a, b = row_series(res1, shaft, slice(None)), row_series(res2, shaft, slice(None))
    worst = 0.0
    for cols in (slice(0, 3), slice(3, 5)):
        scale = max(float(np.max(np.abs(v[:, cols]))) for v in b.values())
        worst = max(
            worst, max(float(np.max(np.abs(a[n][:, cols] - b[n][:, cols]))) for n in a) / scale
        )
    return worst


def main() -> None:
    start = time.perf_counter()
    shaft = read_shaft(MODEL, "lss")
    g = float(np.linalg.norm(shaft.gravity))
    up = -shaft.gravity / g
    arm = shear_arm(RADIUS, HUB_HEIGHT, SHEAR_EXPONENT)
    limit = SHEAR_EXPONENT * RADIUS**2 / (2 * HUB_HEIGHT)
    finer = shear_arm(RADIUS, HUB_HEIGHT, SHEAR_EXPONENT, 128)
    table: list[tuple[str, str, str, float]] = []

    a = run_case("A", 0.3)
    r = a.rotor("rotor")
    lam, ct, thrust = thrust_of(a.joint("rotor").speed, r.wind_speed)
    table += [
        (
            "A tip-speed ratio λ = ωR/v",
            fmt(r.tip_speed_ratio[-1]),
            fmt(lam[-1]),
            rel(r.tip_speed_ratio, lam),
        ),
        (
            f"A C_t(λ, {PITCH_DEG}°), bilinear",
            fmt(r.thrust_coefficient[-1]),
            fmt(ct[-1]),
            rel(r.thrust_coefficient, ct),
        ),
        ("A thrust T [N]", fmt(r.thrust[-1]), fmt(thrust[-1]), rel(r.thrust, thrust)),
    ]
    e = run_case("E", 0.003)
    lam_e, _, thrust_e = thrust_of(e.joint("rotor").speed, e.rotor("rotor").wind_speed)
    table.append(
        (
            f"E thrust T [N] at λ = {lam_e[-1]:.1f}, held at the table's edge",
            fmt(e.rotor("rotor").thrust[-1]),
            fmt(thrust_e[-1]),
            rel(e.rotor("rotor").thrust, thrust_e),
        )
    )
    fx, fz, my = rotor_hub_load(thrust, arm, g)
    a2 = run_case(
        "A'",
        0.3,
        hub=("fixed", ("csv:1", 0.0, "csv:2", 0.0, "csv:3", 0.0)),
        table=np.column_stack([a.time, fx, fz, my]),
    )
    table.append(
        (
            "A vs A′ (the recoded F_x, F_z, M_y): rows, every sample",
            "",
            "",
            twin_check(a, a2, shaft),
        )
    )
    table.append(
        ("A row law −Kδ − Cδ̇ at the step's mean state, every sample", "", "", law_check(a, shaft))
    )
    hubs = [hub_wrench((x, 0.0, z, 0.0, m, 0.0), up) for x, z, m in zip(fx, fz, my, strict=True)]
    statics, inertia, gyro = dynamic_residual(a, shaft, hubs)
    table.append(("A statics of the shaft (no inertia), from 0.01 s", "", "", statics))
    table.append(("A equation of motion with M q̈", "", "", inertia))
    table.append(("A equation of motion with M q̈ and I_zz Ω θ̇", "", "", gyro))

    s = momentum_run().rotor("carrier")
    ct_s = np.array([momentum_ct(x) for x in s.power_coefficient])
    thrust_s = 0.5 * AIR_DENSITY * math.pi * SALEH_RADIUS**2 * s.wind_speed**2 * ct_s
    table.append(
        (
            "S C_t = 4a(1 − a) from the run's C_p = 4a(1 − a)²",
            fmt(s.thrust_coefficient[-1]),
            fmt(ct_s[-1]),
            rel(s.thrust_coefficient, ct_s),
        )
    )
    table.append(("S thrust T [N]", fmt(s.thrust[-1]), fmt(thrust_s[-1]), rel(s.thrust, thrust_s)))

    b = run_case("B", 0.2, hub=("fixed", HUB_LOAD))
    table += statics_table(b, shaft, hub_wrench(HUB_LOAD, up), "B")
    acc_b = float(np.max(np.abs(slides_of(b, "lss", "acceleration"))))

    b2 = run_case("B", 0.2, hub=("rotating", HUB_LOAD))
    psi = float(b2.joint("lss").angle[-1])
    table.append(
        statics_summary(b2, shaft, hub_wrench(HUB_LOAD, up, psi), f"B rotating (ψ = {psi:.2e} rad)")
    )

    c = run_case("C", 0.3, hub=("rotating", HUB_LOAD))
    q_c = slides_of(c, "lss")
    world = [hub_wrench(HUB_LOAD, up, p) for p in c.joint("lss").angle]
    turned = [rot_x(x[3]) @ rot_y(x[4]) for x in q_c]
    fixed = np.array(
        [
            [*(t @ w.force)[[2, 0, 1]], *(t @ w.moment)[[2, 0, 1]]]
            for t, w in zip(turned, world, strict=True)
        ]
    )
    c2 = run_case(
        "C",
        0.3,
        hub=("fixed", tuple(f"csv:{n}" for n in range(1, 7))),
        table=np.column_stack([c.time, fixed]),
    )
    c3 = run_case(
        "C",
        0.3,
        hub=("fixed", tuple(f"csv:{n}" for n in range(1, 7))),
        table=np.column_stack([c.time, fixed_from_rotating(HUB_LOAD, c.joint("lss").angle)]),
    )
    table.append(
        (
            "C vs C′ (the load turned by ψ and the tilts by hand): rows, every sample",
            "",
            "",
            twin_check(c, c2, shaft),
        )
    )
    table.append(("C vs C″ (turned by ψ only)", "", "", twin_check(c, c3, shaft)))
    starts = [x.metadata["initial_deflection"]["residual"] for x in (c, c2)]

    tilt_rate = float(np.max(np.abs(slides_of(a, "lss", "speed")[100:, 3:])))
    omega = float(np.mean(a.joint("lss").speed))
    print(
        f"shear arm ℓ = {arm:.9f} m by 64-node quadrature (128 nodes: {finer - arm:+.1e} m); "
        f"α R²/(2H) = {limit:.6f} m, {limit / arm - 1:+.2%} off"
    )
    print(
        f"run A's hub loads (recoded, last sample): F_x = {fx[-1]:.6e} N, F_z = {fz[-1]:.6e} N, "
        f"M_y = {my[-1]:.6e} N·m"
    )
    print(
        f"steadiness: run B's slides accelerate by at most {acc_b:.1e} (m/s², rad/s²); run A's "
        f"by up to {float(np.max(np.abs(slides_of(a, 'lss', 'acceleration')[100:, :3]))):.3g} m/s² "
        f"(the {shaft.mass:.0f} kg shaft vibrating on its rows); I_zz ω max|θ̇| = "
        f"{shaft.inertia_zz * omega * tilt_rate:.2g} N·m"
    )
    print(
        f"static start of C, C′: relative residual {starts[0]:.1e}, {starts[1]:.1e} (B: "
        f"{b.metadata['initial_deflection']['residual']:.1e})"
    )
    print("\n| quantity | pinwind | recoding | rel. difference |\n|---|---|---|---|")
    for name, ran, rec, d in table:
        print(f"| {name} | {ran} | {rec} | {d:.1e} |")
    print(f"\n{time.perf_counter() - start:.1f} s wall")


if __name__ == "__main__":
    main()
