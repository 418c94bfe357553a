"""Cost of 5-slice compliant meshes against single-line ones on the DTU stage, in one run.

``pinwind.simulate`` of ``models/dtu500_planetary.urdf`` with every mesh compliant (as
``compliant_step.py``: a torque on the carrier, the sun held at speed), once with one contact
line per mesh and once with ``slices=5`` (``MeshCompliance.slices``; nothing misaligned, so the
slices carry alike and only the cost differs). The runs are interleaved A/B ``--repeats`` times
and the median ratio of the time per step is printed (issue 40's budget: ≤ 1.3). The Result
keeps only the last sample.

Measured 2026-12-07 12:21 UTC on the shared 2-core machine: ratio 1.21 (11 repeats, pairwise
0.89-1.79) and 1.11 (21 repeats, pairwise 0.66-2.65); 14:36 UTC with per-slice stiffness and
gaps (relief, helical slices): 1.26 (11 repeats) and 1.25 (21); benchmarks/README.md. With the
slices' line loads recorded (``slice_line_load``), 16:53 UTC, one run each: 5 slices 7.30 µs/step
(ratio 1.326) before, 7.24 µs/step (1.328) after.

Run:  python benchmarks/sliced_mesh_step.py [--steps N] [--dt S] [--repeats R] [--slices N]
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from step_timing import seconds_per_step

import pinwind
from pinwind.model.compliance import MeshCompliance

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "models" / "dtu500_planetary.urdf"
CASE = ("carrier", 1.76e5, "sun", 15.75)  # input joint, torque [N·m], output joint, speed [rad/s]


def time_per_step(gb, steps: int, dt: float, slices: int) -> float:
    meshes = {"all": MeshCompliance(slices=slices)}
    return seconds_per_step(gb, CASE, steps=steps, dt=dt, meshes=meshes)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20_000)
    parser.add_argument("--dt", type=float, default=2e-5)
    parser.add_argument("--repeats", type=int, default=11)
    parser.add_argument("--slices", type=int, default=5)
    args = parser.parse_args()

    gb = pinwind.load(MODEL)
    time_per_step(gb, 1000, args.dt, args.slices)  # warm up
    one, many = [], []
    for _ in range(args.repeats):
        one.append(time_per_step(gb, args.steps, args.dt, 1))
        many.append(time_per_step(gb, args.steps, args.dt, args.slices))
    ratios = [y / x for x, y in zip(one, many, strict=True)]
    print(f"{args.steps} steps of {args.dt:g} s, {args.repeats} interleaved A/B repeats")
    print(
        f"dtu500_planetary: one line {statistics.median(one) * 1e6:.2f} µs/step, "
        f"{args.slices} slices {statistics.median(many) * 1e6:.2f} µs/step, ratio "
        f"{statistics.median(ratios):.3f} (pairwise {min(ratios):.2f}–{max(ratios):.2f})"
    )


if __name__ == "__main__":
    main()
