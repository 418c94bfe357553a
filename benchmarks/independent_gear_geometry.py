"""The gear geometry of every mesh of every shipped model, recoded from the model files alone and
compared with what pinwind reports.

Read with ``xml.etree`` from each ``models/*.urdf``: the gears (teeth, normal module m_n, normal
pressure angle α_n, profile shift x, tip alteration k m_n, helix β, face width b, ``internal``,
centre in the link), the meshes and the joints' origins (every ``rpy`` zero and every axis the
world z, checked, so a link's world origin is the sum of its chain's origins). Recoded (SI,
angles in rad, transverse plane; ISO 21771 with signed tooth numbers, an internal gear's z < 0,
and the ISO sign of x: docs/model_format.md, ``profile_shift``):

- α_t = atan(tan α_n / cos β), m_t = m_n / cos β, r = |z| m_t / 2, r_b = r cos α_t (ISO 21771
  eqs. for the transverse section); tan β_b = tan β cos α_t (base helix).
- inv α_wt = inv α_t + 2 tan α_n (x_1 + x_2)/(z_1 + z_2), solved by Newton on inv α = tan α − α;
  a_w = m_t (z_1 + z_2)/2 · cos α_t / cos α_wt, taken positive (ISO 21771).
- Tip radii r_a = r + m_n (1 + x) + k m_n (external), r_a = r − m_n (1 + x) − k m_n (internal,
  the inner tip circle; docs/model_format.md ``profile_shift`` and ``tip_alteration_mm``,
  h_a* = 1 of the ISO 53 basic rack).
- Path of contact on the transverse line of action, measured from T_1 (gear 1's base-circle
  tangency point) towards the pitch point C (gear 1 external, as in every shipped mesh):
  C at r_b1 tan α_wt; the end E at √(r_a1² − r_b1²) (gear 1's tip); the start A at
  a_w sin α_wt − √(r_a2² − r_b2²) for an external gear 2 (its tip, beyond C from T_2) and at
  √(r_a2² − r_b2²) − a_w sin α_wt for an internal gear 2 (T_2 lies behind T_1, a_w sin α_wt
  from it); g_α = E − A, p_bt = π m_t cos α_t, ε_α = g_α / p_bt, and the single-pair zone
  [g_α − p_bt, p_bt] from A (Niemann & Winter, Maschinenelemente II, §21; ISO 21771 §5.4).
- ε_β = b sin |β| / (π m_n), b the smaller face width of the pair (ISO 21771).
- The bearings' centre distance a′ = |C_B − C_A| from the joint origins and gear offsets, and
  the working pressure angle there, cos α′ = (r_bA + r_bB)/a′ (external) or (r_bB − r_bA)/a′
  (B internal) (docs/model_format.md, "Checks when loading"); working radii r_b / cos α′;
  the pitch point's fraction μ of C_B − C_A from A: r_wA/a′, and −r_wA/a′ when B is internal
  (P beyond A, away from B's centre; ``Mesh.pitch_fraction``'s docstring).
- Planet positions: planet i at ψ_i = 2π (i − 1)/N from +x on the radius of the stage's centre
  distance as the sources give it (models/README.md: Saleh 540 mm, CART 355 mm, DTU the
  sun–planet a_w, NREL Table V's a_w); parallel pinions at +y from their wheel at a_w.
- Tooth phases (docs/model_format.md, "Tooth phases"): the first gear of each train (its first
  mesh in file order) has the leading flank of tooth 0 (the flank facing its positive turn) on
  its link's x axis on its working pitch circle, so its tooth centre lies a half tooth angle
  behind: φ = −ψ(r_w), ψ(r_w) = s_t/d + inv α_t − inv α_wt with s_t/d = (π/2 + 2 x tan α_n)/|z|
  (ISO 21771, the transverse tooth thickness on the reference circle carried to radius r_w along
  the involute). Every other gear's phase follows from interlocking with its already-phased mate:
  on the working pitch circle a tooth centre of one gear faces a space centre of the other, i.e.
  in pitches along the common tangent t at P the two tooth-centre positions differ by ½. With
  θ_P the angle of P seen from a gear's centre, a gear whose positive turn moves its surface at P
  along +t (gear A; an internal B) has its teeth at u = (φ − θ_P) |z|/2π (mod 1), an external B
  (moving along −t) at u = −(φ − θ_P) |z|/2π. The meshes that close a loop (a planetary stage's
  ring meshes after the first) are not used to phase; their interlock residual is printed.

Compared (pinwind): ``pinwind.load(model)``'s meshes (``working_pressure_angle``,
``centre_distance``, ``base_radius_a/b``, ``working_radius_a/b``, ``pitch_fraction``, and their
``path``: ``working_pressure_angle``, ``length``, ``contact_ratio``, ``overlap_ratio``,
``base_pitch``, ``start_roll_1``, ``pitch_roll_1``, ``single_start``, ``single_end``,
``tip_radius_1/2``), ``Gearbox.tooth_phases``, ``pinwind.gears.base_helix_angle`` (β_b, public),
``pinwind.gears.pair_geometry`` (a_w) and the α_w that ``pinwind info`` prints (4 decimals).

Run: ``python benchmarks/independent_gear_geometry.py [--full]`` (one table: per quantity the
largest difference over all models and meshes; ``--full`` every comparison first).
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODELS = sorted((ROOT / "models").glob("*.urdf"))

# The source's own centre distance of each planetary stage / parallel pair (models/README.md):
# (model stem, mesh name) -> a [m]; None: the recoded ISO 21771 a_w of the mesh.
PLANET_RADIUS_MESH = {
    "saleh2017_planetary": ("sun_planet1", 0.540),
    "saleh2017_drivetrain": ("sun_planet1", 0.540),
    "cart600_gearbox": ("planet1_ring", 0.355),
    "dtu500_planetary": ("sun_planet1", None),
    "nrel5mw_gearbox": ("stage1_sun_planet1", 0.863),
}
NREL_STAGE2_RADIUS = 0.584  # Nejad et al. 2016 Table V a_w of stage 2
NREL_STAGE3_DISTANCE = 0.861  # Table V a_w of stage 3


@dataclass
class GearData:
    name: str
    link: str
    z: int  # signed: negative for an internal gear
    mn: float
    alpha_n: float
    beta: float
    x: float
    k_mn: float
    b: float
    internal: bool
    xyz: tuple[float, float, float]

    @property
    def alpha_t(self) -> float:
        return math.atan(math.tan(self.alpha_n) / math.cos(self.beta))

    @property
    def mt(self) -> float:
        return self.mn / math.cos(self.beta)

    @property
    def r(self) -> float:
        return abs(self.z) * self.mt / 2

    @property
    def rb(self) -> float:
        return self.r * math.cos(self.alpha_t)

    @property
    def ra(self) -> float:
        if self.internal:
            return self.r - self.mn * (1 + self.x) - self.k_mn
        return self.r + self.mn * (1 + self.x) + self.k_mn

    @property
    def beta_b(self) -> float:
        return math.atan(math.tan(self.beta) * math.cos(self.alpha_t))


@dataclass
class Model:
    stem: str
    path: Path
    gears: dict[str, GearData]
    meshes: list[tuple[str, str, str]]
    joint_of_link: dict[str, str]
    link_origin: dict[str, tuple[float, float, float]]


def inv(a: float) -> float:
    return math.tan(a) - a


def inv_inverse(v: float) -> float:
    """α with tan α − α = v (Newton from Cheng's start (3v)^(1/3))."""
    a = (3 * v) ** (1 / 3) if v > 0 else 1e-6
    for _ in range(60):
        f = math.tan(a) - a - v
        a_new = a - f / math.tan(a) ** 2
        if abs(a_new - a) < 1e-16:
            return a_new
        a = a_new
    return a


def read_model(path: Path) -> Model:
    root = ET.parse(path).getroot()
    parent_of: dict[str, tuple[str, tuple[float, float, float], str]] = {}
    for j in root.findall("joint"):
        o = j.find("origin")
        xyz = tuple(float(v) for v in o.get("xyz", "0 0 0").split()) if o is not None else (0, 0, 0)
        rpy = tuple(float(v) for v in o.get("rpy", "0 0 0").split()) if o is not None else (0, 0, 0)
        if any(v != 0 for v in rpy):
            raise ValueError(f"{path.name}: joint {j.get('name')} is rotated")
        ax = j.find("axis")
        if ax is not None and [float(v) for v in ax.get("xyz").split()] != [0, 0, 1]:
            raise ValueError(f"{path.name}: joint {j.get('name')} not along z")
        child = j.find("child").get("link")
        parent_of[child] = (j.find("parent").get("link"), xyz, j.get("name"))  # type: ignore[arg-type]

    def origin(link: str) -> tuple[float, float, float]:
        if link not in parent_of:
            return (0.0, 0.0, 0.0)
        p, xyz, _ = parent_of[link]
        po = origin(p)
        return (po[0] + xyz[0], po[1] + xyz[1], po[2] + xyz[2])

    gb = root.find("gearbox")
    gears = {}
    for g in gb.findall("gear"):  # type: ignore[union-attr]
        internal = g.get("internal", "false") == "true"
        z = int(g.get("teeth"))  # type: ignore[arg-type]
        gears[g.get("name")] = GearData(
            name=g.get("name"),  # type: ignore[arg-type]
            link=g.get("link"),  # type: ignore[arg-type]
            z=-z if internal else z,
            mn=float(g.get("module_mm")) * 1e-3,  # type: ignore[arg-type]
            alpha_n=math.radians(float(g.get("pressure_angle_deg", "20"))),
            beta=math.radians(float(g.get("helix_angle_deg", "0"))),
            x=float(g.get("profile_shift", "0")),
            k_mn=float(g.get("tip_alteration_mm", "0")) * 1e-3,
            b=float(g.get("face_width_mm")) * 1e-3,  # type: ignore[arg-type]
            internal=internal,
            xyz=tuple(float(v) for v in g.get("xyz", "0 0 0").split()),  # type: ignore[arg-type]
        )
    meshes = [(m.get("name"), m.get("gear1"), m.get("gear2")) for m in gb.findall("mesh")]  # type: ignore[union-attr]
    links = {lk.get("name") for lk in root.findall("link")}
    joint_of_link = {c: v[2] for c, v in parent_of.items()}
    return Model(
        path.stem,
        path,
        gears,
        meshes,  # type: ignore[arg-type]
        joint_of_link,
        {lk: origin(lk) for lk in links},  # type: ignore[misc]
    )


def centre(model: Model, g: GearData) -> tuple[float, float, float]:
    o = model.link_origin[g.link]
    return (o[0] + g.xyz[0], o[1] + g.xyz[1], o[2] + g.xyz[2])


def iso_pair(g1: GearData, g2: GearData) -> tuple[float, float]:
    """(α_wt, a_w) of ISO 21771 with signed tooth numbers."""
    zs = g1.z + g2.z
    awt = inv_inverse(inv(g1.alpha_t) + 2 * math.tan(g1.alpha_n) * (g1.x + g2.x) / zs)
    aw = abs(g1.mt * zs / 2 * math.cos(g1.alpha_t) / math.cos(awt))
    return awt, aw


def recode_mesh(model: Model, g1: GearData, g2: GearData) -> dict[str, float]:
    assert not g1.internal, "every shipped mesh has an external gear 1"
    awt, aw = iso_pair(g1, g2)
    ca, cb = centre(model, g1), centre(model, g2)
    a_bear = math.hypot(cb[0] - ca[0], cb[1] - ca[1])
    rb1, rb2 = g1.rb, g2.rb
    cos_a = ((rb2 - rb1) if g2.internal else (rb1 + rb2)) / a_bear
    a_prime = math.acos(cos_a)
    e = math.sqrt(g1.ra**2 - rb1**2)
    if g2.internal:
        start = math.sqrt(g2.ra**2 - rb2**2) - aw * math.sin(awt)
    else:
        start = aw * math.sin(awt) - math.sqrt(g2.ra**2 - rb2**2)
    g_alpha = e - start
    pbt = math.pi * g1.mt * math.cos(g1.alpha_t)
    b = min(g1.b, g2.b)
    return {
        "alpha_wt (involute) [rad]": awt,
        "a_w ISO 21771 [m]": aw,
        "a' bearings [m]": a_bear,
        "alpha' at a' [rad]": a_prime,
        "r_b A [m]": rb1,
        "r_b B [m]": rb2,
        "r_w A at a' [m]": rb1 / cos_a,
        "r_w B at a' [m]": rb2 / cos_a,
        "pitch fraction mu": (-1 if g2.internal else 1) * (rb1 / cos_a) / a_bear,
        "r_a 1 [m]": g1.ra,
        "r_a 2 [m]": g2.ra,
        "p_bt [m]": pbt,
        "T1A start [m]": start,
        "T1C pitch [m]": rb1 * math.tan(awt),
        "g_alpha [m]": g_alpha,
        "eps_alpha": g_alpha / pbt,
        "single start [m]": g_alpha - pbt,
        "single end [m]": pbt,
        "eps_beta": b * math.sin(abs(g1.beta)) / (math.pi * g1.mn),
        "beta_b A [rad]": g1.beta_b,
        "helix beta A [rad]": g1.beta,
    }


def path_at_bearings(model: Model, g1: GearData, g2: GearData) -> tuple[float, float]:
    """(g_α at ISO 21771's a_w, g_α at the bearings' a′): the same tips and base circles, the
    line of action's T_1T_2 = a sin α at either centre distance (not compared: pinwind's path
    of contact is at a_w, the forces' α′ at a′; informational)."""
    awt, aw = iso_pair(g1, g2)
    a_prime = bearing_pair(model, g1, g2)
    ca, cb = centre(model, g1), centre(model, g2)
    a_bear = math.hypot(cb[0] - ca[0], cb[1] - ca[1])
    e1 = math.sqrt(g1.ra**2 - g1.rb**2)
    e2 = math.sqrt(g2.ra**2 - g2.rb**2)
    s = -1.0 if g2.internal else 1.0
    return e1 + s * e2 - s * aw * math.sin(awt), e1 + s * e2 - s * a_bear * math.sin(a_prime)


def pinwind_mesh(gb, name: str) -> dict[str, float]:  # type: ignore[no-untyped-def]
    m = gb.mesh(name) if callable(getattr(gb, "mesh", None)) else None
    if m is None:
        m = next(mm for mm in gb.meshes if mm.name == name)
    p = m.path
    import pinwind.gears as G

    sa = m.gear_a.spec
    sb = m.gear_b.spec
    pg = G.pair_geometry(
        sa.teeth,
        sb.teeth,
        module=sa.module,
        pressure_angle=sa.pressure_angle,
        profile_shift_1=sa.profile_shift,
        profile_shift_2=sb.profile_shift,
        helix_angle=sa.helix_angle,
        internal_1=sa.internal,
        internal_2=sb.internal,
    )
    return {
        "alpha_wt (involute) [rad]": p.working_pressure_angle,
        "a_w ISO 21771 [m]": pg.centre_distance,
        "a' bearings [m]": m.centre_distance,
        "alpha' at a' [rad]": m.working_pressure_angle,
        "r_b A [m]": m.base_radius_a,
        "r_b B [m]": m.base_radius_b,
        "r_w A at a' [m]": m.working_radius_a,
        "r_w B at a' [m]": m.working_radius_b,
        "pitch fraction mu": m.pitch_fraction,
        "r_a 1 [m]": p.tip_radius_1,
        "r_a 2 [m]": p.tip_radius_2,
        "p_bt [m]": p.base_pitch,
        "T1A start [m]": p.start_roll_1,
        "T1C pitch [m]": p.pitch_roll_1,
        "g_alpha [m]": p.length,
        "eps_alpha": p.contact_ratio,
        "single start [m]": p.single_start,
        "single end [m]": p.single_end,
        "eps_beta": p.overlap_ratio,
        "beta_b A [rad]": G.base_helix_angle(sa.pressure_angle, sa.helix_angle),
        "helix beta A [rad]": m.helix_angle,
    }


def planet_positions(model: Model) -> list[tuple[str, float, float]]:
    """(quantity, pinwind's file position, recoded) for planet centres and parallel pinions."""
    rows: list[tuple[str, float, float]] = []
    mesh_name, a_src = PLANET_RADIUS_MESH.get(model.stem, (None, None))
    if mesh_name is None:
        return rows

    def place(prefix: str, planets: list[str], radius: float) -> None:
        n = len(planets)
        for i, p in enumerate(planets):
            c = centre(model, model.gears[p])
            psi = 2 * math.pi * i / n
            rows.append((f"{prefix}{p} x [m]", c[0], radius * math.cos(psi)))
            rows.append((f"{prefix}{p} y [m]", c[1], radius * math.sin(psi)))

    if model.stem == "nrel5mw_gearbox":
        place("", [f"stage1_planet{i}" for i in (1, 2, 3)], 0.863)
        place("", [f"stage2_planet{i}" for i in (1, 2, 3)], NREL_STAGE2_RADIUS)
        w, p = (
            centre(model, model.gears["stage3_wheel"]),
            centre(model, model.gears["stage3_pinion"]),
        )
        rows.append(("stage3_pinion y - wheel y [m]", p[1] - w[1], NREL_STAGE3_DISTANCE))
        return rows
    first = next(m for m in model.meshes if m[0] == mesh_name)
    if a_src is None:
        a_src = iso_pair(model.gears[first[1]], model.gears[first[2]])[1]
    planets = sorted({g for m in model.meshes for g in m[1:] if g.startswith("planet")})
    planets = [p for p in planets if not p.endswith("_b")]  # one gear per compound planet
    place("", planets, a_src)
    for mname, w_name, p_name in model.meshes:
        if mname.startswith("stage"):
            w, p = centre(model, model.gears[w_name]), centre(model, model.gears[p_name])
            a = iso_pair(model.gears[w_name], model.gears[p_name])[1]
            rows.append((f"{p_name} y - {w_name} y [m]", p[1] - w[1], a))
            rows.append((f"{p_name} x - {w_name} x [m]", p[0] - w[0], 0.0))
    return rows


def half_tooth_angle_at(g: GearData, awt: float) -> float:
    """ψ(r_w) of an external gear on its working pitch circle (ISO 21771)."""
    assert not g.internal
    return (math.pi / 2 + 2 * g.x * math.tan(g.alpha_n)) / abs(g.z) + inv(g.alpha_t) - inv(awt)


def _u(model: Model, g: GearData, phi: float, p: tuple[float, float], along_t: bool) -> float:
    c = centre(model, g)
    theta = math.atan2(p[1] - c[1], p[0] - c[0])
    u = (phi - theta) * abs(g.z) / (2 * math.pi)
    return u if along_t else -u


def bearing_pair(model: Model, g1: GearData, g2: GearData) -> float:
    """α′ at the bearings' centre distance a′ (docs/model_format.md, "Checks when loading")."""
    ca, cb = centre(model, g1), centre(model, g2)
    a_bear = math.hypot(cb[0] - ca[0], cb[1] - ca[1])
    return math.acos(((g2.rb - g1.rb) if g2.internal else (g1.rb + g2.rb)) / a_bear)


def recode_phases(model: Model, at: str = "bearings") -> tuple[dict[str, float], dict[str, float]]:
    """Tooth-centre angles of every gear (recoded) and each closing mesh's interlock residual
    [pitches]; the working pitch circles at the bearings' a′ (``at="bearings"``) or at ISO
    21771's a_w (``at="iso"``)."""
    phase: dict[str, float] = {}
    residual: dict[str, float] = {}
    for name, n1, n2 in model.meshes:
        g1, g2 = model.gears[n1], model.gears[n2]
        awt = bearing_pair(model, g1, g2) if at == "bearings" else iso_pair(g1, g2)[0]
        ca, cb = centre(model, g1), centre(model, g2)
        d = (cb[0] - ca[0], cb[1] - ca[1])
        dn = math.hypot(*d)
        rw1 = g1.rb / math.cos(awt)
        s = -1.0 if g2.internal else 1.0
        p = (ca[0] + s * rw1 * d[0] / dn, ca[1] + s * rw1 * d[1] / dn)
        if n1 not in phase and n2 not in phase:
            phase[n1] = -half_tooth_angle_at(g1, awt)  # flank on the link's x axis
        along_b = g2.internal
        if n1 in phase and n2 not in phase:
            u1 = _u(model, g1, phase[n1], p, True)
            u2 = u1 + 0.5  # a space of B faces A's tooth centre
            c = centre(model, g2)
            theta = math.atan2(p[1] - c[1], p[0] - c[0])
            du = u2 if along_b else -u2
            phase[n2] = theta + du * 2 * math.pi / abs(g2.z)
        elif n2 in phase and n1 not in phase:
            u2 = _u(model, g2, phase[n2], p, along_b)
            c = centre(model, g1)
            theta = math.atan2(p[1] - c[1], p[0] - c[0])
            phase[n1] = theta + (u2 - 0.5) * 2 * math.pi / abs(g1.z)
        else:
            u1 = _u(model, g1, phase[n1], p, True)
            u2 = _u(model, g2, phase[n2], p, along_b)
            r = (u2 - u1 - 0.5) % 1.0
            residual[name] = min(r, 1 - r)
    return phase, residual


def planetary_stages(model: Model) -> list[tuple[str, str, list[tuple[str, str]]]]:
    """(sun, ring, [(planet gear on the sun, planet gear on the ring)] in planet order)."""
    stages = []
    suns = [g for g in model.gears if g.endswith("sun")]
    for sun in suns:
        on_sun = [m[2] for m in model.meshes if m[1] == sun]
        pairs = []
        ring = ""
        for p in on_sun:
            link = model.gears[p].link
            for _, a, b in model.meshes:
                if model.gears[a].link == link and model.gears[b].internal:
                    pairs.append((p, a))
                    ring = b
        stages.append((sun, ring, pairs))
    return stages


def mesh_phases(model: Model, phases: dict[str, float]) -> list[tuple[str, str, float, float]]:
    """Parker & Lin (2004) mesh phases from pinwind's tooth phases against the closed forms of
    docs/model_format.md ("Tooth phases"), in mesh periods.

    In the carrier's frame each planet turns negatively (the sun positively), so a planet
    tooth's flank at angle φ_f reaches a pitch point at angle θ_P (seen from the planet's centre)
    after τ = frac((φ_f − θ_P) Z_p/2π) mesh periods; the planet's flank that leads its turn
    (φ − ψ_w) is taken on the sun mesh, the other (φ + ψ_w) on the ring mesh, ψ_w its half tooth
    angle on that mesh's working pitch circle at a′. A mesh leads another by frac(τ_other − τ).
    Compared: sun–planet mesh of planet i against planet 1's, frac(−Z_s ψ_i/2π); ring–planet,
    frac(Z_r ψ_i/2π) (ψ_i the planet's angle about the carrier axis)."""
    out: list[tuple[str, str, float, float]] = []
    for sun, ring, pairs in planetary_stages(model):
        zs, zr = abs(model.gears[sun].z), abs(model.gears[ring].z)
        tau_s, tau_r, psi = [], [], []
        for ps, pr in pairs:
            for gname, mate, flank, tau in ((ps, sun, -1, tau_s), (pr, ring, +1, tau_r)):
                g = model.gears[gname]
                m = model.gears[mate]
                c, cm = centre(model, g), centre(model, m)
                theta_p = math.atan2(cm[1] - c[1], cm[0] - c[0])
                if m.internal:
                    theta_p += math.pi  # P beyond the planet, away from the ring's centre
                psi_w = half_tooth_angle_at(g, bearing_pair(model, g, m))
                f = phases[gname] + flank * psi_w
                tau.append(((f - theta_p) * abs(g.z) / (2 * math.pi)) % 1.0)
            c = centre(model, model.gears[ps])
            psi.append(math.atan2(c[1], c[0]))
        for i in range(1, len(pairs)):
            lead_s = (tau_s[0] - tau_s[i]) % 1.0
            lead_r = (tau_r[0] - tau_r[i]) % 1.0
            exp_s = (-zs * psi[i] / (2 * math.pi)) % 1.0
            exp_r = (zr * psi[i] / (2 * math.pi)) % 1.0
            lead_s += round(exp_s - lead_s)  # the same phase, the branch nearest the closed form
            lead_r += round(exp_r - lead_r)
            out.append((pairs[i][0], "sun mesh phase vs planet 1 [period]", lead_s, exp_s))
            out.append((pairs[i][1], "ring mesh phase vs planet 1 [period]", lead_r, exp_r))
    return out


def angle_diff(a: float, b: float, z: int) -> float:
    """|a − b| modulo one angular pitch 2π/|z| [rad]."""
    p = 2 * math.pi / abs(z)
    d = (a - b) % p
    return min(d, p - d)


def info_alpha_w(path: Path) -> dict[str, tuple[float, float]]:
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "info", str(path)],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    ).stdout
    return {
        m.group(1): (float(m.group(2)), float(m.group(3)))
        for m in re.finditer(r"mesh (\S+): .*a_w = ([0-9.]+) mm, α_w = ([0-9.]+)°", out)
    }


