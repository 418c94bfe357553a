"""The compliant bearings' force laws, recoded from runs' displacement series without pinwind's
bearing code.

The recoding reads only docs/model_format.md ("Compliant bearings", "Bearing rows"),
docs/bearing_life.md ("Rows with clearance or preload"), docs/series.md, docs/simulation.md and
the model attributes it writes itself; it takes from each run only the slides' series (their
``angle`` and ``speed``: displacement [m] or tilt [rad] and its rate) and compares what it
computes with pinwind's ``elastic_force``, the bearing reaction (``force_local``,
``moment_local``) and the rows' ``force`` and ``moment``.

Runs (a URDF written here: one 100 kg shaft on one compliant bearing, along z, gravity the known
load; and the shipped NREL 5 MW gearbox with its 24 bearing rows, logged and read back):

- **linear, past c**: k = 1e8 N/m, c = 10 µm, gravity (4, −8.5, 0) m/s² off both radial axes;
  the static start, so |r| = c + m|g|/k exactly and the spring force is −m g.
- **linear, dead band**: c = 20 µm > m g/k, c_r = 400 N·s/m (ζ = 0.02), started undeflected:
  the shaft falls through the dead band and bounces back through it; F = −k max(|r| − c, 0) r/|r|
  at every sample and the damper −c_r ṙ only in contact.
- **axial and tilt**: k_a = 5e7 N/m, k_t = 1e5 N·m/rad, the centre of mass 0.2 m along the axis,
  gravity (0, −9.81, −3): the static z = m g_z/k_a and the tilt θ_u from k_t θ = m L (9.81 cos θ
  + 3 sin θ) (the hinge turns the centre of mass exactly), solved with ``scipy.optimize.brentq``.
- **roller sum**, line (n = 10/9) and point (n = 3/2) contact, c = 0 and 5 µm, Z = 16 elements:
  F = −Σ_j K_n max(r·e_j − c, 0)ⁿ e_j (Harris and Kotzalas, Rolling Bearing Analysis: Q = K_n δⁿ);
  the static deflection from ``scipy.optimize.root`` of F(r) + m g = 0. At c = 0 with the load on
  an element: Q_max Z/F_r = Z/Σ_j max(cos ψ_j, 0)^(n+1) of the discrete sum, against its Z → ∞
  limit 2π/∫cos^(n+1) ψ dψ over |ψ| < π/2 (a quadrature of the same law) and against Stribeck's
  4.37 (point) and 4.08 (line) as NSK's catalogue (E728g, §5 "Bearing internal load
  distribution and displacement", eqs. 4-5, ε = 0.5, zero clearance) quotes them. Harris's
  integral J_r(ε) itself was not readable in a public source here, so it is not written.
- **rows, clearance / preload**: two rows at ∓0.2 m with their own (K_x, K_y, K_z, K_β, K_γ) and
  dampers, row A with c = 5 µm and row B with c = −3 µm preloaded (run 1), both preloaded by
  3 µm (run 2); the centre of mass 0.1 m along the axis, gravity (3, −9.81, −2).
  δ = (z, x + aθ_w, y − aθ_u, θ_u, θ_w), L_j = −K_j δ_j − c_j δ̇_j, each radial direction of a
  row with c: −K [max(δ − c, 0) − max(−δ − c, 0)], the damper while a side touches. The static
  state from ``scipy.optimize.root`` of the five slides' generalized forces (the rows' and
  gravity's, the hinges turning the centre of mass exactly).
- **turned frame**: the same shaft on a bearing along its joint frame's x, the frame turned by
  roll, pitch, yaw (0.3, 0.2, 0.1) rad and ``radial_axis="0 1 1"``: a roller sum of Z = 7 (odd, so
  not symmetric about the load) and the two rows; ``displacement`` and ``elastic_force`` are in
  the joint frame, x u + y w (+ z k).
- **NREL 5 MW**: the shipped model at its rated point (rotor 3 945 990 N·m, generator speed
  driven, rigid meshes), 0.05 s logged and read back, every bearing row recoded from the logged
  slides; again with stage 1's planet rows preloaded by 0.02 mm and stage 2's and the main
  shaft's with a 0.07 mm clearance.

Which state a series belongs to. Written first from docs/model_format.md ("the loads of the step
(at its weighted state)"), docs/series.md and the face-load recoding (a sample's force is the
step's that starts at it; with the default generalized-α at ρ∞ = 1 the weighted state is the
mean of the sample's state and the next one's), then found so:

- ``elastic_force`` and ``displacement`` are of the sample's own state;
- a sample's reaction (``force_local``, ``moment_local``) and row loads are those of the step
  that starts at it, at its weighted state, the dampers at its weighted speed (q_{i+1} − q_i)/h
  (``weighted_speed``: not the mean of the recorded speeds where rigid rows project them);
- a roller sum is linearised about r₀ = r_i + (h/2) ṙ_i, the weighted state the step predicts
  with no acceleration (docs/model_format.md said "about the step's start"), its damper's contact
  set taken there: the reaction is F(r₀) + ∂F/∂r(r₀) (r_mid − r₀) − c_r ṙ_mid;
- the reaction is RNEA at the sample's pose, where the step took the bodies'
  weights (the bias) extrapolated to its weighted state: a tilting shaft's reaction moment
  carries ½ (G_i − G_{i−1}) of its weight moment G besides the hinge's spring and damper
  (4e-7 of the tilt moment here; zero for the slides, whose motion does not move the weight's
  line of action).

Run:  python benchmarks/independent_bearing_laws.py
"""

