"""The NREL 5 MW rotor above rated, recoded without pinwind's rotor, pitch-control or generator
code: the settled pitch and power, Jonkman's baseline pitch controller step by step, and the
aerodynamic torque of every sample.

Runs (``pinwind.runs.scenario``, no log) on ``models/nrel5mw_gearbox.urdf`` as shipped (rigid
meshes, the static start) at dt = 4e-4 s, with the rotor, pitch control and generator of
``scenarios/nrel5mw_turbulent.toml`` (the ``nrel5mw`` rotor preset on joint ``rotor``, its
``pitch_control = "nrel5mw"``, the ``variable-speed`` generator with K = 2.332287 N·m·s²,
T_r = 43 093.55 N·m, ω_r = 1161.963 rpm, 10 % slip on joint ``generator``), the rotor at 12.1 rpm
at the start:

- **hold** at 13, 16, 20 and 24 m/s: each started at the recoded settled pitch β*(v) (below). A
  run whose operating point is β* stays there; a β* off by δβ would leave an aerodynamic torque
  ∂τ/∂β δβ unbalanced and the controller would move the pitch by about δβ within a few of its
  time constants (ω_n ≈ 0.5 rad/s: seconds), so the pitch over the run's second half against β*
  measures the recoding's error, down to the drivetrain's own motion: the static start of this
  turning gearbox under gravity leaves the rotor joint at −9.7e-6 rad/s² (about 560 N·m on its
  5.72e7 kg·m², 1.3e-4 of the rotor torque, off balance), and its lightly damped torsion then
  moves the rotor speed by about 2e-6 rad/s, which the controller follows (≈ 1e-6 of the pitch);
- **scenario start**: 13 m/s from the pitch of ``scenarios/nrel5mw_turbulent.toml``, 6.474160°,
  which is the pitch of 5.2966 MW (ROSCO's rated power, at Jonkman's ratio 97) rather than of
  the 5.2613 MW this model's generator holds at 12.1 rpm (its ratio is 96.354): the run settles
  at β*(13) = 6.536°;
- **step**: 14 → 16 m/s at t = 5 s (a ``step`` wind signal), from β*(14 m/s): the controller's
  transient, replayed sample by sample;
- **small step**: 18 → 18.2 m/s at t = 0.2 s, against the loop linearised at β*(18 m/s) (the
  rotor's J δω̇ = ∂τ/∂ω δω + ∂τ/∂β δβ with the table's slopes, DISCON's filter and PI, dβ/du =
  1/(1 + 2β/θ_K) as GK follows the pitch), J the drivetrain's inertia on the rotor shaft from
  the run's kinetic energy at the start, 2T/ω² (rigid meshes: every body turns in ratio): its
  pair, and the same with Jonkman et al. 2009's inertia (rotor 38 759 236 kg·m² and generator
  534.116 kg·m² times 97²), which docs/loads.md's "as run" pair (0.47 rad/s, ζ 0.66) is.

Recoding, from public sources and the shipped data file only:

- the table: ROSCO's C_p(λ, β) of the NREL 5 MW rotor (``pinwind/loads/data/nrel5mw_cp_ct_cq.txt``,
  Abbas et al. 2022), parsed here, bilinear in (λ, β), held at its edges (docs/loads.md);
- the aerodynamic torque τ = ½ ρ π R² v³ C_p(λ, β) / ω, λ = ω R / v (Burton et al. 2011, Wind
  Energy Handbook §3.2-3.4: P = ½ ρ A U³ C_P), R = 63 m, ρ = 1.225 kg/m³ (Jonkman et al. 2009
  Table 1-1 and §2); the table's own torque coefficient is not used: ROSCO's C_q differs from
  C_p/λ by up to 5.6e-4 (1e-3 of its largest value);
- the torque over a step: τ at the step's mid speed ½ (ω_k + ω_{k+1}) (the step is linearly
  implicit in the laws of the shaft speed, docs/loads.md, and at ρ∞ = 1 its loads are mid-step
  loads), sample k's wind, the step's pitch; the last sample's step is not in the series;
- the generator above rated: the torque law of docs/loads.md, T = min(max(K ω², T_r (ω − ω_s) /
  (ω_r − ω_s)), T_r), ω_s = ω_r / (1 + slip) (Jonkman et al. 2009 §7.2; DISCON's VS_SlPc); at
  12.1 rpm of the rotor the generator turns 12.1 × 96.354 = 1165.9 rpm > ω_r, so it holds T_r,
  and on the rotor N T_r, N = (1 + 56/19)(1 + 93/18)(95/24) from the model's teeth (its gears
  are lossless, its rigid meshes transmit N exactly);
- the settled pitch β*: the root in β of τ(λ(Ω_ref, v), β) = N T_r at the set point Ω_ref =
  12.1 rpm (a PI controller holds the filtered speed there), by bisection to the last bit on
  the bilinear table; the settled aerodynamic power is ½ ρ π R² v³ C_p = N T_r Ω_ref;
- the controller: OpenFAST's DISCON (``share/discon/DISCON.F90``, formerly
  ``reg_tests/5MW_Baseline/ServoData/Source/DISCON.f90``; Jonkman et al. 2009 §7.1, §7.3, §7.4),
  with its constants restated on the rotor shaft as docs/loads.md tabulates them (K_P = 97
  PC_KP, K_I = 97 PC_KI: its generator speed is 97 times the rotor's): every call
  α = exp(−ω_c Δt), ω_f ← (1 − α) ω + α ω_f; GK = 1 / (1 + β_prev / PC_KK); e = ω_f − Ω_ref;
  I ← clamp(I + e Δt, β_min / (GK K_I), β_max / (GK K_I)); β_c = clamp(GK (K_P e + K_I I),
  β_min, β_max); β ← clamp(β_prev + clamp((β_c − β_prev)/Δt, ±β̇_max) Δt, β_min, β_max); its
  first call sets ω_f = ω(0), I = β(0) / (GK(β(0)) K_I). Fed with the run's own rotor speed
  series and its pitch at t = 0 only.

Which speed enters which step: docs/loads.md says the pitch is "moved once per step (at the
step's end, held over the next)". The replay takes sample k + 1's speed (the end of step k) to
make the pitch of step k + 1; the other reading (sample k's speed) is printed beside it.

Found: DISCON holds the integral within [β_min, β_max] / (GK K_I); pinwind holds it within
[β_min, β_max] / K_I, which binds once β/GK(β) > β_max (GK < 1 widens DISCON's bounds as the
pitch grows), i.e. above β = 20.87°, 23.07 m/s in steady wind. Above that the integral cannot
reach the operating point and the rotor overspeeds: at 24 m/s (β* = 21.80°) the pitch stays
near 21.3° and the rotor turns 12.4 rpm. The replay with pinwind's bounds (printed) reproduces
the run exactly.

Run: ``PYTHONPATH=. python benchmarks/independent_pitch_control.py`` (about 1 min on a busy
2-core machine).
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.linalg import expm

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from pinwind.runs.scenario import load_scenario, run  # noqa: E402

MODEL = REPO / "models" / "nrel5mw_gearbox.urdf"
TABLE = REPO / "pinwind" / "loads" / "data" / "nrel5mw_cp_ct_cq.txt"
DT = 4e-4  # s: under half the period of the model's highest torsional-spring mode (1017 Hz)

# Jonkman et al. 2009 Table 1-1 and §2 (air density)
RADIUS = 63.0  # m
AIR_DENSITY = 1.225  # kg/m³
RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # from the model's teeth (Nejad et al. 2016)
ROTOR_RPM = 12.1  # rated rotor speed, the pitch controller's set point (docs/loads.md)
OMEGA_REF = ROTOR_RPM * 2 * math.pi / 60  # rad/s
#: the scenario's pitch at the start, said to be the steady pitch of 13 m/s
SCENARIO_PITCH_DEG = 6.474160

# The generator law of scenarios/nrel5mw_turbulent.toml (docs/loads.md, "Generator laws")
GEN_GAIN = 2.332287  # N·m·s², region 2 (DISCON's VS_Rgn2K)
GEN_RATED_TORQUE = 43093.55  # N·m (ROSCO's VS_RtTq)
GEN_RATED_RPM = 1161.963  # DISCON's VS_RtGnSp
GEN_SLIP = 0.1  # DISCON's VS_SlPc

# OpenFAST DISCON.F90 (Jonkman's baseline controller), on the generator shaft
PC_KP = 0.01882681  # s
PC_KI = 0.008068634
PC_KK = 0.1099965  # rad
CORNER_FREQ = 1.570796  # rad/s
PC_MAX_RAT = 0.1396263  # rad/s
PC_MIN_PIT = 0.0  # rad
DISCON_RATIO = 97.0  # Jonkman's gearbox ratio: DISCON's gains act on 97 × the rotor speed
PC_MAX_PIT_DEG = 90.0  # docs/loads.md: 0 to 90° (DISCON's PC_MaxPit 1.570796 rad)

#: the series the recoding reads (docs/series.md), kept at every sample
KEPT = ("speed", "rotor_torque", "rotor_power", "rotor_wind_speed", "rotor_pitch")
HOLD_WINDS = (13.0, 16.0, 20.0, 24.0)  # m/s
STEP_WIND = (14.0, 16.0, 5.0)  # m/s before, after, time of the step [s]
LINEAR_STEP = (18.0, 0.2, 0.2)  # m/s, its step [m/s], time of the step [s]
#: Jonkman et al. 2009 Table 1-1: the rotor's inertia and the generator's (HSS) times 97²
JONKMAN_INERTIA = 38_759_236.0 + 97.0**2 * 534.116  # kg·m²


# --- the table ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table:
    """ROSCO's performance table: C_p, C_t, C_q [-] on rows of λ (``tsr``) and columns of β
    (``pitch`` [rad])."""

    pitch: np.ndarray
    tsr: np.ndarray
    cp: np.ndarray
    ct: np.ndarray
    cq: np.ndarray


def read_table(path: Path = TABLE) -> Table:
    """Parse a ROSCO ``Cp_Ct_Cq`` text file: a pitch vector [deg], a TSR vector, a wind speed,
    then three matrices (rows: TSR; columns: pitch), each after a comment line naming it."""
    lines = path.read_text().splitlines()

    def after(title: str) -> int:
        return next(i for i, s in enumerate(lines) if s.startswith("#") and title in s) + 1

    def vector(title: str) -> np.ndarray:
        return np.array([float(x) for x in lines[after(title)].split()])

    pitch_deg, tsr = vector("Pitch angle vector"), vector("TSR vector")

    def matrix(title: str) -> np.ndarray:
        rows = [s for s in lines[after(title) :] if s.strip()][: len(tsr)]
        m = np.array([[float(x) for x in s.split()] for s in rows])
        assert m.shape == (len(tsr), len(pitch_deg)), (title, m.shape)
        return m

    return Table(
        pitch=np.radians(pitch_deg),
        tsr=tsr,
        cp=matrix("Power coefficient"),
        ct=matrix("Thrust coefficient"),
        cq=matrix("Torque coefficient"),
    )


def _cell(grid: np.ndarray, x: float) -> tuple[int, float, bool]:
    """Cell i of ``grid`` holding x (held at the edges), x's weight in it, and whether x was
    inside the grid."""
    inside = bool(grid[0] <= x <= grid[-1])
    x = min(max(x, grid[0]), grid[-1])
    i = min(int(np.searchsorted(grid, x, side="right")) - 1, len(grid) - 2)
    return i, (x - grid[i]) / (grid[i + 1] - grid[i]), inside


def bilinear(table: Table, m: np.ndarray, tsr: float, pitch: float) -> tuple[float, float]:
    """m at (λ, β), bilinear on the table's grid, λ and β held at the grid's edges; and its
    slope ∂m/∂λ there (0 where λ is held)."""
    i, u, inside = _cell(table.tsr, tsr)
    j, w, _ = _cell(table.pitch, pitch)
    low = (1 - w) * m[i, j] + w * m[i, j + 1]
    high = (1 - w) * m[i + 1, j] + w * m[i + 1, j + 1]
    slope = (high - low) / (table.tsr[i + 1] - table.tsr[i]) if inside else 0.0
    return float((1 - u) * low + u * high), float(slope)


def aero_torque(table: Table, omega: float, wind: float, pitch: float) -> float:
    """τ = ½ ρ π R² v³ C_p(λ, β) / ω [N·m], λ = ω R / v (ω [rad/s], v [m/s], β [rad])."""
    cp, _ = bilinear(table, table.cp, omega * RADIUS / wind, pitch)
    return 0.5 * AIR_DENSITY * math.pi * RADIUS**2 * wind**3 * cp / omega


def step_torque(table: Table, speed: np.ndarray, wind: np.ndarray, pitch: np.ndarray) -> np.ndarray:
    """The aerodynamic torque over each step but the last [N·m]: τ at the step's mid speed
    ½ (ω_k + ω_{k+1}), sample k's wind and the step's pitch (the step is linearly implicit in
    the laws of the shaft speed, docs/loads.md; at ρ∞ = 1 its forces are those of mid-step)."""
    mid = 0.5 * (speed[:-1] + speed[1:])
    return np.array(
        [
            aero_torque(table, float(w), float(v), float(b))
            for w, v, b in zip(mid, wind[:-1], pitch[:-1], strict=True)
        ]
    )


# --- the generator and the settled operating point ------------------------------------------


def generator_torque(speed: float) -> float:
    """The variable-speed law with rated torque on the generator shaft [N·m] at |ω| [rad/s]:
    min(max(K ω², T_r (ω − ω_s)/(ω_r − ω_s)), T_r), ω_s = ω_r/(1 + slip) (docs/loads.md)."""
    w = abs(speed)
    w_r = GEN_RATED_RPM * 2 * math.pi / 60
    w_s = w_r / (1 + GEN_SLIP)
    line = GEN_RATED_TORQUE * (w - w_s) / (w_r - w_s)
    return min(max(GEN_GAIN * w * w, line), GEN_RATED_TORQUE)


def settled_torque() -> float:
    """The generator's torque at the set point, on the rotor shaft [N·m]: N T(N Ω_ref)."""
    return RATIO * generator_torque(RATIO * OMEGA_REF)