@dataclass
class Row:
    model: str
    item: str
    quantity: str
    pinwind: float
    recoded: float
    absolute: bool = False  # phases and offsets that should be 0: the difference itself

    @property
    def diff(self) -> float:
        """Relative difference |pinwind − recoded| / |recoded|, or the absolute one."""
        if self.absolute or self.recoded == 0.0:
            return abs(self.pinwind - self.recoded)
        return abs(self.pinwind - self.recoded) / abs(self.recoded)


STEEL = 7850.0  # kg/m³, docs/model_format.md "Checks when loading"


def teeth_inertia_bound(model: Model, link: str) -> float:
    """The plausibility check's lower bound of a link's axial inertia (docs/model_format.md,
    "Checks when loading"): each external gear's teeth fill half the ring between its root
    circle r − 1.25 m and its tip circle r + m (ISO 53 basic rack, pitch radius r = z m_t/2),
    all of their mass at the root circle: ½ ρ π b ((r + m)² − (r − 1.25 m)²) (r − 1.25 m)²."""
    total = 0.0
    for g in model.gears.values():
        if g.link == link and not g.internal:
            ro, ri = g.r + g.mn, g.r - 1.25 * g.mn
            total += 0.5 * STEEL * math.pi * g.b * (ro**2 - ri**2) * ri**2
    return total


