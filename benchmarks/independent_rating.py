"""The ISO 6336 and AGMA 2001 rating of two shipped stages, recoded without pinwind's rating code.

The stages: the Saleh 2017 planetary (sun–planet and planet–ring meshes, spur, 24/48/120 teeth,
m = 15 mm, α = 24.5°, b = 380 mm) at its rated point (carrier 1 MN·m at 14.2 rpm, sun
−166 666.7 N·m), and the NREL 5 MW gearbox's helical parallel stage (95/24 teeth, m = 14 mm,
α = 20°, β = 10°, x = 0.669/0.480, tip alteration −0.938 mm, b = 360 mm) at rated (rotor
3 945 990 N·m at 12.1 rpm, the generator's torque balancing it through the ratio 96.354).
``python -m pinwind rate ... --json`` gives pinwind's numbers; this script reads the gear data
from the model file's XML (``xml.etree``) and the operating point from the applied torques, and
computes, without pinwind's gear or rating code (only ε_α, ε_β of the "pinwind" column come from
its ``GearPair``):

- geometry (ISO 21771): r = z m_n/(2 cos β), α_t = atan(tan α_n/cos β), r_b = r cos α_t,
  inv α_wt = inv α_t + 2 tan α_n (x₁ + x₂)/(z₁ + z₂) (z negative for an internal gear), tip
  radius r ± (m_n (1 + x) + k m_n) as docs/model_format.md states, ε_α = g_α/p_bt with
  g_α = √(r_a1² − r_b1²) ± √(r_a2² − r_b2²) ∓ a sin α_wt, ε_β = b sin β/(π m_n);
- the nominal tangential force at the reference circle, F_t = T/(N_p r) of the applied torque
  (row "F_t nominal") and the pitch-line speed (row "v"; for the planetary meshes the speed in
  the carrier's frame, m z_r ω_c/2, as KISSsoft's ISO 6336 report of the NREL 5 MW planetary
  stages takes it, 5/6 of the sun's absolute r_s ω_s); pinwind rates the force and speed of the
  run's last sample, and the rest is recoded from those, to check the formulas, not the run;
- ISO 6336-2 (G. F. S. Rebouças's open "Drivetrain" ISO_6336.m, which prints ISO 6336-2's
  formulas and checks them against ISO/TR 6336-30's first example; an open ISO 6336/DIN 3990
  load-capacity routine): Z_H = √(2 cos β_b cos α_wt/(cos² α_t sin α_wt)),
  Z_E = √(1/(π Σ(1 − ν²)/E)), Z_ε = √((4 − ε_α)/3) (spur),
  √((4 − ε_α)(1 − ε_β)/3 + ε_β/ε_α) (ε_β < 1) or √(1/ε_α), Z_β = 1/√(cos β) (ISO/TR 6336-30's
  example 1 tabulates Z_β = 1.01944 at β = 15.8°: this form; the open routine's DIN 3990 form
  √(cos β) is 1.5 % lower at 10°), Z_B and Z_D from ISO's M₁ and M₂ (below), σ_H0 = Z_H Z_E Z_ε
  Z_β √(F_t (u + 1)/(d₁ b u)) (u = z₂/z₁, negative for an internal pair),
  σ_H = Z_B,D σ_H0 √(K_A K_γ K_v K_Hβ K_Hα), S_H = σ_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X/σ_H;
- ISO 6336-3 method B (the open routine above; the DIN 3990 library "din3990" of hanslhansl,
  Glg D.4.01-03, D.5.05): the 30° tangent's θ from θ = 2G/z_n tan θ − H, s_Fn, ρ_F, the load at
  the outer point of single contact d_en, α_Fen, h_Fe, Y_F = 6 (h_Fe/m) cos α_Fen/((s_Fn/m)²
  cos α_n), Y_S = (1.2 + 0.13 L) q_s^(1/(1.21 + 2.3/L)), for the ISO 53 profile A basic rack
  (h_fP = 1.25 m, ρ_fP = 0.38 m, pinwind's stated tool); for the ring, pinwind's documented
  stand-in (the rack, z_n → ∞, with the ring's profile shift: ISO 6336-3's internal-gear
  procedure is in no source found); Y_β = 1 − ε_β β/120° (ε_β ≤ 1, β ≤ 30°),
  K_Fβ = K_Hβ^N_F, N_F = (b/h)²/(1 + b/h + (b/h)²) (b/h ≥ 3; h = h_aP + k m_n + h_fP, DIN
  3990's tooth depth with the tip alteration, the deeper tooth's),
  σ_F = F_t/(b m_n) Y_F Y_S Y_β K_A K_v K_Fβ K_Fα, S_F = σ_Flim Y_ST Y_NT Y_δ Y_R Y_X/σ_F;
- AGMA 2001-D04 in SI as Saleh 2017 eqs. 32-37 and Shigley's Mechanical Engineering Design
  (10th ed.) eqs. 14-15, 14-16, 14-23, 14-27, 14-30 to 14-35 and 14-38 print it (read in open
  implementations of Shigley's chapter 14): W_t = F_t d₁/d_w1 (the torque at the operating
  pitch circle), I = cos φ_t sin φ_t/(2 m_N) · m_G/(m_G ± 1) at the operating pressure angle
  (m_N = p_N/(0.95 Z) for the helical stage), K_v = ((A + √V)/A)^B, B = 0.25 (12 − Q_v)^(2/3),
  A = 50 + 56 (1 − B) (V in ft/min; Shigley's SI form √(200 v) rounds 196.85 to 200: both rows
  printed), K_m = 1 + C_mc (C_pf C_pm + C_ma C_e) (precision enclosed: 0.0675, 0.0128,
  −0.926e-4; face and diameter in inches), K_R = 0.50 − 0.109 ln(1 − R) (R ≥ 0.99),
  σ_c = C_p √(W_t K_o K_v K_s K_m C_f/(d_w1 F I)), σ = W_t K_o K_v K_s K_m K_B/(F m_t J),
  S_H = s_ac Z_N C_H/(K_T K_R σ_c), S_F = s_at Y_N/(K_T K_R σ);
- Hertz (Jørgensen 2014 eqs. 20-22): p_max = 2F/(π a L), a = √((2/π)(m₁ + m₂)/B · F/L),
  B = ½ (1/ρ₁ + 1/ρ₂), the whole force on one pair from B to D and half of it on each of two
  pairs elsewhere; over each zone the relative curvature is largest at an end, so the largest
  pressure is the largest at A, B, D and E. Jørgensen's model is a spur one: for the helical
  stage it is evaluated in the normal plane (line b/cos β_b, curvatures ρ/cos β_b, flank force
  F_bt/cos β_b) and, as pinwind does, in the transverse plane.

Z_B and Z_D. ISO's Z_B converts the contact stress at the pitch point C to the one at the inner
point B of the pinion's single-pair contact (a base pitch below its tip): the square root of the
ratio of the relative curvatures. For an external pair ρ₁ + ρ₂ = a sin α_wt along the path, so
1/ρ_red = a sin α_wt/(ρ₁ρ₂) and Z_B = √(ρ_C1 ρ_C2/(ρ_B1 ρ_B2)), ISO's M₁ written with the roll
lengths (the row "Z_B (M1 as printed)" evaluates ISO's M₁ as the open sources print it). For an
internal pair ρ₂ − ρ₁ is the constant and the same ratio follows (one public summary, Autodesk
Inventor's ISO 6336 help, sets Z_B = 1 for internal gearing instead).

Taken from pinwind's output (from the run, or from tables no source found reproduces): K_v
(ISO 6336-1:1996 method C), K_Hβ (method C from the mesh stiffness c_γβ), K_Hα, the size
factor Y_X, AGMA's J (AGMA 908-B89 is not public) and the material strengths of the documented
default 18CrNiMo7-6 (pinwind.gears.materials).

Run:  python benchmarks/independent_rating.py
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from pinwind.gears.gear_pair import GearPair  # noqa: E402  (the ε_α, ε_β of pinwind's geometry)

#: ISO 53 profile A basic rack (pinwind.gears.checks TOOL_ADDENDUM, TOOL_TIP_RADIUS) [modules].
H_FP, RHO_FP, H_AP = 1.25, 0.38, 1.0
#: 18CrNiMo7-6 (pinwind's default material, docs/rating.md; pinwind.gears.materials).
E_MOD, NU = 206e9, 0.3
SIGMA_H_LIM, SIGMA_F_LIM = 1500e6, 500e6
KSI = 6.894757e6
S_AC, S_AT = 225 * KSI, 65 * KSI
INCH = 0.0254
#: Tooth count standing in for the rack (z_n → ∞) of an internal wheel's root (pinwind's choice).
RACK_TEETH = 10_000


def inv(a: float) -> float:
    return math.tan(a) - a


def inv_inverse(v: float) -> float:
    a = (3.0 * v) ** (1.0 / 3.0)
    for _ in range(60):
        a -= (math.tan(a) - a - v) / (math.tan(a) ** 2)
    return a


@dataclass
class Gear:
    name: str
    z: int
    m: float
    alpha_n: float
    b: float
    x: float
    beta: float
    internal: bool
    k_mm: float  # tip alteration k·m_n [m]


def read_gears(model: Path) -> dict[str, Gear]:
    root = ET.parse(model).getroot()
    out = {}
    for g in root.iter("gear"):
        a = g.attrib
        out[a["name"]] = Gear(
            name=a["name"],
            z=int(a["teeth"]),
            m=float(a["module_mm"]) * 1e-3,
            alpha_n=math.radians(float(a.get("pressure_angle_deg", "20"))),
            b=float(a["face_width_mm"]) * 1e-3,
            x=float(a.get("profile_shift", "0")),
            beta=math.radians(float(a.get("helix_angle_deg", "0"))),
            internal=a.get("internal", "false") == "true",
            k_mm=float(a.get("tip_alteration_mm", "0")) * 1e-3,
        )
    return out


def pair(g1: Gear, g2: Gear) -> dict[str, float]:
    """Transverse geometry of pinion g1 (external) and wheel g2 (external or internal)."""
    beta = abs(g1.beta)
    m, an = g1.m, g1.alpha_n
    at = math.atan(math.tan(an) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(at))
    s2 = -1.0 if g2.internal else 1.0
    r1 = g1.z * m / (2 * math.cos(beta))
    r2 = g2.z * m / (2 * math.cos(beta))
    rb1, rb2 = r1 * math.cos(at), r2 * math.cos(at)
    z2s = s2 * g2.z
    awt = inv_inverse(inv(at) + 2 * math.tan(an) * (g1.x + g2.x) / (g1.z + z2s))
    a = (rb2 + s2 * rb1) / math.cos(awt) if g2.internal else (rb1 + rb2) / math.cos(awt)
    ra1 = r1 + m * (H_AP + g1.x) + g1.k_mm
    ra2 = r2 - (m * (H_AP + g2.x) + g2.k_mm) if g2.internal else r2 + m * (H_AP + g2.x) + g2.k_mm
    pbt = 2 * math.pi * rb1 / g1.z
    t1 = math.sqrt(ra1**2 - rb1**2)  # roll length pinion tip
    t2 = math.sqrt(ra2**2 - rb2**2)
    gline = a * math.sin(awt)  # |T1T2|
    if g2.internal:
        g_alpha = t1 - t2 + gline
    else:
        g_alpha = t1 + t2 - gline
    eps_a = g_alpha / pbt
    b = min(g1.b, g2.b)
    eps_b = b * math.sin(beta) / (math.pi * m)
    # radii of curvature along the line of action measured from the pinion's tangency point T1
    rho1_c = rb1 * math.tan(awt)
    rho1_a = t1 - g_alpha  # start of active path (wheel tip), from T1
    rho1_e = t1  # end (pinion tip)
    return dict(
        at=at,
        beta_b=beta_b,
        awt=awt,
        a=a,
        r1=r1,
        r2=r2,
        rb1=rb1,
        rb2=rb2,
        ra1=ra1,
        ra2=ra2,
        pbt=pbt,
        g_alpha=g_alpha,
        eps_a=eps_a,
        eps_b=eps_b,
        gline=gline,
        rho1_c=rho1_c,
        rho1_a=rho1_a,
        rho1_e=rho1_e,
        s2=s2,
        b=b,
    )


def rho2_of(geo: dict[str, float], rho1: float) -> float:
    """Wheel's radius of curvature at the point whose pinion radius is rho1 (positive)."""
    return rho1 + geo["gline"] if geo["s2"] < 0 else geo["gline"] - rho1