from __future__ import annotations

import math
import sys
import tempfile
import time
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import integrate, optimize

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import pinwind  # noqa: E402
from pinwind.errors import PinwindWarning  # noqa: E402
from pinwind.model.gearbox import loads  # noqa: E402

MASS = 100.0  # the shaft's mass [kg]
DT = 2e-5  # the dynamic runs' time step [s]
NREL_MODEL = REPO / "models" / "nrel5mw_gearbox.urdf"
#: Stribeck's Q_max Z / F_r at zero clearance (NSK E728g §5 eqs. 4-5)
STRIBECK = {"point": 4.37, "line": 4.08}
EXPONENT = {"point": 1.5, "line": 10.0 / 9.0}


def shaft_model(
    bearing: str,
    gravity: tuple[float, float, float],
    com_z: float = 0.0,
    *,
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0),
    axis: str = "0 0 1",
) -> str:
    """A 100 kg shaft on one bearing at the origin; its centre of mass ``com_z`` along the axis
    (z) or along x for ``axis="1 0 0"``; the joint frame turned by ``rpy`` from the world's."""
    g = " ".join(f"{v:g}" for v in gravity)
    com = f"{com_z:g} 0 0" if axis == "1 0 0" else f"0 0 {com_z:g}"
    turn = " ".join(f"{v:g}" for v in rpy)
    return f"""<?xml version="1.0"?>
<robot name="recoding">
  <link name="ground"/>
  <link name="shaft">
    <inertial><origin xyz="{com}"/><mass value="{MASS:g}"/>
      <inertia ixx="2" iyy="2" izz="2" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="shaft" type="continuous">
    <parent link="ground"/><child link="shaft"/><origin xyz="0.1 0.2 0.3" rpy="{turn}"/>
    <axis xyz="{axis}"/>
  </joint>
  <gearbox gravity="{g}">
    {bearing}
  </gearbox>
</robot>"""


def rotation_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's fixed-axis roll, pitch, yaw: R = R_z(yaw) R_y(pitch) R_x(roll)."""
    cr, sr, cp, sp, cy, sy = (f(a) for a in (roll, pitch, yaw) for f in (math.cos, math.sin))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def bearing_axes(k: np.ndarray, radial_axis: np.ndarray | None) -> np.ndarray:
    """(u, w, k) as columns, joint frame: u the radial axis (else the joint frame's x, or y for
    k along x) made normal to k, w = k × u (docs/model_format.md)."""
    k = k / np.linalg.norm(k)
    if radial_axis is None:
        radial_axis = np.array([0.0, 1.0, 0.0]) if abs(abs(k[0]) - 1) < 1e-12 else np.eye(3)[0]
    u = radial_axis - (radial_axis @ k) * k
    u /= np.linalg.norm(u)
    return np.c_[u, np.cross(k, u), k]


