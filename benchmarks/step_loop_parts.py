"""The step loop's wall time: its compiled calls and the Python around them, against ``mj_step``.

``pinwind.simulate``'s ``metadata["wall_time_s"]`` times the step loop: the compiled
``Stepper.run`` calls (timed here by a wrapper around each) and the Python around each block
(signal tables, checks, derived series). For each model, pairs alternate (pinwind, then
MuJoCo's bare ``qfrc_applied`` + ``mj_step`` loop, as ``vs_mujoco.py``) after a warm-up of
each; printed are the medians over the pairs of

- whole ÷ mj: the whole ``simulate`` call per step over ``mj_step``'s;
- loop ÷ mj: ``wall_time_s`` per step over ``mj_step``'s (issue 37 asks for at most 0.7);
- compiled ÷ mj: the compiled calls alone;
- Python µs/step: the loop's time outside the compiled calls.

The load case is ``step_rate.py``'s closed-form torques, from rest, every sample kept, no log.

    python benchmarks/step_loop_parts.py [--models saleh2017_planetary ...] [--steps 10000] \\
        [--pairs 9]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

import mujoco

import pinwind
from pinwind.dynamics import stepper as stepper_module
from pinwind.errors import TorquesUnbalanced

sys.path.insert(0, str(Path(__file__).resolve().parent))
from vs_mujoco import closed_form_case, mujoco_run  # noqa: E402

#: Seconds spent in the compiled ``run`` calls since the last reset.
_COMPILED = [0.0]


class _TimedStepper:
    """The compiled stepper with its ``run`` calls timed; everything else passed through."""

    def __init__(self, inner: object) -> None:
        self._inner = inner

    def __getattr__(self, name: str) -> object:
        return getattr(self._inner, name)

    def run(self, *args: object) -> object:
        started = time.perf_counter()
        try:
            return self._inner.run(*args)  # type: ignore[attr-defined]
        finally:
            _COMPILED[0] += time.perf_counter() - started


def _time_compiled_calls() -> None:
    """Wraps every CompiledStepper's compiled stepper in ``_TimedStepper`` from now on."""
    cls = stepper_module.CompiledStepper
    init = cls.__init__

    def timed_init(self, *args, **kwargs) -> None:  # type: ignore[no-untyped-def]
        init(self, *args, **kwargs)
        self._stepper = _TimedStepper(self._stepper)

    cls.__init__ = timed_init  # type: ignore[method-assign]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--models", nargs="+", default=["saleh2017_planetary", "saleh2017_drivetrain"]
    )
    parser.add_argument("--steps", type=int, default=10_000, help="steps per run")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--pairs", type=int, default=9, help="pinwind/MuJoCo pairs per model")
    args = parser.parse_args()
    _time_compiled_calls()
    warnings.simplefilter("ignore", TorquesUnbalanced)  # the load case accelerates the train
    print(f"pinwind {pinwind.__version__}, mujoco {mujoco.__version__}")
    for name in args.models:
        gb, torques, mj, tau = closed_form_case(name, args.dt)
        pinwind.simulate(gb, duration=100 * args.dt, dt=args.dt, torques=torques)
        mujoco_run(mj, tau, 1000)
        whole, loop, compiled, python, mj_us = [], [], [], [], []
        for _ in range(args.pairs):
            _COMPILED[0] = 0.0
            started = time.perf_counter()
            res = pinwind.simulate(
                gb, duration=args.steps * args.dt, dt=args.dt, torques=torques, progress=False
            )
            call = (time.perf_counter() - started) / args.steps
            step_loop = res.metadata["wall_time_s"] / args.steps
            inside = _COMPILED[0] / args.steps
            bare = mujoco_run(mj, tau, args.steps)
            whole.append(call / bare)
            loop.append(step_loop / bare)
            compiled.append(inside / bare)
            python.append((step_loop - inside) * 1e6)
            mj_us.append(bare * 1e6)
        print(
            f"{name}: {args.pairs} pairs of {args.steps} steps of {args.dt:g} s, medians: "
            f"whole ÷ mj {statistics.median(whole):.3f}, loop ÷ mj {statistics.median(loop):.3f} "
            f"({min(loop):.3f}–{max(loop):.3f}), compiled ÷ mj {statistics.median(compiled):.3f}, "
            f"Python {statistics.median(python):.2f} µs/step, mj_step "
            f"{statistics.median(mj_us):.2f} µs/step"
        )


if __name__ == "__main__":
    main()
