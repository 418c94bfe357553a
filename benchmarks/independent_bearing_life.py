"""Bearing lives of a logged 5 MW run recoded independently of pinwind's life code.

The run: the NREL 5 MW gearbox at rated (rotor 3 945 990 N·m at 12.1 rpm, generator held at
12.1 · 96.354 rpm, dt = 1e-4 s, 1 s logged at 1 kHz) with the rotor's steady hub loads on the
main shaft (thrust 700 kN, weight 1.1 MN, bending 5.34 MN·m at the rotor centre), as
``benchmarks/bearing_life.py``. This script then reads the log with ``pinwind.read_log`` (the
rows' forces and moments and the joints' speeds) and the rows' data from the model file's XML
(``xml.etree``), and computes every row's lives without pinwind's life code:

- ISO 281:2007 §7: P = F_r + Y1 F_a (F_a/F_r ≤ e) or X2 F_r + Y2 F_a with the row's factors
  (P = F_r for a toroidal row), F_r = |(F_u, F_w)|, F_a = |F_k|; P_eq the revolution-weighted
  p-th power mean (trapezoid rule over the samples), L10 = (C/P_eq)^p [10⁶ rev], L10h at the
  run's mean speed.
- ISO 281:2007 §9 (modified life, on a copy of the model with an assumed fatigue limit
  C_u = 0.12 C, a numeric e_C and the oil's data added, as ``pinwind life --model``): ν from
  ASTM D341's Walther line log log(ν + 0.7) = A − B log T through (40 °C, VG) and (100 °C, ν100)
  (slope B = 3.5 without ν100, pinwind's documented assumption), ν₁ = 45 000 n^−0.83 d_m^−0.5
  (n < 1000 r/min) or 4 500 n^−0.5 d_m^−0.5, κ = ν/ν₁ in [0.1, 4], roller
  a_ISO = 0.1 [1 − (1.5859 − c₂ κ^−c₃)(e_C C_u/P)^0.4]^−9.185 ≤ 50 (c₂ 1.3993, c₃ 0.054381 for
  κ < 0.4; c₂ 1.2348, c₃ 0.19087 below 1 and 0.071739 above), summed by Palmgren-Miner:
  L_nm = Σ n / Σ n (P/C)^p / a_ISO (a₁ = 1 at R = 90 %).
- The internal load distribution (Harris and Kotzalas 2007 §7.3; ISO/TS 16281's slicing): the
  geometry estimated from size_mm as docs/bearing_life.md says (D_we = 0.25 (D − d), L_we = 0.6 B
  or 0.4 B per row, Z = ⌊0.85 π d_m / D_we⌋, α 10° spherical, 15° tapered), rollers at
  ψ_j = 2πj/Z from u, 10 slices, q = δ^(10/9) at zero clearance (the loads do not depend on the
  contact stiffness then), solved for the ring's displacement by a damped Newton method of this
  file, every sample. Q_max = the largest roller's load, checked against Stribeck's
  4.08 F_r/Z (NSK, "Bearing internal load distribution and displacement", line contact). The
  load zone of row r: cos ψ_l = (c − s_r u_z tan α)/ρ (Harris's ε = (1 − cos ψ_l)/2; ε > 1:
  every roller in contact), the widest row's, smallest over the run.
- The reference life as docs/bearing_life.md documents it (ISO/TS 16281's roller formulas are
  not public, so this is pinwind's documented method recoded, not the TS): slice equivalent
  loads (Σ q⁴/Z)^(1/4) on the rotating ring, (Σ q^4.5/Z)^(1/4.5) on the stationary one (a
  planet's outer ring turns), D = Σ_k (q_ei/q_ci)^4.5 + (q_ee/q_ce)^4.5 with
  q_ci/q_ce = ((1 − γ)/(1 + γ))^(143/108), P_ref = (D/D_cal(1 N))^(1/4.5) with D_cal of a
  continuum of rollers under a unit radial load (Sjövall's integrals, by quadrature),
  L10r = (C/P_ref,eq)^p.

``pinwind life LOG --json`` (and ``--model`` the copy) gives pinwind's numbers; the table gives
each row's and their relative differences. The summary's "Q exact" and "P_ref exact" set the
recoding's Q_max and P_ref of every sample against pinwind's load distribution solved for that
exact sample (``load_distribution.distribute``, ``reference_load``): a run's lives group the
samples in cells of load direction 1/200 wide (docs/bearing_life.md), which is the whole of the
Q_max and L10r differences. The load zone agrees since pinwind takes the axial approach into
it (INP-B, pressed by the rotor's thrust, read 180° before; the recoding gives 360°, ε > 1).
Not recoded: rows with a clearance (the slices' contact stiffness is pinwind's rule; the 5 MW
rows have none), ISO 281 Table 13's e_C classes and Annex B's C_u from C₀ (not found in a
public source; numbers given instead), the ISO/TS 16281 roller formulas themselves.

Run:  python benchmarks/independent_bearing_life.py [--duration S]
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from scipy.integrate import quad

import pinwind
from pinwind.dynamics.load_distribution import distribute, estimate_geometry
from pinwind.dynamics.load_distribution import reference_load as pinwind_reference_load
from pinwind.errors import PinwindWarning
from pinwind.loads.hub_loads import constant_hub_load
from pinwind.units import rpm_to_rad_s

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "models" / "nrel5mw_gearbox.urdf"
RATED_TORQUE, ROTOR_RPM = 3945990.3245924464, 12.1
GENERATOR_RPM = -ROTOR_RPM * (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
HUB = [7.0e5, 0.0, -1.1e6, 0.0, 5.34e6, 0.0]
#: Oil and cleanliness added for the modified life (assumed): per bearing, else ``OTHERS``.
OILS = {
    "lss": {"lubricant_vg": "320", "temperature_C": "65", "viscosity_100C_cSt": "24",
            "contamination": "0.5"},
    "hss": {"viscosity_cSt": "50", "contamination": "0.8"},
}  # fmt: skip
OTHERS = {"contamination": "0.6"}
FATIGUE_SHARE = 0.12  # C_u = 0.12 C (assumed)
SLICES, LINE = 10, 10.0 / 9.0
TYPE_FACTORS = {"toroidal_roller": (math.inf, 0.0, 1.0, 0.0)}  # e, Y1, X2, Y2: P = F_r


def run(log: Path, duration: float) -> None:
    gearbox = pinwind.load(MODEL)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        pinwind.simulate(
            gearbox, duration=duration, dt=1e-4, torques={"rotor": RATED_TORQUE},
            speeds={"generator": rpm_to_rad_s(GENERATOR_RPM)},
            initial_speeds={"rotor": rpm_to_rad_s(ROTOR_RPM)},
            hub_loads=[constant_hub_load("lss", HUB, point=(0.0, 0.0, -1.9))],
            log=log, log_rate=1000.0, progress=False, keep="last",
        )  # fmt: skip


def model_rows(tree: ET.ElementTree) -> list[tuple[str, dict[str, str]]]:
    """(joint, the row's attributes over its bearing's) of every ``<row>``."""
    out = []
    for bearing in tree.getroot().iter("bearing"):
        for row in bearing.findall("row"):
            attrs = {k: v for k, v in bearing.attrib.items() if k != "joint"}
            attrs.update(row.attrib)
            attrs["own_factors"] = "e" in row.attrib
            out.append((bearing.get("joint", ""), attrs))
    return out


def variant(path: Path) -> None:
    """The model with C_u, oil and e_C added to every row (for the modified life)."""
    tree = ET.parse(MODEL)
    for bearing in tree.getroot().iter("bearing"):
        for key, value in OILS.get(bearing.get("joint", ""), OTHERS).items():
            bearing.set(key, value)
        for row in bearing.findall("row"):
            row.set("fatigue_limit_kN", repr(FATIGUE_SHARE * float(row.get("rating_c_kN", "0"))))
    tree.write(path)


def pinwind_life(log: Path, model: Path | None = None) -> dict[tuple[str, str], dict]:
    cmd = [sys.executable, "-m", "pinwind", "life", str(log), "--json"]
    if model is not None:
        cmd += ["--model", str(model)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return {(r["bearing"], r["row"]): r for r in json.loads(out)["rows"]}


def trapezoid(values: np.ndarray, time: np.ndarray) -> float:
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(time)))


def equivalent_load(attrs: dict, force: np.ndarray) -> np.ndarray:
    """ISO 281 P per sample [N] from the row's force (F_u, F_w, F_k)."""
    fr, fa = np.hypot(force[:, 0], force[:, 1]), np.abs(force[:, 2])
    if attrs["own_factors"]:
        e, y1, x2, y2 = (float(attrs[k]) for k in ("e", "y1", "x2", "y2"))
    else:
        e, y1, x2, y2 = TYPE_FACTORS[attrs["type"]]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(fa <= e * fr, fr + y1 * fa, x2 * fr + y2 * fa)