def run(text: str, *, duration: float, start: str, dt: float = DT, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        gb = loads(text, path="recoding.urdf")
        return pinwind.simulate(
            gb, duration=duration, dt=dt, initial_deflection=start, progress=False, **kwargs
        )


def slides(res, joint: str, names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The slides' positions and speeds (n, len(names)); a slide the bearing lacks is 0."""
    n = len(res.time)
    q = np.zeros((n, len(names)))
    v = np.zeros((n, len(names)))
    for i, s in enumerate(names):
        if f"{joint}_{s}" in res.joint_names:
            q[:, i] = res.joint(f"{joint}_{s}").angle
            v[:, i] = res.joint(f"{joint}_{s}").speed
    return q, v


def mid(a: np.ndarray) -> np.ndarray:
    """The step's weighted state at ρ∞ = 1: the mean of a sample and the next."""
    return 0.5 * (a[:-1] + a[1:])


def weighted_speed(q: np.ndarray, dt: float = DT) -> np.ndarray:
    """The step's weighted speed at ρ∞ = 1, (v_i + v⁻_{i+1})/2 = (q_{i+1} − q_i)/h: v⁻_{i+1} the
    speed the step reached before the projection onto the rigid rows (post-stabilisation)
    corrected it into the recorded v_{i+1}, so the recorded speeds' mean is not the step's where
    rigid meshes are (the 5 MW runs: 7e-9 of the rows' force)."""
    return (q[1:] - q[:-1]) / dt


def rel(a: np.ndarray, b: np.ndarray, scale: float | None = None) -> float:
    """max |a − b| over the largest |b| (or ``scale``)."""
    s = float(np.max(np.abs(b))) if scale is None else scale
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) / s


@dataclass
class Table:
    rows: list[tuple[str, str, float, float, float]] = field(default_factory=list)

    def add(self, case: str, quantity: str, pinwind_value: float, recoded: float, diff: float):
        self.rows.append((case, quantity, float(pinwind_value), float(recoded), float(diff)))

    def series(self, case: str, quantity: str, pinwind_series, recoded) -> float:
        """A series sample by sample: the largest |value| of each, max |Δ| over max |recoded|."""
        diff = rel(pinwind_series, recoded)
        self.add(case, quantity, np.max(np.abs(pinwind_series)), np.max(np.abs(recoded)), diff)
        return diff

    def value(self, case: str, quantity: str, pinwind_value: float, recoded: float) -> float:
        """One number: |Δ| / |recoded|."""
        diff = abs(pinwind_value - recoded) / abs(recoded)
        self.add(case, quantity, pinwind_value, recoded, diff)
        return diff

    def markdown(self) -> str:
        out = [
            "| case | quantity | pinwind | recoding | rel. difference |",
            "|---|---|---|---|---|",
        ]
        for case, q, a, b, d in self.rows:
            out.append(f"| {case} | {q} | {a:.6g} | {b:.6g} | {d:.1e} |")
        return "\n".join(out)


# ---------------------------------------------------------------------------------- the laws
def linear_radial(r: np.ndarray, k: float, c: float) -> np.ndarray:
    """F = −k max(|r| − c, 0) r/|r| (docs/model_format.md, "Compliant bearings") [N]."""
    n = np.linalg.norm(r, axis=-1, keepdims=True)
    return -k * np.maximum(n - c, 0.0) * r / np.where(n > 0, n, 1.0)


def linear_damper(r: np.ndarray, v: np.ndarray, cr: float, c: float) -> np.ndarray:
    """−c_r ṙ while |r| > c [N]."""
    return np.where(np.linalg.norm(r, axis=-1, keepdims=True) > c, -cr * v, 0.0)


def element_directions(z: int) -> np.ndarray:
    psi = 2 * np.pi * np.arange(z) / z
    return np.c_[np.cos(psi), np.sin(psi)]


def roller_sum(r: np.ndarray, z: int, kn: float, n: float, c: float) -> np.ndarray:
    """F = −Σ_j K_n max(r·e_j − c, 0)ⁿ e_j [N] (Harris and Kotzalas; docs/model_format.md)."""
    e = element_directions(z)
    d = np.maximum(r @ e.T - c, 0.0)
    return -(kn * d**n) @ e


def roller_sum_jacobian(r: np.ndarray, z: int, kn: float, n: float, c: float) -> np.ndarray:
    """∂F/∂r = −Σ_j K_n n max(r·e_j − c, 0)^(n−1) e_j e_jᵀ, (…, 2, 2)."""
    e = element_directions(z)
    d = np.maximum(r @ e.T - c, 0.0)
    w = kn * n * np.where(d > 0, d ** (n - 1), 0.0)
    return -np.einsum("...j,ja,jb->...ab", w, e, e)


def roller_in_contact(r: np.ndarray, z: int, c: float) -> np.ndarray:
    return np.any(r @ element_directions(z).T - c > 0, axis=-1)


@dataclass
class Row:
    a: float  # axial position [m]
    k: np.ndarray  # K_x, K_y, K_z, K_β, K_γ
    c: np.ndarray  # their dampers
    clearance: float = 0.0  # c [m], negative for a preload


def row_loads(q: np.ndarray, v: np.ndarray, row: Row) -> tuple[np.ndarray, np.ndarray]:
    """A row's force (F_u, F_w, F_k) and moment (M_u, M_w, 0) on the shaft.

    q, v: the slides (x, y, z, θ_u, θ_w) and their rates. δ = (z, x + aθ_w, y − aθ_u, θ_u, θ_w)
    against (K_x, K_y, K_z, K_β, K_γ); with a clearance c each radial direction sits between two
    one-sided contacts, −K [max(δ − c, 0) − max(−δ − c, 0)], its damper while a side touches
    (docs/model_format.md, "Bearing rows"; docs/bearing_life.md, "Rows with clearance or
    preload").
    """
    x, y, z, tu, tw = q.T
    dx, dy, dz, dtu, dtw = v.T
    a = row.a
    d = np.c_[z, x + a * tw, y - a * tu, tu, tw]
    dd = np.c_[dz, dx + a * dtw, dy - a * dtu, dtu, dtw]
    spring = -row.k * d
    damper = -row.c * dd
    if row.clearance != 0.0:
        c = row.clearance
        for j in (1, 2):
            s = d[:, j]
            spring[:, j] = -row.k[j] * (np.maximum(s - c, 0) - np.maximum(-s - c, 0))
            damper[:, j] = np.where((s > c) | (-s > c), damper[:, j], 0.0)
    total = spring + damper
    force = np.c_[total[:, 1], total[:, 2], total[:, 0]]
    moment = np.c_[total[:, 3], total[:, 4], np.zeros(len(total))]
    return force, moment


def row_sides(q: np.ndarray, row: Row) -> np.ndarray:
    """How many sides of each radial direction (u, w) of a row touch, (n, 2): 1 without a
    clearance, 0 in a dead band, 2 for a preload pressed on both sides."""
    x, y, _, tu, tw = q.T
    d = np.c_[x + row.a * tw, y - row.a * tu]
    if row.clearance == 0.0:
        return np.ones(d.shape, dtype=int)
    c = row.clearance
    return (d > c).astype(int) + (-d > c).astype(int)


def row_springs(q: np.ndarray, row: Row) -> np.ndarray:
    force, _ = row_loads(q, np.zeros_like(q), row)
    return force


ROW_SLIDES = ("radial_x", "radial_y", "axial", "tilt_x", "tilt_y")


# ----------------------------------------------------------------------------------- the cases
def linear_cases(t: Table) -> None:
    k, c, load_at = 1e8, 10e-6, np.array([4.0, -8.5, 0.0])
    b = (
        f'<bearing joint="shaft" radial_stiffness="{k:g}" radial_damping="2e4" '
        f'radial_clearance_mm="{c * 1e3:g}"/>'
    )
    res = run(shaft_model(b, tuple(load_at)), duration=20 * DT, start="static")
    disp = res.bearing("shaft").displacement[-1, :2]
    ef = res.bearing("shaft").elastic_force[-1, :2]
    load = MASS * np.linalg.norm(load_at)
    depth = optimize.brentq(lambda s: k * max(s - c, 0.0) - load, 0.0, 1.0)
    case = "linear, past c (static)"
    t.value(case, "|r| = c + m|g|/k [µm]", np.linalg.norm(disp) * 1e6, depth * 1e6)
    t.series(
        case, "r along g [µm]", disp * 1e6, depth * load_at[:2] / np.linalg.norm(load_at) * 1e6
    )
    t.series(case, "spring force = −m g [N]", ef, -MASS * load_at[:2])

    # the dead band: fall through it, bounce back through it
    k, c, cr = 1e8, 20e-6, 400.0
    b = (
        f'<bearing joint="shaft" radial_stiffness="{k:g}" radial_damping="{cr:g}" '
        f'radial_clearance_mm="{c * 1e3:g}"/>'
    )
    res = run(shaft_model(b, (0.0, -9.81, 0.0)), duration=0.05, start="none")
    q, _ = slides(res, "shaft", ("radial_x", "radial_y"))
    inside = int(np.sum(np.linalg.norm(q, axis=1) < c))
    case = "linear, dead band (dynamic)"
    ef = res.bearing("shaft").elastic_force[:, :2]
    t.series(case, f"elastic_force ({inside} of {len(q)} samples in the band)", ef,
             linear_radial(q, k, c))  # fmt: skip
    reaction = res.bearing("shaft").force_local[:-1, :2]
    qm, vm = mid(q), weighted_speed(q)
    spring, damper = linear_radial(qm, k, c), linear_damper(qm, vm, cr, c)
    t.series(case, "reaction: spring + c_r ṙ in contact, weighted state", reaction,
             spring + damper)  # fmt: skip
    t.series(case, "of which the damper [N]", reaction - spring, damper)


def axial_tilt_cases(t: Table) -> None:
    kr, ka, kt, ca, ct, length = 1e8, 5e7, 1e5, 2e4, 50.0, 0.2
    g = (0.0, -9.81, -3.0)
    b = (
        f'<bearing joint="shaft" radial_stiffness="{kr:g}" radial_damping="2e4" '
        f'axial_stiffness="{ka:g}" axial_damping="{ca:g}" tilt_stiffness="{kt:g}" '
        f'tilt_damping="{ct:g}"/>'
    )
    text = shaft_model(b, g, com_z=length)
    res = run(text, duration=20 * DT, start="static")

    def weight_moment(theta):
        """Gravity's moment about u on the shaft tilted by θ_u: its centre of mass at
        (0, −L sin θ, L cos θ) [N·m]."""
        return MASS * length * (-g[1] * np.cos(theta) - g[2] * np.sin(theta))

    theta_ref = optimize.brentq(lambda th: kt * th - weight_moment(th), -1.0, 1.0)
    case = "axial and tilt (static)"
    t.value(case, "z = m g_z / k_a [µm]", res.joint("shaft_axial").angle[-1] * 1e6,
            MASS * g[2] / ka * 1e6)  # fmt: skip
    t.value(case, "θ_u from k_t θ = m L (−g_y cos θ − g_z sin θ) [mrad]",
            res.joint("shaft_tilt_x").angle[-1] * 1e3, theta_ref * 1e3)  # fmt: skip
    t.value(case, "tilt moment −k_t θ [N·m]", res.bearing("shaft").moment_local[-1, 0],
            -kt * theta_ref)  # fmt: skip

    res = run(text, duration=0.02, start="none")
    q, _ = slides(res, "shaft", ("axial", "tilt_x"))
    case = "axial and tilt (dynamic)"
    t.series(case, "elastic_force F_k = −k_a z", res.bearing("shaft").elastic_force[:, 2],
             -ka * q[:, 0])  # fmt: skip
    qm, vm = mid(q), weighted_speed(q)
    reaction = res.bearing("shaft").moment_local[:-1, 0]
    recoded = -kt * qm[:, 1] - ct * vm[:, 1]
    t.series(case, "reaction M_u = −k_t θ − c_t θ̇, weighted state", reaction, recoded)
    # The reaction is RNEA at the sample's pose, with the shaft's weight moment G(θ_i) there,
    # where the step took the bias extrapolated to its weighted state, G_i + ½ (G_i − G_{i−1})
    # (the first step: G_0): the reaction carries ½ (G_i − G_{i−1}) besides the hinge's moment.
    weight = weight_moment(q[:, 1])
    bias = np.r_[0.0, 0.5 * (weight[1:-1] - weight[:-2])]
    t.series(case, "… + ½ (G_i − G_{i−1}), the weight's bias at the sample", reaction,
             recoded + bias)  # fmt: skip


def stribeck_limit(n: float) -> float:
    """Z → ∞ of Z/Σ max(cos ψ_j, 0)^(n+1): 2π / ∫_{−π/2}^{π/2} cos^(n+1) ψ dψ."""
    value, _ = integrate.quad(lambda p: math.cos(p) ** (n + 1), -math.pi / 2, math.pi / 2)
    return 2 * math.pi / value


def roller_cases(t: Table) -> None:
    z = 16
    kns = {"line": 2e8, "point": 2.2e10}
    g = np.array([0.0, -9.81, 0.0])  # onto element 12 at ψ = 3π/2 (along −w)
    for contact in ("line", "point"):
        n, kn = EXPONENT[contact], kns[contact]
        for c in (0.0, 5e-6):
            b = (
                f'<bearing joint="shaft" law="roller_sum" rollers="{z}" contact_stiffness="{kn:g}" '
                f'contact="{contact}" radial_clearance_mm="{c * 1e3:g}" radial_damping="2e4"/>'
            )
            text = shaft_model(b, tuple(g))
            case = f"roller sum, {contact}, c = {c * 1e6:g} µm"
            res = run(text, duration=20 * DT, start="static")
            disp = res.bearing("shaft").displacement[-1, :2]
            ef = res.bearing("shaft").elastic_force[-1, :2]
            sol = optimize.root(
                lambda r, kn=kn, n=n, c=c: (roller_sum(r, z, kn, n, c) + MASS * g[:2]) / 1e3,
                x0=np.array([0.0, -1e-5]),
                tol=1e-14,
            )
            t.series(case + " (static)", "deflection (u, w) [µm]", disp * 1e6, sol.x * 1e6)
            t.series(case + " (static)", "spring force = −m g [N]", ef, -MASS * g[:2])
            if c == 0.0:
                q_max = kn * max(-disp[1], 0.0) ** n  # element 12, at ψ = 3π/2
                cosines = np.maximum(np.cos(2 * np.pi * np.arange(z) / z), 0.0)
                discrete = z / float(np.sum(cosines ** (n + 1)))
                t.value(case + " (static)", "Q_max Z/F_r, the discrete sum",
                        q_max * z / np.linalg.norm(ef), discrete)  # fmt: skip
                t.value(case + " (static)", "Q_max Z/F_r: Z→∞ quadrature vs Stribeck",
                        stribeck_limit(n), STRIBECK[contact])  # fmt: skip

            res = run(text, duration=0.02, start="none")
            q, v = slides(res, "shaft", ("radial_x", "radial_y"))
            ef = res.bearing("shaft").elastic_force[:, :2]
            t.series(case + " (dynamic)", "elastic_force", ef, roller_sum(q, z, kn, n, c))
            # the step's force: the law linearised about r₀ = r_i + (h/2) ṙ_i (the weighted
            # state at no acceleration), at the weighted state; the damper where r₀ touches
            qm, vm = mid(q), weighted_speed(q)
            r0 = q[:-1] + 0.5 * DT * v[:-1]
            tangent = roller_sum_jacobian(r0, z, kn, n, c)
            lin = roller_sum(r0, z, kn, n, c) + np.einsum("iab,ib->ia", tangent, qm - r0)
            damper = np.where(roller_in_contact(r0, z, c)[:, None], -2e4 * vm, 0.0)
            reaction = res.bearing("shaft").force_local[:-1, :2]
            t.series(case + " (dynamic)", "reaction: law linearised at r + h ṙ/2, + c_r ṙ",
                     reaction, lin + damper)  # fmt: skip
            t.series(case + " (dynamic)", "(the law itself at the weighted state)", reaction,
                     roller_sum(qm, z, kn, n, c) + damper)  # fmt: skip


def frames_cases(t: Table) -> None:
    """A bearing along the joint frame's x, its frame turned by (0.3, 0.2, 0.1) rad and its
    radial axis u given as (0, 1, 1): a roller sum of Z = 7 (odd: not symmetric about the load)
    and two rows; ``displacement`` and ``elastic_force`` are in the joint frame, x u + y w."""
    rpy = (0.3, 0.2, 0.1)
    axes = bearing_axes(np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 1.0]))
    g = np.array([0.5, -9.81, 0.7])
    g_joint = rotation_rpy(*rpy).T @ g
    z, kn, n, c = 7, 2e8, EXPONENT["line"], 2e-6
    b = (
        f'<bearing joint="shaft" law="roller_sum" rollers="{z}" contact_stiffness="{kn:g}" '
        f'contact="line" radial_clearance_mm="{c * 1e3:g}" radial_damping="2e4" '
        'radial_axis="0 1 1"/>'
    )
    text = shaft_model(b, tuple(g), rpy=rpy, axis="1 0 0")
    case = "turned frame, roller sum Z = 7"
    res = run(text, duration=0.01, start="none")
    q, _ = slides(res, "shaft", ("radial_x", "radial_y"))
    disp = res.bearing("shaft").displacement
    t.series(case + " (dynamic)", "displacement = x u + y w (joint frame)", disp,
             q @ axes[:, :2].T)  # fmt: skip
    law = roller_sum(q, z, kn, n, c) @ axes[:, :2].T
    t.series(case + " (dynamic)", "elastic_force (joint frame)",
             res.bearing("shaft").elastic_force, law)  # fmt: skip
    res = run(text, duration=20 * DT, start="static")
    q, _ = slides(res, "shaft", ("radial_x", "radial_y"))
    load = MASS * (g_joint @ axes[:, :2])
    sol = optimize.root(
        lambda r: (roller_sum(r, z, kn, n, c) + load) / 1e3, x0=np.zeros(2) - 1e-6, tol=1e-14
    )
    t.series(case + " (static)", "deflection (u, w) [µm]", q[-1] * 1e6, sol.x * 1e6)

    kb = np.array([5e7, 4e7, 6e7, 1e5, 2e5])
    kc = np.array([6e7, 5e7, 3e7, 2e5, 1e5])
    damp = np.array([3e3, 1e4, 1e4, 60.0, 60.0])
    rows = [Row(-0.2, kb, damp, 5e-6), Row(0.2, kc, damp, -3e-6)]
    body = "\n    ".join(
        row_xml(nm, r, p) for nm, r, p in zip(("A", "B"), rows, (False, True), strict=True)
    )
    b = (
        '<bearing joint="shaft" radial_stiffness="1e8" axial_stiffness="1e8" '
        f'tilt_stiffness="1e6" radial_axis="0 1 1">\n    {body}\n  </bearing>'
    )
    res = run(shaft_model(b, tuple(g), 0.1, rpy=rpy, axis="1 0 0"), duration=0.01, start="none")
    case = "turned frame, rows"
    q, v = slides(res, "shaft", ROW_SLIDES)
    for nm, row in zip(("A", "B"), rows, strict=True):
        f, m = row_loads(mid(q), weighted_speed(q), row)
        pf, pm = res.row(f"shaft.{nm}").force[:-1], res.row(f"shaft.{nm}").moment[:-1]
        t.series(case + " (dynamic)", f"row {nm} force (u, w, k)", pf, f)
        t.series(case + " (dynamic)", f"row {nm} moment (u, w, k)", pm, m)
    springs = sum(row_springs(q, row) for row in rows) @ axes.T
    ef = res.bearing("shaft").elastic_force
    t.series(case + " (dynamic)", "elastic_force = Σ springs (joint frame)", ef, springs)


