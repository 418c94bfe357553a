"""Friction losses and efficiency of a logged 5 MW run recoded independently of pinwind's loss code.

The run: ``models/nrel5mw_gearbox.urdf`` at rated (rotor 3 945 990 N·m at 12.1 rpm, the
generator held at 12.1 rpm times the train's ratio), every mesh compliant with
``friction_coefficient="iso14179"`` (VG 320 at 70 °C, Ra 0.5 µm, mineral oil) and every bearing
with ``friction_model="iso_tr_14179_2"`` (VG 320 at 70 °C), 0.4 s at dt = 5e-5 s from the static
start, every step logged. This script reads the log with ``pinwind.read_log`` and the gear and
row data from the model file's XML (``xml.etree``) and recodes, without pinwind's loss code:

- the oil: ISO 3448 VG 320 (ν40 = 320 mm²/s), Walther's line of ASTM D341,
  log log(ν + 0.7) = A − B log T (T in K, B = 3.5: docs/losses.md's slope without ν100), as
  the README of github.com/maercaestro/megat-viscosity states it; ρ = ρ15 (1 − 0.00065 (θ − 15 °C)),
  ρ15 = 880 kg/m³ (docs/losses.md's DIN 51757 form: not read in a source), η = ν ρ;
- each mesh's geometry from the involute (ISO 21771, an internal gear's z negative):
  inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2) (the centre distances come out as the
  model's), tip radii r ± m_n (1 + x) + k m_n, the path of contact, ε_α and its two parts, β_b;
- ISO/TR 14179-2's μ_mz after Schlenk, ρ_redC and Ohlendorf's H_V as a public MATLAB loss
  calculation (``Getrieberechnung_Einstufig.m``, after Niemann 2003 and the FZG formula
  collection 2020) writes them:
  μ_mz = 0.048 (F_bt/b / (v_ΣC ρ_redC))^0.2 η^−0.05 Ra^0.25 X_L [N, mm, m/s, mm, mPa·s, µm],
  v_ΣC = 2 v_t sin α_wt, ρ_redC = r_w1 sin α_wt u / ((u + 1) cos β_b),
  H_V = π (u + 1)/(z1 u cos β_b) (1 − ε_α + ε_1² + ε_2²); and the sliding integral that
  bracket stands for, 2 ∫ s(y)|y| dy over the path (s = ½ where two pairs share the load),
  by the midpoint rule; μ_mz at each sample from the mesh's F_bt (``mesh_normal``) and the
  gears' spins relative to the carrier (the joints' speeds summed along each gear's chain),
  v_ΣC = c_v |ω_2 − ω_1|, at most 0.2 (docs/losses.md);
- the flank friction power at each sample: the pairs of the loaded flank at their roll
  positions (the entering pair's ``mesh_contact_position``, the others a base pitch apart
  inside the path), sliding at v_s(x) = v_s,entering + ω_rel (x − x_entering) (``mesh_sliding_
  velocity`` carries the bodies' translation, which moves all pairs alike), the entering pair
  carrying ``mesh_single_tooth_force`` and the others the rest; the helical stage along its
  inclined contact lines (docs/losses.md "Helical pairs"). pinwind's law, found from the run's
  friction force and then read in its code: each pair's friction takes the sign σ_j of its
  sliding in rigid rolling (sgn of ω_rel (x_j − x_P)), not of its sliding, and the power is
  μ Σ F_j σ_j v_s,j, which is below zero where the bodies' vibration reverses the sliding near
  the pitch point (column "P < 0"); "opposing" is how much more a friction opposing each pair's
  own sliding would take;
- the mean μ_mz P H_V, P = F_bt v_t cos α_wt (the after-the-run estimate);
- each row's Palmgren moment as docs/losses.md gives it (the viscous branch
  M0 = 10⁻⁷ f0 (ν n)^(2/3) d_m³ as github.com/cfernandesFEUP/Machine-Elements-Animations-Figures
  ``figures/RB_L3_Palmgren.py`` writes it; the low-speed branch 160·10⁻⁷ f0 d_m³, the larger of
  the two; M1 = f1 P1 d_m, P1 by type and f0, f1 from docs/losses.md's table, their sources not
  found), P1 from the row's force of the step before, at the step's mid speed linearised about
  its start, summed per bearing, power M |ω|;
- efficiency: P_in = Σ max(τ ω, 0) over the revolute joints, the losses per stage
  (docs/losses.md "Per stage"), η = 1 − L/P over the second half, and the energy ledger.

It compares them with the run's series, with ``pinwind.analysis.efficiency`` (and its
``source="estimate"``) and with ``python -m pinwind efficiency`` at the same point, and prints
relative differences (recoding/pinwind − 1). Not recoded: the flank force the step takes μ_mz
and the friction at (a prediction at the step's start, not logged: μ_mz is taken at the sample's
F_bt, hence "μ" and "per sample"); the back flank's friction where both flanks touch (its pairs'
positions are not logged: the mesh rows compare the one-flank samples); ISO/TR 14179-2's no-load
losses (not built in pinwind either); SKF's 2018 bearing model (not what pinwind uses).

Run:  python benchmarks/independent_losses.py [--duration S] [--dt S]
"""

