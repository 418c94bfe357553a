"""Cost of reading a log back: read_log per sample against the compiled step, memory, file size.

For each model: a plain run (no log, ``keep="last"``, no statistics) gives the compiled step
loop's cost per sample (``wall_time_s`` / samples); the same run logged at full rate gives the
file. Then, each in a fresh Python process so that memory figures are its own:

- whole-file ``read_log``: best of ``--repeats`` wall times per sample, and their ratio to the
  step (issue 37 asks for ≤ 0.12); from the second read of the process on, a read writes into
  the memory of the one before (``pinwind.io.read_memory``), as the step loop (``keep="last"``)
  writes into memory it has used before; also the first of them (new memory: the kernel zeroes
  every page first), the same reads each into new memory (``read_memory.release()`` before
  each), the CPU time of the read (all threads), which depends less on what else the machine
  is doing, and the read with one reading thread instead of ``READ_THREADS`` (one per core, 2
  to 8), which says how the read scales with cores;
- the cores the process gets when it asks for two, probed before each read
  (``machine.parallel_capacity``): below 2 while other work shares the machine;
- peak memory of one whole read over the bytes of the arrays it returns (≤ 1.5): the peak
  resident set size above the one before the read (``VmHWM`` in /proc/self/status, reset by
  /proc/self/clear_refs), and the peak of Python's allocations (``tracemalloc``, which numpy
  reports to), in separate processes;
- what reading, decompressing and checking the chunks alone costs (one thread), the floor
  of a whole read of this file format;
- a bare read with the reading threads: each chunk decompressed and its bytes written into new
  memory of the size of its samples' arrays, nothing decoded: the floor of any reader of this
  file into new arrays on this machine;
- a read of 10 % of the time (``start``/``stop``) and of one channel (``/meshes/normal``);
- bytes per sample on disk.

    python benchmarks/read_log.py [--duration 10] [--dt 1e-4] [--repeats 3] [--models ...]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from saleh_loads import INITIAL_SPEEDS, LOADS, MODELS

import pinwind
from pinwind.dynamics.simulate import simulate
from pinwind.io.log_threads import READ_THREADS

#: Run in a fresh process: one measurement, printed as JSON.
CHILD = r"""
import json, sys, time, tracemalloc
import pinwind
from pinwind.io.log_reader import read_log

path, what, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])

def status_kib(key):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith(key))

def array_bytes(res):
    return sum(getattr(res, n).nbytes for n in res.ARRAYS) + sum(
        v.nbytes for v in res.energy.values())

if what == "rss":
    # VmHWM: peak resident set of this process image (ru_maxrss would include the parent's,
    # inherited through fork); reset to the current size first where the kernel allows it.
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass
    before = status_kib("VmRSS:")
    res = read_log(path)
    peak = status_kib("VmHWM:")
    print(json.dumps({"peak": (peak - before) * 1024, "arrays": array_bytes(res)}))
elif what == "chunks":
    # the floor of a whole read: read, decompress and check (zstd checksum) every chunk, one thread
    from pinwind.io import mcap_file
    from pinwind.io.log_reader import LogReader

    with LogReader(path) as log:
        chunks = log._sample_chunks(None)
        best = float("inf")
        for _ in range(repeats):
            start = time.perf_counter()
            for chunk in chunks:
                mcap_file.read_chunk(log._fd, chunk)
            best = min(best, time.perf_counter() - start)
    print(json.dumps({"seconds": best}))
