"""Dask settings for workers that run one simulation at a time (fatigue cases, design sweeps).

Dask's defaults suit many short tasks: every process wakes each 20 ms to check that its event
loop is not blocked, each worker samples its running task's stack each 10 ms for the
dashboard's profile and reads its memory each 100 ms, and each process reads its CPU and
network counters each 500 ms. A LocalCluster of two idle workers spent 0.17 of this machine's
2 cores so (benchmarks/README.md, "fatigue_set.py"): cores that one-core workers running
cases of seconds to minutes need for the cases. `WORKER_CONFIG` keeps every check and makes
them rarer; the dashboard's profile of tasks is off.

The settings must be in force where each process starts: around a ``LocalCluster`` (its
scheduler and nannies live in the process that creates it, and a nanny hands the settings
to its worker) with ``dask.config.set(WORKER_CONFIG)``, as `local_client` does; in a
dask-jobqueue job script as environment variables (`worker_environment`).
"""

from __future__ import annotations

import logging
from collections.abc import Iterator, Mapping
from contextlib import contextmanager, suppress
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["WORKER_CONFIG", "local_client", "worker_environment"]

#: Dask configuration keys and values for one-simulation-at-a-time workers (module docstring).
WORKER_CONFIG: dict[str, str | bool] = {
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.worker.profile.enabled": False,
}


def worker_environment() -> dict[str, str]:
    """`WORKER_CONFIG` as the environment variables Dask reads at start (``DASK_...``).

    Dask's rule: the key upper-cased after ``DASK_``, ``__`` for each dot, ``_`` for ``-``.
    """
    return {
        "DASK_" + key.upper().replace(".", "__").replace("-", "_"): str(value)
        for key, value in WORKER_CONFIG.items()
    }


@contextmanager
def local_client(
    workers: int, *, config: Mapping[str, Any] = WORKER_CONFIG, processes: bool = True
) -> Iterator[Client]:
    """A ``distributed.Client`` of a new LocalCluster of ``workers`` one-thread workers.

    The cluster starts with the Dask settings ``config`` (`WORKER_CONFIG` unless given; ``{}``
    for Dask's own) and no dashboard. On exit the client closes, then the cluster (its workers,
    then its scheduler), with logging off meanwhile in this process (the scheduler and the
    nannies) and in each worker: as a worker stops, its last heartbeat or stream read can meet
    the scheduler's closed connection, and distributed logs that as an error with a
    ``CommClosedError`` traceback, after every result is in. Errors of the run itself come
    before, through the client.

    Args:
        workers: worker processes (threads of this process if not ``processes``).
        config: Dask configuration keys and values in force while the cluster starts.
        processes: workers in processes of their own (False: threads here, for tests).
    """
    import dask
    from distributed import Client, LocalCluster

    # Each process and periodic check reads the settings as it is made.
    with dask.config.set(dict(config)):
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=processes, dashboard_address=None
        )
        try:
            client = Client(cluster)
        except BaseException:
            cluster.close()
            raise
    try:
        yield client
    finally:
        previous = logging.root.manager.disable
        # Workers that are gone already have nothing left to say.
        with suppress(Exception):
            client.run(logging.disable, logging.CRITICAL)
        logging.disable(logging.CRITICAL)
        try:
            client.close()
            cluster.close()
        finally:
            logging.disable(previous)
