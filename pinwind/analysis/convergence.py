"""Is a run converged in its time step? One quantity at dt, dt/2 and dt/4, judged.

For each quantity f compared (``QUANTITIES``: for every mesh the normal force's RMS and maximum
and the single-tooth force's maximum, for every bearing the RMS and maximum of the force
magnitude) it gives the relative changes dt → dt/2 and dt/2 → dt/4 and the observed order of
convergence

    p = log2(|f(dt) − f(dt/2)| / |f(dt/2) − f(dt/4)|),

(1 for a first-order step, 2 for a second-order one, when dt is in the asymptotic range), and a
verdict: the value at dt lies within ``tolerance`` of the value at dt/4, or it does not and dt
should be halved. The reruns at dt/2 and dt/4 that give the values are ``runs/dt_check.py``
(``pinwind simulate ... --check-dt``, ``pinwind run SCENARIO --check-dt``); a fatigue set's
damage is judged the same way with two steps (``life/damage_convergence.py``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

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