elif what == "floor":
    # the floor of any reader of this file into these arrays, with the reading threads: each
    # chunk decompressed (its checksum checked) into a buffer the thread keeps, its bytes copied
    # into new memory of the size of its samples' arrays and the rest of that memory filled;
    # no decoding.
    import threading
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np
    from pinwind.io import mcap_file
    from pinwind.io.log_reader import LogReader
    from pinwind.io.log_threads import READ_THREADS

    res = read_log(path)
    n = len(res)
    per_sample = {"arrays": array_bytes(res) // n}
    del res
    local = threading.local()
    out = {}
    with LogReader(path) as log:
        chunks = log._sample_chunks(None)
        places = np.concatenate([[0], np.cumsum(log._column_counts(chunks, -(2**62), 2**62))])

        def copy(i, into):
            buffer = getattr(local, "buffer", None)
            if buffer is None or buffer.size <= chunks[i].size:
                buffer = local.buffer = np.empty(2 * chunks[i].size, np.uint8)
            data = np.frombuffer(mcap_file.read_chunk(log._fd, chunks[i], buffer), np.uint8)
            lo, hi = int(places[i]) * bytes_per_sample, int(places[i + 1]) * bytes_per_sample
            k = min(len(data), hi - lo)
            into[lo : lo + k] = data[:k]
            into[lo + k : hi] = 0x7F

        for kind, bytes_per_sample in per_sample.items():
            best = float("inf")
            for _ in range(repeats):
                start = time.perf_counter()
                into = np.empty(int(places[-1]) * bytes_per_sample, np.uint8)
                with ThreadPoolExecutor(READ_THREADS) as pool:
                    list(pool.map(lambda i: copy(i, into), range(len(chunks))))
                best = min(best, time.perf_counter() - start)
                del into
            out[kind] = best
    print(json.dumps(out))
elif what == "tracemalloc":
    tracemalloc.start()
    res = read_log(path)
    print(json.dumps({"peak": tracemalloc.get_traced_memory()[1], "arrays": array_bytes(res)}))
else:
    import resource

    def cpu():
        use = resource.getrusage(resource.RUSAGE_SELF)
        return use.ru_utime + use.ru_stime

    kwargs = json.loads(what)
    threads = kwargs.pop("threads", None)
    new_memory = kwargs.pop("new_memory", False)
    from pinwind.io import read_memory
    if threads:
        from pinwind.io import log_threads

        log_threads.READ_THREADS, log_threads.READ_AHEAD = threads, 2 * threads - 1
    sys.path.insert(0, sys.argv[4])
    from machine import parallel_capacity

    times, cores = [], []
    used = 0.0
    for _ in range(repeats):
        res = None  # the last read's arrays are freed before the probe
        if new_memory:
            read_memory.release()
        cores.append(parallel_capacity())
        cpu_start = cpu()
        start = time.perf_counter()
        res = read_log(path, **kwargs)
        times.append(time.perf_counter() - start)
        used += cpu() - cpu_start
    print(json.dumps({
        "seconds": min(times), "first": times[0], "cpu": used / repeats, "samples": len(res),
        "arrays": array_bytes(res), "cores": sorted(cores)[len(cores) // 2],
    }))
"""


def child(path: Path, what: str, repeats: int = 1) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(path), what, str(repeats), str(Path(__file__).parent)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=1e-4, help="time step [s]")
    parser.add_argument("--repeats", type=int, default=3, help="timed reads (best is kept)")
    parser.add_argument("--models", nargs="+", default=list(LOADS), help="names in models/")
    parser.add_argument("--out", type=Path, default=None, help="folder for the logs")
    args = parser.parse_args()
    folder = args.out or Path(tempfile.mkdtemp(prefix="pinwind_read_"))
    folder.mkdir(parents=True, exist_ok=True)

    print(f"pinwind {pinwind.__version__}, {args.duration:g} s at dt = {args.dt:g} s per model\n")
    lines = []
    for name in args.models:
        gearbox = pinwind.load(MODELS / f"{name}.urdf")
        torques = LOADS[name]
        speeds = INITIAL_SPEEDS[name]
        simulate(  # warm-up
            gearbox,
            duration=0.1,
            dt=args.dt,
            torques=torques,
            initial_speeds=speeds,
            progress=False,
        )
        # keep="last": the step itself, without first writes to the Result's fresh memory (which
        # cost more than the step on a fresh virtual machine, and which the loop now does itself)
        plain = simulate(
            gearbox,
            duration=args.duration,
            dt=args.dt,
            torques=torques,
            initial_speeds=speeds,
            keep="last",  # dynamics.simulate folds no statistics (pinwind.simulate would)
        )
        step = plain.metadata["wall_time_s"] / plain.metadata["samples_simulated"]
        path = folder / f"{name}.mcap"
        pinwind.simulate(
            gearbox,
            duration=args.duration,
            dt=args.dt,
            torques=torques,
            initial_speeds=speeds,
            progress=False,
            log=path,
            overwrite=True,
        )
        n = plain.metadata["samples_simulated"]
        whole = child(path, "{}", args.repeats)
        single = child(path, json.dumps({"threads": 1}), args.repeats)
        fresh = child(path, json.dumps({"new_memory": True}), args.repeats)
        rss = child(path, "rss")
        traced = child(path, "tracemalloc")
        t0, t1 = 0.45 * args.duration, 0.55 * args.duration
        window = child(path, json.dumps({"start": t0, "stop": t1}), args.repeats)
        channel = child(path, json.dumps({"channels": ["/meshes/normal"]}), args.repeats)
        floor = child(path, "chunks", args.repeats)["seconds"] / n
        bare = {k: v / n for k, v in child(path, "floor", args.repeats).items()}
        read = whole["seconds"] / whole["samples"]
        size = path.stat().st_size
        print(
            f"== {name}: {n} samples, {size / 1e6:.1f} MB on disk "
            f"({size / n:.0f} bytes/sample), arrays {whole['arrays'] / n:.0f} bytes/sample\n"
            f"  compiled step loop       {step * 1e6:8.2f} µs/sample\n"
            f"  read_log, whole file     {read * 1e6:8.2f} µs/sample  "
            f"ratio to the step {read / step:.3f} (goal ≤ 0.12)\n"
            f"  CPU time of that read    {whole['cpu'] / n * 1e6:8.2f} µs/sample (all threads, "
            "mean of the reads)\n"
            f"  cores available          {whole['cores']:8.2f} (of 2 asked for, median before the "
            "reads)\n"
            f"  first read of the process {whole['first'] / n * 1e6:7.2f} µs/sample (ratio "
            f"{whole['first'] / n / step:.2f}; new memory: the kernel zeroes its pages)\n"
            f"  every read into new memory {fresh['seconds'] / n * 1e6:6.2f} µs/sample (ratio "
            f"{fresh['seconds'] / n / step:.3f}; read_memory.release() before each)\n"
            f"  the same, 1 reading thread {single['seconds'] / n * 1e6:6.2f} µs/sample (ratio "
            f"{single['seconds'] / n / step:.2f}; {READ_THREADS} threads above)\n"
            f"  of which read + unzstd + checksum of the chunks, one thread: {floor * 1e6:.2f} "
            f"µs/sample (ratio {floor / step:.2f})\n"
            f"  bare read, {READ_THREADS} threads: decompress, write the arrays' bytes in new "
            "memory, "
            f"nothing else {bare['arrays'] * 1e6:.2f} µs/sample "
            f"(ratio {bare['arrays'] / step:.2f})\n"
            f"  peak memory / arrays     {rss['peak'] / rss['arrays']:8.2f} (RSS)  "
            f"{traced['peak'] / traced['arrays']:.2f} (tracemalloc)  (goal ≤ 1.5)\n"
            f"  10 % time window         {window['seconds'] * 1e3:8.1f} ms "
            f"({window['samples']} samples, {window['seconds'] / whole['seconds']:.3f} of a "
            "whole read)\n"
            f"  one channel (/meshes/normal) {channel['seconds'] * 1e3:6.1f} ms "
            f"({channel['seconds'] / whole['seconds']:.2f} of a whole read)\n"
        )
        lines.append(
            f"{name:22s} {step * 1e6:7.2f} {read * 1e6:7.2f} {read / step:6.3f} "
            f"{fresh['seconds'] / n / step:6.3f} "
            f"{bare['arrays'] / step:6.2f} "
            f"{rss['peak'] / rss['arrays']:6.2f} {traced['peak'] / traced['arrays']:6.2f} "
            f"{size / n:7.0f} {whole['cores']:6.2f}"
        )
    print(
        "model                  step µs read µs  ratio    new  floor  mem/RSS mem/tm bytes/sample "
        "cores"
    )
    print("\n".join(lines))


if __name__ == "__main__":
    main()
