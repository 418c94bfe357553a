"""A run again at dt/2 and dt/4: ``check_dt``, the reruns that ``--check-dt`` compares.

``check_dt`` reruns the run from t = 0 to the window's end at each step (so every rerun starts
from the same state and sees the same inputs), folds the samples inside the window into the run
statistics (``analysis/run_statistics.py``), and judges each quantity (``analysis/convergence.py``:
the relative changes, the observed order and the verdict). ``pinwind simulate ... --check-dt``
and ``pinwind run SCENARIO --check-dt`` print it.

The default window is the last ``DEFAULT_FRACTION`` of the run, widened so that it holds at
least ``MESH_PERIODS`` mesh periods of the slowest turning mesh (counted at dt from its
entering tooth pair: one mesh period per base pitch rolled).
"""

from __future__ import annotations

import math
import sys
import warnings
from typing import Any

import numpy as np

from pinwind.analysis.convergence import QUANTITIES, REFINEMENTS, TOLERANCE, DtConvergence, dt_row
from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.dynamics.result import Result
from pinwind.dynamics.simulate import simulate
from pinwind.errors import InputError, PinwindWarning
from pinwind.model.gearbox import Gearbox

#: The default window: this last fraction of the run [-].
DEFAULT_FRACTION = 0.1
#: The default window holds at least this many mesh periods of the slowest turning mesh.
MESH_PERIODS = 3


class _WindowObserver:
    """Folds the samples of a run inside a window, counts mesh periods, advances a progress bar.

    A run observer (``dynamics.simulate.RunObserver``) that is done with each block at once.
    """

    holds = 0

    def __init__(self, gearbox: Gearbox, window: tuple[float, float], dt: float, advance):
        self.first, self.last_time = window[0] - 1e-6 * dt, window[1] + 1e-6 * dt
        self.statistics = RunningStatistics()
        self.advance = advance
        self.base_pitch = [m.path.base_pitch if m.path is not None else math.nan
                           for m in gearbox.meshes]  # fmt: skip
        self.last: np.ndarray | None = None
        #: Per mesh, the times at which its entering tooth pair changed: one per mesh period.
        self.changes: list[list[float]] = [[] for _ in gearbox.meshes]

    def begin(self, gearbox: Gearbox, result: Result) -> None:
        """Nothing to prepare."""

    def samples(self, block: Result, start: int) -> None:
        """Folds the block's samples inside the window; notes its tooth-pair changes."""
        time = block.time
        rows = np.flatnonzero((time >= self.first) & (time <= self.last_time))
        if rows.size:
            self.statistics.add(block, rows)
        position = block.mesh_contact_position
        if self.last is not None:
            position = np.vstack([self.last, position])
            time = np.concatenate([[np.nan], time])
        jumps = np.abs(np.diff(position, axis=0)) > 0.5 * np.asarray(self.base_pitch)
        for i in range(position.shape[1]):
            self.changes[i].extend(time[1:][jumps[:, i]].tolist())
        self.last = position[-1:].copy()
        self.advance(len(block))

    def end(self, result: Result, status: str) -> None:
        """Nothing to finish."""

    def start_for_mesh_periods(self, end: float, periods: int) -> float:
        """The latest start that leaves ``periods`` mesh periods of every turning mesh before end.

        0 when a turning mesh has fewer in the whole run; ``end`` when no mesh turns.
        """
        starts = [end]
        for changes in self.changes:
            if not changes:
                continue
            starts.append(changes[-periods - 1] if len(changes) > periods else 0.0)
        return min(starts)


def _check_window(window: tuple[float, float], duration: float) -> tuple[float, float]:
    start, end = (float(x) for x in window)
    if not (math.isfinite(start) and math.isfinite(end)) or not 0.0 <= start < end <= duration:
        raise InputError(
            f"the check window (--check-window) {start:g}:{end:g} s is not inside the run, "
            f"0:{duration:g} s; give START:END with 0 ≤ START < END ≤ {duration:g}"
        )
    return start, end