def z_b_z_d(geo: dict[str, float]) -> tuple[float, float, float]:
    """Z_B, Z_D from the curvatures at B, D and C; also ISO's M1 for an external pair."""
    pbt, c = geo["pbt"], geo["rho1_c"]
    # single-pair contact lies between B (a base pitch below the pinion's tip, E − p_bt: the
    # pinion's inner point) and D (a base pitch above the start A, A + p_bt: the wheel's)
    rb_pt, rd_pt = geo["rho1_e"] - pbt, geo["rho1_a"] + pbt

    def ratio(rp: float) -> float:
        return math.sqrt(c * rho2_of(geo, c) / (rp * rho2_of(geo, rp)))

    mb, md = ratio(rb_pt), ratio(rd_pt)
    return mb, md, ratio(rb_pt)


def m1_iso(geo: dict[str, float], z1: int, z2: int) -> float:
    """ISO 6336-2's M1 as printed (external pair)."""
    e = geo["eps_a"]
    return math.tan(geo["awt"]) / math.sqrt(
        (math.sqrt((geo["ra1"] / geo["rb1"]) ** 2 - 1) - 2 * math.pi / z1)
        * (math.sqrt((geo["ra2"] / geo["rb2"]) ** 2 - 1) - (e - 1) * 2 * math.pi / z2)
    )