def row_xml(name: str, row: Row, preload: bool) -> str:
    k = " ".join(f"{v:g}" for v in row.k)
    c = " ".join(f"{v:g}" for v in row.c)
    extra = f' radial_clearance_mm="{row.clearance * 1e3:g}"' if row.clearance else ""
    extra += ' preload="true"' if preload else ""
    return (
        f'<row name="{name}" type="cylindrical_roller" position_mm="{row.a * 1e3:g}" '
        f'stiffness="{k}" damping="{c}"{extra}/>'
    )


def gravity_forces(q: np.ndarray, g: np.ndarray, length: float) -> np.ndarray:
    """Gravity's generalized forces on the slides (x, y, z, θ_u, θ_w) of a shaft whose centre of
    mass is ``length`` along its axis: p = (x + L sin b, y − L sin a cos b, z + L cos a cos b),
    the hinges R_x(a) R_y(b) exact."""
    _, _, _, a, b = q
    dpa = np.array([0.0, -length * math.cos(a) * math.cos(b), -length * math.sin(a) * math.cos(b)])
    dpb = np.array([length * math.cos(b), length * math.sin(a) * math.sin(b),
                    -length * math.cos(a) * math.sin(b)])  # fmt: skip
    return MASS * np.array([g[0], g[1], g[2], g @ dpa, g @ dpb])


