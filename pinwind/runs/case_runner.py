"""The cases of a fatigue set run, each reduced beside its log, on local processes or Dask.

Each case is run like any scenario (its values are in its log, which ``pinwind run --from-log``
repeats) and reduced (`pinwind.life.case_cycles.CaseCycles`). A rerun computes only the cases
whose log is missing or incomplete or whose reduction is missing, damaged or was made from
other inputs (`case_done`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
import zipfile
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from pinwind.errors import PinwindError
from pinwind.life.case_cycles import CaseCycles, CaseReduction
from pinwind.life.fatigue_set import FatigueSet, LoadCase
from pinwind.life.root_stress import ISO_ROOT_STRESS
from pinwind.runs.kept_blocks import KeptBlocks
from pinwind.runs.scenario import build

#: The series a case's reduction reads (the tooth cycles: ``life/tooth_damage.py``; the
#: bearings' and their rows' load sums: ``life/life_sums.py``), as the run goes
#: (`case_reducer`); the log keeps every series.
CASE_SERIES = (
    "angle", "speed", "mesh_normal", "mesh_flank", "mesh_contact_position", "mesh_pairs",
    "mesh_single_tooth_force", "mesh_face_load_factor", "bearing_force_local",
    "bearing_moment_local", "row_force", "row_moment",
)  # fmt: skip

#: What a case's run is finished into (`_run_reduced`).
_Done = TypeVar("_Done")

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.model.gearbox import Gearbox
    from pinwind.runs.scenario import Scenario


def case_scenario(case: LoadCase, fatigue: FatigueSet) -> Scenario:
    """The scenario of one case: the set's run values with the case's wind, its meshes."""
    from pinwind.model.compliance import MeshCompliance

    scenario = build(fatigue.case_values(case), source=fatigue.source, base=fatigue.base)
    if fatigue.mesh_stiffness is not None or fatigue.mesh_damping is not None:
        compliance = MeshCompliance(stiffness=fatigue.mesh_stiffness, damping=fatigue.mesh_damping)
        meshes: dict[str, Any] = {"all": compliance}
        scenario = dataclasses.replace(scenario, meshes=meshes)
    return scenario


def run_case(case: LoadCase, fatigue: FatigueSet) -> CaseCycles:
    """Simulate one case with its log and reduce it as it runs: its `CaseCycles` in memory.

    The reduction is its tooth cycles and its bearings' (and their rows') load sums, both from
    ``skip_start`` on, of the samples at the set's sample rate (`case_reducer`); the Result
    keeps the last sample only. The cycles returned grow with the case's length: a worker
    writes them with `run_saved_case` instead, without holding them.
    """
    return _run_reduced(case, fatigue, reduced_case)


def run_saved_case(case: LoadCase, fatigue: FatigueSet) -> Path:
    """Simulate one case with its log, reduce it as it runs and write its ``.npz``: the path.

    As `run_case`, but the case's ``.npz`` is written from the files its cycles went to as
    they closed (`save_reduced_case`), so the memory does not grow with the case's length.
    Runs in this process, a local worker or a Dask worker (whose output folder must be the
    one the caller reads: a shared file system).
    """
    return _run_reduced(case, fatigue, save_reduced_case)


def _run_reduced(case: LoadCase, fatigue: FatigueSet, finish: Callable[..., _Done]) -> _Done:
    """Run a case with its reduction fed as it runs, then ``finish`` it.

    ``finish`` is `reduced_case` or `save_reduced_case`, given the case's wall, CPU and thread
    times; the reduction's files go after it.
    """
    import warnings

    from pinwind.model.gearbox import load
    from pinwind.runs.scenario import run

    start, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
    scenario = case_scenario(case, fatigue)
    gearbox = load(scenario.model_path())
    fatigue.out.mkdir(parents=True, exist_ok=True)
    reduction, observer = case_reducer(case, fatigue, gearbox)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            # No run statistics: folding every step into min, max and RMS (for a summary; not
            # logged) would take a thread beside the loop.
            run(
                scenario,
                gearbox=gearbox,
                progress=False,
                command=f"pinwind fatigue {fatigue.source} (case {case.name})",
                statistics=False,
                keep="last",
                keep_series=(),
                observer=observer,
            )
        return finish(
            case,
            fatigue,
            reduction,
            wall_time=time.perf_counter() - start,
            cpu_time=time.process_time() - cpu,
            thread_time=time.thread_time() - own,
        )
    finally:  # its cycles' files go now, also in a worker, which ends without clean-up
        reduction.close()


def case_reducer(
    case: LoadCase,
    fatigue: FatigueSet,
    gearbox: Gearbox,
    *others: Any,
    series: Sequence[str] = (),
) -> tuple[CaseReduction, KeptBlocks]:
    """A case's reduction and the run observer that feeds it as the case runs.

    The observer hands on the samples of `CASE_SERIES` (and ``series``) a Result of the set's
    sample rate would keep (``keep`` of `FatigueSet.case_values`), from ``skip_start`` on, in
    blocks (``pinwind.runs.kept_blocks``), to the reduction and to ``others`` (each with
    ``add(block)``, after the reduction). Pass the observer to the run
    (``pinwind.runs.scenario.run``); then `reduced_case`.
    """
    reduction = case_reduction(fatigue, gearbox)
    observer = KeptBlocks(
        [reduction, *others],
        series=tuple(dict.fromkeys([*CASE_SERIES, *series])),
        stride=int(fatigue.case_values(case)["keep"]),
        skip_start=fatigue.skip_start,
    )
    return reduction, observer


def case_reduction(fatigue: FatigueSet, gearbox: Gearbox) -> CaseReduction:
    """The set's reduction of a case run on ``gearbox``, empty (`CaseReduction`)."""
    return CaseReduction(
        gearbox,
        fatigue.gears,
        materials=fatigue.materials,
        root_stress={g: fatigue.root_stress.get(g, ISO_ROOT_STRESS) for g in fatigue.gears},
        bearing_life=fatigue.bearing_life,
        face_load=fatigue.face_load,
    )


