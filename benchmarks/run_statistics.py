"""Cost of the run statistics: simulate folding every sample into min, max, mean, RMS and final.

When the Result does not keep every sample (``keep="last"``, every N-th, or ``"auto"`` on a long
run), ``simulate`` folds every block into ``result.statistics`` on a thread of its own
(``analysis/run_statistics.RunningStatistics``). For each model, the same unlogged run with
``keep="last"`` without and with the statistics, interleaved A/B ``--repeats`` times: the median
of the per-pair ratios of wall time (the cost the loop sees), and of CPU time (the work, all
threads); then the same pairs logged at full rate (the log's writer thread works on the same
second core). Also the folding alone in one thread, per sample, on blocks of the run's size.

    python benchmarks/run_statistics.py [--duration 10] [--dt 1e-4] [--repeats 7] [--models ...]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from saleh_loads import INITIAL_SPEEDS, LOADS, MODELS

import pinwind
from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.io.log_writer import McapLogger

#: Samples per block of the run (``simulate``'s ``chunk``).
BLOCK = 1000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=1e-4, help="time step [s]")
    parser.add_argument("--repeats", type=int, default=7, help="interleaved pairs")
    parser.add_argument("--models", nargs="+", default=list(LOADS), help="names in models/")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="pinwind_statistics_"))
    print(f"pinwind {pinwind.__version__}, {args.duration:g} s at dt = {args.dt:g} s per run\n")
    lines = []
    for name in args.models:
        gearbox = pinwind.load(MODELS / f"{name}.urdf")

        def run(
            folded: bool,
            logged: bool = False,
            duration: float = args.duration,
            gearbox=gearbox,
            name=name,
        ) -> tuple[float, float]:
            log = McapLogger(folder / f"{name}.mcap", overwrite=True) if logged else None
            wall, cpu = time.perf_counter(), time.process_time()
            res = pinwind.simulate(
                gearbox,
                duration=duration,
                dt=args.dt,
                torques=LOADS[name],
                initial_speeds=INITIAL_SPEEDS[name],
                keep="last",
                statistics=folded,
                observer=log,
                progress=False,
            )
            assert (res.statistics is not None) == folded
            return time.perf_counter() - wall, time.process_time() - cpu

        run(False, duration=0.1), run(True, duration=0.1), run(True, True, 0.1)  # warm-up
        pairs = [(run(False), run(True)) for _ in range(args.repeats)]
        wall = statistics.median(b[0] / a[0] for a, b in pairs)
        cpu = statistics.median(b[1] / a[1] for a, b in pairs)
        logged = [(run(False, True), run(True, True)) for _ in range(args.repeats)]
        wall_logged = statistics.median(b[0] / a[0] for a, b in logged)
        samples = round(args.duration / args.dt) + 1
        plain = statistics.median(a[0] for a, _ in pairs) / samples

        everything = pinwind.simulate(
            gearbox,
            duration=2.0,
            dt=args.dt,
            torques=LOADS[name],
            initial_speeds=INITIAL_SPEEDS[name],
            keep="all",
            progress=False,
        )
        best = float("inf")
        for _ in range(args.repeats):
            folded = RunningStatistics()
            start = time.perf_counter()
            for at in range(0, len(everything), BLOCK):
                folded.add(everything.rows(at, at + BLOCK))
            best = min(best, time.perf_counter() - start)
        fold = best / len(everything)
        print(
            f"== {name}: {samples} samples, {len(folded.rows())} series\n"
            f"  run without statistics        {plain * 1e6:7.2f} µs/sample (median)\n"
            f"  with ÷ without, wall time     {wall:7.3f} (median of {args.repeats} pairs)\n"
            f"  with ÷ without, CPU time      {cpu:7.3f}\n"
            f"  the same, wall, logged runs   {wall_logged:7.3f} (the log's writer thread shares "
            "the other core)\n"
            f"  folding alone, one thread     {fold * 1e6:7.2f} µs/sample "
            f"({fold / plain:.2f} of the run)\n"
        )
        lines.append(
            f"{name:22s} {plain * 1e6:8.2f} {wall:7.3f} {cpu:7.3f} {wall_logged:7.3f} "
            f"{fold * 1e6:8.2f}"
        )
    print("model                  run µs/s  wall    CPU     logged  fold µs/s")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
