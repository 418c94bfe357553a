"""Jørgensen 2014's fatigue set (8 wind bins x 30 s, compliant, TI 10 %): wall time, memory, Dask.

    python benchmarks/fatigue_set.py                       # 8 cases of 30 s, --workers 2
    python benchmarks/fatigue_set.py --duration 3          # a quick try (8 cases of 3 s)
    python benchmarks/fatigue_set.py --memory              # + peak memory of 4 against 8 cases
    python benchmarks/fatigue_set.py --dask                # cases/s on a LocalCluster of 1, 2

The set is scenarios/dtu500_fatigue.toml at one turbulence level ([0.10]), written to a
temporary folder with its output there, and run as ``pinwind fatigue`` runs it (`run_cases`,
then the gear damage and the bearing lives), in a child process each time so that its peak
resident memory is its own: `resource.getrusage` of the child itself (the command, which
combines the cases) and of its children (the largest local worker). Each result line also gives
the load average and the cores this process gets asking for two (`machine.parallel_capacity`),
since other jobs share the machine. Figures in benchmarks/README.md.

``--dask`` starts ``distributed.LocalCluster(n_workers=1, then 2, threads_per_worker=1)``,
warms each worker's imports, and times ``--seeds`` x 8 cases of ``--dask-duration`` seconds on
each: cases per second and the gain of the second worker (1.0: twice the rate of one).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENARIO = HERE.parent / "scenarios" / "dtu500_fatigue.toml"


def set_file(folder: Path, *, duration: float, bins: int, seeds: int) -> Path:
    """The DTU set at TI 10 %, ``bins`` first wind bins, cases of ``duration`` s, in ``folder``."""
    text = SCENARIO.read_text()
    model = (SCENARIO.parent / "../models/dtu500_planetary.urdf").resolve()
    speeds = [6, 8, 10, 12, 14, 16, 18, 20][:bins]
    hours = [45418, 31900, 16320, 6189, 1751, 370, 58, 7][:bins]
    skip = min(1.0, duration / 3.0)
    replace = {
        r"^model = .*$": f'model = "{model.as_posix()}"',
        r"^out = .*$": f'out = "{(folder / "cases").as_posix()}"',
        r"^duration = 30\.0.*$": f"duration = {duration!r}",
        r"^skip_start = 1\.0.*$": f"skip_start = {skip!r}",
        r"^seeds = .*$": f"seeds = {list(range(1, seeds + 1))}",
        r"^turbulence = \[0\.08.*$": "turbulence = [0.10]",
        r"^speeds = .*$": f"speeds = {speeds}",
        r"^hours = .*$": f"hours = {hours}",
    }
    for pattern, line in replace.items():
        text, n = re.subn(pattern, line, text, count=1, flags=re.MULTILINE)
        if n != 1:
            raise SystemExit(f"{SCENARIO}: no line matches {pattern}; update this benchmark")
    path = folder / "set.toml"
    path.write_text(text)
    return path


def machine() -> str:
    """Load average and the cores a process gets asking for two, now."""
    sys.path.insert(0, str(HERE))
    from machine import parallel_capacity

    return f"load {os.getloadavg()[0]:.2f}, {parallel_capacity():.2f} of 2 cores free"


def child(path: Path, workers: int) -> None:
    """Run the set as ``pinwind fatigue --workers N`` does; print wall time and peak memory."""
    from pinwind.life.life_damage import set_damage
    from pinwind.life.load_cases import load_fatigue_set, run_cases
    from pinwind.life.set_bearing_life import set_bearing_lives

    start = time.perf_counter()
    fset = load_fatigue_set(path)
    run = run_cases(fset, workers=workers)
    damage = set_damage(fset)
    lives = set_bearing_lives(fset)
    wall = time.perf_counter() - start
    print(
        json.dumps(
            {
                "cases": run.total,
                "backend": run.backend,
                "wall_s": wall,
                # ru_maxrss is in KiB on Linux
                "command_peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                "worker_peak_mb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024,
                "case_wall_s": sorted(_case_walls(fset)),
                "sun_damage_no_limit": damage.damage["no limit"][0]["sun"].total,
                "bearings": {
                    life.joint: [life.equivalent_load / 1e3, life.l10h]
                    for life in lives[0]
                    if life.rated
                },
            }
        )
    )


def _case_walls(fset) -> list[float]:
    from pinwind.life.load_cases import CaseCycles

    return [CaseCycles.load(fset.cycles_path(c), with_flanks=False).wall_time for c in fset.cases()]


def run_set(*, duration: float, bins: int, workers: int) -> dict:
    """The set in a child process (fresh output folder): its report."""
    with tempfile.TemporaryDirectory(prefix="pinwind_fatigue_bench_") as folder:
        path = set_file(Path(folder), duration=duration, bins=bins, seeds=1)
        out = subprocess.run(
            [sys.executable, __file__, "--child", str(path), "--workers", str(workers)],
            capture_output=True,
            text=True,
            check=False,
        )
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout.strip().splitlines()[-1])


def dask_rate(n_workers: int, *, duration: float, seeds: int) -> tuple[float, int]:
    """(cases per second, cases) of the set on a LocalCluster of ``n_workers`` warm workers."""
    from distributed import Client, LocalCluster

    from pinwind.life.load_cases import load_fatigue_set, run_cases

    with tempfile.TemporaryDirectory(prefix="pinwind_fatigue_dask_") as folder:
        path = set_file(Path(folder), duration=duration, bins=8, seeds=seeds)
        fset = load_fatigue_set(path)
        with (
            LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                         dashboard_address=None) as cluster,
            Client(cluster) as client,
        ):  # fmt: skip
            # Import pinwind (Pinocchio, the step loop) in every worker before the clock starts.
            client.run(lambda: __import__("pinwind.life.load_cases"))
            start = time.perf_counter()
            run = run_cases(fset, scheduler=client)
            wall = time.perf_counter() - start
    return len(run.computed) / wall, len(run.computed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=30.0, help="seconds per case")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes")
    parser.add_argument("--memory", action="store_true", help="also run 4 cases, for memory")
    parser.add_argument("--dask", action="store_true", help="cases/s on a LocalCluster of 1, 2")
    parser.add_argument("--dask-duration", type=float, default=2.0, help="seconds per Dask case")
    parser.add_argument("--seeds", type=int, default=2, help="Dask: seeds per bin (8 x seeds)")
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child is not None:
        child(args.child, args.workers)
        return
    if args.dask:
        rates = []
        for n in (1, 2):
            before = machine()
            rate, cases = dask_rate(n, duration=args.dask_duration, seeds=args.seeds)
            rates.append(rate)
            print(f"Dask LocalCluster of {n}: {cases} cases of {args.dask_duration:g} s, "
                  f"{rate:.3f} cases/s ({before} before; {machine()} after)")  # fmt: skip
        gain = rates[1] / rates[0] - 1.0
        print(f"second worker adds {gain:.0%} of one worker's rate (goal: >= 80 %)")
        return
    sizes = (4, 8) if args.memory else (8,)
    for bins in sizes:
        before = machine()
        report = run_set(duration=args.duration, bins=bins, workers=args.workers)
        print(
            f"{report['cases']} cases x {args.duration:g} s, --workers {args.workers} "
            f"({report['backend']}): wall {report['wall_s']:.1f} s; peak memory: command "
            f"{report['command_peak_mb']:.0f} MB, largest worker {report['worker_peak_mb']:.0f} "
            f"MB; case wall {min(report['case_wall_s']):.1f}-{max(report['case_wall_s']):.1f} s "
            f"({before} before; {machine()} after)"
        )
        bearings = ", ".join(
            f"{joint} {load:.3g} kN, {hours:.3g} h"
            for joint, (load, hours) in report["bearings"].items()
        )
        print(f"  sun damage (no limit) {report['sun_damage_no_limit']:.4g}; bearings P_eq, L10h: "
              f"{bearings}")  # fmt: skip


if __name__ == "__main__":
    main()
