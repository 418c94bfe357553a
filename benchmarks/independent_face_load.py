"""The load across the face width of sliced meshes in two logged runs, recoded without pinwind's
face-load code.

Runs (logged, read back with ``pinwind.read_log``):

- **S**: the Saleh 2017 planetary (spur, 24/48/120 teeth, m = 15 mm, α = 24.5°, b = 380 mm) at its
  rated point (carrier 1 MN·m at 14.2 rpm, sun −166 666.7 N·m), every mesh compliant with a
  constant mesh stiffness c̄ = 7.6·10⁹ N/m (``mean_stiffness``, ``stiffness_variation="constant"``,
  ≈ 20 N/(mm·µm) × b) and cut into N = 8 slices; planet 1 with a helix slope deviation
  f_Hβ = 30 µm (its sun mesh carries over the whole face: ISO's linear distribution), planet 2
  with f_Hβ = 150 µm (its sun mesh lifts off over part of the face), planet 3 with a lead
  crowning C_β = 25 µm, the ring with C_β = 125 µm (planet 3's ring mesh: a crowning of 150 µm
  whose ends lift off). 0.1 s at dt = 5·10⁻⁵ s, every step logged.
- **N**: the NREL 5 MW gearbox at rated (rotor 3 945 990 N·m at 12.1 rpm against the generator's
  balancing torque), every mesh compliant and cut into slices, the helical stage 3 (95/24 teeth,
  β = 10°, b = 360 mm) with N = 10 slices whose stiffness follows the inclined contact lines
  (``stiffness_variation="path"``, ``mean_stiffness`` c̄ = 7.2·10⁹ N/m given so that it is model
  data), no mesh damping on it, the pinion with f_Hβ = 20 µm and C_β = 10 µm, the wheel with
  f_Hβ = 5 µm and an end relief of 15 µm over 40 mm at each face end. 0.2 s at dt = 5·10⁻⁵ s.
  Stage 3's shafts on ideal bearings (θ = 0), once more with both torques reversed (the
  generator driving: the back flanks carry), and again forwards on their shipped compliant
  bearings (the gears tilt; every sample's link poses logged).

The recoding takes only the model's data (the gears' lead modifications read from the model
text with ``xml.etree``, the mesh's c̄ and N) and the logged normal force F of the loaded flank
(``mesh_normal``, with ``mesh_flank`` naming the flank), and follows docs/flank_modifications.md
and the spring-bed (Winkler) model of a face: N independent springs of stiffness k_s, each
behind its gap e_s, pressed by one approach δ, carrying k_s max(0, δ − e_s):

- each slice's gap e_s at ζ_s = (s + ½) b/N from side I: crowning C_β (2ζ/b − 1)², a helix slope
  deviation f_Hβ ζ/b on the front flank and f_Hβ (1 − ζ/b) on the back flank, an end relief C
  (1 − d/L)₊ at the distance d from the nearer face end (docs/model_format.md), summed over both
  gears (the gears turn on rigid bearings, so their relative tilt θ is 0);
- the spring-bed solution for δ from Σ_s k_s (δ − e_s)₊ = F (exactly: the slices sorted by gap,
  the loaded set grown until δ falls below the next gap), each slice's line load
  w_s = N k_s (δ − e_s)₊ / b, the peak line load, the mean F/b, K_Hβ = w_max/w_m and the load
  centre Σ F_s z_s / F;
- the slice stiffness: the spur meshes' c̄/N; the helical slices' n_s c̄ p_bt/(g_α N), n_s the
  tooth pairs on slice s, at roll positions q_s + j p_bt in [0, g_α] from the start of the path A,
  q_s = y − ζ_s tan β_b on the front flank and y − (b − ζ_s) tan β_b on the back flank
  (docs/flank_modifications.md "Helical slices"), y = the logged ``mesh_contact_position`` (from
  gear A's base tangency point) less the distance from there to A. The involute geometry (g_α,
  p_bt, β_b, where A lies) is the independent rating recoding's (benchmarks/independent_rating.py,
  ISO 21771).

Closed forms. ISO 6336-1 writes the face load factor of a linear distribution over the whole face
as K_Hβ = 1 + F_βy c_γβ / (2 F_m/b) (the form as an open ISO 6336 routine prints it, "eq. 41":
``KHbeta = 1 + (F_betay*c_gammabeta)/(2*(Fm/b))``, F_m/b the line load, c_γβ per unit face
width). With c_γβ = c̄/b and F_m = F this is 1 + F_β c̄/(2F). ISO's form for a contact over part
of the face (K_Hβ > 2) was not found in a readable public source and is not quoted; the spring
bed gives it (derived here, the line load of a linear gap F_β ζ/b pressed by δ): loaded length
L = √(2 F b/(c F_β)), K_Hβ = √(2 F_β c̄/F). A crowning C_β over the whole face: w(ζ) =
c (δ − C_β u²), u = 2ζ/b − 1, so K_Hβ = 1 + c̄ C_β/(3F); with its ends lifting (C_β u₀² = δ):
K_Hβ = 3/(2 u₀), u₀ = (3F/(2 c̄ C_β))^(1/3). N slices sample the continuous distribution at
their centres: for the linear whole-face case exactly K_N = 1 + (c̄ F_β/(2F))(1 − 1/N), ISO's
less (K − 1)/N; the other cases differ from the continuum by the slices' width.

The tilting run: θ = (k × k_B)·(k × n) from the logged link poses (docs/flank_modifications.md
"Sliced meshes"; k, k_B the gears' axes, n = s cos α_w t + sin α_w u the flank's line of action,
u from A's centre to B's, t = k × u, cos α_w = (r_b,A + r_b,B)/a at the sample's centre
distance). A sample's force is the step's mean of the forces at its two ends (generalized-α at
ρ∞ = 1, the default), so θ is taken midway, ½ (θ_i + θ_{i+1}); the pairs are those at the
step's start (sample i). Row "+ spin as tilt" adds what pinwind's slice row counts as tilt
over the half step, ½ dt ω_B (k × n)·k_B: gear B's spin ω_B about its own, tilted, axis, which
does not change θ (d/dt of (k × k_B)·(k × n) is ω_B·(k_B × n) − ω_A·(k × n) to first order,
free of either gear's spin), but which the row's tilt rate (k × n)·(ω_B − ω_A) includes.

The comparison: the recoded line loads, peak, mean, K_Hβ and load centre against the run's series
(``slice_line_load``, ``mesh_peak_line_load``, ``mesh_mean_line_load``, ``mesh_face_load_factor``,
``mesh_load_centre``) at every logged sample, and the K_Hβ ``pinwind rate --from-log LOG
--face-load-factor run-max`` / ``run-at`` uses against the recoding's largest over the loaded
samples and its value at the last sample.

Run:  python benchmarks/independent_face_load.py
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))

from independent_rating import pair, read_gears  # noqa: E402  (the ISO 21771 geometry)

import pinwind  # noqa: E402
from pinwind.dynamics.ratios import train_speeds  # noqa: E402
from pinwind.model.gearbox import loads  # noqa: E402

UM = 1e-6
SPUR_MODEL = REPO / "models" / "saleh2017_planetary.urdf"
HELICAL_MODEL = REPO / "models" / "nrel5mw_gearbox.urdf"
SPUR_STIFFNESS, SPUR_SLICES = 7.6e9, 8
HELICAL_STIFFNESS, HELICAL_SLICES = 7.2e9, 10
#: the runs' time step [s]
DT = 5e-5
#: the lead modifications given to the shipped models' gears [µm]
SPUR_LEAD = {
    "planet1": {"helix_slope_deviation_um": 30.0},
    "planet2": {"helix_slope_deviation_um": 150.0},
    "planet3": {"crowning_um": 25.0},
    "ring": {"crowning_um": 125.0},
}
HELICAL_LEAD = {
    "stage3_pinion": {"helix_slope_deviation_um": 20.0, "crowning_um": 10.0},
    "stage3_wheel": {
        "helix_slope_deviation_um": 5.0,
        "end_relief_um": 15.0,
        "end_relief_length_mm": 40.0,
    },
}


def with_attributes(text: str, tag: str, name: str, attributes: dict[str, object]) -> str:
    """The model text with ``attributes`` added to the element ``<tag name="name" .../>``."""
    extra = " ".join(f'{key}="{value}"' for key, value in attributes.items())
    new, count = re.subn(rf'(<{tag} name="{name}"[^>]*?)\s*/>', rf"\1 {extra} />", text)
    if count != 1:
        raise RuntimeError(f"<{tag} name={name}> found {count} times")
    return new


# ------------------------------------------------------------------------------------- recoding
@dataclass
class Lead:
    """One gear's lead modifications [m] (docs/model_format.md)."""

    crowning: float = 0.0
    slope: float = 0.0
    end_relief: float = 0.0
    end_length: float = 0.0