def method_b(g: Gear, geo_eps_a: float, beta_b: float) -> dict[str, float]:
    """ISO 6336-3 method B Y_F, Y_S of an external gear, loaded at the outer point of single
    contact."""
    m, an, beta, x = g.m, g.alpha_n, abs(g.beta), g.x
    zn = g.z / (math.cos(beta_b) ** 2 * math.cos(beta))
    rho_fp, h_fp = RHO_FP * m, H_FP * m
    G = rho_fp / m - h_fp / m + x
    E = math.pi / 4 * m - h_fp * math.tan(an) - (1 - math.sin(an)) * rho_fp / math.cos(an)
    H = 2 / zn * (math.pi / 2 - E / m) - math.pi / 3
    th = math.pi / 6
    for _ in range(200):
        th = 2 * G / zn * math.tan(th) - H
    s_fn = m * (zn * math.sin(math.pi / 3 - th) + math.sqrt(3) * (G / math.cos(th) - rho_fp / m))
    rho_f = rho_fp + m * 2 * G**2 / (math.cos(th) * (zn * math.cos(th) ** 2 - 2 * G))
    d = g.z * m / math.cos(beta)
    da = d + 2 * (m * (H_AP + x) + g.k_mm)
    dn = m * zn
    dbn = dn * math.cos(an)
    dan = dn + da - d
    eps_an = geo_eps_a / math.cos(beta_b) ** 2
    pbn = math.pi * d * math.cos(beta) * math.cos(an) / g.z
    den = 2 * math.sqrt(
        (math.sqrt((dan / 2) ** 2 - (dbn / 2) ** 2) - pbn * (eps_an - 1)) ** 2 + (dbn / 2) ** 2
    )
    alpha_en = math.acos(dbn / den)
    gamma_e = (math.pi / 2 + 2 * x * math.tan(an)) / zn + inv(an) - inv(alpha_en)
    alpha_fen = alpha_en - gamma_e
    h_fe = (
        0.5
        * m
        * (
            (math.cos(gamma_e) - math.sin(gamma_e) * math.tan(alpha_fen)) * den / m
            - zn * math.cos(math.pi / 3 - th)
            - G / math.cos(th)
            + rho_fp / m
        )
    )
    y_f = 6 * (h_fe / m) * math.cos(alpha_fen) / ((s_fn / m) ** 2 * math.cos(an))
    L = s_fn / h_fe
    qs = s_fn / (2 * rho_f)
    y_s = (1.2 + 0.13 * L) * qs ** (1 / (1.21 + 2.3 / L))
    return dict(Y_F=y_f, Y_S=y_s, s_Fn=s_fn, h_Fe=h_fe, rho_F=rho_f, q_s=qs)


