"""Cost of MCAP logging at full rate: µs per step of saleh2017_drivetrain with and without a log.

Runs alternate (plain, logged, plain, logged, ...) in one process after a warm-up of each kind,
so both see the same machine state. Each run is timed end to end (the ``simulate`` call: a logged
run includes opening the file, every chunk, the summary and closing). The logger's own time is
also measured inside its calls, which is less noisy than the difference of two runs. Prints the
medians and the ratio; issue 3 asks for a ratio of at most 1.20.

    python benchmarks/log_overhead.py [--duration 5] [--repeats 5] [--out FOLDER]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import pinwind
from pinwind.dynamics.simulate import simulate
from pinwind.io.mcap_log import McapLogger

MODEL = Path(__file__).resolve().parents[1] / "models" / "saleh2017_drivetrain.urdf"
#: Rotor torque on the carrier [N·m] and its steady counterpart at the generator shaft.
CARRIER_TORQUE = 1.0e6
RATIO = 6.0 * 3.6 * 3.96


class TimedLogger:
    """An McapLogger that adds up the wall time spent in its calls."""

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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=5.0, help="simulated time per run [s]")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--repeats", type=int, default=5, help="runs of each kind")
    parser.add_argument("--out", type=Path, default=None, help="folder for the logs")
    args = parser.parse_args()

    gearbox = pinwind.load(MODEL)
    torques = {"carrier": CARRIER_TORQUE, "stage2_pinion": -CARRIER_TORQUE / RATIO}
    folder = args.out or Path(tempfile.mkdtemp(prefix="pinwind_bench_"))
    folder.mkdir(parents=True, exist_ok=True)
    steps = round(args.duration / args.dt)

    def plain_run(duration: float) -> float:
        start = time.perf_counter()
        simulate(gearbox, duration=duration, dt=args.dt, torques=torques, progress=False)
        return time.perf_counter() - start

    def logged_run(duration: float, path: Path) -> tuple[float, float]:
        observer = TimedLogger(McapLogger(path, overwrite=True))
        start = time.perf_counter()
        simulate(
            gearbox,
            duration=duration,
            dt=args.dt,
            torques=torques,
            progress=False,
            observer=observer,
        )
        return time.perf_counter() - start, observer.seconds

    plain_run(0.2)
    logged_run(0.2, folder / "warmup.mcap")
    plain, logged, logger = [], [], []
    for i in range(args.repeats):
        a = plain_run(args.duration) / steps * 1e6
        b, inside = logged_run(args.duration, folder / f"run{i}.mcap")
        b, inside = b / steps * 1e6, inside / steps * 1e6
        plain.append(a)
        logged.append(b)
        logger.append(inside)
        print(f"run {i}: plain {a:6.1f}  logged {b:6.1f}  (in the logger {inside:5.1f}) µs/step")
    a, b, inside = (statistics.median(x) for x in (plain, logged, logger))
    size = (folder / f"run{args.repeats - 1}.mcap").stat().st_size
    print(
        f"\n{MODEL.name}, {steps} steps of {args.dt:g} s, median of {args.repeats} runs each:\n"
        f"  without log          {a:7.1f} µs/step\n"
        f"  with log             {b:7.1f} µs/step\n"
        f"  ratio                {b / a:7.3f}  (budget 1.20)\n"
        f"  time in the logger   {inside:7.1f} µs/step = {100 * inside / a:.1f} % of a plain step\n"
        f"  log size             {size / 1e6:7.2f} MB for {args.duration:g} s "
        f"({size / args.duration * 60 / 1e6:.0f} MB per simulated minute)"
    )


if __name__ == "__main__":
    main()