def read_leads(text: str) -> dict[str, Lead]:
    out = {}
    for g in ET.fromstring(text).iter("gear"):
        a = g.attrib
        out[a["name"]] = Lead(
            crowning=float(a.get("crowning_um", "0")) * UM,
            slope=float(a.get("helix_slope_deviation_um", "0")) * UM,
            end_relief=float(a.get("end_relief_um", "0")) * UM,
            end_length=float(a.get("end_relief_length_mm", "0")) * 1e-3,
        )
    return out


def slice_gaps(leads: list[Lead], b: float, n: int, flank: float) -> np.ndarray:
    """Both gears' lead gap at the N slice centres [m], side I first, on flank s = ±1."""
    zeta = (np.arange(n) + 0.5) * b / n
    u = 2 * zeta / b - 1
    slope = zeta / b if flank > 0 else 1 - zeta / b
    total = np.zeros(n)
    for g in leads:
        total += g.crowning * u**2 + g.slope * slope
        if g.end_relief:
            # C at each face end, falling linearly to 0 over its length L
            end = np.minimum(zeta, b - zeta)
            total += g.end_relief * np.maximum(0.0, 1 - end / g.end_length)
    return total


def spring_bed(force: float, k: np.ndarray, e: np.ndarray) -> tuple[float, np.ndarray]:
    """δ and each spring's force of springs k behind gaps e pressed to carry ``force``.

    Σ k_s (δ − e_s)₊ = F solved exactly: with the springs sorted by gap, the loaded set is the
    first m for the largest m whose δ_m = (F + Σ_{<m} k e)/Σ_{<m} k reaches e_{m−1}.
    """
    if force <= 0:
        return 0.0, np.zeros_like(e)
    order = np.argsort(e, kind="stable")
    ks, es = k[order], e[order]
    delta = math.nan
    sum_k = sum_ke = 0.0
    for m in range(len(es)):
        if ks[m] <= 0:
            continue
        if sum_k > 0 and (force + sum_ke) / sum_k <= es[m]:
            break
        sum_k += ks[m]
        sum_ke += ks[m] * es[m]
        delta = (force + sum_ke) / sum_k
    return delta, k * np.maximum(delta - e, 0.0)