def reduced_case(
    case: LoadCase,
    fatigue: FatigueSet,
    reduction: CaseReduction,
    *,
    wall_time: float = math.nan,
    cpu_time: float = math.nan,
    thread_time: float = math.nan,
) -> CaseCycles:
    """A case's `CaseCycles` from its reduction fed with its run; its log must be written."""
    flanks, roots, bearings = reduction.reduced()
    record = _case_record(case, fatigue, wall_time, cpu_time, thread_time)
    return dataclasses.replace(record, flanks=flanks, roots=roots, bearings=bearings)


def _case_record(
    case: LoadCase, fatigue: FatigueSet, wall_time: float, cpu_time: float, thread_time: float
) -> CaseCycles:
    """A case's `CaseCycles` without its cycles: what it is, its times and its log's hash."""
    return CaseCycles(
        case,
        fatigue.case_key(case),
        fatigue.counted_seconds,
        wall_time,
        cpu_time=cpu_time,
        thread_time=thread_time,
        log_sha256=file_sha256(fatigue.log_path(case)),
    )


def save_reduced_case(
    case: LoadCase,
    fatigue: FatigueSet,
    reduction: CaseReduction,
    *,
    wall_time: float = math.nan,
    cpu_time: float = math.nan,
    thread_time: float = math.nan,
) -> Path:
    """Write `reduced_case` to the case's ``.npz`` without holding its cycles: the path.

    `CaseReduction.save` writes it from the files the cycles went to as they closed, so the
    memory does not grow with the case's length; `CaseCycles.load` reads it.
    """
    path = fatigue.cycles_path(case)
    reduction.save(path, _case_record(case, fatigue, wall_time, cpu_time, thread_time))
    return path


def reduce_case(
    case: LoadCase,
    fatigue: FatigueSet,
    result: Result,
    gearbox: Gearbox,
    *,
    wall_time: float = math.nan,
    cpu_time: float = math.nan,
    thread_time: float = math.nan,
) -> CaseCycles:
    """A case's run reduced after it ran: tooth cycles (contact and root), bearing and row sums.

    Counted from ``skip_start`` on, as `run_case` counts it while it runs: the kept samples
    are one block of the same `CaseReduction`. The case's log must be written (its SHA-256 is
    kept).

    Args:
        result: the run of `case_scenario` (its kept samples at the set's sample rate), or
            its log read at that rate.
        gearbox: the model it ran.
        wall_time: seconds the run and the reduction took (`CaseCycles.wall_time`).
        cpu_time: CPU seconds of the process meanwhile (`CaseCycles.cpu_time`).
        thread_time: CPU seconds of the calling thread (`CaseCycles.thread_time`).
    """
    first = int(np.searchsorted(result.time, fatigue.skip_start - 1e-12))
    reduction = case_reduction(fatigue, gearbox)
    reduction.add(result.rows(first, len(result)))
    return reduced_case(
        case,
        fatigue,
        reduction,
        wall_time=wall_time,
        cpu_time=cpu_time,
        thread_time=thread_time,
    )


