"""The rotor's thrust, weight and wind-shear moment on the NREL 5 MW main shaft, and the bearing
rows that carry them, recoded from the model file and public formulas without pinwind's rotor,
hub-load or bearing-row code.

Runs (``pinwind.runs.scenario``, no log), on ``models/nrel5mw_gearbox.urdf`` (rigid meshes, every
bearing its rows, the static start), dt = 1e-4 s:

- **A** (rotor): the ``nrel5mw`` rotor preset on joint ``rotor``, its hub on ``lss`` at the main
  shaft's rotor end (``hub_point`` of scenarios/nrel5mw_turbulent.toml), a constant wind of
  10 m/s, the generator held at 12.1 rpm · 96.354 (turning against the rotor), 0.3 s.
- **A′**: A again, the rotor without ``hub_body``, and instead a ``constant_hub_load`` on ``lss``
  with the recoded F_x, F_z, M_y at the same point (fixed frame). A and A′ have the same state
  at every step exactly when the rotor's hub loads are the recoded ones: the rows' loads of the
  two runs then agree to rounding.
- **B** (a hub load, standing): no rotor; the rated rotor torque 3 945 990 N·m on joint
  ``rotor`` against the generator held at standstill (speed 0), and a ``constant_hub_load`` on
  ``lss`` at the hub: F_x = 8e5, F_y = 1.5e5, F_z = −1.2e6 N, M_y = 2.5e6, M_z = −8e5 N·m (fixed
  frame), 0.2 s. The static start puts it in equilibrium: its statics close to rounding.

Recoding (from the model file read with ``xml.etree`` and the shipped ROSCO table only):

- thrust T = ½ ρ π R² v² C_t(λ, β) (Burton et al. 2011, Wind Energy Handbook §3.2: the thrust
  coefficient C_T = T / (½ ρ U² A_D)), λ = ω R / v with ω the rotor joint's speed at the sample,
  C_t bilinear in (λ, β) on the ROSCO table (``pinwind/loads/data/nrel5mw_cp_ct_cq.txt``, read
  here with its own parser); R = 63 m, hub height 90 m, shaft tilt 5°, rotor mass 110 000 kg
  (Jonkman et al. 2009 Table 1-1), ρ = 1.225 kg/m³ (Jonkman et al. 2009's air density), β = 0;
- the wind-shear arm ℓ = (1/πR²) ∫ z (1 + z/H)^{2α} dA over the disc (docs/loads.md; the power-law
  profile v(z) = v_hub (z/z_hub)^α of IEC 61400-1's normal wind profile, α = 0.2, the hub at z = H),
  by Gauss–Legendre quadrature on z = R sin t (the chord 2R cos t makes the integrand smooth),
  beside its small-shear limit α R²/(2H);
- the hub's loads in its fixed frame (x along the shaft downwind, z up): F_x = T + m g sin τ,
  F_z = −m g cos τ, M_y = ℓ T (a moment about y = z × x of the thrust's upper surplus);
- the main shaft ``lss`` as a rigid body on its rows (all four rows of its ``<bearing>``: the
  main bearings INP-A, INP-B and the carrier bearings PLC-A, PLC-B; ``lss`` is the main shaft and
  stage 1's carrier in one body), on the slides of docs/model_format.md ("Compliant bearings":
  x along u, y along w, z along k, then the tilts θ_u about u and θ_w about w through the bearing
  centre) with each row's law δ = (z, x + a θ_w, y − a θ_u, θ_u, θ_w), L = −K δ ("Bearing rows").
  The loads on the shaft: the hub load at its point (its force and moment keep the housing's
  axes; the point moves with the shaft), the shaft's own weight at its centre of mass (the
  model's gravity), and what the gearbox side puts on it: ``lss`` carries the three stage-1
  planets on their compliant bearings, whose reactions do not cancel (the planets' weights and
  the unequal load sharing of the meshes: tens of kN), so they enter as an input: minus each
  planet bearing's reaction (``bearing_force``, ``bearing_moment``, world) at the planet's link
  origin (``body_position``). The rotor torque reaches ``lss`` through the coupling spring on the
  joint's own coordinate, not on the slides. The slides' equilibrium Σ_i B_iᵀ K_i B_i q = Q(q) is
  solved by fixed-point iteration (Q, the loads' virtual work through the exact kinematics of the
  slides, changes with q only through the lever arms); each row's (F_u, F_w, F_k) and (M_u, M_w)
  follow.

Compared with the runs' series: ``rotor("rotor").tip_speed_ratio``, ``thrust_coefficient``,
``thrust``; ``row("lss.<row>").force``, ``moment``; the slides' coordinates
(``joint("lss_radial_x")`` …); the bearing's ``displacement``. Run A turns, so its shaft is not
in statics: the planets orbit and their reactions turn with them; there the recoding's residual
is the shaft's inertia, reported as the slides' largest acceleration times the shaft's mass.

Run: ``PYTHONPATH=. python benchmarks/independent_hub_loads.py`` (about 15 s).
"""