def settled_pitch(table: Table, wind: float) -> float:
    """β* [rad]: τ(λ(Ω_ref, v), β*) = N T_gen, by bisection to adjacent floats (τ falls with β
    above rated)."""
    target = settled_torque()

    def f(b: float) -> float:
        return aero_torque(table, OMEGA_REF, wind, b) - target

    lo, hi = float(table.pitch[0]), float(table.pitch[-1])
    if f(lo) < 0 or f(hi) > 0:
        raise ValueError(f"no pitch in the table holds {target} N·m at {wind} m/s")
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            return lo if abs(f(lo)) <= abs(f(hi)) else hi
        if f(mid) > 0:
            lo = mid
        else:
            hi = mid


# --- the controller ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Discon:
    """DISCON's pitch controller on the rotor shaft (docs/loads.md's table of the preset)."""

    speed_set: float = OMEGA_REF  # rad/s
    kp: float = DISCON_RATIO * PC_KP  # s
    ki: float = DISCON_RATIO * PC_KI
    gain_angle: float = PC_KK  # rad
    corner: float = CORNER_FREQ  # rad/s
    pitch_min: float = PC_MIN_PIT  # rad
    pitch_max: float = math.radians(PC_MAX_PIT_DEG)  # rad
    rate: float = PC_MAX_RAT  # rad/s


