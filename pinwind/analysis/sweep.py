"""Design sweep machinery (000_3b7c4a8fe52a6eee.txt §3.2 Fig. 3, §5): evaluate, run, tables, eq. 41.

Any kind of stage goes through the same path (`StageDesign`; the kinds are `sweep_planetary`
and `sweep_parallel`):

1. `evaluate`: check, build, load and simulate one design with pinwind's dynamics (a short rigid
   run in torque balance, a `pinwind.scenario.Scenario` run like every other run), rate every
   mesh (`analysis.rating.rate`, ISO 6336 and AGMA 2001) and return a row. A design that fails
   to build, simulate or rate is a row with ``status = "failed"`` and the reason; geometry
   findings are listed in ``findings``.
2. `run_sweep`: all local cores (processes) or a Dask cluster, a progress bar, rows written to a
   checkpoint as they finish; a re-run skips the designs already in the output or checkpoint.
   The rows do not depend on the backend: each design is computed on its own, the same way.
3. `write_table` / `read_table`: CSV or Parquet, one column set per kind (``stage`` column).
4. `query`: 000 eq. 41 on the columns every kind has (centre distance, ratio, module, SF).
"""

from __future__ import annotations

import json
import math
import socket
import time
import traceback
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from pinwind.analysis.sweep_design import StageDesign, SweepSettings
from pinwind.analysis.sweep_parallel import ParallelDesign, enumerate_parallel
from pinwind.analysis.sweep_planetary import (
    TABLE_5_INCLUDE,
    PlanetaryDesign,
    enumerate_planetary,
)
from pinwind.errors import InputError, SchedulerUnreachable

__all__ = [
    "SERIAL_BELOW",
    "STAGES",
    "TABLE_5_INCLUDE",
    "ParallelDesign",
    "PlanetaryDesign",
    "StageDesign",
    "SweepRun",
    "SweepSettings",
    "check_workers",
    "design_from_row",
    "design_key",
    "enumerate_parallel",
    "enumerate_planetary",
    "evaluate",
    "evaluate_batch",
    "query",
    "read_checkpoint",
    "read_table",
    "run_sweep",
    "run_tasks",
    "settings_dict",
    "stage_of",
    "write_table",
]

#: What a task of `run_tasks` returns.
T = TypeVar("T")

#: Below this many designs a default sweep runs in this process (see `run_sweep`).
SERIAL_BELOW = 256
#: Stage kinds by the value of a row's ``stage`` column.
STAGES: dict[str, type[StageDesign]] = {
    PlanetaryDesign.kind: PlanetaryDesign,
    ParallelDesign.kind: ParallelDesign,
}


def stage_of(row: dict) -> type[StageDesign]:
    """The kind of a row (tables written before the ``stage`` column are planetary)."""
    name = row.get("stage") or PlanetaryDesign.kind
    try:
        return STAGES[name]
    except KeyError:
        raise InputError(
            f'row #{row.get("number")}: unknown stage "{name}"; stages are {sorted(STAGES)}'
        ) from None


def evaluate(design: StageDesign, settings: SweepSettings) -> dict:
    """Check, build, simulate and rate one design; a failure is a row with its reason.

    Runs in a worker process or on a Dask worker: it imports what it needs and returns plain
    values only.
    """
    start = time.perf_counter()
    row: dict = {c: math.nan for c in design.columns()}
    row.update(design.identity(settings), status="ok", reason="", findings="")
    stage = "building"
    try:
        import warnings

        from pinwind.analysis.rating import rate
        from pinwind.model.gearbox import loads
        from pinwind.scenario import Scenario, run

        findings = design.check(settings)
        row["findings"] = "; ".join(f"{f.severity}: {f.message}" for f in findings)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            gearbox = loads(design.urdf(settings), f"design #{design.number}")
            stage = "simulating"
            torques, speeds = design.loads(settings)
            scenario = Scenario(duration=settings.duration, dt=settings.dt, torques=torques,
                                initial_speeds=speeds)  # fmt: skip
            result = run(scenario, gearbox=gearbox, no_log=True, check_joints=False)
        stage = "rating"
        rating = rate(gearbox, result, materials={g: settings.material for g in gearbox.gears})
        row.update(design.rating_columns(rating))
    except Exception as err:  # noqa: BLE001 (a design's failure is data, not a crash)
        row["status"] = "failed"
        detail = str(err) or type(err).__name__
        if not isinstance(err, pinwind_error_types()):
            detail = f"{type(err).__name__}: {detail} ({traceback.format_exc(limit=1).strip()})"
        row["reason"] = f"{stage}: {detail}"
    row["wall_time_s"] = time.perf_counter() - start
    return row


def evaluate_batch(designs: Sequence[StageDesign], settings: SweepSettings) -> list[dict]:
    """`evaluate` on each design of a batch (one worker task)."""
    return [evaluate(d, settings) for d in designs]


def pinwind_error_types() -> tuple[type, ...]:
    """Error types whose message is enough on its own."""
    from pinwind.errors import PinwindError

    return (PinwindError,)


# --- running many designs -----------------------------------------------------------------------


