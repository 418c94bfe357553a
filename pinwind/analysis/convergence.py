"""Is a run converged in its time step? The same run at dt, dt/2 and dt/4, compared over a window.

``check_dt`` reruns the run from t = 0 to the window's end at each step (so every rerun starts
from the same state and sees the same inputs), folds the samples inside the window into the run
statistics (``analysis/run_statistics.py``), and compares, for every mesh, the normal force's
RMS and maximum and the single-tooth force's maximum, and for every bearing the RMS and maximum
of the force magnitude. For each quantity f it gives the relative changes dt → dt/2 and
dt/2 → dt/4 and the observed order of convergence

    p = log2(|f(dt) − f(dt/2)| / |f(dt/2) − f(dt/4)|),

(1 for a first-order step, 2 for a second-order one, when dt is in the asymptotic range), and a
verdict: the value at dt lies within ``tolerance`` of the value at dt/4, or it does not and dt
should be halved. ``pinwind simulate ... --check-dt`` and ``pinwind run SCENARIO --check-dt``
print it.

The default window is the last ``DEFAULT_FRACTION`` of the run, widened so that it holds at
least ``MESH_PERIODS`` mesh periods of the slowest turning mesh (counted at dt from its
entering tooth pair: one mesh period per base pitch rolled).
"""

from __future__ import annotations

import math
import sys
import warnings
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.dynamics.result import Result
from pinwind.dynamics.simulate import simulate
from pinwind.errors import InputError, PinwindWarning
from pinwind.model.gearbox import Gearbox

#: The default window: this last fraction of the run [-].
DEFAULT_FRACTION = 0.1
#: The default window holds at least this many mesh periods of the slowest turning mesh.
MESH_PERIODS = 3
#: A quantity is converged when its value at dt is within this of the value at dt/4 [-].
TOLERANCE = 0.01
#: The steps compared, as fractions of dt.
REFINEMENTS = (1, 2, 4)

#: (group, statistics quantity, statistic, label, unit) of each quantity compared.
QUANTITIES: tuple[tuple[str, str, str, str, str], ...] = (
    ("mesh", "normal", "rms", "normal force RMS", "N"),
    ("mesh", "normal", "max", "normal force max", "N"),
    ("mesh", "single tooth force", "max", "single-tooth force max", "N"),
    ("bearing", "force (world)", "rms", "|force| RMS", "N"),
    ("bearing", "force (world)", "max", "|force| max", "N"),
)


def relative_change(before: float, after: float) -> float:
    """(after − before) / |after| [-]; 0 when both are 0, infinite when only ``after`` is."""
    if after == before:
        return 0.0
    if after == 0.0:
        return math.inf
    return (after - before) / abs(after)


#: Changes below this fraction of the values are round-off: they give no order [-].
ROUND_OFF = 1e-9


def observed_order(coarse: float, middle: float, fine: float) -> float:
    """Observed order p = log2(|f(h) − f(h/2)| / |f(h/2) − f(h/4)|) of three values at h, h/2, h/4.

    NaN when neither change exceeds round-off (``ROUND_OFF`` of the values: nothing to
    measure), infinite when only the last pair agrees.
    """
    first, second = abs(coarse - middle), abs(middle - fine)
    if max(first, second) <= ROUND_OFF * max(abs(coarse), abs(middle), abs(fine)):
        return math.nan
    if second == 0.0:
        return math.nan if first == 0.0 else math.inf
    if first == 0.0:
        return -math.inf
    return math.log2(first / second)


@dataclass(frozen=True)
class DtRow:
    """One quantity at dt, dt/2 and dt/4 (or at dt and dt/2 only).

    Attributes:
        group: ``mesh`` or ``bearing`` (a fatigue set's: ``contact`` or ``root``).
        element: the mesh or bearing (joint) name (a fatigue set's: the gear).
        quantity: what is compared, e.g. ``normal force RMS``.
        unit: SI unit of the values.
        values: the quantity at dt, dt/2 and dt/4 over the window [unit], or at dt and dt/2.
        change_half: relative change dt → dt/2 [-].
        change_quarter: relative change dt/2 → dt/4 [-] (NaN without dt/4).
        order: observed order p [-] (NaN: no change to measure, or no dt/4).
        error: |f(dt) − f(finest)| / |f(finest)|, how far the run's value is from the value at
            the finest step, dt/4 or dt/2 [-].
        converged: ``error`` ≤ the check's tolerance.
    """

    group: str
    element: str
    quantity: str
    unit: str
    values: tuple[float, ...]
    change_half: float
    change_quarter: float
    order: float
    error: float
    converged: bool

    @property
    def verdict(self) -> str:
        """``converged to 0.3 %`` (dt against the finest step) or ``not converged: halve dt``."""
        if self.converged:
            return f"converged to {100 * self.error:.2g} %"
        return "not converged: halve dt"


def dt_row(
    group: str,
    element: str,
    quantity: str,
    unit: str,
    values: Sequence[float],
    tolerance: float = TOLERANCE,
) -> DtRow:
    """The row of one quantity from its values at dt, dt/2 and dt/4, or at dt and dt/2.

    With two values the run's value is judged against the one at dt/2, and there is no order.
    """
    steps = tuple(float(v) for v in values)
    if len(steps) not in (2, 3):
        raise ValueError(f"dt_row takes the values at dt, dt/2 [and dt/4]; got {len(steps)}")
    coarse, middle, fine = steps if len(steps) == 3 else (*steps, math.nan)
    error = abs(relative_change(coarse, steps[-1]))
    return DtRow(
        group=group,
        element=element,
        quantity=quantity,
        unit=unit,
        values=steps,
        change_half=relative_change(coarse, middle),
        change_quarter=relative_change(middle, fine) if len(steps) == 3 else math.nan,
        order=observed_order(coarse, middle, fine) if len(steps) == 3 else math.nan,
        error=error,
        converged=error <= tolerance,
    )


def row_dict(row: DtRow) -> dict[str, Any]:
    """A row as plain values for JSON, with its verdict (infinite and NaN values as None)."""

    def plain(x: Any) -> Any:
        if isinstance(x, float) and not math.isfinite(x):
            return None
        if isinstance(x, tuple | list):
            return [plain(v) for v in x]
        return x

    return {k: plain(v) for k, v in asdict(row).items()} | {"verdict": row.verdict}


@dataclass(frozen=True)
class DtConvergence:
    """The convergence check of a run in its time step.

    Attributes:
        dt: the run's time step [s]; the reruns take dt/2 and dt/4.
        window: (start, end) of the window compared [s].
        tolerance: the relative distance to the dt/4 value that counts as converged [-].
        rows: one per quantity (``QUANTITIES``) of every mesh and bearing.
    """

    dt: float
    window: tuple[float, float]
    tolerance: float
    rows: list[DtRow]

    @property
    def converged(self) -> bool:
        """Every quantity is converged."""
        return all(row.converged for row in self.rows)

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON (infinite and NaN orders as None)."""
        rows = [row_dict(row) for row in self.rows]
        return {
            "dt": self.dt,
            "steps": [self.dt / r for r in REFINEMENTS],
            "window": list(self.window),
            "tolerance": self.tolerance,
            "converged": self.converged,
            "rows": rows,
        }


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