@dataclass
class _Series:
    flank: np.ndarray
    normal: np.ndarray
    face_load_factor: np.ndarray
    peak_line_load: np.ndarray
    mean_line_load: np.ndarray
    load_centre: np.ndarray


@dataclass
class Recoded:
    w: np.ndarray  # (samples, N) line loads [N/m]
    peak: np.ndarray
    mean: np.ndarray
    k_hb: np.ndarray
    centre: np.ndarray
    delta: np.ndarray


def recode(force, flank, b, n, stiffness, leads, z, tilt=None) -> Recoded:
    """The spring bed at each sample; ``stiffness(i, flank)`` gives the (N,) slice stiffnesses,
    ``tilt`` (samples,) the gears' relative tilt θ [rad] (δ_s = δ − z_s θ − e_s; default 0)."""
    samples = len(force)
    w = np.zeros((samples, n))
    delta = np.zeros(samples)
    for i in range(samples):
        e = slice_gaps(leads, b, n, flank[i])
        if tilt is not None:
            e = e + z * tilt[i]
        delta[i], f_s = spring_bed(float(force[i]), stiffness(i, flank[i]), e)
        w[i] = n * f_s / b
    peak = w.max(axis=1)
    mean = force / b
    with np.errstate(invalid="ignore", divide="ignore"):
        k_hb = np.where(force > 0, peak / mean, 0.0)
        centre = np.where(force > 0, (w * b / n) @ z / force, 0.0)
    return Recoded(w, peak, mean, k_hb, centre, delta)