def save_case(case: LoadCase, fatigue: FatigueSet) -> str:
    """Run one case and write its reduction beside its log (a worker's task): the case's name.

    The worker writes the ``.npz`` itself, as it writes the log, so that only the name travels
    back and the command, which shares the cores with the workers, does not compress cycles;
    it writes it from the cycles' files (`run_saved_case`), so its memory does not grow with
    the case's length.
    """
    run_saved_case(case, fatigue)
    return case.name


def file_sha256(path: Path) -> str:
    """SHA-256 of a file's bytes, as hex."""
    with path.open("rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def case_done(fatigue: FatigueSet, case: LoadCase) -> bool:
    """Whether a case's log is complete and its reduction was made from the same inputs.

    A reduction that fails its CRC check or cannot be read, or a log whose SHA-256 differs from
    the one the reduction recorded (a flipped byte), is damaged: a `CaseFileDamaged` warning
    names the file, and the case is not done (it is computed again).
    """
    from pinwind.io.log_reader import LogReader

    log, cycles = fatigue.log_path(case), fatigue.cycles_path(case)
    if not (log.is_file() and cycles.is_file()):
        return False
    try:
        with zipfile.ZipFile(cycles) as archive:
            bad = archive.testzip()  # every member read and checked against its CRC-32
        if bad is not None:
            raise zipfile.BadZipFile(f"its member {bad} fails its CRC-32 check")
        with np.load(cycles) as data:
            meta = json.loads(str(data["meta"]))
        key, recorded = meta["key"], meta.get("log_sha256", "")
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, zlib.error) as err:
        _damaged(f"{cycles}: the kept reduction of case {case.name} is damaged ({err})")
        return False
    if recorded and file_sha256(log) != recorded:
        _damaged(
            f"{log}: the kept log of case {case.name} is not the one its reduction was made "
            f"from (sha256 {recorded[:12]}… recorded, {file_sha256(log)[:12]}… now): it was "
            "damaged or changed"
        )
        return False
    try:
        with LogReader(log) as reader:
            complete = reader.complete
    except PinwindError:
        return False
    return complete and key == fatigue.case_key(case)


def _damaged(what: str) -> None:
    """Warn, at the caller of `run_cases`, that a kept case file is damaged and redone."""
    import warnings

    from pinwind.errors import CaseFileDamaged

    warnings.warn(CaseFileDamaged(f"{what}; the case is computed again"), stacklevel=4)


@dataclass
class FatigueRun:
    """How the cases of a fatigue set were obtained.

    Attributes:
        computed: names of the cases run in this call (the others were reused).
        total: distinct cases in the set (`LoadCase.name`).
        backend: ``"serial"``, ``"processes (N)"`` or ``"dask (ADDRESS)"`` (`run_tasks`).
        wall_time: seconds for this call.
    """

    computed: list[str]
    total: int
    backend: str
    wall_time: float


def run_cases(
    fatigue: FatigueSet,
    *,
    workers: int | None = None,
    scheduler: str | object | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> FatigueRun:
    """Run the cases not done yet (`case_done`) on local processes or Dask, saving each.

    Each worker writes its case's log and reduction (`save_case`) as soon as the case is done,
    so an interrupted set keeps its finished cases; only the case names come back here.

    Args:
        workers: local worker processes (default: all cores, 1 for a single case).
        scheduler: a Dask scheduler address or ``distributed.Client``; overrides ``workers``.
        progress: called as progress(finished, total) after each case.
    """
    import os

    from pinwind.runs.executor import check_workers, run_tasks

    check_workers(workers)
    start = time.perf_counter()
    cases = fatigue.cases()
    unique = {c.name: c for c in cases}
    todo = []
    for case in unique.values():  # a loop, not a comprehension: warnings point at the caller
        if not case_done(fatigue, case):
            todo.append(case)
    finished, computed = len(unique) - len(todo), []
    if progress:
        progress(finished, len(unique))

    def accept(name: str) -> None:
        nonlocal finished
        computed.append(name)
        finished += 1
        if progress:
            progress(finished, len(unique))

    backend = run_tasks(
        save_case,
        todo,
        accept=accept,
        workers=workers or os.cpu_count() or 1,
        scheduler=scheduler,
        fatigue=fatigue,
    )
    return FatigueRun(computed, len(unique), backend, time.perf_counter() - start)
