"""The lock a run holds on its log while it writes it, so that a reader can tell.

A log without its end-status record is either cut short (the run was killed, the file
truncated) or still being written. The writer holds an exclusive advisory lock (``flock``) on
the file from ``begin`` until it closes it; the operating system releases it when the process
ends, however it ends. A reader that cannot take a shared lock at once knows that a run is
writing the file. Where ``flock`` does not exist (Windows) nothing is locked and a log being
written reads as cut short.
"""

from __future__ import annotations

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]


def hold_for_writing(fd: int) -> None:
    """Take the writer's lock on an open log (nothing when another process holds one)."""
    if fcntl is None:
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # a reader holds it this instant, or the file system has no locks
        pass


def held_by_writer(fd: int) -> bool:
    """Whether a run holds the writer's lock on the log open as ``fd``."""
    if fcntl is None:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    except OSError:  # no locks on this file system
        return False
    fcntl.flock(fd, fcntl.LOCK_UN)
    return False
