"""What the machine gives a benchmark while it runs: the cores a process gets asking for two."""

from __future__ import annotations

import os
import threading
import time
import zlib

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
