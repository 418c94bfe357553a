"""Cost of compliant bearings against ideal ones on the same compliant-mesh model, in one run.

For each model, ``pinwind.simulate`` with every mesh compliant (as ``compliant_step.py``) and ideal
bearings, then the same with compliant bearings (radial stiffness 2e9 N/m, damping 1e4 N·s/m: two
slides per bearing, ``docs/model_format.md`` "Compliant bearings"): every turning bearing, or one
(``--bearings all sun carrier``: one case each), under the same loads: a torque on the input and a
speed driver on the output. The runs are interleaved A/B ``--repeats`` times and the median ratio of
the time per step is printed (issue 24's budget: ≤ 1.5). The Result keeps only the last sample.

Measured 2026-11-27 on the shared 2-core machine under a load average of 8 to 14 (other
helpers compiling; 10000 steps, 3 repeats, ``--bearings all``; the wall clock is too noisy
there to resolve the change, pairwise ratios spread 1.0-3.0): all five turning bearings
compliant (nv 6 -> 16), the module before and after the changes below (built from 65c975f,
whose meshes' Hessian loop cost 0.9k instructions per step more than the final one), runs
interleaved, means of two runs' medians: saleh2017_planetary 1.99 -> 1.80, dtu500_planetary
2.01 -> 1.75. Instruction counts are the steady measure (below): 2.23 -> 2.03
(saleh2017_planetary) and 2.24 -> 2.04 (dtu500_planetary: 41.2k -> 92.4k before, 38.0k ->
77.6k now), still above issue 24's 1.5.

On the idle machine (2026-11-27 07:34, load average 0.5, nothing else running; the module
built from b793e7f, default arguments: 20000 steps of 20 µs, 3 interleaved repeats), time per
step, mesh-only -> compliant bearings: all five bearings (nv 6 -> 16) 13.05 -> 22.15 µs, 1.89
(saleh2017_planetary, pairwise 1.51-2.17) and 13.42 -> 24.52 µs, 1.80 (dtu500_planetary,
1.71-1.97): above issue 24's 1.5; one compliant bearing (nv 6 -> 8): sun 1.16 / 1.19, carrier
1.20 / 1.21 (within 1.5).

Where the time goes (valgrind --tool=callgrind --toggle-collect='pinwind::Stepper::run*' on a
3000-step run of the case, saleh2017_planetary, all five bearings; instructions per step, ideal
-> compliant bearings). Before: 41.5k -> 92.6k. Of the +51k, the bearing springs themselves
(BearingSprings: force, tangent, settle, energy) were 2.1k; the rest is nv 6 -> 16 (and 6 -> 16
joints): the QP solve +17.7k (Eigen's pivoted LDLT of the 16x16 Hessian, 14.0k, and its solves,
redone every step as the compliant meshes change H), M by composite inertias +6.0k, b +4.5k,
the Jacobians and mesh geometry +5.2k, the meshes' implicit terms on the larger H +3.8k and
their prepare +1.9k, velocity kinematics +1.5k, the bearing reactions (RNEA) +2.4k, the
sample's record +3.4k and advance +1.4k; outside the step loop, the per-block statistics
(fold_block) 1.7k. Now: 38.5k -> 78.0k. The Hessian and the Schur complement are factorised
by a small Cholesky (``cpp/small_cholesky.hpp``; the QP solve 25.8k -> 16.3k, and 8.1k -> 4.9k
with ideal bearings), and the slides, which carry no mass, skip their bodies' inertia terms in
M, b and the bearing reactions (-4.7k). What is left of the +39.6k is the per-joint passes
over ten more joints (kinematics and mesh geometry, M, b, RNEA, record: about 25k) and the
nv-sized solve: at 1.5x the step could grow by 19.2k only. The budget needs fewer joints
(a radial bearing's two slides and revolute as one planar joint would run the per-joint passes
over 6 joints, not 16), not a cheaper bearing element or solve.

Run:  python benchmarks/compliant_bearing_step.py [--steps N] [--dt S] [--repeats R]
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from pathlib import Path

import pinwind
from pinwind.errors import PinwindWarning
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
    joint_in, torque, joint_out, speed = case
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        pinwind.simulate(
            gb,
            duration=steps * dt,
            dt=dt,
            torques={joint_in: torque},
            speeds={joint_out: speed},
            meshes={"all": "compliant"},
            keep="last",
            progress=False,
        )
    return (time.perf_counter() - started) / steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20_000)
    parser.add_argument("--dt", type=float, default=2e-5)
    parser.add_argument("--repeats", type=int, default=3)
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