from __future__ import annotations

import math
import sys
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from pinwind.runs.scenario import load_scenario, run  # noqa: E402

MODEL = REPO / "models" / "nrel5mw_gearbox.urdf"
TABLE = REPO / "pinwind" / "loads" / "data" / "nrel5mw_cp_ct_cq.txt"
DT = 1e-4

# Jonkman et al. 2009 Table 1-1 (and §6's air density)
RADIUS = 63.0  # m
HUB_HEIGHT = 90.0  # m
TILT = math.radians(5.0)
ROTOR_MASS = 110_000.0  # kg
AIR_DENSITY = 1.225  # kg/m³
SHEAR_EXPONENT = 0.2  # IEC 61400-1 normal wind profile
WIND = 10.0  # m/s
ROTOR_RPM = 12.1
RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # from the teeth
HUB_POINT = (0.0, 0.0, -0.88709638554)  # m, in the lss frame: the rotor joint's z
RATED_TORQUE = 3945990.3245924464  # N·m, 5 MW at 12.1 rpm
#: run B's hub load in the hub's fixed frame: F_x, F_y, F_z [N], M_x, M_y, M_z [N·m]
HUB_LOAD_B = (8.0e5, 1.5e5, -1.2e6, 0.0, 2.5e6, -8.0e5)
ROWS_LSS = ("INP-A", "INP-B", "PLC-A", "PLC-B")


# --- the rotor ------------------------------------------------------------------------------


def read_performance(path: Path) -> dict[str, np.ndarray]:
    """The ROSCO table: pitch [deg], tsr, and the C_p, C_t matrices (rows λ, columns β)."""
    lines = path.read_text().splitlines()

    def vector_after(title: str) -> np.ndarray:
        i = next(n for n, s in enumerate(lines) if s.startswith("#") and title in s)
        return np.array([float(v) for v in lines[i + 1].split()])

    pitch, tsr = vector_after("Pitch angle vector"), vector_after("TSR vector")

    def matrix_after(title: str) -> np.ndarray:
        i = next(n for n, s in enumerate(lines) if s.startswith("#") and title in s)
        rows = [s for s in lines[i + 1 :] if s.strip()][: len(tsr)]
        m = np.array([[float(v) for v in s.split()] for s in rows])
        if m.shape != (len(tsr), len(pitch)):
            raise ValueError(f"{title}: shape {m.shape}")
        return m

    return {
        "pitch_deg": pitch,
        "tsr": tsr,
        "cp": matrix_after("Power coefficient"),
        "ct": matrix_after("Thrust coefficient"),
    }


def bilinear(xs: np.ndarray, ys: np.ndarray, m: np.ndarray, x: float, y: float) -> float:
    """m[i, j] at (xs[i], ys[j]) interpolated bilinearly at (x, y) inside the grid."""
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


def shear_arm(radius: float, hub_height: float, alpha: float, nodes: int = 64) -> float:
    """ℓ = (1/πR²) ∫ z (1 + z/H)^{2α} dA over the disc [m]: with z = R sin t the strip of height
    dz has the chord 2R cos t, ℓ = (2R/π) ∫_{−π/2}^{π/2} sin t cos² t (1 + R sin t/H)^{2α} dt."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    t = 0.5 * math.pi * x
    f = np.sin(t) * np.cos(t) ** 2 * (1 + radius * np.sin(t) / hub_height) ** (2 * alpha)
    return float(2 * radius / math.pi * 0.5 * math.pi * np.sum(w * f))


def rotor_hub_load(thrust: float, arm: float, g: float) -> tuple[float, float, float]:
    """F_x, F_z [N] and M_y [N·m] of the rotor on its hub, hub's fixed frame (docs/loads.md)."""
    return (
        thrust + ROTOR_MASS * g * math.sin(TILT),
        -ROTOR_MASS * g * math.cos(TILT),
        arm * thrust,
    )


# --- the shaft on its rows -------------------------------------------------------------------


@dataclass
class Shaft:
    """A shaft's joint origin in the world [m] (axes the world's), its mass [kg] and centre of
    mass along k [m], gravity [m/s²], its rows (name, a [m], (K_x, K_y, K_z, K_β, K_γ))."""

    origin: np.ndarray
    mass: float
    com_a: float
    gravity: np.ndarray
    rows: list[tuple[str, float, np.ndarray]]
    children: list[str]