def helical_stiffness(geo, c_bar, b, n, y):
    """Slice stiffnesses n_s c̄ p_bt/(g_α N) at roll y of the front section (docstring)."""
    p, g, tb = geo["pbt"], geo["g_alpha"], math.tan(geo["beta_b"])
    zeta = (np.arange(n) + 0.5) * b / n

    def at(i: int, flank: float) -> np.ndarray:
        lag = zeta * tb if flank > 0 else (b - zeta) * tb
        q = y[i] - lag
        # pairs j with 0 ≤ q + j p ≤ g
        count = np.floor((g - q) / p) - np.ceil(-q / p) + 1
        return count * c_bar * p / (g * n)

    return at


# ------------------------------------------------------------------------------------- runs
def spur_run(log: Path) -> tuple[pinwind.Result, str]:
    text = SPUR_MODEL.read_text()
    for mesh in re.findall(r'<mesh name="([^"]+)"', text):
        text = with_attributes(
            text,
            "mesh",
            mesh,
            {
                "type": "compliant",
                "slices": SPUR_SLICES,
                "mean_stiffness": SPUR_STIFFNESS,
                "stiffness_variation": "constant",
            },
        )
    for gear, attrs in SPUR_LEAD.items():
        text = with_attributes(text, "gear", gear, attrs)
    gb = loads(text, path=str(SPUR_MODEL))
    pinwind.simulate(
        gb,
        duration=0.1,
        dt=DT,
        torques={"carrier": 1e6, "sun": -166666.7},
        initial_speeds={"carrier": 14.2 * math.pi / 30},
        log=log,
        overwrite=True,
    )
    return pinwind.read_log(log), text


def helical_run(
    log: Path, *, tilting: bool = False, reverse: bool = False
) -> tuple[pinwind.Result, str]:
    """The 5 MW run (docstring); ``tilting``: stage 3's shafts on their shipped compliant
    bearings, every sample's link poses logged (for θ); ``reverse``: both torques reversed
    (the generator driving the rotor), which loads the back flanks."""
    text = HELICAL_MODEL.read_text()
    # stage 3's shafts on ideal bearings (their rows' stiffness and the bearings' compliance
    # dropped): the gears do not tilt, θ = 0
    for joint in () if tilting else ("ims", "hss"):
        text, count = re.subn(
            rf'<bearing joint="{joint}"[^>]*>.*?</bearing>',
            f'<bearing joint="{joint}" type="cylindrical_roller" />',
            text,
            flags=re.S,
        )
        if count != 1:
            raise RuntimeError(f"bearing {joint} found {count} times")
    for mesh in re.findall(r'<mesh name="([^"]+)"', text):
        attrs: dict[str, object] = {"type": "compliant", "slices": 4}
        if mesh == "stage3":
            attrs = {
                "type": "compliant",
                "slices": HELICAL_SLICES,
                "mean_stiffness": HELICAL_STIFFNESS,
                "damping": 0,
            }
        text = with_attributes(text, "mesh", mesh, attrs)
    for gear, attrs in HELICAL_LEAD.items():
        text = with_attributes(text, "gear", gear, attrs)
    gb = loads(text, path=str(HELICAL_MODEL))
    rotor_speed, rotor_torque = 12.1 * math.pi / 30, 3945990.0
    sign = -1.0 if reverse else 1.0
    speeds = train_speeds(gb, {"rotor": rotor_speed}, through_springs=True)
    ratio = speeds[gb.v_index("generator")] / rotor_speed
    pinwind.simulate(
        gb,
        duration=0.2,
        dt=DT,
        torques={"rotor": sign * rotor_torque, "generator": -sign * rotor_torque / ratio},
        initial_speeds={"rotor": rotor_speed, "lss": rotor_speed},
        log=log,
        overwrite=True,
        **({"pose_rate": None, "view_rate": None} if tilting else {}),
    )
    return pinwind.read_log(log), text


def g2_link(text: str, gear: str) -> str:
    """The link (and joint) name of a gear."""
    for g in ET.fromstring(text).iter("gear"):
        if g.attrib["name"] == gear:
            return g.attrib["link"]
    raise KeyError(gear)


