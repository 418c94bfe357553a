"""Cost of MCAP logging at full rate: µs per step of saleh2017_drivetrain with and without a log.

Runs alternate (plain, logged, plain, logged, ...) in one process so that both see the same
machine state; each run is timed end to end (``simulate`` call, so the logged runs include opening,
every chunk, the summary and closing the file). Prints the medians and their ratio; issue 3 asks
for a ratio of at most 1.20.

    python benchmarks/log_overhead.py [--duration 3] [--repeats 3] [--out /tmp/pinwind_bench]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import pinwind

MODEL = Path(__file__).resolve().parents[1] / "models" / "saleh2017_drivetrain.urdf"
#: Rotor torque on the carrier and its steady counterpart at the generator shaft [N·m].
CARRIER_TORQUE = 1.0e6
RATIO = 6.0 * 3.6 * 3.96


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=3.0, help="simulated time per run [s]")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--repeats", type=int, default=3, help="runs of each kind")
    parser.add_argument("--out", type=Path, default=None, help="folder for the logs")
    args = parser.parse_args()

    gearbox = pinwind.load(MODEL)
    torques = {"carrier": CARRIER_TORQUE, "stage2_pinion": -CARRIER_TORQUE / RATIO}
    folder = args.out or Path(tempfile.mkdtemp(prefix="pinwind_bench_"))
    folder.mkdir(parents=True, exist_ok=True)
    steps = round(args.duration / args.dt)
    plain, logged = [], []
    size = 0
    for i in range(args.repeats):
        for kind in ("plain", "logged"):
            log = folder / f"run{i}.mcap" if kind == "logged" else None
            start = time.perf_counter()
            pinwind.simulate(
                gearbox, duration=args.duration, dt=args.dt, torques=torques, log=log,
                overwrite=True, progress=False,
            )  # fmt: skip
            per_step = (time.perf_counter() - start) / steps * 1e6
            (logged if log else plain).append(per_step)
            if log:
                size = log.stat().st_size
            print(f"{kind:6s} run {i}: {per_step:7.1f} µs/step")
    a, b = statistics.median(plain), statistics.median(logged)
    print(
        f"\n{MODEL.name}, {steps} steps of {args.dt:g} s, median of {args.repeats}:\n"
        f"  without log {a:7.1f} µs/step\n  with log    {b:7.1f} µs/step\n"
        f"  ratio       {b / a:7.3f}  (logging costs {100 * (b / a - 1):.1f} %; budget 20 %)\n"
        f"  log size    {size / 1e6:.2f} MB for {args.duration:g} s "
        f"({size / args.duration * 60 / 1e6:.0f} MB per simulated minute)"
    )


if __name__ == "__main__":
    main()