def replay(
    c: Discon, speed: np.ndarray, pitch0: float, dt: float, *, lag: int = 1, scheduled: bool = True
) -> np.ndarray:
    """The pitch over each step [rad] from the rotor speed at the samples [rad/s] and the pitch
    at t = 0, by DISCON's update (OpenFAST share/discon/DISCON.F90) once per step: step k's
    pitch is made at the end of step k − 1 from sample (k − 1 + lag)'s speed (lag 1: the end of
    the step, docs/loads.md; lag 0: its start). ``scheduled``: the integral is held to the pitch
    limits over GK K_I, as DISCON holds it; False: over K_I alone."""
    n = len(speed)
    out = np.empty(n)
    beta = pitch0
    filtered = float(speed[0])
    integral = pitch0 / (c.ki / (1 + pitch0 / c.gain_angle))
    alpha = math.exp(-c.corner * dt)
    out[0] = beta
    for k in range(1, n):
        filtered = (1 - alpha) * float(speed[k - 1 + lag]) + alpha * filtered
        gk = 1 / (1 + beta / c.gain_angle)  # of the previous command (DISCON's PitCom(1))
        err = filtered - c.speed_set
        held = gk * c.ki if scheduled else c.ki
        integral = min(max(integral + err * dt, c.pitch_min / held), c.pitch_max / held)
        command = min(max(gk * (c.kp * err + c.ki * integral), c.pitch_min), c.pitch_max)
        rate = min(max((command - beta) / dt, -c.rate), c.rate)
        beta = min(max(beta + rate * dt, c.pitch_min), c.pitch_max)
        out[k] = beta
    return out


