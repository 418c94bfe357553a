"""The memory a log read's arrays live in: new pages, or those of an earlier read, used again.

A read places every series of a log into one (series, samples) float64 array. New memory costs
the kernel a zeroing of every page on its first write, and on a virtual machine that zeroing is
the largest part of a read: 38 % of a 70 MB drivetrain read's CPU time (`perf record`, 2026-12-08),
more than decompressing it. So the arrays of a read whose arrays have all been dropped are kept
(one set, up to ``KEPT_BYTES``) and the next read that fits in them writes into them: no page
faults, no zeroing. Such memory holds the old values, so that read writes every value (a series
that is +0.0 is written too); a read into new memory leaves those pages untouched.

The memory kept is released by ``release`` or when a larger read replaces it. Nothing a caller
holds is ever reused: an array is reused only when no array, view or buffer of it is left (its
reference count).
"""

from __future__ import annotations

import sys
import threading

import numpy as np

#: The kernel's huge pages: 2 MiB, at addresses that are multiples of it.
HUGE_PAGE = 2 << 20
#: The largest allocation kept for the next read once its arrays are dropped [bytes].
KEPT_BYTES = 512 << 20

_lock = threading.Lock()
#: at most one allocation, kept for the next read (float64, 1-D, owning its memory)
_kept: list[np.ndarray] = []


def read_arrays(rows: int, columns: int) -> tuple[np.ndarray, bool]:
    """A (rows, columns) float64 array for a read, and whether it is zeros (new memory).

    Small arrays (under two huge pages) are new zeros. A larger one is the kept allocation of
    an earlier read when nothing refers to it any more and it is large enough (its values are
    then whatever that read left: the caller writes every value); otherwise new zeros that
    start at a huge page's address, kept in turn for the next read if at most ``KEPT_BYTES``.

    numpy asks the kernel for huge pages for an array of 4 MiB or more, but the kernel backs only
    the whole 2 MiB pages inside it by them: an array that starts anywhere else has its first
    and last partial 2 MiB in 4 kB pages, about 500 page faults of a 70 MB read (each costs more
    than the kernel's zeroing of its 4 kB). Starting at a multiple of 2 MiB leaves only the end
    in 4 kB pages; the up to 2 MiB skipped before it is never touched, so it takes no memory.
    """
    size = rows * columns
    if 8 * size < 2 * HUGE_PAGE:  # small: no huge pages
        return np.zeros((rows, columns)), True
    with _lock:
        # references: the list and getrefcount's argument; a view, array or buffer of it adds one
        if _kept and sys.getrefcount(_kept[0]) == 2 and _kept[0].size >= size + HUGE_PAGE // 8:
            return _aligned(_kept[0], rows, columns), False
        arena = np.zeros(size + HUGE_PAGE // 8)
        if 8 * arena.size <= KEPT_BYTES:
            _kept[:] = [arena]  # the one kept before, if still used, is freed with its arrays
        return _aligned(arena, rows, columns), True


def release() -> None:
    """Let go of the memory kept for the next read (it is freed once no array of it is left)."""
    with _lock:
        _kept.clear()


def _aligned(arena: np.ndarray, rows: int, columns: int) -> np.ndarray:
    """The (rows, columns) view of ``arena`` that starts at its first huge-page address."""
    skip = (-arena.ctypes.data % HUGE_PAGE) // 8
    return arena[skip : skip + rows * columns].reshape(rows, columns)
