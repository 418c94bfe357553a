"""The design sweep (Saleh 2017 §3.2 Fig. 3, §5): evaluate each design, run them all.

Any kind of stage goes through the same path (`StageDesign`; the kinds are `sweep_planetary`
and `sweep_parallel` in `pinwind.analysis`):

1. `evaluate`: check, build, load and simulate one design with pinwind's dynamics (a short rigid
   run in torque balance, a `pinwind.runs.scenario.Scenario` run like every other run), rate
   every mesh (`analysis.rating.rate`, ISO 6336 and AGMA 2001) and return a row. A design that
   fails to build, simulate or rate is a row with ``status = "failed"`` and the reason; geometry
   findings are listed in ``findings``.
2. `run_sweep`: all local cores (processes) or a Dask cluster (`runs/executor.py`), a progress
   bar, rows written to a checkpoint as they finish; a re-run skips the designs already in the
   output or checkpoint. The rows do not depend on the backend: each design is computed on its
   own, the same way.

The rows' tables and eq. 41's query are `pinwind.analysis.sweep_table`.
"""

from __future__ import annotations

import json
import math
import time
import traceback
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from pinwind.analysis.sweep_design import StageDesign, SweepSettings
from pinwind.analysis.sweep_table import design_key
from pinwind.runs.executor import check_workers, run_tasks

__all__ = ["SERIAL_BELOW", "SweepRun", "evaluate", "evaluate_batch", "run_sweep"]

#: Below this many designs a default sweep runs in this process (see `run_sweep`).
SERIAL_BELOW = 256


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
        from pinwind.runs.scenario import Scenario, run

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