def walther(t_c: float, vg: float, nu100: float | None) -> float:
    """ν [mm²/s] at t_c [°C]: ASTM D341's line through (40 °C, VG) and (100 °C, ν100)."""

    def w(nu: float) -> float:
        return math.log10(math.log10(nu + 0.7))

    slope = 3.5 if nu100 is None else (w(vg) - w(nu100)) / math.log10(373.15 / 313.15)
    return 10 ** (10 ** (w(vg) - slope * math.log10((t_c + 273.15) / 313.15))) - 0.7


def a_iso_roller(kappa: np.ndarray, x: np.ndarray) -> np.ndarray:
    k = np.clip(kappa, 0.1, 4.0)
    c2 = np.where(k < 0.4, 1.3993, 1.2348)
    c3 = np.where(k < 0.4, 0.054381, np.where(k < 1.0, 0.19087, 0.071739))
    bracket = 1.0 - (1.5859 - c2 * k**-c3) * x**0.4
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(bracket > 0.0, 0.1 * np.abs(bracket) ** -9.185, 50.0)
    return np.minimum(a, 50.0)


def modified_life(attrs: dict, p: np.ndarray, omega: np.ndarray, time: np.ndarray) -> float:
    outer, bore, _ = (float(v) for v in attrs["size_mm"].split())
    dm = 0.5 * (outer + bore)
    if "viscosity_cSt" in attrs:
        nu = float(attrs["viscosity_cSt"])
    else:
        nu100 = attrs.get("viscosity_100C_cSt")
        nu = walther(
            float(attrs.get("temperature_C", 70)), float(attrs.get("lubricant_vg", 320)),
            None if nu100 is None else float(nu100),
        )  # fmt: skip
    n = np.abs(omega) * 60 / (2 * math.pi)
    with np.errstate(divide="ignore"):
        nu1 = np.where(n < 1000, 45000 * n**-0.83 * dm**-0.5, 4500 * n**-0.5 * dm**-0.5)
    c = float(attrs["rating_c_kN"]) * 1e3
    x = float(attrs["contamination"]) * float(attrs["fatigue_limit_kN"]) * 1e3 / p
    damage = np.abs(omega) * (p / c) ** (10 / 3) / a_iso_roller(nu / nu1, x)
    return trapezoid(np.abs(omega), time) / trapezoid(damage, time)