from __future__ import annotations

import argparse
import csv
import math
import re
import subprocess
import sys
import tempfile
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import pinwind
from pinwind.analysis.efficiency import efficiency
from pinwind.errors import PinwindWarning
from pinwind.losses.oil import Lubricant

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "models" / "nrel5mw_gearbox.urdf"
RPM = 2.0 * math.pi / 60.0
RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # Nejad et al. 2016: 97.0
ROTOR_RPM = 12.1
RATED_TORQUE = 5e6 / (ROTOR_RPM * RPM)  # [N·m]
VG, OIL_C, RA_UM = 320, 70.0, 0.5
MESH_OIL = (
    f'type="compliant" friction_coefficient="iso14179" lubricant_vg="{VG}" '
    f'temperature_C="{OIL_C:g}" roughness_um="{RA_UM:g}"'
)
BEARING_OIL = f'friction_model="iso_tr_14179_2" lubricant_vg="{VG}" temperature_C="{OIL_C:g}"'
# docs/losses.md, "Bearing friction": (f0, f1) by type
PALMGREN = {
    "deep_groove_ball": (1.75, 0.0007),
    "angular_contact_ball": (2.0, 0.001),
    "cylindrical_roller": (2.5, 0.000275),
    "tapered_roller": (4.0, 0.0004),
    "spherical_roller": (5.0, 0.0004),
    "toroidal_roller": (5.0, 0.0004),
}
CONTACT_ANGLE_DEG = {"spherical_roller": 10.0, "tapered_roller": 15.0}  # docs/bearing_life.md
MU_MAX = 0.2


def model_text() -> str:
    """The shipped model with every mesh compliant on μ_mz and every bearing on Palmgren."""
    text = re.sub(r"<mesh (name=\"[^\"]+\" gear1=\"[^\"]+\" gear2=\"[^\"]+\") />",
                  rf"<mesh \1 {MESH_OIL} />", MODEL.read_text())  # fmt: skip
    return text.replace("<bearing joint=", f"<bearing {BEARING_OIL} joint=")


def run(model: Path, log: Path, duration: float, dt: float) -> None:
    gearbox = pinwind.load(model)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        pinwind.simulate(
            gearbox, duration=duration, dt=dt, torques={"rotor": RATED_TORQUE},
            speeds={"generator": -ROTOR_RPM * RPM * RATIO},
            initial_speeds={"rotor": ROTOR_RPM * RPM}, log=log, progress=False, keep="last",
        )  # fmt: skip


# ---------------------------------------------------------------- the oil


def kinematic_viscosity(t_c: float) -> float:
    """ν [mm²/s] at t_c [°C]: Walther's line through (40 °C, VG) with slope 3.5 (ASTM D341)."""

    def w(nu: float) -> float:
        return math.log10(math.log10(nu + 0.7))

    return 10 ** (10 ** (w(VG) - 3.5 * math.log10((t_c + 273.15) / 313.15))) - 0.7


def density(t_c: float) -> float:
    return 880.0 * (1.0 - 0.00065 * (t_c - 15.0))


# ---------------------------------------------------------------- mesh geometry


def inv(a: float) -> float:
    return math.tan(a) - a


def inv_inverse(y: float) -> float:
    a = 0.5
    for _ in range(60):
        a -= (inv(a) - y) / math.tan(a) ** 2
    return a


@dataclass
class Pair:
    name: str
    z1: int
    z2: int  # negative for a ring
    b: float  # face width [m]
    alpha_wt: float
    beta_b: float
    rb1: float
    rw1: float
    rw2: float  # |r_w2|
    p_bt: float
    x_pitch: float  # roll distance from gear A's base tangency to the pitch point [m]
    x_start: float  # roll distance of the path's start A [m]
    g_alpha: float
    eps_alpha: float
    eps_1: float
    eps_2: float
    delta: float  # b tan β_b [m]
    rho_red: float  # ρ_redC [m]
    h_v: float  # Ohlendorf's closed form
    h_v_integral: float  # the same sliding integral by quadrature (equal shares in double contact)


