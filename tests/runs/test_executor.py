"""The executor of many runs (``runs/executor.py``): here, on local processes or on Dask."""

import gc
import time
import weakref

import pytest

from pinwind.runs.executor import run_tasks


class _Payload:
    """A task's result whose lifetime a weak reference can watch."""

    def __init__(self, item: int):
        self.item = item


def _payload(item: int) -> _Payload:
    return _Payload(item)


@pytest.mark.parametrize("backend", ["processes", "dask"])
def test_executor_lets_each_result_go_once_accepted(backend):
    # Memory flat in the number of items: no result is held after ``accept`` returns.
    refs: list[weakref.ref] = []
    still_held = []

    def accept(result: _Payload) -> None:
        # An in-process Dask worker drops its copy when the scheduler's release reaches it, a
        # moment after ``future.release()``: wait for that (a held result never goes).
        deadline = time.monotonic() + 5.0
        while True:
            gc.collect()
            held = sum(ref() is not None for ref in refs)
            if held == 0 or time.monotonic() > deadline:
                break
            time.sleep(0.01)
        still_held.append(held)
        refs.append(weakref.ref(result))

    items = list(range(6))
    if backend == "processes":
        run_tasks(_payload, items, accept=accept, workers=2)
    else:
        distributed = pytest.importorskip("distributed")
        with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                      dashboard_address=None) as cluster:  # fmt: skip
            with distributed.Client(cluster) as client:
                run_tasks(_payload, items, accept=accept, scheduler=client)
    assert len(still_held) == len(items)
    assert still_held == [0] * len(items)
