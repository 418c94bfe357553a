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

``--dask`` starts a LocalCluster of 1, then of 2 one-thread workers
(`pinwind.runs.dask_workers.local_client`, which also closes it without the traceback
distributed logs when a worker's last message meets the closed scheduler), warms each worker's
imports, and times ``--seeds`` x 8 cases of ``--dask-duration`` seconds on each: cases per
second and the gain of the second worker (1.0: twice the rate of one). It is a measurement of
the scaling only if the machine's other processes used less than ``OTHERS_LIMIT`` (0.1) cores
while each run was timed: the machine's busy CPU time (/proc/stat through psutil) less that of
this process and its children (the scheduler, nannies and workers), over the wall time
(`machine.others_cores`); the output prints it. The load average cannot tell: this
benchmark's own workers raise it to 1.3-1.9 on 2 cores.
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
#: Cores the other processes of the machine may use while a ``--dask`` run is timed [cores].
OTHERS_LIMIT = 0.1


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
    from pinwind.life.set_bearing_life import set_bearing_lives
    from pinwind.life.set_damage import set_damage
    from pinwind.runs.case_runner import run_cases
    from pinwind.runs.fatigue_set_file import load_fatigue_set

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
    from pinwind.life.case_cycles import CaseCycles

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


def _process_cpu() -> float:
    """CPU seconds of the calling process so far, all its threads [s]."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _workers_cpu(client) -> float:
    """CPU seconds of every worker process so far [s]."""
    return sum(client.run(_process_cpu).values())


def dask_rate(n_workers: int, *, duration: float, seeds: int, settings: dict) -> dict:
    """The set on a LocalCluster of ``n_workers`` warm one-thread workers: rates and CPU.

    Warm-up: two short cases per worker through `run_cases` (imports, the model, the first
    run's own costs) before the clock starts. Then ``seeds`` x 8 cases of ``duration`` s, timed
    from the submission to the last case written. CPU seconds are read from each process
    (`resource.getrusage`, all threads): the workers, and this process, which is the command
    (the client) and, in a LocalCluster, the scheduler and the workers' nannies too. Over the
    same span, the cores the other processes of the machine used (`machine.others_cores`).
    ``settings``: the Dask configuration of every process of the cluster.
    """
    sys.path.insert(0, str(HERE))
    from machine import cpu_sample, others_cores

    from pinwind.life.case_cycles import CaseCycles
    from pinwind.runs.case_runner import run_cases
    from pinwind.runs.dask_workers import local_client
    from pinwind.runs.fatigue_set_file import load_fatigue_set

    with tempfile.TemporaryDirectory(prefix="pinwind_fatigue_dask_") as folder:
        (Path(folder) / "warm").mkdir()
        warm = load_fatigue_set(
            set_file(Path(folder) / "warm", duration=0.1, bins=2 * n_workers, seeds=1)
        )
        fset = load_fatigue_set(set_file(Path(folder), duration=duration, bins=8, seeds=seeds))
        with local_client(n_workers, config=settings) as client:
            run_cases(warm, scheduler=client)
            before = machine_state()
            workers_cpu = _workers_cpu(client)
            sample = cpu_sample()
            command_cpu, start = _process_cpu(), time.perf_counter()
            run = run_cases(fset, scheduler=client)
            wall = time.perf_counter() - start
            command_cpu = _process_cpu() - command_cpu
            others = others_cores(sample, cpu_sample())
            workers_cpu = _workers_cpu(client) - workers_cpu
            after = machine_state()
        reduced = [CaseCycles.load(fset.cycles_path(c), with_flanks=False) for c in fset.cases()]
        cases = len(run.computed)
        return {
            "workers": n_workers,
            "cases": cases,
            "wall_s": wall,
            "rate": cases / wall,
            "case_wall_s": sum(r.wall_time for r in reduced) / cases,
            "case_cpu_s": sum(r.cpu_time for r in reduced) / cases,
            "case_thread_s": sum(r.thread_time for r in reduced) / cases,
            "worker_cpu_s": workers_cpu / cases,
            "command_cpu_s": command_cpu / cases,
            "command_cores": command_cpu / wall,
            "npz_mb": sum(fset.cycles_path(c).stat().st_size for c in fset.cases()) / cases / 1e6,
            "log_mb": sum(fset.log_path(c).stat().st_size for c in fset.cases()) / cases / 1e6,
            "others_cores": others,
            "before": before,
            "after": after,
        }


def machine_state() -> tuple[float, float]:
    """(load average over the last minute, cores a process gets asking for two) now."""
    sys.path.insert(0, str(HERE))
    from machine import parallel_capacity

    return os.getloadavg()[0], parallel_capacity()


def print_dask(runs: list[dict], duration: float, settings: dict) -> None:
    """The two LocalCluster runs, what each case cost, and what that allows on two cores."""
    print(
        f"Dask LocalCluster, one thread per worker, {runs[0]['cases']} cases of {duration:g} s "
        "(8 wind bins x seeds), warm workers; CPU = user + system of a process, all threads; "
        + (
            "Dask settings: pinwind.runs.dask_workers.WORKER_CONFIG"
            if settings
            else "Dask's default settings"
        )
    )
    for r in runs:
        (load0, free0), (load1, free1) = r["before"], r["after"]
        print(
            f"  {r['workers']} worker(s): {r['rate']:.3f} cases/s ({r['cases']} cases in "
            f"{r['wall_s']:.1f} s)\n"
            f"    a case in its worker: wall {r['case_wall_s']:.2f} s, CPU {r['case_cpu_s']:.2f} s "
            f"= {r['case_cpu_s'] / r['case_wall_s']:.2f} cores busy; its own thread "
            f"{r['case_thread_s']:.2f} s: it keeps {r['case_cpu_s'] / r['case_thread_s']:.2f} "
            "cores busy on free cores (the rest: the log writer's and Dask's threads)\n"
            f"    CPU per case: workers {r['worker_cpu_s']:.2f} s (whole processes), command "
            f"{r['command_cpu_s']:.3f} s (client, scheduler, nannies: {r['command_cores']:.3f} "
            "cores)\n"
            f"    other processes: {r['others_cores']:.3f} cores while timed (the machine's busy "
            "CPU less this process's and its children's, psutil); load average "
            f"{load0:.2f} -> {load1:.2f} (counts the workers too), {free0:.2f} -> {free1:.2f} of "
            "2 cores free (before -> after)"
        )
    one, two = runs
    print(
        f"  each case sends back its name only; its worker writes its log ({one['log_mb']:.1f} "
        f"MB) and its cycles ({one['npz_mb']:.2f} MB .npz) to the shared folder"
    )
    gain = two["rate"] / one["rate"] - 1.0
    # One worker on free cores runs a case in C / b seconds of wall (b: the cores it keeps
    # busy); two share what the command leaves of the 2 cores, at C each if they do not slow
    # each other, at C2 / C1 times that if they do.
    busy = one["case_cpu_s"] / one["case_thread_s"]
    bound = (2.0 - two["command_cores"]) / busy
    contention = two["worker_cpu_s"] / one["worker_cpu_s"]
    print(
        f"second worker adds {gain:.0%} of one worker's rate (goal: >= 80 %)\n"
        f"  what the CPU per case allows on 2 free cores: {bound - 1.0:.0%} = (2 - command cores)"
        f" / (cores a case keeps busy) - 1; with the workers' CPU per case with 2 / with 1 "
        f"({contention:.2f}; above 1: the workers slow each other by shared caches, memory or "
        f"host cores; a few % either way on a busy machine): {bound / contention - 1.0:.0%}"
    )
    others = max(r["others_cores"] for r in runs)
    # Each core others take while two workers run costs the second worker's gain up to 1.0.
    if others < OTHERS_LIMIT:
        print(
            f"  a measurement of the scaling: other processes used at most {others:.3f} cores "
            f"while timed (limit {OTHERS_LIMIT:g}; they lower the gain by "
            f"{100 * others:.1f} points at most)"
        )
    else:
        print(
            f"  NOT a measurement of the scaling: other processes used up to {others:.2f} cores "
            f"while timed (limit {OTHERS_LIMIT:g}): rerun on a quiet machine"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=30.0, help="seconds per case")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes")
    parser.add_argument("--memory", action="store_true", help="also run 4 cases, for memory")
    parser.add_argument("--dask", action="store_true", help="cases/s on a LocalCluster of 1, 2")
    parser.add_argument("--dask-duration", type=float, default=2.0, help="seconds per Dask case")
    parser.add_argument("--seeds", type=int, default=2, help="Dask: seeds per bin (8 x seeds)")
    parser.add_argument(
        "--dask-defaults", action="store_true", help="Dask's own settings, not WORKER_CONFIG"
    )
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child is not None:
        child(args.child, args.workers)
        return
    if args.dask:
        from pinwind.runs.dask_workers import WORKER_CONFIG

        settings = {} if args.dask_defaults else WORKER_CONFIG
        runs = [
            dask_rate(n, duration=args.dask_duration, seeds=args.seeds, settings=settings)
            for n in (1, 2)
        ]
        print_dask(runs, args.dask_duration, settings)
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
