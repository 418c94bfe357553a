"""The one executor of pinwind's many-run commands: tasks here, on local processes or on Dask.

The design sweeps (`runs/sweep.py`) and ``pinwind fatigue`` (`runs/case_runner.py`) hand it a
module-level task and its items; it runs them in this process, in worker processes that die with
it, or on a Dask cluster (its workers set up by `runs/dask_workers.py`), and passes each result
back as it finishes.
"""

from __future__ import annotations

import socket
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from pinwind.errors import InputError, SchedulerUnreachable

__all__ = ["SCHEDULER_TIMEOUT", "check_workers", "run_tasks"]

#: What a task of `run_tasks` returns.
T = TypeVar("T")


def check_workers(workers: int | None) -> None:
    """Refuse a number of local worker processes below 1 (``--workers 0`` ran on all cores).

    Raises:
        InputError: naming the number and the default.
    """
    import os

    if workers is not None and workers < 1:
        raise InputError(
            f"--workers {workers}: give 1 or more worker processes (1 runs in this process), "
            f"or leave it out for one per core ({os.cpu_count() or 1} here)"
        )


def run_tasks(
    task: Callable[..., T],
    items: Sequence[Any],
    *,
    accept: Callable[[T], None],
    workers: int = 1,
    scheduler: str | object | None = None,
    batch_size: int = 1,
    **common: Any,
) -> str:
    """Run ``task(item, **common)`` for every item here, on local processes or on Dask.

    The one executor of pinwind's many-run commands (the design sweeps, ``pinwind fatigue``).
    ``task`` must be a module-level function (it is pickled to the workers) that imports what
    it needs and returns plain values; results arrive in ``accept`` as they finish, in any order.

    Args:
        task: the function run on each item.
        items: the items, one task each (``batch_size`` per task on local processes).
        accept: called with each result, in this process.
        workers: local worker processes; 1 (or a single item) runs in this process.
        scheduler: a Dask scheduler address (``tcp://host:8786``) or a ``distributed.Client``;
            overrides ``workers``.
        batch_size: items per local task.
        **common: keyword arguments of every call.

    Returns:
        The backend: ``"serial"``, ``"processes (N)"`` or ``"dask (ADDRESS)"``.
    """
    if scheduler is not None:
        return _run_dask(task, items, common, scheduler, accept)
    return _run_local(task, items, common, workers, batch_size, accept)


def _run_batch(task: Callable[..., T], batch: Sequence[Any], common: dict[str, Any]) -> list[T]:
    """``task`` on each item of a batch (one local worker task)."""
    return [task(item, **common) for item in batch]


def _run_local(
    task: Callable[..., T],
    items: Sequence[Any],
    common: dict[str, Any],
    n: int,
    size: int,
    accept: Callable[[T], None],
) -> str:
    """``task`` on each batch of items in ``n`` worker processes (or here, for one).

    An error of a task stops the items not started and waits for the running ones (their
    results are kept: a fatigue case's files); an interrupt (Ctrl-C, or SIGTERM raised as one)
    stops the workers at once. A worker dies with this process, even when it is killed
    (`_worker_started`), so that none is left running, holding the command's output open.
    """
    if n <= 1 or len(items) <= 1:
        for item in items:
            accept(task(item, **common))
        return "serial"
    import multiprocessing as mp
    import os
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # "spawn" keeps the workers free of the parent's threads (rerun, dask) and their locks.
    batches = [items[i : i + size] for i in range(0, len(items), size)]
    pool = ProcessPoolExecutor(
        max_workers=n,
        mp_context=mp.get_context("spawn"),
        initializer=_worker_started,
        initargs=(os.getpid(),),
    )
    futures = {pool.submit(_run_batch, task, batch, common) for batch in batches}
    try:
        for future in as_completed(futures):
            # A finished future keeps its results: let it go, so that memory stays flat in
            # the number of items (a fatigue case's cycles are tens of MB).
            futures.discard(future)
            for result in future.result():
                accept(result)
    except Exception:
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    except BaseException:  # Ctrl-C, SIGTERM: the running tasks are not waited for
        _stop_workers(pool)
        raise
    pool.shutdown(wait=True)
    return f"processes ({n})"


#: Linux's prctl option that sends the calling process a signal when its parent dies.
_PR_SET_PDEATHSIG = 1


def _worker_started(parent: int) -> None:
    """A worker's start: it dies with ``parent``, and leaves Ctrl-C to it.

    The terminal sends Ctrl-C to every process of the command; the parent stops the workers
    itself (`_run_local`), so a worker ignores it instead of printing its own traceback. When
    the parent is killed (SIGKILL, which it cannot handle), Linux sends the worker SIGKILL
    (``prctl(PR_SET_PDEATHSIG)``); elsewhere a killed parent's workers finish their task.
    """
    import ctypes
    import os
    import signal
    import sys

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if os.getppid() != parent:  # the parent died before the request was made
        os._exit(1)


def _stop_workers(pool: Any) -> None:
    """Stop a process pool's workers now: cancel its tasks and terminate its processes."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.terminate()
    for process in processes:
        process.join(timeout=5.0)
        if process.is_alive():
            process.kill()
            process.join()
    pool.shutdown(wait=True)  # the pool's own thread sees its workers gone, and ends


#: How long a sweep tries to reach a Dask scheduler before it gives up [s] (Dask's own: 30 s).
SCHEDULER_TIMEOUT = 10.0


def _connect(client_type: type, address: str) -> Any:
    """A ``distributed.Client`` of the scheduler at ``address``, or one line saying why not.

    A TCP address is tried with a plain socket first: a refused port or an unknown host fails
    at once instead of after Dask's connection retries.

    Raises:
        SchedulerUnreachable: nothing answers there, or the address cannot be read.
    """
    protocol, _, rest = address.rpartition("://")
    if protocol in ("", "tcp", "tls"):
        host, _, port = rest.rpartition(":")
        if not host:  # no port given: Dask's default
            host, port = rest, "8786"
        try:
            socket.create_connection((host.strip("[]"), int(port)), SCHEDULER_TIMEOUT).close()
        except (OSError, ValueError) as err:
            reason = getattr(err, "strerror", None) or str(err) or type(err).__name__
            raise SchedulerUnreachable(address, reason) from err
    try:
        return client_type(address, timeout=f"{SCHEDULER_TIMEOUT:g}s")
    except (OSError, ValueError, TypeError) as err:  # timeouts are OSErrors
        raise SchedulerUnreachable(address, str(err) or type(err).__name__) from err


def _run_dask(
    task: Callable[..., T],
    items: Sequence[Any],
    common: dict[str, Any],
    scheduler: str | object,
    accept: Callable[[T], None],
) -> str:
    try:
        from distributed import Client, as_completed
    except ImportError as err:  # pragma: no cover - distributed is a dependency
        raise InputError("--scheduler needs dask.distributed: pip install distributed") from err
    own = not isinstance(scheduler, Client)
    client = scheduler if isinstance(scheduler, Client) else _connect(Client, str(scheduler))
    try:
        futures = client.map(task, items, pure=False, **common)
        pending = as_completed(futures)
        del futures  # held by ``pending`` until each is yielded
        for future in pending:
            result = future.result()
            future.release()  # the worker may drop its copy now
            accept(result)
    finally:
        if own:
            client.close()
    return f"dask ({client.scheduler.address if client.scheduler else scheduler})"
