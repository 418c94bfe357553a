"""The NREL 5 MW fatigue set on Dask: 3 wind bins x 2 seeds, timed on 1 and then 2 workers.

    python benchmarks/nrel5mw_fatigue_set.py                 # 6 cases of 2 s, 1 then 2 workers
    python benchmarks/nrel5mw_fatigue_set.py --duration 5    # longer cases

The set is the example's (``examples/nrel5mw_drivetrain.py``: ``scenarios/nrel5mw_turbulent.toml``
with its ``FATIGUE`` table: compliant meshes, dt 1e-4 s, histories at 1 kHz, every gear (the
helical stage 3's too) and every bearing row rated) over three wind bins of the same class I site
(10-12, 12-14, 14-16 m/s: the example's bin and one either side), class B turbulence, seeds 1
and 2, cases of ``--duration`` s counted from a quarter of it. Every case starts at the
scenario's initial speed and pitch (12.1 rpm, the steady pitch of 13 m/s), so the other bins'
first seconds are a transient (the pitch controller's). The figures are
the cost of the set, not its damage.

Each cluster is a ``LocalCluster`` of one-thread workers (``pinwind.runs.dask_workers``), warmed
by one short case per worker (imports, the model) before the clock starts; the set is then run
as ``pinwind fatigue --scheduler`` runs it (`run_cases`), timed from the submission to the last
case written, and the gear damage and bearing lives are combined (`set_damage`,
`set_bearing_lives`). Printed per cluster: cases per second, a case's wall and CPU time in its
worker, and the cores the machine's other processes used meanwhile (``machine.others_cores``):
above ``OTHERS_LIMIT`` the gain of the second worker is not a measurement of the scaling.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import resource
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parent / "examples" / "nrel5mw_drivetrain.py"
#: The set's wind bins [m/s] (edges) and seeds.
EDGES = [10.0, 12.0, 14.0, 16.0]
SEEDS = [1, 2]
#: Cores the other processes of the machine may use while a run is timed [cores].
OTHERS_LIMIT = 0.1


def example() -> Any:
    """The example's module (its ``FATIGUE`` table and ``SCENARIO``)."""
    spec = importlib.util.spec_from_file_location("nrel5mw_drivetrain", EXAMPLE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def fatigue_set(out: Path, *, duration: float, edges: list[float], seeds: list[int]) -> Any:
    """The example's set over ``edges`` and ``seeds``, cases of ``duration`` s, in ``out``."""
    from pinwind.runs.fatigue_set_file import load_fatigue_set

    ex = example()
    table = {
        **ex.FATIGUE,
        "out": str(out),
        "duration": duration,
        "skip_start": duration / 4,
        "seeds": seeds,
        "site": {**ex.FATIGUE["site"], "edges": edges},
    }
    return load_fatigue_set(ex.SCENARIO, fatigue=table)


def _process_cpu() -> float:
    """CPU seconds of the calling process so far, all its threads [s]."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def timed(n_workers: int, folder: Path, duration: float) -> dict[str, Any]:
    """The set on a LocalCluster of ``n_workers`` warm workers: wall, CPU, others' cores."""
    sys.path.insert(0, str(HERE))
    from machine import cpu_sample, others_cores

    from pinwind.life.case_cycles import CaseCycles
    from pinwind.life.damage_ranking import damage_ranking
    from pinwind.life.set_bearing_life import set_bearing_lives
    from pinwind.life.set_damage import set_damage
    from pinwind.runs.case_runner import run_cases
    from pinwind.runs.dask_workers import WORKER_CONFIG, local_client

    warm = fatigue_set(folder / f"warm{n_workers}", duration=0.05, edges=EDGES[: n_workers + 1],
                       seeds=[1])  # fmt: skip
    fset = fatigue_set(folder / f"set{n_workers}", duration=duration, edges=EDGES, seeds=SEEDS)
    with local_client(n_workers, config=WORKER_CONFIG) as client:
        run_cases(warm, scheduler=client)
        workers_cpu = sum(client.run(_process_cpu).values())
        sample, command_cpu = cpu_sample(), _process_cpu()
        start = time.perf_counter()
        run = run_cases(fset, scheduler=client)
        wall = time.perf_counter() - start
        others = others_cores(sample, cpu_sample())
        command_cpu = _process_cpu() - command_cpu
        workers_cpu = sum(client.run(_process_cpu).values()) - workers_cpu
    combine = time.perf_counter()
    ranking = damage_ranking(set_damage(fset), set_bearing_lives(fset))
    combine = time.perf_counter() - combine
    reduced = [CaseCycles.load(fset.cycles_path(c), with_flanks=False) for c in fset.cases()]
    cases = len(run.computed)
    return {
        "workers": n_workers,
        "cases": cases,
        "wall": wall,
        "rate": cases / wall,
        "case_wall": sum(r.wall_time for r in reduced) / cases,
        "case_cpu": sum(r.cpu_time for r in reduced) / cases,
        "worker_cpu": workers_cpu / cases,
        "command_cpu": command_cpu / cases,
        "others": others,
        "load": os.getloadavg()[0],
        "combine": combine,
        "top": ranking[:3],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=2.0, help="simulated seconds per case")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="pinwind_nrel5mw_set_") as name:
        runs = [timed(n, Path(name), args.duration) for n in (1, 2)]
    print(
        f"NREL 5 MW fatigue set: {len(EDGES) - 1} wind bins x {len(SEEDS)} seeds = "
        f"{runs[0]['cases']} cases of {args.duration:g} s (dt 1e-4 s, 13 compliant meshes), "
        "Dask LocalCluster of one-thread workers, warm"
    )
    for r in runs:
        print(
            f"  {r['workers']} worker(s): {r['wall']:.1f} s wall, {r['rate']:.3f} cases/s; a case "
            f"in its worker {r['case_wall']:.1f} s wall, {r['case_cpu']:.1f} s CPU; CPU per case: "
            f"workers {r['worker_cpu']:.1f} s, command {r['command_cpu']:.2f} s; other processes "
            f"{r['others']:.2f} cores while timed, load average {r['load']:.1f} after; damage and "
            f"lives combined in {r['combine']:.1f} s"
        )
    one, two = runs
    gain = two["rate"] / one["rate"] - 1.0
    others = max(r["others"] for r in runs)
    verdict = (
        "a measurement of the scaling"
        if others < OTHERS_LIMIT
        else f"NOT a measurement of the scaling (other processes used up to {others:.2f} cores, "
        f"limit {OTHERS_LIMIT:g}): rerun on a quiet machine"
    )
    print(f"  the second worker adds {gain:.0%} of one worker's rate: {verdict}")
    top = ", ".join(f"{i.name} ({i.kind}) {i.damage:.3g}" for i in runs[1]["top"])
    print(f"  most damaged (these short cases' hours, not a life): {top}")


if __name__ == "__main__":
    main()
