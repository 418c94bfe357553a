"""Cost of compliant bearings against ideal ones on the same compliant-mesh model, in one run.

For each model, ``pinwind.simulate`` with every mesh compliant (as ``compliant_step.py``) and ideal
bearings, then the same with compliant bearings (radial stiffness 2e9 N/m, damping 1e4 N·s/m: two
slides per bearing, ``docs/model_format.md`` "Compliant bearings"): every turning bearing, or one
(``--bearings all sun carrier``: one case each), under the same loads: a torque on the input and a
speed driver on the output. The runs are interleaved A/B ``--repeats`` times (21 by default)
and the median ratio of the time per step is printed (issue 24's budget: ≤ 1.5). The Result
keeps only the last sample.

Measured 2026-11-27 on the idle 2-core machine, time per step, mesh-only -> compliant
bearings, all five turning bearings (nv 6 -> 16): with 21 repeats (14:48, the module `pip
install -e` builds, two runs) 1.48 and 1.44 (saleh2017_planetary), 1.42 and 1.45
(dtu500_planetary); with 7 repeats, in eight runs from 13:50 to 14:47, 1.32-1.49, and once 1.54
(dtu500_planetary, pairwise 1.11-1.71). One compliant bearing (nv 6 -> 8): 1.09-1.19. At 11:58,
before the QP's solves were taken four at a time, the dual residual dropped and the bearing
series derived in C++: 1.46-1.58 (7 repeats). The machine's speed drifts by up to 2x within
minutes (pairwise ratios spread 0.8-2.2), so only the median of many interleaved repeats means
anything: hence 21 by default.

Measured 2026-12-07 with each mesh flank in contact on its own (issue 36), alternating with
d7f877a's module in separate processes (21 repeats, a busier machine: mesh-only steps 4.4-7.2
µs): all five bearings, dtu500_planetary 1.55 and 1.53 (d7f877a 1.56 and 1.53),
saleh2017_planetary 1.44; one bearing 1.11-1.14 (d7f877a 1.11-1.13).

Where the time goes (valgrind --tool=callgrind --toggle-collect='pinwind::Stepper::run*' on a
3000-step run of the case, saleh2017_planetary, all five bearings; instructions per step, ideal
-> compliant bearings): 37.7k -> 66.6k (1.77; 38.5k -> 69.0k before the solves were taken four
at a time and the dual residual dropped, 41.5k -> 92.6k before the small Cholesky). Of the
+28.9k: the QP's 16 x 16 Cholesky (factorised two rows at a time) and its solves of M a = f
and M x = Jᵀ together, the meshes' implicit terms on the larger Hessian (lower triangle only),
the mass matrix, the mesh rows over more columns, and the per-joint passes (velocity, bias
forces, joint forces). The slides are placed directly (cpp/joint_jacobians.cpp) and their rows
of M and J̇ taken as pure translations. What is left scales with nv (6 -> 16). Outside the
step, the bearings' displacement and elastic-force series are computed in C++
(``_native.bearing_slide_series``): with numpy's (samples, 3) @ (3, 3) per bearing they took
0.46 µs per sample, a tenth of the compliant step. Not tried: fewer joints per bearing (a
planar joint: nq != nv). Tried and dropped: an envelope order, leaves first, halved the
factorisation's products but its indexing cost as much again; a kinetic energy summed body by
body (Pinocchio's vtiv) cost more than the 16 x 16 product.

Run:  python benchmarks/compliant_bearing_step.py [--steps N] [--dt S] [--repeats R]
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from step_timing import seconds_per_step

import pinwind
from pinwind.model.gearbox import loads

ROOT = Path(__file__).resolve().parents[1]
#: model → (input joint, input torque [N·m], output joint held at speed, its speed [rad/s])
CASES = {
    "saleh2017_planetary": ("carrier", 1e6, "sun", 8.92),
    "dtu500_planetary": ("carrier", 1.76e5, "sun", 15.75),
}
#: The compliance given to every turning bearing.
BEARING = 'radial_stiffness="2e9" radial_damping="1e4"'


def with_compliant_bearings(gb, joints: list[str] | None = None) -> pinwind.Gearbox:
    """The model with bearings ``joints`` made compliant (default: every one that turns)."""
    if joints is None:
        joints = [j for j in gb.joint_names if j not in gb.locked_joints]
    lines = "".join(f'  <bearing joint="{j}" {BEARING}/>\n' for j in joints)
    text = gb.source_text
    for j in set(gb.source.bearings) & set(joints):  # a rated bearing keeps its rating
        text = text.replace(f'<bearing joint="{j}"', f'<bearing joint="{j}" {BEARING}', 1)
        lines = lines.replace(f'  <bearing joint="{j}" {BEARING}/>\n', "")
    return loads(text.replace("</gearbox>", lines + "</gearbox>"), str(gb.path))


def time_per_step(gb, steps: int, dt: float, case) -> float:
    return seconds_per_step(gb, case, steps=steps, dt=dt, meshes={"all": "compliant"})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20_000)
    parser.add_argument("--dt", type=float, default=2e-5)
    parser.add_argument("--repeats", type=int, default=21)
    parser.add_argument("--models", nargs="*", default=list(CASES))
    parser.add_argument(
        "--bearings",
        nargs="*",
        default=["all", "sun", "carrier"],
        help="which bearings are compliant, one case each: all (every one that turns) or a joint",
    )
    args = parser.parse_args()

    print(f"{args.steps} steps of {args.dt:g} s, {args.repeats} interleaved A/B repeats")
    print(f"{'model, compliant bearings':34} {'mesh µs':>9} {'+bearings µs':>13} {'ratio':>6}")
    for name, which in ((m, b) for m in args.models for b in args.bearings):
        ideal = pinwind.load(ROOT / "models" / f"{name}.urdf")
        compliant = with_compliant_bearings(ideal, None if which == "all" else [which])
        case = CASES[name]
        a, b = [], []
        time_per_step(compliant, 1000, args.dt, case)  # warm up
        for _ in range(args.repeats):
            a.append(time_per_step(ideal, args.steps, args.dt, case))
            b.append(time_per_step(compliant, args.steps, args.dt, case))
        ratios = [y / x for x, y in zip(a, b, strict=True)]
        label = f"{name}, {which} (nv {ideal.model.nv} -> {compliant.model.nv})"
        print(
            f"{label:34} {statistics.median(a) * 1e6:9.2f} {statistics.median(b) * 1e6:13.2f} "
            f"{statistics.median(ratios):6.2f}   (pairwise {min(ratios):.2f}–{max(ratios):.2f})"
        )


if __name__ == "__main__":
    main()