def row_generalized(q: np.ndarray, rows: list[Row]) -> np.ndarray:
    """The rows' springs' generalized forces on (x, y, z, θ_u, θ_w) (δ linear in q)."""
    out = np.zeros(5)
    for row in rows:
        f, m = row_loads(q[None], np.zeros((1, 5)), row)
        fu, fw, fk = f[0]
        mu, mw, _ = m[0]
        # δ_y = x + a θ_w, δ_z = y − a θ_u: virtual work Fu δx + Fw δy + Fk δz + (Mu − a Fw) δθu
        # + (Mw + a Fu) δθw
        out += [fu, fw, fk, mu - row.a * fw, mw + row.a * fu]
    return out


def hinge_rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """R_x(a) R_y(b), (n, 3, 3): the tilt hinges about u, then about the turned w."""
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    zero, one = np.zeros_like(a), np.ones_like(a)
    rx = np.stack([np.stack([one, zero, zero], -1), np.stack([zero, ca, -sa], -1),
                   np.stack([zero, sa, ca], -1)], -2)  # fmt: skip
    ry = np.stack([np.stack([cb, zero, sb], -1), np.stack([zero, one, zero], -1),
                   np.stack([-sb, zero, cb], -1)], -2)  # fmt: skip
    return rx @ ry


