"""Cost of tooth-flank friction on every compliant mesh against the same compliant model without it.

For each model, ``pinwind.simulate`` with every mesh compliant (the model file's compliance or
the defaults), then the same with ``friction_coefficient`` μ = 0.05 on every mesh
(``cpp/flank_friction.hpp``), under the same loads as ``benchmarks/compliant_step.py``: a torque
on the input and a speed driver on the output. The runs are interleaved A/B ``--repeats`` times
in one process and the median of the pairwise ratios is printed (issue 41's budget: ≤ 1.15).
Each run is timed by the process's CPU time (``time.process_time``), not the wall clock: on a
machine shared with other jobs the wall time of a run swings by ±30 % with their load.

Run:  python benchmarks/flank_friction_step.py [--steps N] [--dt S] [--repeats R]
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace
from pathlib import Path

from step_timing import seconds_per_step

import pinwind
from pinwind.model.compliance import MeshCompliance

ROOT = Path(__file__).resolve().parents[1]
#: model → (input joint, input torque [N·m], output joint held at speed, its speed [rad/s])
CASES = {
    "saleh2017_planetary": ("carrier", 1e6, "sun", 8.92),
    "dtu500_planetary": ("carrier", 1.76e5, "sun", 15.75),
}
MU = 0.05


def time_per_step(gb, meshes, steps: int, dt: float, case) -> float:
    return seconds_per_step(gb, case, steps=steps, dt=dt, meshes=meshes, clock=time.process_time)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=50_000)
    parser.add_argument("--dt", type=float, default=2e-5)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--models", nargs="*", default=list(CASES))
    args = parser.parse_args()

    print(f"{args.steps} steps of {args.dt:g} s, {args.repeats} interleaved A/B repeats, μ = {MU}")
    print(f"{'model':24} {'compliant µs':>13} {'+ friction µs':>14} {'ratio':>6}")
    for name in args.models:
        gb = pinwind.load(ROOT / "models" / f"{name}.urdf")
        case = CASES[name]
        plain = {m.name: m.compliance or MeshCompliance() for m in gb.meshes}
        rubbing = {k: replace(c, friction_coefficient=MU) for k, c in plain.items()}
        time_per_step(gb, rubbing, 1000, args.dt, case)  # warm up
        without, with_friction = [], []
        for _ in range(args.repeats):
            without.append(time_per_step(gb, plain, args.steps, args.dt, case))
            with_friction.append(time_per_step(gb, rubbing, args.steps, args.dt, case))
        a, b = statistics.median(without), statistics.median(with_friction)
        ratios = [y / x for x, y in zip(without, with_friction, strict=True)]
        print(
            f"{name:24} {a * 1e6:13.2f} {b * 1e6:14.2f} {statistics.median(ratios):6.3f}"
            f"   (pairwise ratios {min(ratios):.3f}–{max(ratios):.3f})"
        )


if __name__ == "__main__":
    main()