def hertz_pmax(geo: dict[str, float], f_n: float) -> float:
    """Largest Hertz pressure along the path (Jørgensen 2014 eqs. 20-22).

    Over each zone the force is constant and the relative curvature largest at one of its
    ends, so the largest pressure is the largest at A, B, D and E (B and D under the whole
    force, A and E under half of it).
    """
    mm = (1 - NU**2) / E_MOD
    L = geo["b"] / math.cos(geo["beta_b"])
    a0, a1, pbt = geo["rho1_a"], geo["rho1_e"], geo["pbt"]
    best = 0.0
    for r1, F in ((a0, f_n / 2), (a1 - pbt, f_n), (a0 + pbt, f_n), (a1, f_n / 2)):
        r2 = rho2_of(geo, r1)
        curv = 1 / r1 + (-1 / r2 if geo["s2"] < 0 else 1 / r2)
        a = math.sqrt(2 / math.pi * 2 * mm / (0.5 * curv) * F / L)
        best = max(best, 2 * F / (math.pi * a * L))
    return best


def agma_kv(v: float, qv: float) -> float:
    B = 0.25 * (12 - qv) ** (2 / 3)
    A = 50 + 56 * (1 - B)
    return ((A + math.sqrt(200 * v)) / A) ** B


def agma_km(b: float, d: float) -> float:
    F, dp = b / INCH, d / INCH
    ratio = max(F / (10 * dp), 0.05)
    if F <= 1:
        cpf = ratio - 0.025
    elif F <= 17:
        cpf = ratio - 0.0375 + 0.0125 * F
    else:
        cpf = ratio - 0.1109 + 0.0207 * F - 0.000228 * F**2
    cma = 0.0675 + 0.0128 * F - 0.926e-4 * F**2
    return 1 + 1.0 * (cpf * 1.0 + cma * 1.0)