def quaternion_rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate vectors v (n, 3) by unit quaternions q (n, 4), scalar last [x, y, z, w]."""
    u, w = q[:, :3], q[:, 3:4]
    t = 2 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def tilt_of(res: pinwind.Result, text: str, gear_a: str, gear_b: str, flank, geo) -> tuple:
    """θ = (k × k_B)·(k × n) at every sample from the logged link poses (docstring), and the
    rate ω_B (k × n)·k_B that gear B's spin about its tilted axis adds to (k × n)·(ω_B − ω_A).

    k, k_B: the gears' axes (their ``axis`` in their links, turned by the links' poses);
    n = s cos α_w t + sin α_w u on flank s, u the unit vector from A's centre to B's normal
    to k, t = k × u, cos α_w = (r_b,A + r_b,B)/a at the sample's centre distance a.
    """
    gears = {g.attrib["name"]: g.attrib for g in ET.fromstring(text).iter("gear")}
    axes, centres, links = [], [], []
    for name in (gear_a, gear_b):
        a = gears[name]
        body = res.body(a["link"])
        q = body.quaternion
        axis = np.tile([float(x) for x in a.get("axis", "0 0 1").split()], (len(q), 1))
        xyz = np.tile([float(x) for x in a.get("xyz", "0 0 0").split()], (len(q), 1))
        axes.append(quaternion_rotate(q, axis))
        centres.append(body.position + quaternion_rotate(q, xyz))
        links.append(a["link"])
    k, k_b = axes
    d = centres[1] - centres[0]
    d -= np.sum(d * k, axis=1)[:, None] * k
    a_w = np.linalg.norm(d, axis=1)
    u = d / a_w[:, None]
    cos_w = (geo["rb1"] + geo["rb2"]) / a_w
    n = np.asarray(flank)[:, None] * cos_w[:, None] * np.cross(k, u)
    n += np.sqrt(1 - cos_w**2)[:, None] * u
    theta = np.sum(np.cross(k, k_b) * np.cross(k, n), axis=1)
    lean = np.sum(np.cross(k, n) * k_b, axis=1)
    return theta, res.joint(links[1]).speed * lean, lean


def rate_face_load(log: Path, which: str) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", "--from-log", str(log)]
        + ["--face-load-factor", which, "--json"],
        check=True,
        capture_output=True,
        text=True,
        env=env,
        cwd=REPO,
    )
    data = json.loads(out.stdout)
    return {m["mesh"]: m["iso"]["factors"]["K_Hbeta"] for m in data["meshes"]}


# ------------------------------------------------------------------------------------- compare
def rel(a: np.ndarray, b: np.ndarray, scale: float) -> float:
    """Largest |a − b| over ``scale``."""
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) / scale


def main() -> None:
    t0 = time.perf_counter()
    rows: list[tuple] = []
    closed: list[tuple] = []
    tilts: list[float] = []
    with tempfile.TemporaryDirectory() as tmp:
        spur_log, helical_log = Path(tmp) / "spur.mcap", Path(tmp) / "helical.mcap"
        res, text = spur_run(spur_log)
        leads = read_leads(text)
        gears = read_gears(SPUR_MODEL)
        rated_max = rate_face_load(spur_log, "run-max")
        rated_at = rate_face_load(spur_log, "run-at")
        for mesh in res.mesh_names:
            g1, g2 = re.search(
                rf'<mesh name="{mesh}" gear1="([^"]+)" gear2="([^"]+)"', text
            ).groups()
            b = min(gears[g1].b, gears[g2].b)
            n = SPUR_SLICES
            z = (np.arange(n) + 0.5) * b / n - b / 2
            e = res.mesh(mesh)
            k = np.full(n, SPUR_STIFFNESS / n)
            r = recode(e.normal, e.flank, b, n, lambda i, f, k=k: k, [leads[g1], leads[g2]], z)
            compare(rows, f"S/{mesh}", res, mesh, r, z, b, rated_max, rated_at)
            closed_forms(closed, f"S/{mesh}", r, e, leads[g1], leads[g2], b, n, SPUR_STIFFNESS)

        g1, g2 = "stage3_wheel", "stage3_pinion"
        gears = read_gears(HELICAL_MODEL)
        geo = pair(gears[g1], gears[g2])
        b, n = geo["b"], HELICAL_SLICES
        z = (np.arange(n) + 0.5) * b / n - b / 2
        for label, reverse in (("N/stage3", False), ("N/stage3 back", True)):
            res, text = helical_run(helical_log, reverse=reverse)
            leads = read_leads(text)
            e = res.mesh("stage3")
            # the front section's roll from the start of the path A: the logged contact position
            # is the face centre section's, from gear A's (the wheel's) base tangency point; on
            # either flank (its slices lag by ζ_s tan β_b on the front, (b − ζ_s) tan β_b on the
            # back)
            y = e.contact_position - geo["rho1_a"] + b / 2 * math.tan(geo["beta_b"])
            stiff = helical_stiffness(geo, HELICAL_STIFFNESS, b, n, y)
            r = recode(e.normal, e.flank, b, n, stiff, [leads[g1], leads[g2]], z)
            rated_max = rate_face_load(helical_log, "run-max")
            rated_at = rate_face_load(helical_log, "run-at")
            compare(rows, label, res, "stage3", r, z, b, rated_max, rated_at)

        # the same with stage 3's shafts on their compliant bearings: the gears tilt
        res, text = helical_run(helical_log, tilting=True)
        e = res.mesh("stage3")
        y = e.contact_position - geo["rho1_a"] + b / 2 * math.tan(geo["beta_b"])
        stiff = helical_stiffness(geo, HELICAL_STIFFNESS, b, n, y)
        theta, spin, lean = tilt_of(res, text, g1, g2, e.flank, geo)
        # the moment the slices' forces would put on B's spin through a row that counted B's
        # spin as tilt: F z_c (k × n)·k_B
        moment = e.normal * e.load_centre * lean
        power = moment * res.joint(g2_link(text, g2)).speed
        # a sample's force is the step's mean of its forces at both ends (ρ∞ = 1): θ midway
        mid = np.append(0.5 * (theta[:-1] + theta[1:]), theta[-1])
        keep = slice(0, len(theta) - 1)
        rated_max = rate_face_load(helical_log, "run-max")
        rated_at = rate_face_load(helical_log, "run-at")
        for label, tilt in (
            ("N/stage3 tilting", mid),
            ("  + spin as tilt", mid + 0.5 * DT * spin),
        ):
            r = recode(e.normal, e.flank, b, n, stiff, [leads[g1], leads[g2]], z, tilt)
            compare(rows, label, res, "stage3", r, z, b, rated_max, rated_at, keep)
        tilts.append(float(np.max(np.abs(theta))))
        tilts.append(float(np.max(np.abs(0.5 * DT * spin))))
        tilts.append(float(np.mean(moment)))
        tilts.append(float(np.mean(power)))
    print_table(rows, closed)
    print(
        f"tilting run: |θ| up to {tilts[0]:.2e} rad; gear B's spin counted as tilt over half a"
        f" step, ½ dt ω_B (k × n)·k_B, up to {tilts[1]:.2e} rad (the step did until"
        f" 2026-12-08);\nthe moment F z_c (k × n)·k_B that counting would put on B's spin:"
        f" mean {tilts[2]:.3g} N·m, its power {tilts[3]:.3g} W"
    )
    print(f"({time.perf_counter() - t0:.0f} s)")


def compare(rows, label, res, mesh, r: Recoded, z, b, rated_max, rated_at, keep=None) -> None:
    """One row of the table: the recoding against the run's series at the samples ``keep``."""
    keep = slice(None) if keep is None else keep
    e = res.mesh(mesh)
    zp, wp = res.slice_line_loads(mesh)
    e = _Series(
        flank=e.flank[keep],
        normal=e.normal[keep],
        face_load_factor=e.face_load_factor[keep],
        peak_line_load=e.peak_line_load[keep],
        mean_line_load=e.mean_line_load[keep],
        load_centre=e.load_centre[keep],
    )
    wp = wp[keep]
    r = Recoded(*(getattr(r, f)[keep] for f in ("w", "peak", "mean", "k_hb", "centre", "delta")))
    loaded = e.normal > 0
    scale = float(np.max(r.mean))
    i_max = int(np.argmax(np.where(loaded, r.k_hb, 0.0)))
    rows.append(
        (
            label,
            float(r.k_hb[-1]),
            float(e.face_load_factor[-1]),
            rel(zp, z, b),
            rel(wp, r.w, scale),
            rel(e.peak_line_load, r.peak, scale),
            rel(e.mean_line_load, r.mean, scale),
            rel(e.face_load_factor[loaded], r.k_hb[loaded], 1.0),
            rel(e.load_centre[loaded], r.centre[loaded], b),
            float(r.k_hb[i_max]),
            rated_max[mesh] - float(r.k_hb[i_max]),
            # the last sample is left out where ``keep`` drops it (its θ needs the next sample)
            rated_at[mesh] - float(r.k_hb[-1]) if keep == slice(None) else math.nan,
            int(e.flank[-1]),
        )
    )


