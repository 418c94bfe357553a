"""What the machine gives a benchmark while it runs.

Two views: the cores a process gets asking for two, now (`parallel_capacity`, a probe that
takes both cores for a moment), and the cores other processes used while the benchmark ran
(`others_cores` between two `cpu_sample`: the machine's busy CPU time less the benchmark's own
processes'), which the load average cannot tell: it counts the benchmark's own processes too.
"""

from __future__ import annotations

import os
import threading
import time
import zlib
from dataclasses import dataclass

_PROBE = os.urandom(8 << 20)


def parallel_capacity() -> float:
    """Cores this process gets when it asks for two (2.0: two free cores).

    CPU ÷ wall time of two threads that checksum 40 MB each without the GIL; below 2 when
    other work (another process, another virtual machine on the host) takes a core.
    """

    def work() -> None:
        for _ in range(5):
            zlib.crc32(_PROBE)

    wall, cpu = time.perf_counter(), time.process_time()
    threads = [threading.Thread(target=work) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return (time.process_time() - cpu) / (time.perf_counter() - wall)


@dataclass(frozen=True)
class CpuSample:
    """CPU seconds used so far, by the whole machine and by each process of this benchmark.

    Attributes:
        wall_s: `time.monotonic` when taken [s].
        machine_s: busy CPU time of all cores since boot [s] (/proc/stat: user, nice, system,
            irq, softirq and steal, the time the host gave other virtual machines; guest time is
            in user).
        own_s: CPU time (user + system, all threads) of this process and of each of its
            descendants [s], by (process id, start time): a process id can be reused.
    """

    wall_s: float
    machine_s: float
    own_s: dict[tuple[int, float], float]


def cpu_sample() -> CpuSample:
    """The CPU time of the machine and of this process and its descendants, now (psutil)."""
    import psutil

    times = psutil.cpu_times()
    busy = times.user + times.nice + times.system + times.irq + times.softirq + times.steal
    own = {}
    me = psutil.Process()
    for process in (me, *me.children(recursive=True)):
        try:
            with process.oneshot():
                cpu = process.cpu_times()
                own[process.pid, process.create_time()] = cpu.user + cpu.system
        except psutil.NoSuchProcess:  # ended since listed: its CPU is gone with it
            continue
    return CpuSample(time.monotonic(), busy, own)


def others_cores(before: CpuSample, after: CpuSample) -> float:
    """Cores that processes other than this benchmark's used on average between two samples.

    The machine's busy CPU time over the span less that of this process and its descendants
    (those that started since count whole, from their start), over the wall time; never below 0
    (the two are read at slightly different moments, in 10 ms ticks). A descendant that ended
    between the samples counts as another's: the benchmark samples around spans in which none
    of its processes ends.
    """
    machine = after.machine_s - before.machine_s
    own = sum(cpu - before.own_s.get(key, 0.0) for key, cpu in after.own_s.items())
    return max(0.0, machine - own) / (after.wall_s - before.wall_s)
