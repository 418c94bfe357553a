"""Cost of compliant meshes against rigid ones on the same model, at the same dt, in one run.

For each model, ``pinwind.simulate`` with every mesh rigid, then with every mesh compliant
(ISO 6336-1 single-pair stiffness along the path of contact, damping ratio 0.05), under the same
loads: a torque on the input and a speed driver on the output, so both runs carry load. The runs
are interleaved A/B ``--repeats`` times and the median time per step is compared. The Result
keeps only the last sample (and folds no statistics), so the figures are of the step loop and
its streaming, not of filling memory.

With ``--dtu``, also runs ``examples/dtu500_planetary.py`` (30 s simulated) in a subprocess and
prints its wall time and peak memory (the issue's budget: ≤ 30 s and ≤ 1 GB on 2 cores).

Measured 2026-12-07 on the 2-core machine, each flank in contact on its own (issue 36), six
rounds alternating this tree with d7f877a's (one flank at a time) in separate processes, median
of the rounds' ratios: saleh2017_planetary 1.125 (d7f877a 1.095), dtu500_planetary 1.15
(1.085); rigid steps 3.1-3.7 µs. The whole ``simulate`` call is timed: ``prepare`` now
linearises the machine (5 ms rigid, 10 ms compliant), 0.1-0.2 µs a step over 50 000 steps.

Run:  python benchmarks/compliant_step.py [--steps N] [--dt S] [--repeats R] [--dtu]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from step_timing import seconds_per_step

import pinwind

ROOT = Path(__file__).resolve().parents[1]
#: model → (input joint, input torque [N·m], output joint held at speed, its speed [rad/s])
CASES = {
    "saleh2017_planetary": ("carrier", 1e6, "sun", 8.92),
    "saleh2017_drivetrain": ("carrier", 1e6, "stage2_pinion", 127.5),
    "dtu500_planetary": ("carrier", 1.76e5, "sun", 15.75),
    "cart600_gearbox": ("carrier", 1e5, "stage1_pinion", 150.0),
}


def time_per_step(gb, kind: str, steps: int, dt: float, case) -> float:
    return seconds_per_step(gb, case, steps=steps, dt=dt, meshes={"all": kind})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=50_000)
    parser.add_argument("--dt", type=float, default=2e-5)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--models", nargs="*", default=list(CASES))
    parser.add_argument("--dtu", action="store_true", help="also time the 30 s DTU example")
    args = parser.parse_args()

    print(f"{args.steps} steps of {args.dt:g} s, {args.repeats} interleaved A/B repeats")
    print(f"{'model':24} {'rigid µs':>9} {'compliant µs':>13} {'ratio':>6}")
    for name in args.models:
        gb = pinwind.load(ROOT / "models" / f"{name}.urdf")
        case = CASES[name]
        if case[2] not in gb.joint_names:
            print(f"{name:24} skipped: no joint {case[2]}")
            continue
        rigid, compliant = [], []
        time_per_step(gb, "compliant", 1000, args.dt, case)  # warm up
        for _ in range(args.repeats):
            rigid.append(time_per_step(gb, "rigid", args.steps, args.dt, case))
            compliant.append(time_per_step(gb, "compliant", args.steps, args.dt, case))
        r, c = statistics.median(rigid), statistics.median(compliant)
        ratios = [b / a for a, b in zip(rigid, compliant, strict=True)]
        print(
            f"{name:24} {r * 1e6:9.2f} {c * 1e6:13.2f} {statistics.median(ratios):6.2f}"
            f"   (pairwise ratios {min(ratios):.2f}–{max(ratios):.2f})"
        )
    if args.dtu:
        started = time.perf_counter()
        subprocess.run(
            [sys.executable, str(ROOT / "examples" / "dtu500_planetary.py"), "--duration", "30"],
            check=True,
            stdout=subprocess.DEVNULL,
        )
        wall = time.perf_counter() - started
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
        print(
            f"examples/dtu500_planetary.py, 30 s simulated: {wall:.1f} s wall, peak {peak:.0f} MB"
        )


if __name__ == "__main__":
    main()