def run_pinwind(args: list[str]) -> dict:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", *args, "--json"],
        check=True,
        capture_output=True,
        text=True,
        env=env,
        cwd=REPO,
    )
    return json.loads(out.stdout)


def rate_mesh(g1: Gear, g2: Gear, f_t: float, v: float, pw: dict, rows: list, label: str) -> None:
    """Recode one mesh (g1 pinion, external) and append (quantity, pinwind, recoding) rows."""
    geo = pair(g1, g2)
    iso, f = pw["iso"], pw["iso"]["factors"]
    ag, fa = pw["agma"], pw["agma"]["factors"]
    u = geo["s2"] * g2.z / g1.z
    beta = abs(g1.beta)
    d1 = 2 * geo["r1"]
    b = geo["b"]

    def row(q: str, p: float | None, r: float | None) -> None:
        rows.append((f"{label} {q}", p, r))

    row("F_t nominal [kN]", pw["tangential_force_N"] / 1e3, f_t / 1e3)
    # pinwind rates the force of the run's last sample; the stresses below are recoded from that
    # force (the row above compares it with the nominal one of the applied torques)
    f_t = pw["tangential_force_N"]
    row("v [m/s]", pw["pitch_line_speed_m_s"], v)
    v = pw["pitch_line_speed_m_s"]  # the run's, as the force
    ref = GearPair(
        g1.z,
        g2.z,
        module=g1.m,
        pressure_angle=g1.alpha_n,
        face_width=b,
        profile_shift_1=g1.x,
        profile_shift_2=g2.x,
        helix_angle=beta,
        internal_2=g2.internal,
        tip_alteration_1=g1.k_mm,
        tip_alteration_2=g2.k_mm,
    ).path
    row("ε_α", ref.contact_ratio, geo["eps_a"])
    if beta:
        row("ε_β", ref.overlap_ratio, geo["eps_b"])
    zh = math.sqrt(
        2
        * math.cos(geo["beta_b"])
        * math.cos(geo["awt"])
        / (math.cos(geo["at"]) ** 2 * math.sin(geo["awt"]))
    )
    ze = math.sqrt(1 / (math.pi * 2 * (1 - NU**2) / E_MOD))
    ea, eb = geo["eps_a"], geo["eps_b"]
    if beta == 0:
        zeps = math.sqrt((4 - ea) / 3)
    elif eb < 1:
        zeps = math.sqrt((4 - ea) * (1 - eb) / 3 + eb / ea)
    else:
        zeps = math.sqrt(1 / ea)
    zbeta = 1 / math.sqrt(math.cos(beta))
    mb, md, _ = z_b_z_d(geo)
    if not g2.internal and eb == 0:
        row("Z_B (M1 as printed)", f["Z_B"], max(1.0, m1_iso(geo, g1.z, g2.z)))
    if eb >= 1:
        zb, zd = 1.0, 1.0
    else:
        zb = max(1.0, mb - eb * (mb - 1))
        zd = 1.0 if g2.internal else max(1.0, md - eb * (md - 1))
    row("Z_H", f["Z_H"], zh)
    if label.startswith("S/sun"):
        row("Z_E [√MPa]", f["Z_E"] / 1e3, ze / 1e3)
    row("Z_ε", f["Z_eps"], zeps)
    if beta:
        row("Z_β", f["Z_beta"], zbeta)
    row("Z_B", f["Z_B"], zb)
    row("Z_D", f["Z_D"], zd)
    sh0 = zh * ze * zeps * zbeta * math.sqrt(f_t / (d1 * b) * (u + 1) / u)
    row("σ_H0 [MPa]", iso["sigma_H0"] / 1e6, sh0 / 1e6)
    kh = f["K_A"] * f["K_gamma"] * f["K_v"] * f["K_Hbeta"] * f["K_Halpha"]
    sh = [zb * sh0 * math.sqrt(kh), zd * sh0 * math.sqrt(kh)]
    for i, gname in enumerate((g1.name, g2.name)):
        row(f"σ_H {gname} [MPa]", iso["sigma_H"][i] / 1e6, sh[i] / 1e6)
        row(f"S_H {gname}", iso["S_H"][i], SIGMA_H_LIM / sh[i])
    # root
    # the tooth depth h = h_aP + k m_n + h_fP (DIN 3990), the deeper tooth's (smaller b/h)
    h = (H_AP + H_FP) * g1.m + max(g1.k_mm, g2.k_mm)
    hb = max(b / h, 3.0)
    kfb = f["K_Hbeta"] ** (hb**2 / (1 + hb + hb**2))
    row("K_Fβ", f["K_Fbeta"], kfb)
    ybeta = 1 - min(eb, 1.0) * min(math.degrees(beta), 30.0) / 120
    if beta:
        row("Y_β", f["Y_beta"], ybeta)
    for i, g in enumerate((g1, g2)):
        if g.internal:
            # ISO 6336-3's internal-gear procedure is not in the sources; pinwind's documented
            # stand-in, the rack (z_n → ∞) with the ring's profile shift, recoded instead
            rack = Gear(g.name, RACK_TEETH, g.m, g.alpha_n, g.b, g.x, g.beta, False, g.k_mm)
            mb_ = method_b(rack, ea, geo["beta_b"])
        else:
            mb_ = method_b(g, ea, geo["beta_b"])
        row(f"Y_F {g.name}", f["Y_F"][i], mb_["Y_F"])
        row(f"Y_S {g.name}", f["Y_S"][i], mb_["Y_S"])
        sf0 = f_t / (b * g.m) * mb_["Y_F"] * mb_["Y_S"] * ybeta
        sf = sf0 * f["K_A"] * f["K_v"] * kfb * f["K_Falpha"]
        row(f"σ_F {g.name} [MPa]", iso["sigma_F"][i] / 1e6, sf / 1e6)
        sfp = SIGMA_F_LIM * 2.0 * f["Y_X"][i]
        row(f"S_F {g.name}", iso["S_F"][i], sfp / sf)
    # AGMA
    mg = g2.z / g1.z
    phi_t = geo["awt"]  # the operating transverse pressure angle
    d_w1 = 2 * geo["rb1"] / math.cos(geo["awt"])
    w_t = f_t * d1 / d_w1  # the same torque at the operating pitch circle
    i_fac = (
        math.cos(phi_t) * math.sin(phi_t) / 2 * (mg / (mg - 1) if g2.internal else mg / (mg + 1))
    )
    if beta:
        # helical: m_N = p_N/(0.95 Z), p_N the normal base pitch, Z the transverse path length
        i_fac *= 1 / (math.pi * g1.m * math.cos(g1.alpha_n) / (0.95 * geo["g_alpha"]))
    row("AGMA I", fa["I"], i_fac)
    row("AGMA K_v (SI form, √(200 v))", fa["K_v"], agma_kv(v, fa["quality"]))
    kv = agma_kv(v / 0.00508 / 200, fa["quality"])
    row("AGMA K_v (V = v/0.00508 ft/min)", fa["K_v"], kv)
    km = agma_km(b, d1)
    row("AGMA K_m", fa["K_m"], km)
    R = fa["reliability_percent"] / 100.0
    kr = 0.50 - 0.109 * math.log(1 - R) if R >= 0.99 else 0.658 - 0.0759 * math.log(1 - R)
    row("AGMA K_R", fa["K_R"], kr)
    if True:
        sc = ze * math.sqrt(w_t * fa["K_o"] * kv * 1.0 * km * 1.0 / (d_w1 * b * i_fac))
        row("AGMA σ_c [MPa]", ag["contact_stress"][0] / 1e6, sc / 1e6)
        row("AGMA S_H", ag["S_H"][0], S_AC / (kr * sc))
        mt = g1.m / math.cos(beta)
        for i, g in enumerate((g1, g2)):
            sb = w_t * fa["K_o"] * kv * 1.0 * km * 1.0 / (b * mt * fa["J"][i])
            row(f"AGMA σ {g.name} [MPa]", ag["bending_stress"][i] / 1e6, sb / 1e6)
            row(f"AGMA S_F {g.name}", ag["S_F"][i], S_AT / (kr * sb))
    if beta == 0:
        row(
            "Hertz p_max [MPa]",
            pw["hertz_p_max_Pa"] / 1e6,
            hertz_pmax(geo, pw["normal_force_N"]) / 1e6,
        )
    else:
        # Jørgensen 2014 is a spur (transverse-plane) model: recoded in the normal plane (line
        # b/cos β_b long, curvatures ρ/cos β_b, flank force F_bt/cos β_b) it is √cos β_b lower
        row(
            "Hertz p_max, normal plane [MPa]",
            pw["hertz_p_max_Pa"] / 1e6,
            hertz_pmax(geo, pw["normal_force_N"]) / 1e6,
        )
        flat = dict(geo, beta_b=0.0)
        row(
            "Hertz p_max, transverse [MPa]",
            pw["hertz_p_max_Pa"] / 1e6,
            hertz_pmax(flat, pw["normal_force_N"]) / 1e6,
        )