def row_cases(t: Table) -> None:
    kb = np.array([5e7, 4e7, 6e7, 1e5, 2e5])
    kc = np.array([6e7, 5e7, 3e7, 2e5, 1e5])
    damp = np.array([3e3, 1e4, 1e4, 60.0, 60.0])
    g = np.array([3.0, -9.81, -2.0])
    length = 0.1
    for label, rows, preload in (
        ("clearance 5 µm + preload 3 µm", [Row(-0.2, kb, damp, 5e-6), Row(0.2, kc, damp, -3e-6)],
         [False, True]),
        ("both preloaded 3 µm", [Row(-0.2, kb, damp, -3e-6), Row(0.2, kc, damp, -3e-6)],
         [True, True]),
    ):  # fmt: skip
        body = "\n    ".join(
            row_xml(nm, r, p) for nm, r, p in zip(("A", "B"), rows, preload, strict=True)
        )
        b = (
            '<bearing joint="shaft" radial_stiffness="1e8" axial_stiffness="1e8" '
            f'tilt_stiffness="1e6">\n    {body}\n  </bearing>'
        )
        text = shaft_model(b, tuple(g), com_z=length)
        case = f"rows, {label}"
        res = run(text, duration=20 * DT, start="static")
        q, _ = slides(res, "shaft", ROW_SLIDES)
        sol = optimize.root(
            lambda s, rows=rows: (
                row_generalized(s * 1e-6, rows) + gravity_forces(s * 1e-6, g, length)
            ),
            x0=q[-1] * 1e6,
            tol=1e-14,
        )
        t.series(case + " (static)", "slides (x, y, z, θ_u, θ_w) [µm, µrad]", q[-1] * 1e6, sol.x)
        total = sum(res.row(f"shaft.{nm}").force[-1] for nm in ("A", "B"))
        t.series(case + " (static)", "Σ rows' force = −m g [N]", total, -MASS * g)

        res = run(text, duration=0.02, start="none")
        q, v = slides(res, "shaft", ROW_SLIDES)
        qm, vm = mid(q), weighted_speed(q)
        springs = np.zeros((len(q), 3))
        for nm, row in zip(("A", "B"), rows, strict=True):
            f, m = row_loads(qm, vm, row)
            pf = res.row(f"shaft.{nm}").force[:-1]
            pm = res.row(f"shaft.{nm}").moment[:-1]
            sides = row_sides(qm, row)
            band, both = np.sum(np.any(sides == 0, 1)), np.sum(np.any(sides == 2, 1))
            t.series(case + " (dynamic)", f"row {nm} force, weighted state ({band}/{both} samples"
                     " in its dead band/pressed on both sides)", pf, f)  # fmt: skip
            t.series(case + " (dynamic)", f"row {nm} moment", pm, m)
            springs += row_springs(q, row)
        ef = res.bearing("shaft").elastic_force
        t.series(case + " (dynamic)", "elastic_force = Σ rows' springs at the sample", ef, springs)
        # Σ F_i against the reaction (joint frame, which tilts with the shaft: R_x(θ_u) R_y(θ_w)
        # at the sample's pose); the rows' axes u, w, k do not tilt
        total = sum(res.row(f"shaft.{nm}").force[:-1] for nm in ("A", "B"))
        reaction = res.bearing("shaft").force_local[:-1]
        t.series(case + " (dynamic)", "Σ rows' force vs the reaction", reaction, total)
        turned = np.einsum("iba,ib->ia", hinge_rotation(q[:-1, 3], q[:-1, 4]), total)
        t.series(case + " (dynamic)", "… in the tilted joint frame", reaction, turned)


