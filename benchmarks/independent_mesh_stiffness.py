"""The ISO 6336-1 mesh stiffness of the shipped models' meshes and its variation along the path
of contact, recoded from the model files' gear data without pinwind's stiffness code, and
compared with what pinwind loads and what a compliant run's samples imply.

Recoding (each mesh, from the ``<gear>`` attributes read with ``xml.etree``):

- involute geometry (ISO 21771): α_t = atan(tan α_n / cos β), d = z m_n / cos β, d_b = d cos α_t,
  inv α_wt = inv α_t + 2 tan α_n (x_1 + x_2)/(z_1 + z_2) (an internal gear's z and d negative),
  a_w = (z_1 + z_2) m_n cos α_t / (2 cos β cos α_wt), tip diameters d ± 2 m_n (1 + x) ± 2 k m_n
  (docs/model_format.md), the path of contact g_α from the tip circles at a_w, ε_α = g_α / p_bt
  (p_bt = π m_n cos α_t / cos β), ε_β = b sin β / (π m_n), the path start A as a roll distance
  from gear A's base tangency point;
- ISO 6336-1 method B as gfsReboucas/Drivetrain ``Gear_Set.m`` (``get.cprime_th``,
  ``get.cprime``, ``get.c_gamma_alpha``) prints it: q′ = C1 + C2/z_n1 + C3/z_n2 + C4 x_1 +
  C5 x_1/z_n1 + C6 x_2 + C7 x_2/z_n2 + C8 x_1² + C9 x_2² [mm·µm/N] with C1..C9 = 0.04723,
  0.15551, 0.25791, −0.00635, −0.11654, −0.00193, −0.24188, 0.00529, 0.00182; the file prints
  the last term C9 x_1², after C8 x_1² (a slip, since every other coefficient pairs gear 1 and
  gear 2 terms): x_2² is taken here, and the table shows what x_1² would change.
  z_n = z / (cos β cos² β_b) (``Gear.m`` ``get.z_n``); gear 1 the pinion, the gear with fewer
  teeth (Eritenel, drivetrainhub notebooks-gears, "Chapter 2 - Spur Gears"), an internal gear
  second; c′_th = 1/q′; c′ = c′_th C_M C_R C_B cos β with C_M = 0.8, C_R = 1 (solid discs),
  C_B = (1 + 0.5 (1.2 − h_fP/m_n)) (1 − 0.02 (20° − α_n)), h_fP = 1.25 m_n (ISO 53);
  c_γα = c′ (0.75 ε_α + 0.25). Two readings of an internal gear 2 are printed: (a) ``Gear_Set.m``'s
  negative tooth count, so a negative z_n2 in C3/z_n2 and C7 x_2/z_n2; (b) a rack, z_n2 = ∞ (the
  ISO text is not available here to settle which the standard means);
- the stiffness along the path (docs/model_format.md "stiffness_variation"): spur, c′b with one
  pair in contact and 1.75 c′b with two (the entering pair at x from A, the next at x + p_bt);
  helical, c_γα b L(x)/L̄ with L(x) the total length of the contact lines in the plane of action
  (each inclined at β_b across the face, centred on the mid-face section) and L̄ = ε_α b / cos β_b
  its mean.

Compared with: ``pinwind.load(model).mesh(name).path`` (ε_α, ε_β, the path start A, g_α) and,
from a 0.02 s run (dt = 2·10⁻⁵ s) with every mesh compliant and undamped
(``MeshCompliance(damping=0)``), every sample's k = F_n / δ̄: ``mesh_normal`` over the mean of
``mesh_deflection`` at the sample and the next (a sample's force is that of the step starting
there: at ρ∞ = 1 the mean of the forces at its two ends with the tooth pairs of its start,
docs/validation.md), on the samples whose step keeps one flank in contact; and ``mesh_pairs``,
each against the recoded k(x) and pair count at the logged ``mesh_contact_position``.

The DTU 500 kW stage is also compared with Jørgensen 2014 §2.4 and Fig. 8: the planet/ring path
s_min = 0.043967 m, s_switch = 0.064022 m, s_max = 0.073488 m from the planet's base tangency, and
a single-tooth stiffness of "around 3.5·10⁹ N/m" from their FEM.

Run: ``PYTHONPATH=. python benchmarks/independent_mesh_stiffness.py`` (about half a minute).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

# ISO 6336-1 method B, q′ coefficients C1..C9 (gfsReboucas/Drivetrain Gear_Set.m get.cprime_th).
C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
C_M = 0.8  # correction factor, solid discs (Gear_Set.m get.cprime)
C_R = 1.0  # gear blank factor, solid discs
H_FP = 1.25  # basic rack dedendum / m_n (ISO 53)


def inv(a: float) -> float:
    return math.tan(a) - a


def solve_inv(v: float) -> float:
    """The angle whose involute is v (Newton from 0.5 rad)."""
    a = 0.5
    for _ in range(100):
        step = (inv(a) - v) / math.tan(a) ** 2
        a -= step
        if abs(step) < 1e-16:
            break
    return a


def gears_of(model: Path) -> tuple[dict[str, dict[str, float]], list[tuple[str, str, str]]]:
    """The ``<gear>`` data [SI, rad] and the ``(name, gear1, gear2)`` of each ``<mesh>``."""
    root = ET.parse(model).getroot()
    gears = {}
    for g in root.iter("gear"):
        a = g.attrib
        gears[a["name"]] = {
            "z": float(a["teeth"]),
            "m": float(a["module_mm"]) * 1e-3,
            "alpha": math.radians(float(a.get("pressure_angle_deg", "20"))),
            "b": float(a["face_width_mm"]) * 1e-3,
            "x": float(a.get("profile_shift", "0")),
            "beta": math.radians(float(a.get("helix_angle_deg", "0"))),
            "km": float(a.get("tip_alteration_mm", "0")) * 1e-3,
            "internal": a.get("internal", "false") == "true",
        }
    meshes = [(m.attrib["name"], m.attrib["gear1"], m.attrib["gear2"]) for m in root.iter("mesh")]
    return gears, meshes


def recode(
    ga: dict[str, float],
    gb: dict[str, float],
    c9_on_x1: bool = False,
    ring_as_rack: bool = False,
    pinion_first: bool = True,
) -> dict[str, float]:
    """ISO 21771 geometry and ISO 6336-1 method B stiffness of the pair A–B (A is ``gear1``)."""
    m, an = ga["m"], ga["alpha"]
    beta = abs(ga["beta"])
    at = math.atan(math.tan(an) / math.cos(beta))
    bb = math.atan(math.tan(beta) * math.cos(at))
    internal = gb["internal"] or ga["internal"]
    za = -ga["z"] if ga["internal"] else ga["z"]
    zb = -gb["z"] if gb["internal"] else gb["z"]
    awt = solve_inv(inv(at) + 2 * math.tan(an) * (ga["x"] + gb["x"]) / (za + zb))
    aw = abs((za + zb) * m * math.cos(at) / (2 * math.cos(beta) * math.cos(awt)))

    def radii(g: dict[str, float], z: float) -> tuple[float, float]:
        d = abs(z) * m / math.cos(beta)
        sign = -1.0 if g["internal"] else 1.0
        da = d + sign * 2 * (m * (1 + g["x"]) + g["km"])
        return d * math.cos(at) / 2, da / 2

    rba, raa = radii(ga, za)
    rbb, rab = radii(gb, zb)
    ea, eb = math.sqrt(raa**2 - rba**2), math.sqrt(rab**2 - rbb**2)
    if ga["internal"]:
        raise ValueError("the shipped models name the internal gear second (gear2)")
    # A (the path start) where B's tip circle cuts the line of action; E at A's tip circle
    s_a = eb - aw * math.sin(awt) if internal else aw * math.sin(awt) - eb
    g_alpha = ea - s_a
    pbt = math.pi * m * math.cos(at) / math.cos(beta)
    b = min(ga["b"], gb["b"])
    eps_a = g_alpha / pbt
    eps_b = b * math.sin(beta) / (math.pi * m)
    # ISO 6336-1 method B: gear 1 the pinion (external, fewer teeth)
    if pinion_first and not gb["internal"] and gb["z"] < ga["z"]:
        (z1, x1), (z2, x2) = (zb, gb["x"]), (za, ga["x"])
    else:
        (z1, x1), (z2, x2) = (za, ga["x"]), (zb, gb["x"])
    zn1 = z1 / (math.cos(beta) * math.cos(bb) ** 2)
    zn2 = math.inf if ring_as_rack and internal else z2 / (math.cos(beta) * math.cos(bb) ** 2)
    q = (
        C[0]
        + C[1] / zn1
        + C[2] / zn2
        + C[3] * x1
        + C[4] * x1 / zn1
        + C[5] * x2
        + C[6] * x2 / zn2
        + C[7] * x1**2
        + C[8] * (x1 if c9_on_x1 else x2) ** 2
    )
    cth = 1 / q  # N/(mm·µm)
    cb_rack = (1 + 0.5 * (1.2 - H_FP)) * (1 - 0.02 * (20 - math.degrees(an)))
    cprime = cth * C_M * C_R * cb_rack * math.cos(beta)
    cga = cprime * (0.75 * eps_a + 0.25)
    return {
        "aw": aw,
        "awt": awt,
        "pbt": pbt,
        "g_alpha": g_alpha,
        "eps_a": eps_a,
        "eps_b": eps_b,
        "s_a": s_a,
        "b": b,
        "beta_b": bb,
        "zn1": zn1,
        "zn2": zn2,
        "q": q,
        "cth": cth,
        "C_B": cb_rack,
        "cprime": cprime,
        "cga": cga,
        "kb": cprime * b * 1e9,
        "kmean": cga * b * 1e9,  # N/(mm·µm) × b [m] × 1e9 = N/m
    }


def stiffness_at(r: dict[str, float], x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """k(x) [N/m] and the pair count with the entering pair at roll x from A (mid-face)."""
    g, p, b = r["g_alpha"], r["pbt"], r["b"]
    if r["eps_b"] == 0.0:
        two = x + p <= g
        return np.where(two, 1.75 * r["kb"], r["kb"]), np.where(two, 2, 1)
    t = math.tan(r["beta_b"])
    total = np.zeros_like(x)
    pairs = np.zeros_like(x, dtype=int)
    for j in range(-6, 7):
        # the line u(z) = x + j p + (z - b/2) tan β_b, z in [0, b], inside 0 <= u <= g
        lo = np.clip((0 - (x + j * p)) / t + b / 2, 0, b)
        hi = np.clip((g - (x + j * p)) / t + b / 2, 0, b)
        length = np.maximum(hi - lo, 0.0)
        total += length
        pairs += length > 0
    return r["kmean"] * total / (r["eps_a"] * b), pairs


MODELS = {
    "dtu500_planetary": dict(
        torques={"carrier": 2e5, "sun": -2e5 / 5.55}, speeds={"carrier": 20.0, "sun": 111.0}
    ),
    "saleh2017_planetary": dict(
        torques={"carrier": 1e6, "sun": -1e6 / 6}, speeds={"carrier": 10.0, "sun": 60.0}
    ),
    "nrel5mw_gearbox": dict(
        torques={"rotor": 3.94599e6, "generator": 3.94599e6 / 96.3542},
        speeds={"rotor": 2.0, "lss": 2.0},
    ),
    "cai_spur_pair": dict(
        torques={"input_shaft": 200.0, "output_shaft": 400.0}, speeds={"input_shaft": 100.0}
    ),
}


def main() -> None:
    import pinwind
    from pinwind.model.compliance import MeshCompliance

    jor = {"s_min": 0.043967, "s_switch": 0.064022, "s_max": 0.073488}
    print(
        "c′, c_γα [N/(mm·µm)] as Gear_Set.m reads ISO (a ring's z_n2 negative); c′b, c_γα b [N/m];"
    )
    print("Δpath: pinwind's ε_α, ε_β, path start and length against the recoding (over p_bt);")
    print("Δk run: max |k_run/k_rec − 1| over the run's samples, k_rec the recoded k(x) with")
    print("(a) a ring's z_n2 negative, (b) a ring as a rack, z_n2 = ∞, (c) as (b) with the file's")
    print("gear1 as ISO's gear 1 instead of the pinion; pairs: the run's mesh_pairs against the")
    print("recoded count; C9x1²: c′ with C9 x_1² (as Gear_Set.m prints it) over c′ − 1\n")
    print(
        f"{'model':20s} {'mesh':20s} {'c′':>6s} {'c_γα':>6s} {'ε_α':>7s} {'ε_β':>6s} "
        f"{'c′b':>10s} {'c_γα b':>10s} {'Δpath':>7s} {'Δk run a':>9s} {'b':>8s} {'c':>8s} "
        f"{'pairs':>5s} {'C9x1²':>7s}"
    )
    for name, run in MODELS.items():
        model = ROOT / "models" / f"{name}.urdf"
        gears, meshes = gears_of(model)
        gb = pinwind.load(model)
        res = pinwind.simulate(
            gb,
            duration=0.02,
            dt=2e-5,
            torques=run["torques"],
            initial_speeds=run["speeds"],
            meshes={m[0]: MeshCompliance(damping=0.0) for m in meshes},
        )
        for mname, a, b in meshes:
            r = recode(gears[a], gears[b])
            variants = (
                r,
                recode(gears[a], gears[b], ring_as_rack=True),
                recode(gears[a], gears[b], ring_as_rack=True, pinion_first=False),
            )
            r9 = recode(gears[a], gears[b], c9_on_x1=True)
            path = gb.mesh(mname).path
            dpath = max(
                abs(path.contact_ratio - r["eps_a"]),
                abs(path.overlap_ratio - r["eps_b"]),
                abs(path.start_roll_1 - r["s_a"]) / r["pbt"],
                abs(path.length - r["g_alpha"]) / r["pbt"],
            )
            s = res.mesh(mname)
            f, d = np.asarray(s.normal), np.asarray(s.deflection)
            x = np.asarray(s.contact_position) - r["s_a"]
            # A sample's force is the step's: at ρ∞ = 1 the stiffness of the pairs at the step's
            # start times the mean of the deflections at its two ends; samples whose step keeps
            # one flank in contact throughout.
            flank = np.asarray(s.flank)
            nxt = np.append(d[1:], np.nan)
            same = np.append(flank[:-1] == flank[1:], False)
            ok = (d > 1e-9) & (nxt > 1e-9) & same & (f > 0)
            k_run = f[ok] / (0.5 * (d[ok] + nxt[ok]))
            dk = []
            for v in variants:
                k_rec, n_rec = stiffness_at(v, x[ok])
                dk.append(float(np.max(np.abs(k_run / k_rec - 1))))
            pairs_ok = bool(np.all(np.asarray(s.pairs)[ok] == n_rec))
            print(
                f"{name:20s} {mname:20s} {r['cprime']:6.3f} {r['cga']:6.3f} "
                f"{r['eps_a']:7.4f} {r['eps_b']:6.3f} {r['kb']:10.4e} {r['kmean']:10.4e} "
                f"{dpath:7.0e} {dk[0]:9.1e} {dk[1]:8.1e} {dk[2]:8.1e} "
                f"{'same' if pairs_ok else 'DIFF':>5s} {r9['cprime'] / r['cprime'] - 1:+7.1e}"
                f"   ({int(ok.sum())} samples)"
            )
            if name == "dtu500_planetary" and mname == "planet1_ring":
                jor_rec = {
                    "s_min": r["s_a"],
                    "s_switch": r["s_a"] + r["g_alpha"] - r["pbt"],
                    "s_max": r["s_a"] + r["pbt"],
                }
                jor_line = ", ".join(f"{k} {jor_rec[k]:.6f} m ({v:.6f})" for k, v in jor.items())
                jor_k = (r["kb"], variants[1]["kb"])
    print(
        "\nDTU 500 kW planet/ring against Jørgensen 2014 §2.4 and Fig. 8 (in brackets):\n"
        f"{jor_line};"
    )
    print(
        f"c′b = {jor_k[0]:.3e} N/m (a), {jor_k[1]:.3e} N/m (b), their FEM single-tooth "
        "stiffness 'around 3.5e9 N/m'"
    )


if __name__ == "__main__":
    main()