def compare(models: list[Path] | None = None, cli: bool = True) -> list[Row]:
    import warnings

    import pinwind

    rows: list[Row] = []
    for path in models or MODELS:
        model = read_model(path)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            gb = pinwind.load(str(path))
        for w in caught:
            hit = re.search(
                r'<link name="(\w+)">: axial inertia .*? teeth alone give, ([0-9.e-]+) kg',
                str(w.message),
            )
            if hit:
                rows.append(
                    Row(
                        model.stem,
                        hit.group(1),
                        "teeth-alone inertia bound [kg m2]",
                        float(hit.group(2)),
                        float(f"{teeth_inertia_bound(model, hit.group(1)):.4g}"),
                    )
                )
        for name, n1, n2 in model.meshes:
            rec = recode_mesh(model, model.gears[n1], model.gears[n2])
            pw = pinwind_mesh(gb, name)
            for q, v in rec.items():
                rows.append(Row(model.stem, name, q, pw[q], v))
        if cli:
            for name, (mm, deg) in info_alpha_w(path).items():
                n1, n2 = next((m[1], m[2]) for m in model.meshes if m[0] == name)
                rec = recode_mesh(model, model.gears[n1], model.gears[n2])
                a_mm = round(rec["a' bearings [m]"] * 1e3, 4)
                rows.append(Row(model.stem, name, "info a_w = a' [mm, 4 dp]", mm, a_mm))
                a_deg = round(math.degrees(rec["alpha' at a' [rad]"]), 4)
                rows.append(Row(model.stem, name, "info alpha_w = alpha' [deg, 4 dp]", deg, a_deg))
        for q, pv, rv in planet_positions(model):
            rows.append(Row(model.stem, "layout", q, pv, rv))
        for at in ("bearings", "iso"):
            phases, residual = recode_phases(model, at)
            for g, phi in phases.items():
                # compared modulo one pitch: the difference of the two, wrapped
                d = angle_diff(gb.tooth_phases[g], phi, model.gears[g].z)
                rows.append(Row(model.stem, g, f"|tooth phase diff| at {at} [rad]", d, 0.0, True))
            for name, r in residual.items():
                rows.append(
                    Row(model.stem, name, f"loop interlock residual at {at} [pitch]", r, 0.0, True)
                )
        for item, q, pv, rv in mesh_phases(model, gb.tooth_phases):
            rows.append(Row(model.stem, item, q, pv, rv, True))
    return rows