def pair_geometry(name: str, g1: dict, g2: dict) -> Pair:
    m_n = float(g1["module_mm"]) * 1e-3
    alpha_n = math.radians(float(g1.get("pressure_angle_deg", "20")))
    beta = abs(math.radians(float(g1.get("helix_angle_deg", "0"))))
    z1 = int(g1["teeth"]) * (-1 if g1.get("internal") == "true" else 1)
    z2 = int(g2["teeth"]) * (-1 if g2.get("internal") == "true" else 1)
    x1, x2 = float(g1.get("profile_shift", "0")), float(g2.get("profile_shift", "0"))
    alpha_t = math.atan(math.tan(alpha_n) / math.cos(beta))
    m_t = m_n / math.cos(beta)
    alpha_wt = inv_inverse(inv(alpha_t) + 2 * math.tan(alpha_n) * (x1 + x2) / (z1 + z2))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))

    def circles(z: int, x: float, g: dict) -> tuple[float, float]:
        d = abs(z) * m_t
        k_mn = float(g.get("tip_alteration_mm", "0")) * 1e-3
        d_a = d - 2 * (m_n * (1 + x) + k_mn) if z < 0 else d + 2 * (m_n * (1 + x) + k_mn)
        return d * math.cos(alpha_t) / 2, d_a / 2  # r_b, r_a

    rb1, ra1 = circles(z1, x1, g1)
    rb2, ra2 = circles(z2, x2, g2)
    rw1, rw2 = rb1 / math.cos(alpha_wt), rb2 / math.cos(alpha_wt)
    part1 = math.sqrt(ra1**2 - rb1**2) - rb1 * math.tan(alpha_wt)  # A's tip side of the pitch point
    if z2 > 0:
        part2 = math.sqrt(ra2**2 - rb2**2) - rb2 * math.tan(alpha_wt)
    else:  # the ring's tip: inside its pitch circle
        part2 = rb2 * math.tan(alpha_wt) - math.sqrt(ra2**2 - rb2**2)
    p_bt = math.pi * m_t * math.cos(alpha_t)
    g_alpha = part1 + part2
    x_pitch = rb1 * math.tan(alpha_wt)
    u = z2 / z1
    eps_1, eps_2 = part1 / p_bt, part2 / p_bt
    eps_alpha = eps_1 + eps_2
    h_v = math.pi * (u + 1) / (z1 * u * math.cos(beta_b)) * (1 - eps_alpha + eps_1**2 + eps_2**2)
    rho_red = rw1 * math.sin(alpha_wt) * u / ((u + 1) * math.cos(beta_b))
    # 2 ∫ s(y) |y| dy over the path [−ε_2, ε_1] in base pitches, s = ½ in the double zones
    n = 2_000_000
    y = -eps_2 + (np.arange(n) + 0.5) * eps_alpha / n
    s = np.where((y < -eps_2 + eps_alpha - 1) | (y > eps_1 - (eps_alpha - 1)), 0.5, 1.0)
    bracket = 2 * float(np.sum(s * np.abs(y))) * eps_alpha / n
    h_v_integral = math.pi * (u + 1) / (z1 * u * math.cos(beta_b)) * bracket
    b = min(float(g1["face_width_mm"]), float(g2["face_width_mm"])) * 1e-3
    return Pair(
        name, z1, z2, b, alpha_wt, beta_b, rb1, rw1, rw2, p_bt, x_pitch, x_pitch - part2,
        g_alpha, eps_alpha, eps_1, eps_2, b * math.tan(beta_b), rho_red, h_v, h_v_integral,
    )  # fmt: skip


def mu_mz(pair: Pair, f_bt: np.ndarray, v_sum: np.ndarray, eta_mpas: float) -> np.ndarray:
    """ISO/TR 14179-2 μ_mz (Schlenk), the standard's units; 0 without load, at most 0.2."""
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = (
            0.048
            * (np.maximum(f_bt, 0.0) / (pair.b * 1e3) / (v_sum * pair.rho_red * 1e3)) ** 0.2
            * eta_mpas**-0.05
            * RA_UM**0.25
        )  # X_L = 1, mineral oil
    return np.minimum(np.nan_to_num(mu), MU_MAX)


def _abs_linear_integral(c: float, slope: float, a: float, b: float) -> float:
    """∫_a^b |c + slope (y − a)| dy, a ≤ b."""
    s0, s1 = c, c + slope * (b - a)
    if abs(slope) < 1e-300:
        return abs(c) * (b - a)
    lo, hi = min(s0, s1), max(s0, s1)
    if lo >= 0:
        area = (hi * hi - lo * lo) / 2
    elif hi <= 0:
        area = (lo * lo - hi * hi) / 2
    else:
        area = (lo * lo + hi * hi) / 2
    return area / abs(slope)