def read_shaft(model: Path, joint: str) -> Shaft:
    root = ET.parse(model).getroot()
    j = next(e for e in root.iter("joint") if e.get("name") == joint)
    if j.find("origin").get("rpy", "0 0 0").split() != ["0", "0", "0"]:  # type: ignore[union-attr]
        raise ValueError("the recoding takes a joint frame with the world's axes")
    if j.find("axis").get("xyz").split() != ["0", "0", "1"]:  # type: ignore[union-attr]
        raise ValueError("the recoding takes a joint along z")
    origin = np.array([float(v) for v in j.find("origin").get("xyz").split()])  # type: ignore[union-attr]
    link = j.find("child").get("link")  # type: ignore[union-attr]
    inertial = next(e for e in root.iter("link") if e.get("name") == link).find("inertial")
    com = [float(v) for v in inertial.find("origin").get("xyz").split()]  # type: ignore[union-attr]
    mass = float(inertial.find("mass").get("value"))  # type: ignore[union-attr]
    gearbox = root.find("gearbox")
    gravity = np.array([float(v) for v in gearbox.get("gravity").split()])  # type: ignore[union-attr]
    bearing = next(b for b in gearbox.iter("bearing") if b.get("joint") == joint)  # type: ignore[union-attr]
    rows = [
        (
            r.get("name"),
            float(r.get("position_mm")) / 1000.0,
            np.array([float(v) for v in r.get("stiffness").split()]),
        )
        for r in bearing.iter("row")
    ]
    children = [
        e.get("name")
        for e in root.iter("joint")
        if e.find("parent").get("link") == link and e.get("type") != "fixed"  # type: ignore[union-attr]
    ]
    return Shaft(origin, mass, com[2], gravity, rows, children)  # type: ignore[arg-type]


def row_map(a: float) -> np.ndarray:
    """B with δ = B q, q = (x, y, z, θ_u, θ_w), δ = (z, x + a θ_w, y − a θ_u, θ_u, θ_w)."""
    b = np.zeros((5, 5))
    b[0, 2] = 1.0
    b[1, 0], b[1, 4] = 1.0, a
    b[2, 1], b[2, 3] = 1.0, -a
    b[3, 3] = 1.0
    b[4, 4] = 1.0
    return b


