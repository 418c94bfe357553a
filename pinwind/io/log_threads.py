"""The reading threads of a log read: chunks read, decompressed and checked ahead of their use.

``READ_THREADS`` threads, one per core, each take a chunk, read it, decompress it and check its
CRC (zstd and zlib release the GIL), and run a function on it while it is in their cache (copy
a format 3 chunk's columns into their place, find a format 1 or 2 chunk's rows), while the main
thread hands out the chunks before them in file order (``read_ahead``), or waits for them all
(``run_all``, when nothing of a chunk is kept). Decompressed chunks go into buffers used again
once nothing refers to them (``ChunkBuffers``).
"""

from __future__ import annotations

import os
import sys
import threading
from collections import deque
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from pinwind.io.mcap_file import ChunkRef


def _cores() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 2


#: Threads that read, decompress and (format 3) copy chunks: one per core this process may
#: use, 2 to 8 (beyond that the copies are bound by memory bandwidth).
READ_THREADS = max(2, min(8, _cores()))
#: Chunks read ahead of the one being copied (1000 samples of a shipped model: ~1 MB decompressed).
READ_AHEAD = 2 * READ_THREADS - 1


class ChunkBuffers:
    """Decompression buffers used again once nothing refers to them (thread-safe).

    A chunk's column blocks are views of its buffer; when the last view is gone (its samples
    are copied), only this list holds the buffer, and the next chunk decompresses into it.
    """

    #: references to a free buffer while ``take`` looks at it: the list, the loop variable and
    #: the argument of getrefcount
    _FREE = 3

    def __init__(self) -> None:
        self._all: list[np.ndarray] = []
        self._lock = threading.Lock()

    def take(self, size: int) -> np.ndarray | None:
        """A free buffer larger than ``size`` bytes (None when size is unknown)."""
        if size <= 0:
            return None
        with self._lock:
            for buffer in self._all:
                if buffer.size > size and sys.getrefcount(buffer) == self._FREE:
                    return buffer
            buffer = np.empty(size + size // 8 + 64, dtype=np.uint8)
            self._all.append(buffer)
            return buffer


def read_ahead(
    chunks: list[ChunkRef], load: Callable[[ChunkRef, Any], tuple], wanted: Any
) -> Iterator[tuple]:
    """(chunk, *load(chunk, wanted)) for every chunk, in order, loaded ahead by reading threads.

    ``READ_THREADS`` threads run ``load`` (thread-safe) on up to ``READ_AHEAD`` + 1 chunks
    ahead of the one handed out; those not handed out are cancelled when the caller stops.
    """
    if not chunks:
        return
    with ThreadPoolExecutor(READ_THREADS, thread_name_prefix="pinwind-read") as pool:
        pending: deque = deque()
        ahead = iter(chunks)
        try:
            for chunk in ahead:
                pending.append((chunk, pool.submit(load, chunk, wanted)))
                if len(pending) > READ_AHEAD:
                    break
            while pending:
                chunk, future = pending.popleft()
                following = next(ahead, None)
                if following is not None:
                    pending.append((following, pool.submit(load, following, wanted)))
                yield (chunk, *future.result())
        finally:
            for _, future in pending:
                future.cancel()


def run_all(chunks: list[ChunkRef], load: Callable[[ChunkRef, Any], tuple], wanted: Any) -> list:
    """[(chunk, *load(chunk, wanted)) for every chunk], in order, loaded by the reading threads.

    For a ``load`` that keeps nothing of a chunk once it returns (a format 3 chunk copied into
    its place): every chunk is handed to the threads at once, and the caller waits once for
    all of them, instead of once a chunk as with ``read_ahead`` (each wait wakes it, and it
    takes a core from the reading threads). An exception of ``load`` is raised when all have
    ended.
    """
    with ThreadPoolExecutor(READ_THREADS, thread_name_prefix="pinwind-read") as pool:
        futures = [pool.submit(load, chunk, wanted) for chunk in chunks]
    return [(chunk, *future.result()) for chunk, future in zip(chunks, futures, strict=True)]