def main() -> None:
    full = "--full" in sys.argv[1:]
    rows = compare()
    if full:
        head = (
            f"{'model':21s} {'item':20s} {'quantity':42s} {'pinwind':>19s} {'recoded':>19s}"
            f" {'diff':>8s}"
        )
        print(head + "  (diff relative; absolute where marked *)")
        for r in rows:
            mark = "*" if r.absolute or r.recoded == 0.0 else " "
            print(
                f"{r.model:21s} {r.item:20s} {r.quantity:42s} {r.pinwind:19.12g}"
                f" {r.recoded:19.12g} {r.diff:8.1e}{mark}"
            )
        print()
    worst: dict[str, Row] = {}
    count: dict[str, int] = {}
    for r in rows:
        key = r.quantity if r.item != "layout" else "layout: " + r.quantity.split()[-2]
        count[key] = count.get(key, 0) + 1
        if (
            key not in worst
            or r.diff > worst[key].diff
            or (r.diff == worst[key].diff and abs(r.recoded) > abs(worst[key].recoded))
        ):  # ties: the largest value (a helical mesh's ε_β rather than a spur mesh's 0)
            worst[key] = r
    print(
        f"{len(rows)} comparisons over {len(MODELS)} models; per quantity the largest difference"
        " (relative; * absolute) and where (--full: every row)"
    )
    print(f"{'quantity':44s} {'n':>4s} {'pinwind':>17s} {'recoded':>17s} {'diff':>8s}  where")
    for q, r in worst.items():
        mark = "*" if r.absolute or r.recoded == 0.0 else " "
        print(
            f"{q:44s} {count[q]:4d} {r.pinwind:17.11g} {r.recoded:17.11g} {r.diff:8.1e}{mark}"
            f" {r.model} {r.item}"
        )
    print("\nnot compared: the path of contact at the bearings' a' instead of ISO 21771's a_w")
    print(
        f"{'model':21s} {'mesh':20s} {'a_w [mm]':>9s} {'a_prime [mm]':>12s}"
        f" {'g_a(a_w) [mm]':>13s} {'g_a(a_prime)':>12s} {'rel':>8s}"
    )
    seen = set()
    for path in MODELS:
        model = read_model(path)
        for name, n1, n2 in model.meshes:
            g1, g2 = model.gears[n1], model.gears[n2]
            aw = iso_pair(g1, g2)[1]
            ca, cb = centre(model, g1), centre(model, g2)
            ab = math.hypot(cb[0] - ca[0], cb[1] - ca[1])
            ga, gb_ = path_at_bearings(model, g1, g2)
            key = (model.stem, round(aw, 12), round(ab, 12), round(ga, 12))
            if abs(gb_ - ga) > 1e-9 * ga and key not in seen:  # one planet per stage
                seen.add(key)
                print(
                    f"{model.stem:21s} {name:20s} {aw * 1e3:9.4f} {ab * 1e3:12.4f}"
                    f" {ga * 1e3:13.4f} {gb_ * 1e3:12.4f} {abs(gb_ - ga) / ga:8.1e}"
                )


if __name__ == "__main__":
    main()