def _signed_integral(c: float, slope: float, a: float, b: float, x_p: float, w: float) -> float:
    """∫_a^b sgn(w (y − x_P)) (c + slope (y − a)) dy."""

    def lin(lo: float, hi: float) -> float:
        return (c + slope * ((lo + hi) / 2 - a)) * (hi - lo)

    total = 0.0
    for lo, hi, side in ((a, min(b, x_p), -1.0), (max(a, x_p), b, 1.0)):
        if hi > lo:
            total += np.sign(w) * side * lin(lo, hi)
    return total


def pair_sums(pair: Pair, k: int, x_ent, v_ent, f_n, f_ent, pairs, w_sig) -> np.ndarray:
    """Sums over the pairs in contact of the loaded flank at sample k.

    Returns (Σ_j F_j |v_s,j|, Σ_j F_j σ_j v_s,j, Σ_j F_j σ_j): the friction power per unit μ of
    a friction opposing each pair's sliding, the same with the sign σ_j of the sliding in rigid
    rolling (sgn of the relative spin times the pair's offset from the pitch point), and the
    friction force per unit μ with that sign. The pairs sit a base pitch apart inside the path;
    a pair at x slides at v_s(x) = v_s,entering + w_sig (x − x_entering) (the gears' relative
    spin times the distance along the line of action; a translation of the bodies moves all
    pairs alike). Spur: the entering pair carries ``single_tooth_force``, the others the rest
    equally. Helical: each pair's line covers [x − Δ/2, x + Δ/2] ∩ path, the load
    F_bt / cos β_b uniform along all lines (docs/losses.md "Helical pairs").
    """
    lo, hi = pair.x_start, pair.x_start + pair.g_alpha
    x_e, v_e, w = x_ent[k], v_ent[k], w_sig[k]
    if pair.beta_b == 0.0:
        xs = [x_e]
        for j in (1, -1, 2, -2, 3, -3):
            x = x_e + j * pair.p_bt
            if lo - 1e-9 <= x <= hi + 1e-9:
                xs.append(x)
        xs = xs[: max(int(round(pairs[k])), 1)]
        rest = (f_n[k] - f_ent[k]) / max(len(xs) - 1, 1)
        shares = [f_ent[k]] + [rest] * (len(xs) - 1)
        vs = [v_e + w * (x - x_e) for x in xs]
        signs = [np.sign(w * (x - pair.x_pitch)) for x in xs]
        return np.array([
            sum(f * abs(v) for f, v in zip(shares, vs, strict=True)),
            sum(f * g * v for f, g, v in zip(shares, signs, vs, strict=True)),
            sum(f * g for f, g in zip(shares, signs, strict=True)),
        ])  # fmt: skip
    sums = np.zeros(3)
    den = 0.0
    for j in range(-4, 5):
        c = x_e + j * pair.p_bt
        a, b = max(c - pair.delta / 2, lo), min(c + pair.delta / 2, hi)
        if b <= a:
            continue
        v_a = v_e + w * (a - x_e)
        sums += [
            _abs_linear_integral(v_a, w, a, b),
            _signed_integral(v_a, w, a, b, pair.x_pitch, w),
            _signed_integral(1.0, 0.0, a, b, pair.x_pitch, w),
        ]
        den += b - a
    return sums * f_n[k] / math.cos(pair.beta_b) / den if den > 0 else sums


# ---------------------------------------------------------------- bearings


def friction_load(kind: str, f_r: np.ndarray, f_a: np.ndarray) -> np.ndarray:
    """P1 of M1 (docs/losses.md): F_r, or max(0.8 F_a cot α, F_r), or max(3 F_a − 0.1 F_r, F_r)."""
    if kind in ("spherical_roller", "tapered_roller"):
        cot = 1.0 / math.tan(math.radians(CONTACT_ANGLE_DEG[kind]))
        return np.maximum(0.8 * np.abs(f_a) * cot, f_r)
    if kind == "deep_groove_ball":
        return np.maximum(3 * np.abs(f_a) - 0.1 * f_r, f_r)
    return f_r


def palmgren_moment(row: dict, nu: float, n_rpm: np.ndarray, p1: np.ndarray) -> np.ndarray:
    """M0 + M1 [N·m] of one row at n [rpm] and P1 [N]."""
    f0, f1 = PALMGREN[row["type"]]
    outer, bore, _ = (float(v) for v in row["size_mm"].split())
    d_m = (outer + bore) / 2
    m0 = 1e-7 * f0 * np.maximum((nu * n_rpm) ** (2 / 3), 160.0) * d_m**3
    return (m0 + f1 * p1 * d_m) * 1e-3