def main() -> None:
    rows: list = []
    # --- Saleh 2017 planetary at its rated point
    model = REPO / "models" / "saleh2017_planetary.urdf"
    t_sun, carrier_rpm, n_p = 166666.7, 14.2, 3
    pw = run_pinwind(
        [
            str(model),
            "--initial-speed",
            f"carrier={carrier_rpm}",
            "--torque",
            "carrier=1e6",
            "--torque",
            f"sun={-t_sun}",
        ]
    )
    gears = read_gears(model)
    sun, planet, ring = gears["sun"], gears["planet1"], gears["ring"]
    r_sun = sun.z * sun.m / 2
    f_t = t_sun / (n_p * r_sun)
    w_c = carrier_rpm * math.pi / 30
    w_sun = w_c * (1 + ring.z / sun.z)
    meshes = {m["mesh"]: m for m in pw["meshes"]}
    # sun–planet: the pitch-line speed in the carrier's frame, r_s (ω_s − ω_c) = r_s ω_c z_r/z_s
    rate_mesh(sun, planet, f_t, (w_sun - w_c) * r_sun, meshes["sun_planet1"], rows, "S/sun-planet")
    r_ring = ring.z * ring.m / 2
    rate_mesh(planet, ring, f_t, w_c * r_ring, meshes["planet1_ring"], rows, "S/planet-ring")

    # --- NREL 5 MW gearbox, helical parallel stage, at rated
    model = REPO / "models" / "nrel5mw_gearbox.urdf"
    t_rotor, rotor_rpm = 3945990.0, 12.1
    gears = read_gears(model)
    g = gears
    ratio = (1 + g["stage1_ring"].z / g["stage1_sun"].z) * (
        1 + g["stage2_ring"].z / g["stage2_sun"].z
    )
    ratio *= g["stage3_wheel"].z / g["stage3_pinion"].z
    t_gen = t_rotor / ratio  # the train turns the generator against the rotor's sense
    pw = run_pinwind(
        [
            str(model),
            "--initial-speed",
            f"rotor={rotor_rpm}",
            "--torque",
            f"rotor={t_rotor}",
            "--torque",
            f"generator={t_gen!r}",
        ]
    )
    meshes = {m["mesh"]: m for m in pw["meshes"]}
    pinion, wheel = g["stage3_pinion"], g["stage3_wheel"]
    r_p = pinion.z * pinion.m / (2 * math.cos(pinion.beta))
    w_hss = rotor_rpm * math.pi / 30 * ratio
    rate_mesh(pinion, wheel, t_gen / r_p, w_hss * r_p, meshes["stage3"], rows, "N/stage3")

    width = max(len(r[0]) for r in rows)
    print(f"{'quantity':<{width}}  {'pinwind':>14}  {'recoding':>14}  {'rel. diff':>10}")
    for q, p, r in rows:
        ps = f"{p:14.8g}" if p is not None else f"{'—':>14}"
        rs = f"{r:14.8g}" if r is not None else f"{'—':>14}"
        if p is not None and r is not None:
            d = (r - p) / p if p else r
            ds = f"{d:10.1e}"
        else:
            ds = f"{'':>10}"
        print(f"{q:<{width}}  {ps}  {rs}  {ds}")
    # rows whose difference is not the formulas': the run's force and speed against the nominal
    # ones, Shigley's rounded SI K_v, the helical stage's Hertz in the normal plane
    apart = ("F_t nominal", " v [m/s]", "SI form", "normal plane")
    rest = [
        abs((r - p) / p)
        for q, p, r in rows
        if p is not None and r is not None and not any(a in q for a in apart)
    ]
    print(f"largest |rel. diff| of the other {len(rest)} rows: {max(rest):.1e}")


if __name__ == "__main__":
    main()