def loop_matrix(table: Table, wind: float, inertia: float, c: Discon | None = None) -> np.ndarray:
    """The controller's loop linearised at (Ω_ref, β*(wind)) on the states (δω, δω_f, I):
    J δω̇ = ∂τ/∂ω δω + ∂τ/∂β δβ (the generator's torque is constant in region 3), the filter
    δω̇_f = ω_c (δω − δω_f), İ = δω_f, and δβ = (K_P δω_f + K_I I) / (1 + 2β*/θ_K) (β = GK(β) u
    with GK at the pitch itself: dβ/du = 1/(1 + 2β/θ_K)); the table's slopes by central
    differences. ``inertia`` [kg·m²] on the rotor shaft."""
    c = c or Discon()
    b, w = settled_pitch(table, wind), OMEGA_REF
    dw, db = 1e-6, 1e-7
    t_w = (aero_torque(table, w + dw, wind, b) - aero_torque(table, w - dw, wind, b)) / (2 * dw)
    t_b = (aero_torque(table, w, wind, b + db) - aero_torque(table, w, wind, b - db)) / (2 * db)
    g = 1 / (1 + 2 * b / c.gain_angle)
    return np.array(
        [
            [t_w / inertia, t_b * g * c.kp / inertia, t_b * g * c.ki / inertia],
            [c.corner, -c.corner, 0.0],
            [0.0, 1.0, 0.0],
        ]
    )