def model_rows(root: ET.Element) -> dict[str, list[dict]]:
    out: dict[str, list[dict]] = {}
    for bearing in root.iter("bearing"):
        out[bearing.get("joint", "")] = [
            {**bearing.attrib, **row.attrib} for row in bearing.findall("row")
        ]
    return out


# ---------------------------------------------------------------- the comparison


def rel(a: float, b: float) -> float:
    return a / b - 1.0 if b != 0 else (0.0 if a == 0 else math.inf)


@dataclass
class MeshRecoding:
    """One mesh's recoded series and the checks against the run's, over the second half."""

    pair: Pair
    loss: np.ndarray  # Σ_j μ_mz F_j σ_j v_s,j at each sample [W]
    mean_mu: float
    estimate_closed: float  # mean μ_mz P H_V, Ohlendorf's closed form [W]
    estimate_integral: float  # mean μ_mz P H_V, the sliding integral [W]
    rigid: float  # mean Σ_j μ_mz F_j ω_rel |x_j − x_P| [W]
    one_flank: float  # share of samples with one flank loaded
    one_flank_theirs: float  # mean of the run's series on those samples [W]
    one_flank_ours: float
    kinematics: float  # max |μ_step Σ F_j σ_j v_j − P| / mean P on those samples
    mu_ratio: float  # mean μ_mz / mean μ_step − 1
    negative: float  # −Σ min(P, 0) / Σ P: the run's friction power below zero
    opposing: float  # Σ μ F_j |v_j| / Σ μ F_j σ_j v_j − 1
    per_sample: float  # max |recoded − run| / mean, one-flank samples
    cycles: float  # mesh cycles in the window