def nrel_rows(text: str) -> dict[str, tuple[np.ndarray, dict[str, Row]]]:
    """Per bearing with stiff rows: its axes (u, w, k) as columns in its joint frame and its
    rows, from the model text alone."""
    root = ET.fromstring(text)
    joint_axis = {
        j.attrib["name"]: np.array([float(v) for v in j.find("axis").attrib["xyz"].split()])
        for j in root.iter("joint")
        if j.find("axis") is not None
    }
    out = {}
    for b in root.iter("bearing"):
        rows = {}
        for r in b.iter("row"):
            a = r.attrib
            if "stiffness" not in a:
                continue
            rows[a["name"]] = Row(
                float(a.get("position_mm", "0")) * 1e-3,
                np.array([float(v) for v in a["stiffness"].split()]),
                np.array([float(v) for v in a.get("damping", "0 0 0 0 0").split()]),
                float(a.get("radial_clearance_mm", "0")) * 1e-3,
            )
        if rows:
            joint = b.attrib["joint"]
            given = b.attrib.get("radial_axis")
            radial = None if given is None else np.array([float(v) for v in given.split()])
            out[joint] = (bearing_axes(joint_axis[joint], radial), rows)
    return out


def with_row_clearances(text: str) -> str:
    """Stage 1's planet rows preloaded by 0.02 mm, stage 2's and the main shaft's (lss) rows
    with a 0.07 mm clearance."""
    out = []
    joint = ""
    for line in text.splitlines():
        if "<bearing " in line:
            joint = line.split('joint="')[1].split('"')[0]
        if "<row " in line and joint.startswith("stage1_planet"):
            line = line.replace("<row ", '<row radial_clearance_mm="-0.02" preload="true" ')
        if "<row " in line and (joint.startswith("stage2_planet") or joint == "lss"):
            line = line.replace("<row ", '<row radial_clearance_mm="0.07" ')
        out.append(line)
    return "\n".join(out)


