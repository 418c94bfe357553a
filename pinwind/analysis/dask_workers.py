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
to its worker) with ``dask.config.set(WORKER_CONFIG)``; in a dask-jobqueue job script as
environment variables (`worker_environment`).
"""

from __future__ import annotations

__all__ = ["WORKER_CONFIG", "worker_environment"]

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