def geometry(kind: str, size_mm: str) -> dict:
    outer, bore, width = (float(v) * 1e-3 for v in size_mm.split())
    dwe, dm = 0.25 * (outer - bore), 0.5 * (outer + bore)
    rows = 2 if kind == "spherical_roller" else 1
    alpha = {"spherical_roller": 10.0, "tapered_roller": 15.0}.get(kind, 0.0)
    return {
        "kind": kind, "rows": rows, "alpha": math.radians(alpha), "dwe": dwe, "dm": dm,
        "length": (0.4 if rows == 2 else 0.6) * width,
        "z": math.floor(0.85 * math.pi * dm / dwe),
    }  # fmt: skip


def distribution(g: dict, force: np.ndarray, moment: np.ndarray):
    """Slice loads q (n, rows, Z, slices) [N], displacement (n, 5), relative residual (n,).

    Zero clearance: q = δ^(10/9) with a unit stiffness (the loads balance W whatever the
    stiffness). Only a cylindrical row carries tilt; α = 0 rows carry no axial load.
    """
    z, radius = g["z"], 0.5 * g["dm"]
    psi = 2 * np.pi * np.arange(z) / z
    zk = (np.arange(SLICES) + 0.5) / SLICES * g["length"] - 0.5 * g["length"]
    signs = (1.0, -1.0)[: g["rows"]]
    c, s = np.cos(psi)[:, None], np.sin(psi)[:, None]
    dirs = np.zeros((len(signs), z, SLICES, 5))
    for r, sign in enumerate(signs):
        ca, sa = math.cos(g["alpha"]), sign * math.sin(g["alpha"])
        dirs[r, ..., 0], dirs[r, ..., 1], dirs[r, ..., 2] = ca * c, ca * s, sa
        dirs[r, ..., 3] = -zk[None, :] * ca * s + radius * sa * s
        dirs[r, ..., 4] = zk[None, :] * ca * c - radius * sa * c
    free = (
        [0, 1] + ([2] if g["alpha"] else []) + ([3, 4] if g["kind"] == "cylindrical_roller" else [])
    )
    e = dirs[..., free].reshape(-1, len(free))
    ee = (e[:, :, None] * e[:, None, :]).reshape(len(e), -1)
    # the rollers balance the load on the shaft: Σ q ∂δ/∂u = −(F, M)
    w = -np.concatenate([force, moment[:, :2]], axis=1)[:, free]
    scale = np.maximum(np.linalg.norm(w, axis=1), 1e-300)
    w = w / scale[:, None]
    u = np.zeros((len(w), len(free)))
    u[:, :2] = w[:, :2] * (4.0 / (z * SLICES)) ** (1 / LINE)

    def residual(x, rows=slice(None)):
        d = x @ e.T
        return d, np.maximum(d, 0.0) ** LINE @ e - w[rows]

    delta, res = residual(u)
    stalled = np.zeros(len(w), dtype=bool)  # no step lowers the residual: no equilibrium
    for _ in range(80):
        norm = np.linalg.norm(res, axis=1)
        todo = np.flatnonzero((norm > 1e-13) & ~stalled)
        if len(todo) == 0:
            break
        slope = LINE * np.maximum(delta[todo], 0.0) ** (LINE - 1) * (delta[todo] > 0)
        jac = (slope @ ee).reshape(len(todo), len(free), len(free)) + 1e-14 * np.eye(len(free))
        step = np.linalg.solve(jac, -res[todo][..., None])[..., 0]
        lam = np.ones(len(todo))
        for _ in range(30):
            d_t, r_t = residual(u[todo] + lam[:, None] * step, todo)
            worse = np.linalg.norm(r_t, axis=1) > norm[todo]
            if not worse.any():
                break
            lam = np.where(worse, 0.5 * lam, lam)
        stalled[todo[worse]] = True
        u[todo] += lam[:, None] * step
        delta[todo], res[todo] = d_t, r_t
    q = (
        np.maximum(delta, 0.0).reshape((len(w),) + dirs.shape[:3]) ** LINE
        * scale[:, None, None, None]
    )
    full = np.zeros((len(w), 5))
    full[:, free] = u
    return q, full, np.linalg.norm(res, axis=1)


