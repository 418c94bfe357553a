"""Cost of ``pinwind modes`` and of a Campbell diagram (issue 24: < 1 s and < 10 s).

- ``pinwind modes MODEL`` as a user runs it, a fresh process each time: best and median wall
  time of ``--repeats`` runs, and the process's CPU time (user + system, which depends less on
  what else the machine is doing); then, in this process, what the command spends its time on:
  importing pinwind and the CLI, loading the model, linearising and solving.
- A Campbell diagram of ``--speeds`` input speeds: ``campbell`` itself (one linearisation at
  the top of the range: the modes of torsional coordinates do not change with speed), and the
  cost if every speed were linearised and solved (``linearise(speeds=...).modes()`` at each;
  a model whose gyroscopic terms act linearises once and solves at each of ``--points``
  speeds, cheaper than this); ``pinwind campbell`` as a process too.
- The cores this process gets asking for two (``machine.parallel_capacity``): below 2 while other
  work shares the machine, when wall times are longer than the CPU times.

    python benchmarks/modes.py [--model models/cart600_gearbox.urdf] [--repeats 5] [--speeds 100]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import parallel_capacity

ROOT = Path(__file__).resolve().parents[1]


def process_times(args: list[str], repeats: int) -> tuple[list[float], list[float]]:
    """Wall and CPU times [s] of ``python -m pinwind ARGS`` run ``repeats`` times."""
    walls, cpus = [], []
    for _ in range(repeats):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "pinwind", *args], check=True, capture_output=True, cwd=ROOT
        )
        walls.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return walls, cpus


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default=str(ROOT / "models" / "cart600_gearbox.urdf"))
    parser.add_argument("--joint", default="carrier")
    parser.add_argument("--rpm", type=float, default=30.0, help="top of the Campbell range")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--speeds", type=int, default=100)
    args = parser.parse_args()
    os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])

    print(f"cores given when asking for two: {parallel_capacity():.2f}")
    walls, cpus = process_times(["modes", args.model], args.repeats)
    print(
        f"pinwind modes {Path(args.model).name}: wall best {min(walls):.3f} s, median "
        f"{statistics.median(walls):.3f} s; CPU best {min(cpus):.3f} s ({args.repeats} runs)"
    )

    start, cpu = time.perf_counter(), time.process_time()
    import pinwind
    from pinwind.analysis.campbell import campbell
    from pinwind.cli import app  # noqa: F401  (the command imports the CLI too)
    from pinwind.dynamics.linearisation import linearise

    imported, imported_cpu = time.perf_counter(), time.process_time()
    gearbox = pinwind.load(args.model)
    loaded = time.perf_counter()
    modes = linearise(gearbox, meshes={"all": "compliant"}).modes()
    solved = time.perf_counter()
    print(
        f"  in process: import {imported - start:.3f} s (CPU {imported_cpu - cpu:.3f} s), load "
        f"{loaded - imported:.3f} s, linearise + modes {solved - loaded:.4f} s ({len(modes)} modes)"
    )

    top = args.rpm * 2 * 3.141592653589793 / 60
    start, cpu = time.perf_counter(), time.process_time()
    diagram = campbell(gearbox, args.joint, (0.0, top), meshes={"all": "compliant"})
    once, once_cpu = time.perf_counter() - start, time.process_time() - cpu
    start, cpu = time.perf_counter(), time.process_time()
    for k in range(args.speeds):
        speed = top * k / (args.speeds - 1)
        linearise(gearbox, meshes={"all": "compliant"}, speeds={args.joint: speed}).modes()
    each, each_cpu = time.perf_counter() - start, time.process_time() - cpu
    print(
        f"campbell 0-{args.rpm:g} rpm on {args.joint}: {once:.4f} s (CPU {once_cpu:.4f} s, "
        f"{len(diagram.crossings)} crossings); {args.speeds} speeds each linearised: "
        f"{each:.3f} s (CPU {each_cpu:.3f} s)"
    )
    walls, cpus = process_times(
        ["campbell", args.model, "--joint", args.joint, "--speed-range", f"0:{args.rpm:g}"],
        args.repeats,
    )
    print(
        f"pinwind campbell: wall best {min(walls):.3f} s, median {statistics.median(walls):.3f} s;"
        f" CPU best {min(cpus):.3f} s"
    )


if __name__ == "__main__":
    main()
