"""The whole ``pinwind.simulate`` call against MuJoCo's bare ``mj_step``, per step, A/B interleaved.

For each model, pairs of runs alternate (pinwind, then MuJoCo, then pinwind, ...) after a
warm-up of each, so that both see the same machine state; each pair gives a ratio, and the
median of the ratios is printed (issue 12 asks for at most 1.2). pinwind is timed end to end
(``pinwind.simulate(gb, duration=steps*dt, dt=dt, torques=...)``, no log: set-up, every step,
recording of mesh forces, bearing reactions, energy and poses), and its compiled step loop
alone (``metadata["wall_time_s"]``, issue 37 asks for at most 0.7 × ``mj_step``); MuJoCo as
its bare loop, ``qfrc_applied`` + ``mj_step``, on the model that
``step_rate.mjcf_from_gearbox`` builds from the same gearbox (MuJoCo's default solref/solimp),
reading no force. The load case is the one of ``step_rate.py``: the closed-form torques of the
Saleh models, from rest.

    python benchmarks/vs_mujoco.py [--models saleh2017_planetary] [--steps 10000] [--repeats 11]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

import mujoco
import numpy as np

import pinwind
from pinwind.errors import TorquesUnbalanced

sys.path.insert(0, str(Path(__file__).resolve().parent))
from step_rate import closed_form, mjcf_from_gearbox, mujoco_dof, resolve  # noqa: E402


def pinwind_run(gb: pinwind.Gearbox, torques: dict, steps: int, dt: float) -> tuple[float, float]:
    """Seconds per step of the whole simulate call and of its compiled step loop alone."""
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TorquesUnbalanced)  # the load case accelerates the train
        res = pinwind.simulate(gb, duration=steps * dt, dt=dt, torques=torques, progress=False)
    whole = (time.perf_counter() - started) / steps
    return whole, res.metadata["wall_time_s"] / steps


def mujoco_run(mj: mujoco.MjModel, tau: np.ndarray, steps: int) -> float:
    """Seconds per step of ``qfrc_applied`` + ``mj_step`` from rest."""
    d = mujoco.MjData(mj)
    started = time.perf_counter()
    for _ in range(steps):
        d.qfrc_applied[:] = tau
        mujoco.mj_step(mj, d)
    return (time.perf_counter() - started) / steps


def closed_form_case(
    name: str, dt: float
) -> tuple[pinwind.Gearbox, dict, mujoco.MjModel, np.ndarray]:
    """A Saleh model's closed-form load case: the gearbox and its torques, MuJoCo's model of it
    (``step_rate.mjcf_from_gearbox``) and the same torques as MuJoCo's ``qfrc_applied``."""
    path = resolve(name)
    gb = pinwind.load(path)
    cf = closed_form(path)
    mj = mujoco.MjModel.from_xml_string(mjcf_from_gearbox(gb, dt=dt))
    tau = np.zeros(mj.nv)
    for joint, value in cf.torques.items():
        tau[mujoco_dof(mj, gb)[joint]] = value
    return gb, cf.torques, mj, tau


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=["saleh2017_planetary"])
    parser.add_argument("--steps", type=int, default=10_000, help="steps per run")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--repeats", type=int, default=11, help="A/B pairs")
    args = parser.parse_args()
    print(f"pinwind {pinwind.__version__}, mujoco {mujoco.__version__}, numpy {np.__version__}")
    for name in args.models:
        gb, torques, mj, tau = closed_form_case(name, args.dt)
        pinwind_run(gb, torques, 100, args.dt)
        mujoco_run(mj, tau, 1000)
        pairs, loops = [], []
        for _ in range(args.repeats):
            a, loop = pinwind_run(gb, torques, args.steps, args.dt)
            b = mujoco_run(mj, tau, args.steps)
            pairs.append((a, b))
            loops.append((loop, b))
        ratios = [a / b for a, b in pairs]
        loop_ratios = [a / b for a, b in loops]
        pw = statistics.median(a for a, _ in pairs) * 1e6
        pw_loop = statistics.median(a for a, _ in loops) * 1e6
        mjs = statistics.median(b for _, b in pairs) * 1e6
        print(
            f"\n{gb.name}: {args.steps} steps of {args.dt:g} s, {args.repeats} interleaved pairs\n"
            f"  pinwind.simulate (whole call)  {pw:7.2f} µs/step (median)\n"
            f"  MuJoCo mj_step (bare loop)     {mjs:7.2f} µs/step (median)\n"
            f"  ratio per pair: median {statistics.median(ratios):.3f}, "
            f"min {min(ratios):.3f}, max {max(ratios):.3f}  (goal ≤ 1.2)\n"
            f"  pinwind step loop alone        {pw_loop:7.2f} µs/step (median; "
            f"metadata['wall_time_s'])\n"
            f"  ratio per pair, step loop ÷ mj_step: median "
            f"{statistics.median(loop_ratios):.3f}, min {min(loop_ratios):.3f}, "
            f"max {max(loop_ratios):.3f}  (issue 37's goal ≤ 0.7)"
        )


if __name__ == "__main__":
    main()