def nrel_cases(t: Table, directory: Path, duration: float = 0.05, dt: float = 1e-4) -> None:
    base = NREL_MODEL.read_text()
    ratio = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
    rotor = 12.1 * math.pi / 30
    variants = (("as shipped", base), ("rows with c or preload", with_row_clearances(base)))
    for label, text in variants:
        log = directory / f"nrel_{len(label)}.mcap"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PinwindWarning)
            gb = loads(text, path=str(NREL_MODEL))
            pinwind.simulate(
                gb, duration=duration, dt=dt, torques={"rotor": 3945990.3245924464},
                speeds={"generator": -rotor * ratio}, initial_speeds={"rotor": rotor},
                progress=False, log=log, overwrite=True,
            )  # fmt: skip
            res = pinwind.read_log(log)
        case = f"NREL 5 MW, {label} (logged)"
        got: dict[str, list[float]] = {
            "force": [0, 0, 0],
            "moment": [0, 0, 0],
            "elastic": [0, 0, 0],
        }
        count, band, both = 0, 0, 0

        def fold(key: str, pinwind_series: np.ndarray, recoded: np.ndarray, got=got) -> None:
            scale = max(float(np.max(np.abs(pinwind_series))), 1.0)
            entry = got[key]
            entry[0] = max(entry[0], scale)
            entry[1] = max(entry[1], float(np.max(np.abs(recoded))))
            entry[2] = max(entry[2], rel(recoded, pinwind_series, scale))

        for joint, (axes, rows) in nrel_rows(text).items():
            q, _ = slides(res, joint, ROW_SLIDES)
            springs = np.zeros((len(q), 3))
            for name, row in rows.items():
                f, m = row_loads(mid(q), weighted_speed(q, dt), row)
                fold("force", res.row(f"{joint}.{name}").force[:-1], f)
                fold("moment", res.row(f"{joint}.{name}").moment[:-1], m)
                springs += row_springs(q, row)
                count += 1
                touching = row_sides(mid(q), row)
                band += int(np.sum(np.any(touching == 0, axis=1)))
                both += int(np.sum(np.any(touching == 2, axis=1)))
            fold("elastic", res.bearing(joint).elastic_force, springs @ axes.T)
        for key, quantity in (
            ("force", f"{count} rows' force, weighted state ({band}/{both} row-samples in a dead"
             " band/pressed on both sides)"),
            ("moment", f"{count} rows' moment"),
            ("elastic", "elastic_force = Σ rows' springs (joint frame)"),
        ):  # fmt: skip
            t.add(case, quantity, *got[key])


def main() -> None:
    started = time.perf_counter()
    t = Table()
    linear_cases(t)
    axial_tilt_cases(t)
    roller_cases(t)
    row_cases(t)
    frames_cases(t)
    with tempfile.TemporaryDirectory() as d:
        nrel_cases(t, Path(d))
    print(t.markdown())
    print(f"\n({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