def recode_mesh(res, i: int, pair: Pair, spins, planet_first: bool | None, eta_mpas: float):
    """The mesh's μ_mz, friction power and μ_mz P H_V from the run's series (module docstring).

    spins: (ω_1, ω_2) of gear 1 and 2 relative to the carrier [rad/s]; planet_first: which gear
    is the planet (None: a parallel pair), for the estimate's pitch-line speed.
    """
    n = len(res.time)
    half = slice(n // 2, None)
    w1, w2 = spins
    w_rel = np.abs(w1 - w2)
    c_v = 2 * math.sin(pair.alpha_wt) * pair.rw1 * pair.rw2
    c_v /= pair.rw2 + pair.rw1 if pair.z2 > 0 else pair.rw2 - pair.rw1
    f_bt = res.mesh_normal[:, i]
    mu = mu_mz(pair, f_bt, c_v * w_rel, eta_mpas)
    x_e, v_e = res.mesh_contact_position[:, i], res.mesh_sliding_velocity[:, i]
    f_ent, pairs = res.mesh_single_tooth_force[:, i], res.mesh_pairs[:, i]
    w_sig = np.sign(np.sum(v_e * (x_e - pair.x_pitch))) * w_rel
    sums = np.array([pair_sums(pair, k, x_e, v_e, f_bt, f_ent, pairs, w_sig) for k in range(n)])
    v_rigid = w_sig * (x_e - pair.x_pitch)
    rigid = np.array([pair_sums(pair, k, x_e, v_rigid, f_bt, f_ent, pairs, w_sig)[0]
                      for k in range(n)])  # fmt: skip
    loss = mu * sums[:, 1]
    theirs = res.mesh_friction_power[:, i]
    one = (res.mesh_normal_front[:, i] == 0) | (res.mesh_normal_back[:, i] == 0)
    sel = one.copy()
    sel[: n // 2] = False
    ok = sel & (np.abs(sums[:, 2]) > 0.2 * f_bt) & (f_bt > 0)
    mu_step = np.abs(res.mesh_friction_force[:, i]) / np.where(ok, np.abs(sums[:, 2]), 1.0)
    mean = np.mean(theirs[half])
    # the estimate: v_t at the planet's working pitch circle (gear 1's of a parallel pair)
    v_t = pair.rw2 * np.abs(w2) if planet_first is False else pair.rw1 * np.abs(w1)
    mu_est = mu_mz(pair, f_bt, 2 * v_t * math.sin(pair.alpha_wt), eta_mpas)
    p_mesh = f_bt * v_t * math.cos(pair.alpha_wt)
    return MeshRecoding(
        pair=pair,
        loss=loss,
        mean_mu=float(np.mean(mu[half])),
        estimate_closed=float(np.mean((p_mesh * mu_est * pair.h_v)[half])),
        estimate_integral=float(np.mean((p_mesh * mu_est * pair.h_v_integral)[half])),
        rigid=float(np.mean((mu * rigid)[half])),
        one_flank=float(np.mean(one[half])),
        one_flank_theirs=float(np.mean(theirs[sel])),
        one_flank_ours=float(np.mean(loss[sel])),
        kinematics=float(np.max(np.abs(mu_step[ok] * sums[ok, 1] - theirs[ok])) / mean),
        mu_ratio=float(np.mean(mu[ok]) / np.mean(mu_step[ok]) - 1),
        negative=float(-np.sum(np.minimum(theirs[half], 0)) / np.sum(theirs[half])),
        opposing=float(np.mean((mu * sums[:, 0])[half]) / np.mean(loss[half]) - 1),
        per_sample=float(np.max(np.abs(loss[sel] - theirs[sel])) / mean),
        cycles=float(abs(np.trapezoid(w1[half], res.time[half])) * abs(pair.z1) / (2 * math.pi)),
    )


def recode_bearing(res, name: str, rows: list[dict], nu: float) -> np.ndarray:
    """The bearing's friction power [W] at each sample: its rows' Palmgren moments summed.

    The step's moment: at its weighted speed (the trapezoidal rule's mid-step speed),
    linearised about its start (M0 ∝ ω^(2/3) on the viscous branch), P1 from the step before;
    its power at the sample's speed.
    """
    omega = res.speed[:, res.joint_names.index(name)]
    n_rpm = np.abs(omega) / RPM
    mid = (omega + np.concatenate([omega[1:], omega[-1:]])) / 2
    moment = np.zeros(len(omega))
    for row in rows:
        r = res.row_names.index(f"{name}.{row['name']}")
        p1 = friction_load(row["type"], res.row_radial[:, r], res.row_axial[:, r])
        p1 = np.concatenate([[0.0], p1[:-1]])
        m0 = palmgren_moment(row, nu, n_rpm, np.zeros_like(p1))
        slope = np.where(nu * n_rpm >= 2000.0, 2 / 3 * m0 / np.maximum(np.abs(omega), 1e-300), 0.0)
        moment += palmgren_moment(row, nu, n_rpm, p1) + slope * (np.abs(mid) - np.abs(omega))
    return moment * np.abs(omega)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=0.4)
    parser.add_argument("--dt", type=float, default=5e-5)
    args = parser.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="independent_losses_"))
    model, log = tmp / "nrel5mw_losses.urdf", tmp / "run.mcap"
    model.write_text(model_text())
    run(model, log, args.duration, args.dt)
    res = pinwind.read_log(log)
    t = res.time
    half = slice(len(t) // 2, None)
    root = ET.parse(model).getroot()
    gears = {g.get("name", ""): dict(g.attrib) for g in root.iter("gear")}
    meshes = [dict(m.attrib) for m in root.iter("mesh")]
    rows = model_rows(root)
    joints = {j.get("name", ""): j for j in root.iter("joint")}
    parent = {n: j.find("parent").get("link") for n, j in joints.items()}  # type: ignore[union-attr]
    child = {j.find("child").get("link"): n for n, j in joints.items()}  # type: ignore[union-attr]
    speed = {n: res.speed[:, i] for i, n in enumerate(res.joint_names)}

    def spin(link: str) -> np.ndarray:
        """A link's spin about z [rad/s]: its revolute joints' speeds along the chain."""
        total = np.zeros(len(t))
        while link in child:
            total = total + speed.get(child[link], 0.0)
            link = parent[child[link]]
        return total

    def carrier_of(gear: dict) -> str | None:
        """The carrier link of a planet (a gear turning on a joint of a turning body)."""
        joint = child.get(gear["link"], "")
        if joints[joint].get("type") == "continuous" and parent[joint] != "housing":
            return parent[joint]
        return None

    nu = kinematic_viscosity(OIL_C)
    eta = nu * 1e-6 * density(OIL_C)  # [Pa·s]
    print(f"NREL 5 MW at rated, friction in the step (μ_mz, Palmgren), {t[-1]:g} s at "
          f"dt = {args.dt:g} s, every step logged; means over the second half")  # fmt: skip
    print(f"oil VG {VG} at {OIL_C:g} °C: ν = {nu:.4f} mm²/s, ρ = {density(OIL_C):.2f} kg/m³, "
          f"η = {eta * 1e3:.4f} mPa·s")  # fmt: skip

    recoded: list[MeshRecoding] = []
    for i, m in enumerate(meshes):
        g1, g2 = gears[m["gear1"]], gears[m["gear2"]]
        c1, c2 = carrier_of(g1), carrier_of(g2)
        carrier = c1 or c2
        w_c = spin(carrier) if carrier else np.zeros(len(t))
        spins = (spin(g1["link"]) - w_c, spin(g2["link"]) - w_c)
        planet_first = None if carrier is None else c1 is not None
        pair = pair_geometry(m["name"], g1, g2)
        recoded.append(recode_mesh(res, i, pair, spins, planet_first, eta * 1e3))
    mesh_loss = np.stack([r.loss for r in recoded], axis=1)
    bearing_loss = np.zeros((len(t), len(res.bearing_names)))
    for b, name in enumerate(res.bearing_names):
        if rows.get(name):
            bearing_loss[:, b] = recode_bearing(res, name, rows[name], nu)

    print("\nmeshes [kW]: μ_mz P H_V with Ohlendorf's closed form and with the sliding integral;")
    print("the step's law at the rigid sliding ω_rel |x_j − x_P|; the recoding; the run's series")
    print(f"{'mesh':22s} {'ε_α':>6s} {'ε_1':>6s} {'ε_2':>6s} {'H_V':>7s} {'H_V ∫':>7s} "
          f"{'μ_mz':>7s} "
          f"{'μPH_V':>7s} {'μPH_V∫':>7s} {'rigid':>7s} {'recoded':>7s} {'pinwind':>7s} "
          f"{'cycles':>6s} {'1-flank':>7s}")  # fmt: skip
    for i, r in enumerate(recoded):
        p = r.pair
        print(f"{p.name:22s} {p.eps_alpha:6.3f} {p.eps_1:6.3f} {p.eps_2:6.3f} {p.h_v:7.4f} "
              f"{p.h_v_integral:7.4f} {r.mean_mu:7.4f} {r.estimate_closed / 1e3:7.2f} "
              f"{r.estimate_integral / 1e3:7.2f} {r.rigid / 1e3:7.2f} "
              f"{np.mean(r.loss[half]) / 1e3:7.2f} "
              f"{np.mean(res.mesh_friction_power[half, i]) / 1e3:7.2f} "
              f"{r.cycles:6.1f} {r.one_flank:7.3f}")  # fmt: skip

    table: list[tuple[str, float, float]] = []  # element, pinwind, recoding
    for r in recoded:
        table.append((f"mesh {r.pair.name}, one-flank samples [kW]", r.one_flank_theirs / 1e3,
                      r.one_flank_ours / 1e3))  # fmt: skip
    for b, name in enumerate(res.bearing_names):
        if rows.get(name):
            theirs = np.mean(res.bearing_friction_power[half, b])
            table.append((f"bearing {name} [kW]", theirs / 1e3,
                          np.mean(bearing_loss[half, b]) / 1e3))  # fmt: skip
    gearbox = pinwind.load(model)
    oil = Lubricant(VG, OIL_C + 273.15)
    eff = efficiency(res, gearbox, oil=oil)
    estimate = efficiency(res, gearbox, oil=oil, source="estimate", roughness=RA_UM * 1e-6)
    for r in recoded:
        comp = next(c for c in estimate.components if c.kind == "mesh" and c.name == r.pair.name)
        table.append((f"μ_mz P H_V {r.pair.name} (estimate) [kW]", np.mean(comp.power[half]) / 1e3,
                      r.estimate_integral / 1e3))  # fmt: skip

    # efficiency: the stages of docs/losses.md "Per stage" by hand
    revolute = [i for i, k in enumerate(res.joint_kinds) if k != "prismatic"]
    power = res.torque[:, revolute] * res.speed[:, revolute]
    p_in = np.maximum(power, 0).sum(1)
    stages = [("stage1", ("lss", "stage1_planet")), ("stage2", ("iss", "stage2_planet")),
              ("stage3", ("ims", "hss"))]  # fmt: skip

    def stage_efficiencies(meshes_w: np.ndarray, bearings_w: np.ndarray) -> list[float]:
        received, out = np.mean(p_in[half]), []
        for label, members in stages:
            m_idx = [i for i, m in enumerate(meshes) if m["name"].startswith(label)]
            b_idx = [b for b, n in enumerate(res.bearing_names) if n.startswith(members)]
            lost = np.mean(meshes_w[half][:, m_idx].sum(1) + bearings_w[half][:, b_idx].sum(1))
            out.append(1 - lost / received)
            received -= lost
        total = np.mean(meshes_w[half].sum(1) + bearings_w[half].sum(1))
        return [*out, 1 - total / np.mean(p_in[half])]

    from_series = stage_efficiencies(res.mesh_friction_power, res.bearing_friction_power)
    for s_idx, st in enumerate(eff.stages):
        eta_s = 1 - np.mean((st.mesh_loss + st.bearing_loss)[half]) / np.mean(st.input_power[half])
        table.append((f"η {st.stage.name} [%]", 100 * eta_s, 100 * from_series[s_idx]))
    eta_all = 1 - np.mean(eff.loss[half]) / np.mean(eff.input_power[half])
    table.append(("η overall, efficiency() [%]", 100 * eta_all, 100 * from_series[-1]))
    table.append(("P_in [kW]", np.mean(eff.input_power[half]) / 1e3, np.mean(p_in[half]) / 1e3))
    cli = tmp / "map"
    subprocess.run(
        [sys.executable, "-m", "pinwind", "efficiency", str(model), "--input", "rotor",
         "--output", "generator", "--torque", f"{RATED_TORQUE}:{RATED_TORQUE}",
         "--speed", f"{ROTOR_RPM}:{ROTOR_RPM}", "--points", "1", "--duration", f"{args.duration}",
         "--dt", f"{args.dt}", "--out", str(cli)],
        check=True, capture_output=True,
    )  # fmt: skip
    with open(cli / "efficiency_map.csv") as f:
        point = next(csv.DictReader(f))
    table.append(("η overall, pinwind efficiency [%]", 100 * float(point["efficiency"]),
                  100 * from_series[-1]))  # fmt: skip
    recoded_eta = stage_efficiencies(mesh_loss, bearing_loss)
    table.append(("η overall, recoded losses [%]", 100 * eta_all, 100 * recoded_eta[-1]))

    # the energy ledger
    energy = res.energy
    work_io = float(np.sum(res.torque[:-1, revolute] * np.diff(res.angle[:, revolute], axis=0)))
    table.append(("Σ τ_k Δθ_k vs work_applied + work_drivers [kJ]",
                  (energy["work_applied"][-1] + energy["work_drivers"][-1]) / 1e3,
                  work_io / 1e3))  # fmt: skip
    losses = res.mesh_friction_power.sum(1) + res.bearing_friction_power.sum(1)
    table.append(("∫ Σ losses dt vs friction_loss [kJ]", energy["friction_loss"][-1] / 1e3,
                  np.trapezoid(losses, t) / 1e3))  # fmt: skip
    stored = sum(energy[k][-1] - energy[k][0] for k in ("kinetic", "potential_spring"))
    sources = energy["work_gravity"][-1] + energy["work_parametric"][-1] - energy["numerical"][-1]
    table.append(("W_io − friction_loss vs ΔE + W_damp − W_g − W_par + W_num [kJ]",
                  (stored + energy["dissipated"][-1] - sources) / 1e3,
                  (work_io - energy["friction_loss"][-1]) / 1e3))  # fmt: skip

    print(f"\n{'element':58s} {'pinwind':>11s} {'recoding':>11s} {'rel. diff':>9s}")
    for name, theirs, ours in table:
        print(f"{name:58s} {theirs:11.6g} {ours:11.6g} {rel(ours, theirs):+9.1e}")
    print(
        "\nmeshes, second half, one-flank samples: kinematics = max |μ_step Σ F_j σ_j v_j − P| / "
        "mean P with μ_step = |F_f| / |Σ F_j σ_j|;"
    )
    print("μ = mean μ_mz / mean μ_step − 1; per sample = max |recoded − P| / mean P;")
    print("all samples: P < 0 = −Σ min(P, 0) / Σ P; opposing = Σ μ F_j |v_j| / Σ μ F_j σ_j v_j − 1")
    print(
        f"{'mesh':22s} {'kinematics':>10s} {'μ':>9s} {'per sample':>10s} {'P < 0':>9s} "
        f"{'opposing':>9s}"
    )
    for r in recoded:
        print(f"{r.pair.name:22s} {r.kinematics:10.1e} {r.mu_ratio:+9.1e} {r.per_sample:10.1e} "
              f"{r.negative:9.1e} {r.opposing:+9.1e}")  # fmt: skip
    inner = slice(len(t) // 2, len(t) - 1)  # the last sample has no step after it
    worst = max(
        float(np.max(np.abs(bearing_loss[inner, b] / res.bearing_friction_power[inner, b] - 1)))
        for b, name in enumerate(res.bearing_names)
        if rows.get(name)
    )
    print(f"bearings: largest |recoded / run − 1| per sample {worst:.1e}")


if __name__ == "__main__":
    main()
