"""Cost of MCAP logging at full rate: µs per step with and without a log, bytes, reading back.

For each model, runs alternate (plain, logged, plain, logged, ...) in one process after a
warm-up of each kind, so both see the same machine state. Each run is timed end to end (the
``simulate`` call: a logged run includes opening the file, every chunk, the summary and
closing), in wall time and in CPU time of the process (all threads: what the log costs when no
core is free). Before each pair, a probe measures how many cores the process gets when it runs
two threads (the log's thread overlaps the steps only when a second core is free). The
logger's own time in the simulation thread (``begin``, ``samples``, ``end``) is also measured.
Then the last log is read back with ``read_log`` (best of ``--repeats``) and its cost per
sample compared with the compiled step loop's (``metadata["wall_time_s"]``). Prints medians
and the ratios; issue 12 asks for logged ÷ plain ≤ 1.15. Its read ÷ step ≤ 0.1 is measured on
10 s logs by ``read_log.py``: this short log's read includes costs that do not depend on its
length, such as opening the file (1–2 ms of the drivetrain's 13–19 ms at 20 001 samples).

    python benchmarks/log_overhead.py [--models ...] [--duration 20] [--repeats 5] [--out DIR]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from machine import parallel_capacity
from saleh_loads import INITIAL_SPEEDS, LOADS, MODELS

import pinwind
from pinwind.dynamics.simulate import simulate
from pinwind.io.log_reader import read_log
from pinwind.io.log_writer import McapLogger


class TimedLogger:
    """An McapLogger that adds up the wall time spent in its calls (simulation thread)."""

    def __init__(self, logger: McapLogger):
        self.logger = logger
        self.seconds = 0.0

    def _timed(self, method, *args) -> None:
        start = time.perf_counter()
        try:
            method(*args)
        finally:
            self.seconds += time.perf_counter() - start

    def begin(self, gearbox, result) -> None:
        self._timed(self.logger.begin, gearbox, result)

    def samples(self, block, start: int) -> None:
        self._timed(self.logger.samples, block, start)

    def end(self, result, status: str) -> None:
        self._timed(self.logger.end, result, status)


def measure(name: str, duration: float, dt: float, repeats: int, folder: Path) -> None:
    gearbox = pinwind.load(MODELS / f"{name}.urdf")
    torques = LOADS[name]
    steps = round(duration / dt)

    def run(path: Path | None) -> tuple[float, float, float, float]:
        """(wall, CPU, step loop, in the logger) seconds per step."""
        observer = TimedLogger(McapLogger(path, overwrite=True)) if path else None
        wall, cpu = time.perf_counter(), time.process_time()
        res = simulate(
            gearbox,
            duration=duration,
            dt=dt,
            torques=torques,
            initial_speeds=INITIAL_SPEEDS[name],
            progress=False,
            observer=observer,
        )
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        inside = observer.seconds if observer else 0.0
        return wall / steps, cpu / steps, res.metadata["wall_time_s"] / steps, inside / steps

    run(None)
    run(folder / f"{name}_warmup.mcap")
    plain, logged, cores = [], [], []
    for i in range(repeats):
        cores.append(parallel_capacity())
        plain.append(run(None))
        logged.append(run(folder / f"{name}_{i}.mcap"))
        a, b = plain[-1], logged[-1]
        print(
            f"  run {i}: plain {a[0] * 1e6:6.2f}  logged {b[0] * 1e6:6.2f} µs/step wall "
            f"(CPU {a[1] * 1e6:6.2f} / {b[1] * 1e6:6.2f}; in the logger {b[3] * 1e6:5.2f}; "
            f"cores {cores[-1]:.2f})"
        )
    ratios = [b[0] / a[0] for a, b in zip(plain, logged, strict=True)]
    cpu_ratios = [b[1] / a[1] for a, b in zip(plain, logged, strict=True)]
    median = statistics.median
    path = folder / f"{name}_{repeats - 1}.mcap"
    size = path.stat().st_size
    samples = steps + 1
    read = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        back = read_log(path)
        read = min(read, time.perf_counter() - start)
    assert len(back) == samples
    step_loop = median(a[2] for a in plain)
    print(
        f"{name}, {steps} steps of {dt:g} s, {repeats} interleaved pairs (medians):\n"
        f"  without log              {median(a[0] for a in plain) * 1e6:7.2f} µs/step\n"
        f"  with log                 {median(b[0] for b in logged) * 1e6:7.2f} µs/step\n"
        f"  logged ÷ plain, wall     {median(ratios):7.3f}  (pairs {min(ratios):.3f} to "
        f"{max(ratios):.3f}; budget 1.15)\n"
        f"  logged ÷ plain, CPU      {median(cpu_ratios):7.3f}  (all threads)\n"
        f"  cores available          {median(cores):7.2f}  (of 2 asked for, before each pair)\n"
        f"  in the logger's calls    {median(b[3] for b in logged) * 1e6:7.2f} µs/step\n"
        f"  log size                 {size / 1e6:7.2f} MB, {size / samples:.0f} bytes per sample\n"
        f"  read_log                 {read / samples * 1e6:7.2f} µs/sample = "
        f"{read / samples / step_loop:.3f} × the step loop ({step_loop * 1e6:.2f} µs; a short "
        "log, with the fixed cost of opening it: see read_log.py)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=list(LOADS), choices=list(LOADS))
    parser.add_argument("--duration", type=float, default=20.0, help="simulated time per run [s]")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--repeats", type=int, default=5, help="runs of each kind")
    parser.add_argument("--out", type=Path, default=None, help="folder for the logs")
    args = parser.parse_args()
    folder = args.out or Path(tempfile.mkdtemp(prefix="pinwind_bench_"))
    folder.mkdir(parents=True, exist_ok=True)
    for name in args.models:
        measure(name, args.duration, args.dt, args.repeats, folder)


if __name__ == "__main__":
    main()
