"""The NREL 5 MW gearbox (13 compliant meshes): the dt its single-tooth forces converge at, and
its step's cost beside the DTU 500 kW single stage's, in one run.

1. Convergence: the 5 MW model at rated (rotor 3 945 990 N·m at 12.1 rpm, generator held at
   12.1 · 96.354 rpm), every mesh compliant, run ``--duration`` s at dt, dt/2 and dt/4; for
   each stage, the largest single-tooth force over the last half of the run. The change from
   dt/2 to dt/4 and from dt to dt/2 is printed per stage: the figure is converged within 1 % at
   the coarsest dt whose change to its half is below 1 %.
2. Cost: the time per step of the 5 MW model and of ``dtu500_planetary`` (all meshes
   compliant, rated), interleaved ``--repeats`` times at the same dt; the median ratio.

Run:  python benchmarks/nrel5mw_step.py [--dt S] [--duration S] [--repeats R]
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

import pinwind
from pinwind.errors import PinwindWarning
from pinwind.units import rpm_to_rad_s

ROOT = Path(__file__).resolve().parents[1]
#: The 5 MW rated point (scenarios/nrel5mw_rated.toml): rotor torque [N·m], rotor speed [rpm],
#: and the generator's speed [rpm] by the teeth's ratio (1 + 56/19)(1 + 93/18)(95/24).
RATED_TORQUE, ROTOR_RPM = 3945990.3245924464, 12.1
GENERATOR_RPM = -ROTOR_RPM * (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
STAGES = ("stage1", "stage2", "stage3")


def run_5mw(gb, dt: float, duration: float):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(
            gb, duration=duration, dt=dt, meshes={"all": "compliant"},
            torques={"rotor": RATED_TORQUE}, speeds={"generator": rpm_to_rad_s(GENERATOR_RPM)},
            initial_speeds={"rotor": rpm_to_rad_s(ROTOR_RPM)}, progress=False,
        )  # fmt: skip


def peaks(res) -> dict[str, float]:
    """Largest single-tooth force of each stage over the run's last half [N]."""
    half = res.time >= res.time[-1] / 2
    out = {}
    for stage in STAGES:
        names = [m for m in res.mesh_names if m.startswith(stage)]
        out[stage] = max(float(np.max(res.mesh(m).single_tooth_force[half])) for m in names)
    return out


def seconds_per_step(gb, dt: float, steps: int, **loads) -> float:
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        pinwind.simulate(gb, duration=steps * dt, dt=dt, meshes={"all": "compliant"},
                         keep="last", progress=False, **loads)  # fmt: skip
    return (time.perf_counter() - started) / steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dt", type=float, default=2e-5, help="coarsest dt [s]")
    parser.add_argument("--duration", type=float, default=0.05, help="each run [s]")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--steps", type=int, default=5000, help="steps per timed run")
    args = parser.parse_args()
    gb5 = pinwind.load(ROOT / "models" / "nrel5mw_gearbox.urdf")
    gbd = pinwind.load(ROOT / "models" / "dtu500_planetary.urdf")

    found = {}
    for factor in (1, 2, 4):
        dt = args.dt / factor
        found[factor] = peaks(run_5mw(gb5, dt, args.duration))
    print(f"largest single-tooth force over the last half of {args.duration} s [kN]:")
    print(f"{'stage':8} {'dt':>10} {'dt/2':>10} {'dt/4':>10} {'dt→dt/2':>9} {'dt/2→dt/4':>10}")
    for stage in STAGES:
        f1, f2, f4 = (found[k][stage] for k in (1, 2, 4))
        print(f"{stage:8} {f1 / 1e3:10.3f} {f2 / 1e3:10.3f} {f4 / 1e3:10.3f} "
              f"{abs(f2 - f1) / f2:9.2%} {abs(f4 - f2) / f4:10.2%}")  # fmt: skip

    dtu = {"torques": {"carrier": 1.76e5}, "speeds": {"sun": 15.75}}
    big = {
        "torques": {"rotor": RATED_TORQUE},
        "speeds": {"generator": rpm_to_rad_s(GENERATOR_RPM)},
        "initial_speeds": {"rotor": rpm_to_rad_s(ROTOR_RPM)},
    }
    ratios, per_step = [], []
    for _ in range(args.repeats):
        a = seconds_per_step(gb5, args.dt, args.steps, **big)
        b = seconds_per_step(gbd, args.dt, args.steps, **dtu)
        ratios.append(a / b)
        per_step.append((a, b))
    median = statistics.median(ratios)
    a_med = statistics.median(a for a, _ in per_step) * 1e6
    b_med = statistics.median(b for _, b in per_step) * 1e6
    print(f"time per step at dt = {args.dt:g} s, {args.steps} steps, {args.repeats} interleaved "
          f"pairs: 5 MW {a_med:.1f} µs, DTU {b_med:.1f} µs, median ratio {median:.2f} "
          f"(range {min(ratios):.2f}-{max(ratios):.2f})")  # fmt: skip


if __name__ == "__main__":
    main()