#: slices of the recoding's own spring bed at the run's last force, towards the continuum
FINE_SLICES = 20_000


def closed_forms(out, label, r: Recoded, e, lead1: Lead, lead2: Lead, b, n, c_bar) -> None:
    """The last sample's K_Hβ against the continuous and N-slice closed forms (docstring).

    Each row also gives the recoding's spring bed at the same force with FINE_SLICES and twice
    as many slices, extrapolated to N → ∞: the continuous closed form is its limit.
    """
    f = float(e.normal[-1])
    slope = lead1.slope + lead2.slope
    crown = lead1.crowning + lead2.crowning
    k = float(r.k_hb[-1])
    flank = float(e.flank[-1])
    gaps = [lead1, lead2]

    def fine(m: int) -> float:
        _, f_s = spring_bed(f, np.full(m, c_bar / m), slice_gaps(gaps, b, m, flank))
        return float(f_s.max() * m / f)

    # the N-slice value's error is O(1/N) where the peak sits at a face end: Richardson's
    # 2 K(2N) − K(N) removes it
    k_fine = 2 * fine(2 * FINE_SLICES) - fine(FINE_SLICES)
    if crown == 0 and slope:
        iso = 1 + slope * c_bar / (2 * f)
        if iso <= 2:
            out.append((label, "linear, whole face", k, 1 + (iso - 1) * (1 - 1 / n), k_fine, iso))
        else:
            cont = math.sqrt(2 * slope * c_bar / f)
            out.append((label, "linear, part of face", k, None, k_fine, cont))
    elif slope == 0 and crown:
        whole = 1 + c_bar * crown / (3 * f)
        delta = f / c_bar + crown / 3
        if delta >= crown:
            out.append((label, "crowning, whole face", k, None, k_fine, whole))
        else:
            u0 = (3 * f / (2 * c_bar * crown)) ** (1 / 3)
            out.append((label, "crowning, ends lift", k, None, k_fine, 3 / (2 * u0)))
    else:
        out.append((label, "crowning + slope", k, None, k_fine, None))