def widest_zone(g: dict, u: np.ndarray) -> np.ndarray:
    """cos ψ_l of the widest row, unclipped (< −1: every roller in contact)."""
    rho = np.hypot(u[:, 0], u[:, 1])
    cos_l = np.full(len(u), np.inf)
    for sign in (1.0, -1.0)[: g["rows"]]:
        cos_l = np.minimum(cos_l, -sign * u[:, 2] * math.tan(g["alpha"]) / rho)
    return cos_l


def reference_load(g: dict, q: np.ndarray, inner_rotates: bool) -> np.ndarray:
    """P_ref per sample [N] (docs/bearing_life.md's reference load)."""
    ki, ke = (4.0, 4.5) if inner_rotates else (4.5, 4.0)
    gamma = g["dwe"] * math.cos(g["alpha"]) / g["dm"]
    q_ci = ((1 - gamma) / (1 + gamma)) ** (143 / 108)  # q_ce = 1

    def equivalent(values: np.ndarray, k: float) -> np.ndarray:
        return (np.sum(values**k, axis=2) / g["z"]) ** (1 / k)

    damage = np.sum((equivalent(q, ki) / q_ci) ** 4.5 + equivalent(q, ke) ** 4.5, axis=(1, 2))
    # calibration: a continuum of rollers, unit radial load shared by the rows, zero clearance
    half = math.pi / 2

    def mean_power(k: float) -> float:
        return quad(lambda x: math.cos(x) ** k, -half, half)[0] / (2 * math.pi)

    q_max = 1.0 / (g["rows"] * g["z"] * SLICES * mean_power(LINE + 1) * math.cos(g["alpha"]))
    slice_cal = (mean_power(LINE * ki) ** (1 / ki) * q_max / q_ci) ** 4.5 + (
        mean_power(LINE * ke) ** (1 / ke) * q_max
    ) ** 4.5
    return (damage / (g["rows"] * SLICES * slice_cal)) ** (1 / 4.5)


