"""The memory a log read's arrays live in: new pages, or those of an earlier read, used again.

A read places every series of a log into one (series, samples) float64 array. New memory costs
the kernel a zeroing of every page on its first write, and on a virtual machine that zeroing is
the largest part of a read: 38 % of a 70 MB drivetrain read's CPU time (`perf record`, 2026-12-08),
more than decompressing it. So the allocation of a read whose arrays have all been dropped is
kept (one, up to ``KEPT_BYTES``) and the next read that fits writes into it: no page faults, no
zeroing. It holds that read's values, so the next read writes every value (+0.0 too) but in the
rows the last read left at +0.0 (``written``) and that are still +0.0 (the arrays were the
caller's to write: checked): a read puts its arrays that stay zero at the end
(``log_columns.zero_destinations``), so those rows' pages stay untouched or zero.

Nothing a caller holds is ever used again: an allocation is given again only when no array, view
or buffer of it is left (its reference count). ``release`` lets go of the memory kept.
"""

from __future__ import annotations

import sys
import threading
from dataclasses import dataclass

import numpy as np

#: The kernel's huge pages: 2 MiB, at addresses that are multiples of it.
HUGE_PAGE = 2 << 20
#: The largest allocation kept for the next read once its arrays are dropped [bytes].
KEPT_BYTES = 512 << 20


@dataclass
class _Kept:
    """An allocation kept for the next read, and what is known of its values."""

    arena: np.ndarray  # float64, 1-D, owning its memory
    #: the address from which it holds +0.0 to its end
    zero_from: int
    #: zero_from before the read that now writes into it (``written`` needs it)
    zero_from_before: int


_lock = threading.Lock()
_kept: list[_Kept] = []  # at most one


def read_arrays(rows: int, columns: int) -> tuple[np.ndarray, int]:
    """A (rows, columns) float64 array for a read, and its first row of +0.0 throughout.

    Rows from the one returned on are +0.0 (0: new memory, every row zero); the rows before it
    hold an earlier read's values, so the caller writes every value there. Small arrays (under
    two huge pages) are new zeros. A larger one is the kept allocation of an earlier read when
    nothing refers to it any more and it is large enough; otherwise new zeros, kept in turn for
    the next read when at most ``KEPT_BYTES``. Tell ``written`` what the read left at +0.0.

    A large array starts at a huge page's address: numpy asks the kernel for huge pages for an
    array of 4 MiB or more, but the kernel backs only the whole 2 MiB pages inside it by them,
    so an array that starts anywhere else has its first and last partial 2 MiB in 4 kB pages,
    about 500 page faults of a 70 MB read (each costs more than the kernel's zeroing of its
    4 kB). The up to 2 MiB skipped before it is never touched, so it takes no memory.
    """
    size = rows * columns
    if 8 * size < 2 * HUGE_PAGE:  # small: no huge pages
        return np.zeros((rows, columns)), 0
    with _lock:
        kept = _kept[0] if _kept else None
        # references: the _Kept and getrefcount's argument; an array, view or buffer of it adds
        unused = kept is not None and sys.getrefcount(kept.arena) == 2
        if kept and unused and kept.arena.size < size + HUGE_PAGE // 8:
            _kept.clear()  # too small: freed before the new allocation, not after
            kept = None
        if kept and unused:
            array = _aligned(kept.arena, rows, columns)
            row_bytes = 8 * columns
            ahead = kept.zero_from - array.ctypes.data
            first_zero = min(rows, max(0, -(-ahead // row_bytes)))  # rounded up
            # the arrays were the caller's to write: check that those rows are still all +0.0
            # (a read of 26 MB takes 1-2 ms, where writing their zeros took 13 ms of CPU)
            if first_zero < rows and array[first_zero:].view(np.uint64).max() != 0:
                first_zero = rows
            kept.zero_from_before, kept.zero_from = kept.zero_from, _end(kept.arena)
            return array, first_zero
        arena = np.zeros(size + HUGE_PAGE // 8)
        if 8 * arena.size <= KEPT_BYTES:
            # the one kept before, if still used, is freed with its arrays
            _kept[:] = [_Kept(arena, _end(arena), arena.ctypes.data)]
        return _aligned(arena, rows, columns), 0


def written(array: np.ndarray, last_row: int, complete: bool) -> None:
    """Tell the memory kept that a read into ``array`` left its rows after ``last_row`` at +0.0.

    ``array`` is one ``read_arrays`` gave; ``last_row`` the last row the read gave a value other
    than +0.0 (-1: none); ``complete`` whether it wrote every sample of the rows it wrote. The
    next read into the same memory then leaves those rows' +0.0 as they are. Without this call
    (a read that stopped, or placed its samples another way) nothing is known of the values.
    """
    with _lock:
        kept = _kept[0] if _kept else None
        if kept is None or array.base is not kept.arena:
            return
        start = array.ctypes.data
        end = start + array.nbytes
        if kept.zero_from_before > end:  # what lies past this read's rows holds older values
            kept.zero_from = kept.zero_from_before
        elif complete:
            kept.zero_from = start + 8 * array.shape[1] * (last_row + 1)
        else:
            kept.zero_from = end


def release() -> None:
    """Let go of the memory kept for the next read (it is freed once no array of it is left)."""
    with _lock:
        _kept.clear()


def _end(arena: np.ndarray) -> int:
    return arena.ctypes.data + arena.nbytes


def _aligned(arena: np.ndarray, rows: int, columns: int) -> np.ndarray:
    """The (rows, columns) view of ``arena`` that starts at its first huge-page address."""
    skip = (-arena.ctypes.data % HUGE_PAGE) // 8
    return arena[skip : skip + rows * columns].reshape(rows, columns)