def loop_pair(a: np.ndarray) -> tuple[float, float]:
    """ω_n [rad/s] and ζ of the complex pair of ``a``'s eigenvalues."""
    e = next(e for e in np.linalg.eigvals(a) if e.imag > 0)
    return float(abs(e)), float(-e.real / abs(e))


def loop_response(a: np.ndarray, forcing: float, time: np.ndarray, at: float) -> np.ndarray:
    """δω(t) [rad/s] of the linear loop under a step of torque ``forcing`` / J [rad/s²] at
    ``at`` [s], sampled at ``time`` (exact per step: the matrix exponential)."""
    dt = float(time[1] - time[0])
    ad = expm(a * dt)
    bd = np.linalg.solve(a, (ad - np.eye(3)) @ np.array([forcing, 0.0, 0.0]))
    x, out = np.zeros(3), np.zeros(len(time))
    for i in range(1, len(time)):
        x = ad @ x + (bd if time[i - 1] >= at - 1e-12 else 0.0)
        out[i] = x[0]
    return out


# --- runs -----------------------------------------------------------------------------------


def scenario_text(wind: str, pitch: float, duration: float, dt: float) -> str:
    """The scenario TOML: the NREL 5 MW with its rotor, pitch control and generator law
    (scenarios/nrel5mw_turbulent.toml's), ``wind`` a signal text, ``pitch`` [rad] at t = 0."""
    return (
        f'model = "{MODEL.as_posix()}"\ndt = {dt!r}\nduration = {duration!r}\nno_log = true\n'
        f"initial_speed = {{ rotor = {ROTOR_RPM!r} }}\nwind = {wind}\n"
        f'[rotor.rotor]\npreset = "nrel5mw"\npitch_deg = {math.degrees(pitch)!r}\n'
        'pitch_control = "nrel5mw"\n'
        f'[generator.generator]\nlaw = "variable-speed"\ngain = {GEN_GAIN!r}\n'
        f"rated_torque = {GEN_RATED_TORQUE!r}\nrated_rpm = {GEN_RATED_RPM!r}\n"
        f"slip = {GEN_SLIP!r}\n"
    )


def run_case(wind: str, pitch: float, duration: float, dt: float = DT) -> Any:
    """Run one case (warnings are errors: dt must satisfy the dt advice); returns the Result,
    every sample of the series the recoding reads."""
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "case.toml"
        path.write_text(scenario_text(wind, pitch, duration, dt))
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            res = run(load_scenario(path), progress=False, keep="all", keep_series=KEPT)
    if not np.allclose(np.diff(res.time), dt, rtol=1e-9, atol=0.0):
        raise RuntimeError("the Result does not hold every step's sample")
    return res