def self_checks() -> str:
    """The recoded distribution against Harris's continuum at two public points (NSK catalogue,
    "Bearing internal load distribution and displacement", line contact, zero clearance): a pure
    radial load gives Q_max = 4.08 F_r/Z (Stribeck), and a single angular row with
    F_a = 1.260 F_r tan α has ε = 0.5 (180°) and Q_max = 4.08 F_r/(Z cos α)."""
    half = math.pi / 2
    j_r = quad(lambda x: math.cos(x) ** (LINE + 1), -half, half)[0] / (2 * math.pi)
    out = [f"1/J_r(0.5) = {1 / j_r:.4f}"]
    g = geometry("cylindrical_roller", "1750 1250 375")
    q, _, _ = distribution(g, np.array([[-1.0e5, 0.0, 0.0]]), np.zeros((1, 3)))
    out.append(f"radial, Z = {g['z']}: Q_max Z/F_r = {q.sum(axis=3).max() * g['z'] / 1e5:.4f}")
    g = geometry("tapered_roller", "1750 1250 375")
    f_r = 1.0e5
    f_a = 1.260 * f_r * math.tan(g["alpha"])
    q, u, _ = distribution(g, np.array([[-f_r, 0.0, -f_a]]), np.zeros((1, 3)))
    cos_l = float(widest_zone(g, u)[0])
    ratio = q.sum(axis=3).max() * g["z"] * math.cos(g["alpha"]) / f_r
    out.append(
        f"tapered, F_a = 1.26 F_r tan α, Z = {g['z']}: ε = {0.5 * (1 - cos_l):.4f}, "
        f"Q_max Z cos α/F_r = {ratio:.4f}"
    )
    return "; ".join(out)


