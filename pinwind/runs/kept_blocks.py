"""A run's kept samples of some series handed on in blocks as it runs, in bounded memory.

`KeptBlocks` is a run observer (``pinwind.dynamics.simulate.RunObserver``, as the log writer
and the run statistics are): from each block the run steps it copies the samples a Result of
``keep`` = ``stride`` would keep (every stride-th step and the last, ``simulate``'s
``_kept_samples``) from ``skip_start`` on, of the series named, and hands them on in blocks of
about ``block`` samples to consumers, each with ``add(block: Result)``. A fatigue case is
reduced so as it runs (``runs/case_runner.py``): the Result needs not keep its history, and
the memory is that of one block, whatever the run's length.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

import numpy as np

from pinwind.dynamics.result import concatenate
from pinwind.dynamics.simulate import _kept_samples
from pinwind.errors import InputError

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.model.gearbox import Gearbox

#: Kept samples per block handed on (at 1250 Hz, 1.6 s of the 5 MW case: 6.5 MB of its series;
#: 4096 let the example's peak RSS reach 1.14 times its 30 s peak at 240 s, 2048 1.08 for 3 %
#: more CPU, 1024 1.06 for 20 % more: benchmarks/README.md).
BLOCK_SAMPLES = 2048


class BlockConsumer(Protocol):
    """Takes a run's kept samples block by block, in time order, each block after the last."""

    def add(self, block: Result) -> None:
        """The next kept samples (a Result of the series asked for)."""


def _begin_consumers(consumers: Sequence[BlockConsumer], result: Result) -> None:
    """Each consumer with a ``begin(result)`` sees the run's Result (its metadata) first."""
    for consumer in consumers:
        begin = getattr(consumer, "begin", None)
        if begin is not None:
            begin(result)


class KeptBlocks:
    """Hands the kept samples of a run on, block by block, to consumers (module docstring).

    Args:
        consumers: each gets every block (``add``), in the order given.
        series: the series of the blocks (names of ``Result`` arrays).
        stride: every how many steps a sample is kept (``simulate``'s ``keep`` as a number).
        skip_start: samples before this time [s] are not handed on.
        block: kept samples per block handed on (the last may be shorter).

    Attributes:
        samples_handed: kept samples handed on so far.
    """

    #: Done with a block once ``samples`` returns (its samples are copied).
    holds = 0

    def __init__(
        self,
        consumers: Sequence[BlockConsumer],
        *,
        series: Sequence[str],
        stride: int,
        skip_start: float = 0.0,
        block: int = BLOCK_SAMPLES,
    ) -> None:
        if isinstance(stride, bool) or not isinstance(stride, int | np.integer) or stride < 1:
            raise InputError(
                f"the stride of the kept samples must be a whole number ≥ 1, got {stride!r}"
            )
        if not block >= 1:
            raise InputError(f"a block must hold at least one sample, got {block!r}")
        self.consumers = list(consumers)
        self.series = tuple(series)
        self.stride = int(stride)
        self.skip_start = float(skip_start)
        self.block = int(block)
        self.samples_handed = 0
        self._kept = np.zeros(0, dtype=int)
        self._parts: list[Result] = []
        self._held = 0

    def begin(self, gearbox: Gearbox, result: Result) -> None:
        """The run's kept samples follow from its samples (``metadata["samples_simulated"]``)."""
        self._kept = _kept_samples(int(result.metadata["samples_simulated"]), self.stride)
        result.schema.only(self.series)  # unknown names fail before the run
        _begin_consumers(self.consumers, result)

    def samples(self, block: Result, start: int) -> None:
        """Copies the block's kept samples from ``skip_start`` on; hands on a full block."""
        lo, hi = np.searchsorted(self._kept, [start, start + len(block)])
        rows = self._kept[lo:hi] - start
        rows = rows[block.time[rows] >= self.skip_start - 1e-12]
        if not rows.size:
            return
        part = block.series_of(block.schema.only(self.series), poses=False).take(rows)
        self._parts.append(part)
        self._held += len(part)
        if self._held >= self.block:
            self._hand_on()

    def end(self, result: Result, status: str) -> None:
        """Hands on the samples held, when the run completed (else they are dropped)."""
        if status == "completed":
            self._hand_on()
        self._parts, self._held = [], 0

    def _hand_on(self) -> None:
        if not self._parts:
            return
        joined = concatenate(self._parts)
        self._parts, self._held = [], 0
        for consumer in self.consumers:
            consumer.add(joined)
        self.samples_handed += len(joined)