@dataclass
class Recoded:
    """A run's series and what the recoding makes of them."""

    name: str
    time: np.ndarray  # [s]
    pitch: np.ndarray  # the run's, over each step [rad]
    speed: np.ndarray  # rotor joint, at the samples [rad/s]
    wind: np.ndarray  # at the samples [m/s]
    torque: np.ndarray  # the run's aerodynamic torque [N·m]
    power: np.ndarray  # the run's aerodynamic power [W]
    replay_end: np.ndarray  # DISCON replayed, sample k + 1's speed into step k + 1
    replay_start: np.ndarray  # the same from sample k's speed
    replay_unscheduled: np.ndarray  # replay_end with the integral held over K_I alone
    torque_recoded: np.ndarray  # over each step but the last, from the run's speed, wind, pitch


def recode(name: str, res: Any, table: Table, dt: float = DT) -> Recoded:
    """Recode a run: its controller from its speed series and first pitch, its torque from its
    speed, wind and pitch."""
    r = res.rotor("rotor")
    pitch = np.asarray(r.pitch, float)
    speed = np.asarray(res.joint("rotor").speed, float)
    wind = np.asarray(r.wind_speed, float)
    c, b0 = Discon(), float(pitch[0])
    return Recoded(
        name=name,
        time=np.asarray(res.time, float),
        pitch=pitch,
        speed=speed,
        wind=wind,
        torque=np.asarray(r.torque, float),
        power=np.asarray(r.power, float),
        replay_end=replay(c, speed, b0, dt, lag=1),
        replay_start=replay(c, speed, b0, dt, lag=0),
        replay_unscheduled=replay(c, speed, b0, dt, lag=1, scheduled=False),
        torque_recoded=step_torque(table, speed, wind, pitch),
    )


def hold(table: Table, wind: float, duration: float) -> Recoded:
    """A run in a steady ``wind`` [m/s] started at the recoded settled pitch β*(wind)."""
    res = run_case(repr(wind), settled_pitch(table, wind), duration)
    return recode(f"hold {wind:g} m/s", res, table)


def step_run(
    table: Table, duration: float, wind: tuple[float, float, float] = STEP_WIND
) -> Recoded:
    """A run in a wind step (before, after [m/s], at [s]) from β*(before)."""
    before, after, at = wind
    text = f'"step(time={at!r}, before={before!r}, after={after!r})"'
    res = run_case(text, settled_pitch(table, before), duration)
    return recode(f"step {before:g} to {after:g} m/s", res, table)