def rel(a: float | None, b: float | None) -> float:
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
        return math.nan
    return b / a - 1.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=1.0, help="simulated time [s]")
    args = parser.parse_args()
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        log, copy = Path(tmp) / "nrel5mw_rated_hub.mcap", Path(tmp) / "with_oil.urdf"
        run(log, args.duration)
        variant(copy)
        theirs, theirs_nm = pinwind_life(log), pinwind_life(log, copy)
        res = pinwind.read_log(log)
        rows, rows_nm = (
            model_rows(ET.parse(MODEL)),
            dict(((j, a["name"]), a) for j, a in model_rows(ET.parse(copy))),
        )
    t = res.time
    print(f"NREL 5 MW at rated with hub loads, {args.duration:g} s logged at 1 kHz")
    head = (
        f"{'row':24} {'L10h pinwind':>13} {'ΔL10h':>9} {'ΔL_nm':>9} {'ΔL10r':>9} "
        f"{'Q_max kN':>9} {'ΔQ_max':>9} {'zone° pinwind':>13} {'recoded':>8} {'ε min':>6}"
    )
    print(head)
    worst: dict[str, float] = {}
    for joint, attrs in rows:
        name = attrs["name"]
        ours = theirs[(joint, name)]
        series = res.row(f"{joint}.{name}")
        omega = np.abs(res.joint(joint).speed)
        p = equivalent_load(attrs, series.force)
        revs = trapezoid(omega, t)
        p_eq = (trapezoid(p ** (10 / 3) * omega, t) / revs) ** 0.3
        c = float(attrs["rating_c_kN"]) * 1e3
        l10 = (c / p_eq) ** (10 / 3)
        hours = l10 * 1e6 / (revs / (2 * math.pi) / (t[-1] - t[0]) * 3600)
        lnm = modified_life(rows_nm[(joint, name)], p, omega, t)
        d = {
            "P_eq": rel(ours["equivalent_load_N"], p_eq),
            "L10": rel(ours["l10_million_rev"], l10),
            "L10h": rel(ours["l10_h"], hours),
            "L_nm": rel(theirs_nm[(joint, name)]["lnm_million_rev"], lnm),
        }
        g = geometry(attrs["type"], attrs["size_mm"])
        q, u, residual = distribution(g, series.force, series.moment)
        zone = cos_l = math.nan
        if residual.max() < 1e-9:
            q_max = float(q.sum(axis=3).max())
            cos_l = float(np.max(widest_zone(g, u)))
            zone = math.degrees(2 * math.acos(max(min(cos_l, 1.0), -1.0)))
            p_ref = reference_load(g, q, inner_rotates=not joint.startswith("stage"))
            p_ref_eq = (trapezoid(p_ref ** (10 / 3) * omega, t) / revs) ** 0.3
            d["L10r"] = rel(ours["l10r_million_rev"], (c / p_ref_eq) ** (10 / 3))
            d["Q_max"] = rel(ours["max_element_load_N"], q_max)
            d["zone"] = rel(ours["load_zone_min_deg"], zone)
            # pinwind's own solve of each exact sample (its run groups the samples in cells of
            # load direction 1/200 wide): the recoding's Q_max against it isolates the grouping
            size = tuple(float(v) * 1e-3 for v in attrs["size_mm"].split())
            inner = "outer" if joint.startswith("stage") else "inner"
            theirs_geometry = estimate_geometry(attrs["type"], size, rotating=inner)
            exact = distribute(
                theirs_geometry, -np.concatenate([series.force, series.moment[:, :2]], axis=1)
            )
            q_exact = q.sum(axis=3).max(axis=(1, 2)) / exact.max_element_load - 1
            p_exact = p_ref / pinwind_reference_load(theirs_geometry, exact.slice_loads) - 1
            d["Q exact"] = float(np.max(np.abs(q_exact)))
            d["P_ref exact"] = float(np.max(np.abs(p_exact)))
        else:  # a single tapered row below its induced thrust: no equilibrium (nor pinwind's)
            d["L10r"] = d["Q_max"] = math.nan
            assert ours["l10r_million_rev"] is None and ours["max_element_load_N"] is None
        for key, value in d.items():
            if math.isfinite(value):
                worst[key] = max(worst.get(key, 0.0), abs(value))
        q_pw = ours["max_element_load_N"]
        zone_pw = ours["load_zone_min_deg"]
        print(
            f"{joint + '/' + name:24} {ours['l10_h']:13.5g} {d['L10h']:+9.1e} {d['L_nm']:+9.1e} "
            f"{d['L10r']:+9.1e} {(q_pw or math.nan) / 1e3:9.2f} {d['Q_max']:+9.1e} "
            f"{zone_pw if zone_pw is not None else math.nan:13.1f} {zone:8.1f} "
            f"{0.5 * (1 - cos_l):6.3f}"
        )
    print("largest |relative difference|: " + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))
    print(
        "(Q exact, P_ref exact: the recoding's Q_max and P_ref per sample against pinwind's"
        " distribution solved for each exact sample rather than per cell of load direction)"
    )
    print("self-checks of the recoding (4.08 by Harris): " + self_checks())
    print(f"wall time {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
