"""Interrupts held back while a unit of work that must not be cut is finished.

Ctrl-C (SIGINT) raises ``KeyboardInterrupt`` between any two bytecodes of the main thread, and
the CLI's SIGTERM handler raises too. A signal landing between the compiled step's return and
the hand-over of its samples to the log dropped the block just simulated; one landing between a
chunk's write and the offsets that index it left a summary that did not match the file.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

#: The signals held: Ctrl-C, and SIGTERM (``kill``, a batch system's stop).
HELD = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def interrupts_deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM for the body; raise those that arrived, to their handlers, after.

    Off the main thread (where Python runs no signal handler) it holds nothing. A signal whose
    handler was not set from Python is left alone.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = {}
    for s in HELD:
        if signal.getsignal(s) is not None:
            previous[s] = signal.signal(s, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        for signum in caught:
            signal.raise_signal(signum)