def print_table(rows, closed) -> None:
    head = (
        f"{'mesh':<16} {'s':>2} {'K_Hβ last':>9} {'pinwind':>9} {'Δz_s':>7} {'Δw_s':>7}"
        f" {'Δpeak':>7} {'Δmean':>7} {'ΔK_Hβ':>7} {'Δcentre':>7} {'K_Hβ max':>8}"
        f" {'Δrun-max':>8} {'Δrun-at':>8}"
    )
    print(head)
    for lab, k, kp, dz, dw, dp, dm, dk, dc, kmax, drm, dra, flank in rows:
        ra = f"{dra:+8.0e}" if not math.isnan(dra) else f"{'—':>8}"
        print(
            f"{lab:<16} {flank:+2d} {k:9.6f} {kp:9.6f} {dz:7.0e} {dw:7.1e} {dp:7.1e} {dm:7.1e}"
            f" {dk:7.1e} {dc:7.1e} {kmax:8.5f} {drm:+8.0e} {ra}"
        )
    print()
    print(
        f"{'mesh':<16} {'case':<21} {'K_Hβ, N slices':>14} {'N-slice form':>12} {'Δ':>8}"
        f" {'N → ∞':>13} {'continuum':>10} {'Δ':>8}"
    )
    for lab, case, k, disc, fine, cont in closed:
        ds = f"{disc:12.9f} {k / disc - 1:8.1e}" if disc is not None else f"{'—':>12} {'':>8}"
        cs = f"{cont:10.6f} {fine / cont - 1:8.1e}" if cont is not None else f"{'—':>10} {'':>8}"
        print(f"{lab:<16} {case:<21} {k:14.9f} {ds} {fine:13.6f} {cs}")


if __name__ == "__main__":
    main()