def rel(a: Any, b: Any) -> float:
    """max |a − b| over max |b|."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def tail(x: np.ndarray, t: np.ndarray) -> float:
    """The mean of x over the run's second half."""
    return float(np.mean(x[t >= 0.5 * t[-1]]))


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    p.add_argument("--hold", type=float, default=10.0, help="each hold run [s]")
    p.add_argument("--settle", type=float, default=30.0, help="the scenario-start run [s]")
    p.add_argument("--step", type=float, default=30.0, help="the step run [s]")
    p.add_argument("--linear", type=float, default=20.0, help="the small step run [s]")
    a = p.parse_args(argv)
    table = read_table()
    t0 = time.time()
    rows: list[tuple[str, str, str, str]] = []

    def row(q: str, pw: float | str, rc: float | str, d: float | None) -> None:
        def text(x: float | str) -> str:
            return x if isinstance(x, str) else f"{x:.10g}"

        rows.append((q, text(pw), text(rc), "-" if d is None else f"{d:.1e}"))

    power = settled_torque() * OMEGA_REF
    row("settled torque on the rotor N T_r [N·m]", "", settled_torque(), None)
    runs = []
    for v in HOLD_WINDS:
        b = settled_pitch(table, v)
        rr = hold(table, v, a.hold)
        runs.append(rr)
        pw = math.degrees(tail(rr.pitch, rr.time))
        row(
            f"{v:g} m/s: settled pitch [deg], 2nd half",
            pw,
            math.degrees(b),
            abs(pw / math.degrees(b) - 1),
        )
        pw = tail(rr.speed, rr.time) * 30 / math.pi
        row(f"{v:g} m/s: rotor speed [rpm], 2nd half", pw, ROTOR_RPM, abs(pw / ROTOR_RPM - 1))
        pw = tail(rr.power, rr.time)
        row(f"{v:g} m/s: aero power [W], 2nd half", pw, power, abs(pw / power - 1))
    v0 = HOLD_WINDS[0]
    res = run_case(repr(v0), math.radians(SCENARIO_PITCH_DEG), a.settle)
    rr = recode(f"{v0:g} m/s from {SCENARIO_PITCH_DEG:g} deg", res, table)
    runs.append(rr)
    pw, rc = math.degrees(rr.pitch[-1]), math.degrees(settled_pitch(table, v0))
    row(
        f"{v0:g} m/s from {SCENARIO_PITCH_DEG:g} deg: pitch [deg] at {a.settle:g} s",
        pw,
        rc,
        abs(pw / rc - 1),
    )
    rr = step_run(table, a.step)
    runs.append(rr)
    pw, rc = math.degrees(rr.pitch[-1]), math.degrees(settled_pitch(table, STEP_WIND[1]))
    row(f"step: pitch [deg] at {a.step:g} s", pw, rc, abs(pw / rc - 1))
    # the loop's pair: a small step; the drivetrain's inertia on the rotor shaft from its kinetic
    # energy at the start, J = 2 T / ω² (rigid meshes: every body turns in ratio with the rotor)
    v1, dv, at = LINEAR_STEP
    res = run_case(
        f'"step(time={at!r}, before={v1!r}, after={v1 + dv!r})"', settled_pitch(table, v1), a.linear
    )
    rr = recode(f"step {v1:g} to {v1 + dv:g} m/s", res, table)
    runs.append(rr)
    inertia = 2 * float(np.asarray(res.energy["kinetic"])[0]) / rr.speed[0] ** 2
    row("drivetrain inertia on the rotor shaft [kg·m²], 2T/ω²", inertia, "", None)
    loop = loop_matrix(table, v1, inertia)
    wn, zeta = loop_pair(loop)
    row(f"{v1:g} m/s: loop's pair, ω_n [rad/s]", "", wn, None)
    row(f"{v1:g} m/s: loop's pair, ζ", "", zeta, None)
    b1 = settled_pitch(table, v1)
    t_v = (
        aero_torque(table, OMEGA_REF, v1 + 1e-4, b1) - aero_torque(table, OMEGA_REF, v1 - 1e-4, b1)
    ) / 2e-4
    lin = loop_response(loop, t_v * dv / inertia, rr.time, at)
    dw = rr.speed - OMEGA_REF
    row(
        f"{v1:g} m/s: δω, run against the linear loop (of its peak)",
        float(np.max(np.abs(dw))),
        float(np.max(np.abs(lin))),
        rel(dw, lin),
    )
    jonkman = loop_matrix(table, v1, JONKMAN_INERTIA)
    wn, zeta = loop_pair(jonkman)
    row(f"{v1:g} m/s: the same with Jonkman's inertia, ω_n, ζ", "", f"{wn:.4f}, {zeta:.4f}", None)
    for rr in runs:
        n = len(rr.torque_recoded)
        row(f"{rr.name}: pitch per sample, DISCON replayed", "", "", rel(rr.pitch, rr.replay_end))
        row(
            f"{rr.name}: the same, integral held over K_I",
            "",
            "",
            rel(rr.pitch, rr.replay_unscheduled),
        )
        row(
            f"{rr.name}: the same, sample k's speed into step k+1",
            "",
            "",
            rel(rr.pitch, rr.replay_start),
        )
        row(f"{rr.name}: aero torque per step", "", "", rel(rr.torque[:n], rr.torque_recoded))
    wall = time.time() - t0
    w = max(len(r[0]) for r in rows)
    print(f"{'quantity':<{w}}  {'pinwind':>16}  {'recoding':>16}  rel. diff")
    for q, pw_, rc_, d in rows:
        print(f"{q:<{w}}  {pw_:>16}  {rc_:>16}  {d}")
    print(f"({wall:.0f} s)")


if __name__ == "__main__":
    main()