def check_dt(
    gearbox: Gearbox,
    *,
    dt: float,
    window: tuple[float, float] | None = None,
    tolerance: float = TOLERANCE,
    progress: bool | None = None,
    **simulate_kwargs: Any,
) -> DtConvergence:
    """Rerun a run at dt, dt/2 and dt/4 and compare its mesh and bearing forces over a window.

    Args:
        gearbox: the model.
        dt: the run's time step [s].
        window: (start, end) of the window compared [s]; default the last ``DEFAULT_FRACTION``
            of the run, with at least ``MESH_PERIODS`` mesh periods of every turning mesh.
        tolerance: relative distance of the value at dt to the one at dt/4 that counts as
            converged [-].
        progress: a progress bar over the reruns (default: on a terminal).
        **simulate_kwargs: the run's other arguments of ``dynamics.simulate.simulate``
            (``duration`` [s], ``torques``, ``meshes``, ...; e.g. ``Scenario.simulate_kwargs()``).

    Returns:
        The ``DtConvergence``: one row per quantity, mesh and bearing.

    Raises:
        InputError: a window outside the run, naming ``--check-window`` and the run's span.
    """
    kwargs = dict(simulate_kwargs)
    for managed in ("keep", "observer", "progress"):
        kwargs.pop(managed, None)
    duration = float(kwargs.pop("duration"))
    fixed = window is not None
    start, end = _check_window(
        window if window is not None else ((1.0 - DEFAULT_FRACTION) * duration, duration),
        duration,
    )
    # Every rerun ends on a step of dt (and so of dt/2 and dt/4).
    end = math.floor(end / dt + 1e-9) * dt
    if end <= start:
        raise InputError(
            f"the check window (--check-window) {start:g}:{end:g} s holds no step of "
            f"dt = {dt:g} s; give a longer window inside the run, 0:{duration:g} s"
        )
    steps = sum(round(end * r / dt) for r in REFINEMENTS)
    show = progress if progress is not None else sys.stderr.isatty()
    with _Progress(show, steps) as bar:

        def rerun(refinement: int, window: tuple[float, float]) -> _WindowObserver:
            step = dt / refinement
            observer = _WindowObserver(gearbox, window, step, bar.advance)
            simulate(gearbox, duration=end, dt=step, keep="last", observer=observer,
                     progress=False, **kwargs)  # fmt: skip
            return observer

        first = rerun(1, (start, end))
        if not fixed:
            wider = first.start_for_mesh_periods(end, MESH_PERIODS)
            if wider < start:
                start = wider
                bar.add(round(end / dt))
                first = rerun(1, (start, end))
        observers = [first]
        with warnings.catch_warnings():
            # The run at dt has said what the model and the step deserve to be warned about.
            warnings.simplefilter("ignore", PinwindWarning)
            observers += [rerun(r, (start, end)) for r in REFINEMENTS[1:]]
    rows = []
    for group, name, statistic, label, unit in QUANTITIES:
        names = observers[0].statistics.rows()
        elements = list(dict.fromkeys(r.element for r in names if r.group == group))
        for element in elements:
            component = "|.|" if group == "bearing" else ""
            values = [
                getattr(o.statistics.row(group, element, name, component), statistic)
                for o in observers
            ]
            rows.append(dt_row(group, element, label, unit, values, tolerance))
    rows.sort(key=lambda r: (r.group != "mesh", r.group, r.element))
    return DtConvergence(dt=dt, window=(start, end), tolerance=tolerance, rows=rows)


class _Progress:
    """A rich progress bar over the steps of every rerun, or nothing."""

    def __init__(self, show: bool, total: int):
        self.bar = None
        if show:
            from rich.console import Console
            from rich.progress import Progress

            self.bar = Progress(console=Console(stderr=True), transient=True)
            self.task = self.bar.add_task("dt, dt/2, dt/4", total=total)

    def __enter__(self) -> _Progress:
        if self.bar is not None:
            self.bar.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()

    def advance(self, steps: int) -> None:
        """Count steps done."""
        if self.bar is not None:
            self.bar.advance(self.task, steps)

    def add(self, steps: int) -> None:
        """Count more steps to do."""
        if self.bar is not None:
            total = self.bar.tasks[0].total or 0
            self.bar.update(self.task, total=total + steps)
