"""Design sweep throughput: designs per second on one core, all cores and a 2-worker Dask cluster.

    python benchmarks/sweep.py [--repeat 3]

The 39 designs of Saleh 2017 Table 5 are swept (build, load, 10-step rigid run,
ISO + AGMA + Hertz rating each). Then one design is timed stage by stage to show where the time
goes. Figures in benchmarks/README.md.
"""

from __future__ import annotations

import argparse
import math
import os
import time
import warnings

from pinwind.analysis.sweep_design import SweepSettings
from pinwind.analysis.sweep_planetary import TABLE_5_INCLUDE, enumerate_planetary
from pinwind.runs.sweep import run_sweep


def designs():
    return enumerate_planetary(
        [0.42, 0.48, 0.54, 0.60],
        [m / 1000 for m in (5, 6, 7, 8, 9, 10, 12, 15)],
        ratio_window=(6.0, 6.4),
        include=TABLE_5_INCLUDE,
    )


def best_of(repeat, fn):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def stages(design, settings, repeat=20):
    from pinwind.analysis.rating import rate
    from pinwind.dynamics.simulate import simulate
    from pinwind.gears.checks import check_planetary
    from pinwind.model.builders import planetary_urdf
    from pinwind.model.gearbox import loads

    out = {"checks": 0.0, "build URDF": 0.0, "load (Pinocchio)": 0.0, "simulate": 0.0,
           "rate": 0.0}  # fmt: skip
    for _ in range(repeat):
        t0 = time.perf_counter()
        check_planetary(sun=design.sun, planet=design.planet, ring=design.ring, planets=3,
                        module=design.module, pressure_angle=settings.pressure_angle,
                        face_width=settings.face_width)  # fmt: skip
        t1 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            text = planetary_urdf(sun=design.sun, planet=design.planet, ring=design.ring,
                                  planets=3, module=design.module,
                                  pressure_angle=settings.pressure_angle,
                                  face_width=settings.face_width)  # fmt: skip
            t2 = time.perf_counter()
            gb = loads(text)
            t3 = time.perf_counter()
            res = simulate(gb, duration=settings.duration, dt=settings.dt,
                           torques={"carrier": 1e6, "sun": -1e6 / design.ratio},
                           initial_speeds={"carrier": settings.input_speed})  # fmt: skip
        t4 = time.perf_counter()
        rate(gb, res)
        t5 = time.perf_counter()
        for key, dt in zip(out, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4), strict=True):
            out[key] += dt / repeat
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    items = designs()
    settings = SweepSettings()
    n = len(items)
    cores = os.cpu_count() or 1
    print(f"{n} designs, {cores} cores")
    serial = best_of(args.repeat, lambda: run_sweep(items, settings, workers=1))
    print(f"one core:         {serial:6.2f} s  {n / serial:7.1f} designs/s")
    local = best_of(args.repeat, lambda: run_sweep(items, settings, workers=cores))
    print(f"all cores ({cores}):    {local:6.2f} s  {n / local:7.1f} designs/s (incl. pool start)")
    many = items * 20  # 780 designs: enough to amortise the pool's start
    big_1 = best_of(1, lambda: run_sweep(many, settings, workers=1))
    big_n = best_of(1, lambda: run_sweep(many, settings, workers=cores))
    print(
        f"{len(many)} designs:    one core {len(many) / big_1:.1f}/s, {cores} cores "
        f"{len(many) / big_n:.1f}/s (incl. pool start)"
    )
    from pinwind.runs.dask_workers import local_client

    with local_client(2, config={}) as client:  # Dask's own settings: designs take milliseconds
        run_sweep(items[:2], settings, scheduler=client)  # warm the workers' imports
        dask = best_of(args.repeat, lambda: run_sweep(items, settings, scheduler=client))
    print(f"Dask, 2 workers:  {dask:6.2f} s  {n / dask:7.1f} designs/s (warm workers)")
    parts = stages(items[30], settings)
    total = sum(parts.values())
    print(f"one design (#31), {total * 1e3:.2f} ms:")
    for key, value in parts.items():
        print(f"  {key:18s} {value * 1e3:6.2f} ms  {value / total:5.1%}")
    assert math.isfinite(total)


if __name__ == "__main__":
    main()