def rot_x(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


@dataclass
class Wrench:
    """A force [N] and a moment [N·m] (world axes) at a point: on the shaft's axis at ``a`` [m]
    from the bearing centre (moves with the shaft), or at a world ``point`` [m]."""

    force: np.ndarray
    moment: np.ndarray
    a: float | None = None
    point: np.ndarray | None = None


def generalised(shaft: Shaft, q: np.ndarray, wrenches: list[Wrench]) -> np.ndarray:
    """The wrenches' virtual work through the slides x, y, z, θ_u, θ_w (exact kinematics)."""
    u, w, k = np.eye(3)
    centre = shaft.origin + q[0] * u + q[1] * w + q[2] * k
    turn = rot_x(q[3]) @ rot_y(q[4])
    w_tilted = rot_x(q[3]) @ w
    out = np.zeros(5)
    for e in wrenches:
        p = centre + turn @ (e.a * k) if e.a is not None else e.point
        m = e.moment + np.cross(p - centre, e.force)
        out += (e.force @ u, e.force @ w, e.force @ k, m @ u, m @ w_tilted)
    return out


def solve_shaft(shaft: Shaft, wrenches: list[Wrench]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """q at Σ B_iᵀ K_i B_i q = Q(q), and each row's loads L = −K B q (F_u, F_w, F_k, M_u, M_w)."""
    stiffness = sum(row_map(a).T @ np.diag(k) @ row_map(a) for _, a, k in shaft.rows)
    q = np.zeros(5)
    for _ in range(50):
        q_new = np.linalg.solve(stiffness, generalised(shaft, q, wrenches))
        if np.max(np.abs(q_new - q)) <= 1e-15 * max(1e-3, np.max(np.abs(q_new))):
            q = q_new
            break
        q = q_new
    loads = {}
    for name, a, k in shaft.rows:
        delta_load = -k * (row_map(a) @ q)  # along (k, u, w, u, w)
        loads[name] = np.array([delta_load[1], delta_load[2], delta_load[0], *delta_load[3:]])
    return q, loads


def weight(shaft: Shaft) -> Wrench:
    return Wrench(shaft.mass * shaft.gravity, np.zeros(3), a=shaft.com_a)


def hub_wrench(loads: tuple[float, ...], up: np.ndarray) -> Wrench:
    """A fixed-frame hub load (F_x, F_y, F_z, M_x, M_y, M_z) in world axes: x the shaft's axis k,
    z the vertical ``up`` across it, y = z × x."""
    x = np.array([0.0, 0.0, 1.0])
    z = up - (up @ x) * x
    z /= np.linalg.norm(z)
    y = np.cross(z, x)
    f = loads[0] * x + loads[1] * y + loads[2] * z
    m = loads[3] * x + loads[4] * y + loads[5] * z
    return Wrench(f, m, a=HUB_POINT[2])


def planet_wrenches(res, shaft: Shaft, i: int) -> list[Wrench]:
    """Minus each child bearing's reaction (the force on the child at its centre), at sample i."""
    out = []
    positions = res.pose_at_samples("body_position")
    for name in shaft.children:
        b = res.bearing(name)
        p = positions[i, res.body_names.index(name)]
        out.append(Wrench(-b.force[i], -b.moment[i], point=p))
    return out


# --- runs ------------------------------------------------------------------------------------

HEAD = f"""model = "{MODEL.as_posix()}"
dt = {DT!r}
no_log = true
"""


def scenario_text(case: str, duration: float, hub: tuple[float | str, ...] | None = None) -> str:
    """Scenario TOML of run ``case`` ("A", "A'" or "B"); a hub component is a number or a signal
    text."""
    text = HEAD + f"duration = {duration!r}\n"
    if case in ("A", "A'"):
        text += f"initial_speed = {{ rotor = {ROTOR_RPM!r} }}\nwind = {WIND!r}\n"
        text += f"pose_rate = {1.0 / DT!r}\n"
        text += f"[speed]\ngenerator = {-ROTOR_RPM * RATIO!r}\n"
        text += '[rotor.rotor]\npreset = "nrel5mw"\n'
        if case == "A":
            text += f'hub_body = "lss"\nhub_point = {list(HUB_POINT)!r}\n'
    else:
        text += f"[torque]\nrotor = {RATED_TORQUE!r}\n[speed]\ngenerator = 0.0\n"
    if hub is not None:
        names = ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")
        text += "[hub_load.lss]\n" + "".join(
            f"{n} = {v!r}\n" if isinstance(v, float) else f"{n} = '{v}'\n" for n, v in zip(names, hub)
        )
        text += f'point = {list(HUB_POINT)!r}\nframe = "fixed"\n'
    return text


def run_case(case: str, duration: float, hub=None, table: np.ndarray | None = None):
    """Run ``case``; ``table`` (time, F_x, M_y rows) becomes ``hub.csv`` beside the scenario,
    read by the hub components "csv:1" and "csv:2"."""
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "case.toml"
        if table is not None:
            csv = Path(d) / "hub.csv"
            np.savetxt(csv, table, delimiter=",", fmt="%.17g")
            hub = tuple(
                f'csv(file="{csv.as_posix()}", column={v[4:]})' if isinstance(v, str) else v
                for v in hub
            )
        path.write_text(scenario_text(case, duration, hub))
        return run(load_scenario(path), progress=False)


def rel(a, b, scale=None) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    s = float(np.max(np.abs(b))) if scale is None else scale
    return float(np.max(np.abs(a - b)) / s)


# --- the comparison ---------------------------------------------------------------------------

SLIDES = ("radial_x", "radial_y", "axial", "tilt_x", "tilt_y")


def slides_of(res, joint: str, i) -> np.ndarray:
    return np.array([res.joint(f"{joint}_{s}").angle[i] for s in SLIDES]).T


def rotor_rows(res) -> list[tuple[str, float, float]]:
    """λ, C_t and T of run A against the recoding, over every sample."""
    table = read_performance(TABLE)
    omega = res.joint("rotor").speed
    v = res.rotor("rotor").wind_speed
    lam = omega * RADIUS / v
    ct = np.array([bilinear(table["tsr"], table["pitch_deg"], table["ct"], x, 0.0) for x in lam])
    thrust = 0.5 * AIR_DENSITY * math.pi * RADIUS**2 * v**2 * ct
    r = res.rotor("rotor")
    return [
        ("λ = ωR/v", float(r.tip_speed_ratio[-1]), float(lam[-1]), rel(r.tip_speed_ratio, lam)),
        ("C_t(λ, 0)", float(r.thrust_coefficient[-1]), float(ct[-1]), rel(r.thrust_coefficient, ct)),
        ("thrust T [N]", float(r.thrust[-1]), float(thrust[-1]), rel(r.thrust, thrust)),
    ]


def shaft_rows(res, shaft: Shaft, hub: Wrench, i: int, label: str) -> list[tuple[str, float, float, float]]:
    """Every lss row's five loads and the slides at sample i against the statics."""
    q, loads = solve_shaft(shaft, [hub, weight(shaft), *planet_wrenches(res, shaft, i)])
    out = []
    scale = max(float(np.max(np.abs(v[:3]))) for v in loads.values())
    for name in ROWS_LSS:
        row = res.row(f"lss.{name}")
        ran = np.concatenate([row.force[i], row.moment[i][:2]])
        for c, comp in enumerate(("F_u", "F_w", "F_k", "M_u", "M_w")):
            if abs(loads[name][c]) < 1e-9 * scale and abs(ran[c]) < 1e-9 * scale:
                continue
            ref = abs(loads[name][c]) if c < 3 else abs(loads[name][c])
            out.append(
                (f"{label} {name} {comp}", float(ran[c]), float(loads[name][c]), abs(ran[c] - loads[name][c]) / ref)
            )
    q_run = slides_of(res, "lss", i)
    for c, s in enumerate(SLIDES):
        out.append((f"{label} lss_{s}", float(q_run[c]), float(q[c]), abs(q_run[c] - q[c]) / abs(q[c])))
    return out


def main() -> None:
    shaft = read_shaft(MODEL, "lss")
    g = float(np.linalg.norm(shaft.gravity))
    up = -shaft.gravity / g
    arm = shear_arm(RADIUS, HUB_HEIGHT, SHEAR_EXPONENT)
    limit = SHEAR_EXPONENT * RADIUS**2 / (2 * HUB_HEIGHT)
    print(f"shear arm ℓ = {arm:.9f} m by quadrature (64 and 128 nodes differ by "
          f"{abs(shear_arm(RADIUS, HUB_HEIGHT, SHEAR_EXPONENT, 128) - arm):.1e} m); "
          f"α R²/(2H) = {limit:.9f} m ({arm / limit - 1:+.3%})")

    a = run_case("A", 0.3)
    rows = rotor_rows(a)
    thrust = a.rotor("rotor").thrust
    if np.ptp(thrust) > 1e-6 * thrust[0]:
        print(f"note: run A's thrust moves by {np.ptp(thrust):.3g} N over the run")
    fx, fz, my = rotor_hub_load(float(thrust[0]), arm, g)
    # the recoded F_x, M_y at every sample of A (from its thrust, equal to the recoded one above)
    fx_t, _, my_t = rotor_hub_load(thrust, arm, g)
    table = np.column_stack([a.time, fx_t, my_t])
    a2 = run_case("A'", 0.3, hub=("csv:1", 0.0, fz, 0.0, "csv:2", 0.0), table=table)
    for name in ROWS_LSS:
        ra, rb = a.row(f"lss.{name}"), a2.row(f"lss.{name}")
        for c, comp in enumerate(("F_u", "F_w", "F_k")):
            if np.max(np.abs(rb.force[:, c])) > 1.0:
                rows.append((f"A vs A′ {name} {comp}", float(ra.force[-1, c]), float(rb.force[-1, c]),
                             rel(ra.force[:, c], rb.force[:, c])))
    hub_a = hub_wrench((fx, 0.0, fz, 0.0, my, 0.0), up)
    last = len(a.time) - 1
    rows += shaft_rows(a, shaft, hub_a, last, "A")
    acc = max(float(np.max(np.abs(a.joint(f"lss_{s}").acceleration[100:]))) for s in SLIDES[:3])

    b = run_case("B", 0.2, hub=HUB_LOAD_B)
    rows += shaft_rows(b, shaft, hub_wrench(HUB_LOAD_B, up), len(b.time) - 1, "B")
    acc_b = max(float(np.max(np.abs(b.joint(f"lss_{s}").acceleration))) for s in SLIDES)
    print(f"hub loads of run A's rotor (recoded): F_x = {fx:.6e} N, F_z = {fz:.6e} N, M_y = {my:.6e} N·m")
    print(f"residual: run A's slides accelerate by up to {acc:.3g} m/s² ({acc * shaft.mass:.3g} N on "
          f"the {shaft.mass:.0f} kg shaft); run B's slides by up to {acc_b:.2g} (m/s², rad/s²)")
    print(f"\n| quantity | pinwind | recoding | rel. difference |\n|---|---|---|---|")
    for name, ran, ref, d in rows:
        print(f"| {name} | {ran:.9g} | {ref:.9g} | {d:.1e} |")


if __name__ == "__main__":
    main()