@dataclass
class SweepRun:
    """Rows of a sweep and how they were obtained.

    Attributes:
        rows: one dict per design (`StageDesign.columns`), ordered by design number.
        computed: how many designs were computed in this call (the rest were reused).
        wall_time: seconds for this call.
        backend: ``"serial"``, ``"processes (N)"`` or ``"dask (ADDRESS)"``.
    """

    rows: list[dict] = field(default_factory=list)
    computed: int = 0
    wall_time: float = 0.0
    backend: str = ""


def design_key(row: dict) -> tuple:
    """What identifies a design across runs: its kind and ``KEY`` columns (lengths in µm).

    The key of a design is ``design_key(design.identity(settings))``, so the face width the
    settings give is part of it: a re-run with another width recomputes every design.
    """
    kind = stage_of(row)
    values: list = [kind.kind]
    for column in kind.KEY:
        value = row[column]
        if column.endswith("_mm"):
            values.append(round(float(value) * 1e3))
        elif column.endswith("_deg"):
            values.append(round(float(value) * 1e6))
        else:
            values.append(int(value))
    return tuple(values)


def run_sweep(
    designs: Sequence[StageDesign],
    settings: SweepSettings,
    *,
    workers: int | None = None,
    scheduler: str | object | None = None,
    checkpoint: Path | None = None,
    done: Iterable[dict] = (),
    progress: Callable[[int, int], None] | None = None,
) -> SweepRun:
    """Evaluate designs on local processes or a Dask cluster; skip those already ``done``.

    Args:
        designs: from `enumerate_planetary` or `enumerate_parallel`.
        settings: one set of settings for every design.
        workers: local worker processes (default: all cores, except that fewer than
            `SERIAL_BELOW` designs run in this process: starting the pool and importing pinwind
            in each worker takes about a second, 200 designs' worth; 1 always runs here).
        scheduler: a Dask scheduler address (``tcp://host:8786``) or a ``distributed.Client``;
            overrides ``workers``.
        checkpoint: JSON-lines file; each finished row is appended as soon as it arrives.
        done: rows of an earlier run; designs with the same `design_key` are not recomputed,
            and their rows are kept (renumbered).
        progress: called as progress(finished, total) after each design.
    """
    import os

    start = time.perf_counter()
    previous = {}
    for row in done:
        previous[design_key(row)] = row
    rows: dict[int, dict] = {}
    todo: list[StageDesign] = []
    for d in designs:
        old = previous.get(design_key(d.identity(settings)))
        if old is not None:
            rows[d.number] = {**old, "number": d.number}
        else:
            todo.append(d)
    total, finished = len(designs), len(rows)
    if progress:
        progress(finished, total)
    sink = checkpoint.open("a", encoding="utf-8") if checkpoint is not None else None

    def accept(row: dict) -> None:
        nonlocal finished
        rows[int(row["number"])] = row
        finished += 1
        if sink is not None:
            sink.write(json.dumps(row) + "\n")
            sink.flush()
        if progress:
            progress(finished, total)

    check_workers(workers)
    n = workers or (1 if len(todo) < SERIAL_BELOW else os.cpu_count() or 1)
    # Batches of a few designs per task: each design takes milliseconds, so one task per design
    # would spend its time in inter-process traffic; small batches keep the progress bar live.
    size = max(1, min(16, len(todo) // (8 * n)))
    try:
        backend = run_tasks(
            evaluate, todo, accept=accept, workers=n, scheduler=scheduler, batch_size=size,
            settings=settings,
        )  # fmt: skip
    finally:
        if sink is not None:
            sink.close()
    ordered = [rows[k] for k in sorted(rows)]
    return SweepRun(ordered, len(todo), time.perf_counter() - start, backend)


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


# --- tables -------------------------------------------------------------------------------------


def write_table(rows: Sequence[dict], path: Path) -> Path:
    """Write rows of one kind as CSV, or Parquet when the suffix is ``.parquet``.

    Raises:
        InputError: rows of more than one kind (write one table per stage kind).
    """
    import pyarrow as pa

    kinds = {stage_of(r) for r in rows} or {PlanetaryDesign}
    if len(kinds) > 1:
        raise InputError(
            f"rows of {len(kinds)} stage kinds ({', '.join(sorted(k.kind for k in kinds))}) in one "
            "table; write one table per kind"
        )
    columns = kinds.pop().columns()
    table = pa.Table.from_pylist([{c: r.get(c) for c in columns} for r in rows])
    path = Path(path)
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        pq.write_table(table, path)
    else:
        import pyarrow.csv as pc

        pc.write_csv(table, path)
    return path


def read_table(path: Path) -> list[dict]:
    """Rows of a table written by `write_table` (CSV or Parquet)."""
    path = Path(path)
    if not path.exists():
        raise InputError(
            f"{path}: no such sweep table; run pinwind sweep planetary (or parallel) first"
        )
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        table = pq.read_table(path)
    else:
        import pyarrow.csv as pc

        table = pc.read_csv(path)
    rows = table.to_pylist()
    for row in rows:
        for k in ("reason", "findings"):
            if row.get(k) is None:
                row[k] = ""
    return rows


def read_checkpoint(path: Path) -> list[dict]:
    """Rows of a checkpoint (JSON lines); a torn last line is ignored."""
    rows: list[dict] = []
    if not Path(path).exists():
        return rows
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        try:
            rows.append(json.loads(line))
        except json.JSONDecodeError:
            continue
    return rows


# --- eq. 41: picking designs ----------------------------------------------------------------------


def query(
    rows: Iterable[dict],
    *,
    centre_distance: float | None = None,
    ratio: float | None = None,
    ratio_tolerance: float = 0.05,
    module: float | None = None,
    min_sf: float | None = None,
    sf_column: str = "agma_SF_min",
    minimise: str | None = None,
) -> list[dict]:
    """Designs that satisfy every given criterion (000 eq. 41: a ∪ i ∪ m ∪ SF).

    Args:
        rows: sweep rows.
        centre_distance: required centre distance [m] (matched to the micrometre).
        ratio: required speed ratio, matched within ``ratio_tolerance`` (the paper's 6.3 picks
            6.32 and not 6.15).
        module: required module [m].
        min_sf: smallest acceptable safety factor: ``row[sf_column] > min_sf`` (the paper's
            "SF > 1"); failed designs never pass.
        sf_column: which safety factor (default the smallest AGMA one of the design).
        minimise: a column to minimise (``"centre_distance_mm"``, ``"module_mm"``, ...); only
            the designs at its smallest value are returned.

    Raises:
        InputError: ``sf_column`` or ``minimise`` is not a column of the table.
    """
    rows = list(rows)
    if min_sf is not None and rows and sf_column not in rows[0]:
        raise InputError(
            f'--sf "{sf_column}": not a column of the sweep table; safety-factor columns are '
            + ", ".join(c for c in rows[0] if "SF" in c or "_S_" in c)
        )
    keep = []
    for row in rows:
        if row.get("status") != "ok":
            continue
        if centre_distance is not None and round(float(row["centre_distance_mm"]) * 1e3) != round(
            centre_distance * 1e6
        ):
            continue
        if module is not None and round(float(row["module_mm"]) * 1e3) != round(module * 1e6):
            continue
        if ratio is not None and abs(float(row["ratio"]) - ratio) > ratio_tolerance:
            continue
        if min_sf is not None and not float(row[sf_column]) > min_sf:
            continue
        keep.append(row)
    if minimise and keep:
        if minimise not in keep[0]:
            raise InputError(
                f'--minimise "{minimise}": not a column; columns are {", ".join(keep[0])}'
            )
        best = min(float(r[minimise]) for r in keep)
        keep = [r for r in keep if float(r[minimise]) == best]
    return keep


def best_found(
    rows: Iterable[dict],
    *,
    centre_distance: float | None = None,
    ratio: float | None = None,
    ratio_tolerance: float = 0.05,
    module: float | None = None,
    min_sf: float | None = None,
    sf_column: str = "agma_SF_min",
) -> list[str]:
    """What each criterion of a ``query`` finds on its own, for a query no design meets.

    Per criterion given, over the designs that ran (status ok): the best value (the largest
    safety factor, the nearest centre distance, ratio or module), its design number, and how
    many designs meet that criterion alone. One line each, in the CLI's units and flags.
    """
    ok = [r for r in rows if r.get("status") == "ok"]
    if not ok:
        return ["no design of the table ran (none has status ok)"]

    def nearest(column: str, target: float) -> dict:
        return min(ok, key=lambda r: abs(float(r[column]) - target))

    lines = []
    if min_sf is not None:
        best = max(ok, key=lambda r: float(r[sf_column]))
        meet = sum(float(r[sf_column]) > min_sf for r in ok)
        lines.append(
            f"--min-sf {min_sf:g}: the largest {sf_column} is {float(best[sf_column]):.3f} "
            f"(#{int(best['number'])}); {meet} design(s) exceed {min_sf:g}"
        )
    if ratio is not None:
        best = nearest("ratio", ratio)
        meet = sum(abs(float(r["ratio"]) - ratio) <= ratio_tolerance for r in ok)
        lines.append(
            f"--ratio {ratio:g}: the nearest ratio is {float(best['ratio']):.4g} "
            f"(#{int(best['number'])}); {meet} design(s) within ±{ratio_tolerance:g}"
        )
    # Lengths: the table's columns are in mm; "at it" to the µm, as query matches them.
    for flag, column, length in (
        ("--center-distance", "centre_distance_mm", centre_distance),
        ("--module", "module_mm", module),
    ):
        if length is None:
            continue
        target = length * 1e3
        best = nearest(column, target)
        meet = sum(round(float(r[column]) * 1e3) == round(target * 1e3) for r in ok)
        lines.append(
            f"{flag} {target:g}: the nearest is {float(best[column]):g} mm "
            f"(#{int(best['number'])}); {meet} design(s) at it"
        )
    return lines


def design_from_row(row: dict) -> StageDesign:
    """The design of a row, of the row's kind."""
    return stage_of(row).from_row(row)


def settings_dict(settings: SweepSettings) -> dict:
    """Settings as plain values (for messages and metadata)."""
    return asdict(settings)
