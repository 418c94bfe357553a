"""Is a fatigue set's damage converged in its time step? The same set at dt/2, compared.

A dynamic result comes with its dt convergence: the same figure at dt/2. ``half_step_set`` is a
fatigue set with its time step halved and its cases written to a sibling folder (the set's
``out`` with ``HALF_STEP_SUFFIX``), resumable like the set itself; its stress histories are read
at the same sample times (the sample stride doubles), so that only the step differs.
``damage_dt_check`` compares the two sets' damage (`pinwind.life.set_damage.set_damage`) per
turbulence level: every gear's total damage in each S-N variant, of the contact and of the root
stress, and its largest contact and root stress, each as a row of
`pinwind.analysis.convergence` (``dt_row`` with the values at dt and dt/2: the relative change and
whether it is within the tolerance).

The damage goes as σ^m (m = 3.4 for Jørgensen 2014's curves, 6.6-8.7 for ISO 6336's below the
knee), so it magnifies a change of the stress: ``TOLERANCE`` (5 %) on the damage is about 1.5 %
on the stress for Jørgensen 2014's m. Near an endurance limit the damage may be zero at one step
and not at the other (a change of ±100 % or infinite): such a figure is not resolved by the step
either. A damage below ``NEGLIGIBLE_DAMAGE`` at both steps (ISO 6336's curves far below the knee
give 1e-40) is shown but not judged: its relative change says nothing about the life.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pinwind.analysis.convergence import DtRow, dt_row, row_dict
from pinwind.errors import InputError
from pinwind.life.fatigue_set import FatigueSet
from pinwind.life.set_damage import LOCATIONS, VARIANTS, SetDamage

#: A figure is converged when its value at dt is within this of its value at dt/2 [-].
TOLERANCE = 0.05
#: A damage below this at dt and at dt/2 is no damage: its change is not judged [-].
NEGLIGIBLE_DAMAGE = 1e-6
#: The dt/2 set's folder is the set's ``out`` with this appended.
HALF_STEP_SUFFIX = "_half_dt"
#: Rates are whole numbers of steps when within this relative distance of one [-].
_WHOLE = 1e-6


def half_step_set(fatigue: FatigueSet) -> FatigueSet:
    """The same fatigue set at dt/2, its cases in ``out`` + ``HALF_STEP_SUFFIX``.

    Raises:
        InputError: the set's ``sample_rate`` (or the scenario's ``log_rate``) is not a whole
            number of steps at dt, so that the dt/2 histories would be read (or logged) at
            other times than the set's.
    """
    dt = fatigue.dt
    rates = [("sample_rate", "[fatigue] sample_rate", fatigue.sample_rate)]
    if fatigue.values.get("log_rate") is not None:
        rates.append(("log_rate", "log_rate", float(fatigue.values["log_rate"])))
    for key, where, rate in rates:
        steps = 1.0 / (rate * dt)
        if steps < 1.0 - _WHOLE or abs(steps - round(steps)) > _WHOLE * steps:
            raise InputError(
                f"{fatigue.source}: --check-dt reruns the set at dt/2 = {dt / 2:g} s and compares "
                f"it at the same sample times, but {where} = {rate:g} Hz is not a whole number of "
                f"steps at dt = {dt:g} s (1 / ({key} · dt) = {steps:.4g}); give a {key} that "
                f"divides 1/dt = {1.0 / dt:g} Hz"
            )
    return dataclasses.replace(
        fatigue,
        values={**fatigue.values, "dt": dt / 2.0},
        out=fatigue.out.with_name(fatigue.out.name + HALF_STEP_SUFFIX),
    )


@dataclass(frozen=True)
class DamageDtCheck:
    """A fatigue set's damage and largest stresses at dt against the same at dt/2.

    Attributes:
        dt: the set's time step [s]; the check's is dt/2.
        out: the folder of the dt/2 cases.
        levels: the turbulence levels' labels.
        tolerance: the relative change dt → dt/2 that counts as converged [-].
        rows: level index → one row per gear, location (``contact``, ``root``) and figure:
            ``damage (VARIANT)`` [-] of each S-N variant and ``max stress`` [Pa].
    """

    dt: float
    out: Path
    levels: tuple[str, ...]
    tolerance: float
    rows: list[list[DtRow]]

    @property
    def converged(self) -> bool:
        """Every judged figure is converged."""
        return all(row.converged for level in self.rows for row in level if judged(row))

    def largest(self) -> tuple[str, DtRow] | None:
        """(level label, row) of the largest judged change dt → dt/2; None without any."""
        pairs = [
            (label, row)
            for label, rows in zip(self.levels, self.rows, strict=True)
            for row in rows
            if judged(row)
        ]
        return max(pairs, key=lambda p: p[1].error, default=None)

    @property
    def verdict(self) -> str:
        """One line: converged within X %, or not, and the advice of a smaller dt."""
        largest = self.largest()
        if largest is None:
            return "nothing to compare: no gear was rated, or no damage is above negligible"
        label, row = largest
        where = f"{row.element} {row.group} {row.quantity} at {label}"
        if self.converged:
            return (
                f"converged within {100 * row.error:.2g} %: every damage and largest stress at "
                f"dt = {self.dt:g} s is within {100 * self.tolerance:g} % of its value at dt/2 "
                f"(largest change: {where})"
            )
        bad = sum(not r.converged for rows in self.rows for r in rows if judged(r))
        total = sum(judged(r) for rows in self.rows for r in rows)
        return (
            f"not converged: {bad} of {total} judged figures change by more than "
            f"{100 * self.tolerance:g} % at dt/2 = {self.dt / 2:g} s (largest: {where}, "
            f"{100 * row.change_half:+.3g} %); run the set at a smaller dt (dt = "
            f"{self.dt / 2:g} s or less) and check again"
        )

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON (infinite changes as None)."""
        return {
            "dt": self.dt,
            "dt_half": self.dt / 2.0,
            "out": str(self.out),
            "tolerance": self.tolerance,
            "converged": self.converged,
            "verdict": self.verdict,
            "levels": [
                {"level": label, "rows": [_judged_dict(row) for row in rows]}
                for label, rows in zip(self.levels, self.rows, strict=True)
            ],
        }


def judged(row: DtRow) -> bool:
    """Whether a row counts in the verdict: a stress, or a damage not negligible at both steps."""
    return row.unit != "-" or max(abs(v) for v in row.values) >= NEGLIGIBLE_DAMAGE


def _judged_dict(row: DtRow) -> dict[str, Any]:
    """`row_dict` with whether the row is judged, and the verdict of one that is not."""
    plain = row_dict(row) | {"judged": judged(row)}
    if not plain["judged"]:
        plain["verdict"] = f"negligible damage (below {NEGLIGIBLE_DAMAGE:g}): not judged"
    return plain


def damage_dt_check(
    damage: SetDamage,
    half: SetDamage,
    *,
    dt: float,
    out: Path,
    tolerance: float = TOLERANCE,
) -> DamageDtCheck:
    """Compare a set's damage at dt with the same set's at dt/2 (`half_step_set`).

    Args:
        damage: the set's damage at dt.
        half: the dt/2 set's damage.
        dt: the set's time step [s].
        out: the dt/2 set's folder, for the report.
        tolerance: the relative change dt → dt/2 that counts as converged [-].
    """
    rows: list[list[DtRow]] = []
    for level in range(len(damage.levels)):
        level_rows = []
        for gear in damage.gears:
            for location in LOCATIONS:
                coarse = damage.damage if location == "contact" else damage.root_damage
                fine = half.damage if location == "contact" else half.root_damage
                if not coarse or gear not in coarse["limit"][level]:
                    continue
                for variant in VARIANTS:
                    values = (coarse[variant][level][gear].total, fine[variant][level][gear].total)
                    level_rows.append(
                        dt_row(location, gear, f"damage ({variant})", "-", values, tolerance)
                    )
                peaks = (
                    coarse["limit"][level][gear].peak_stress,
                    fine["limit"][level][gear].peak_stress,
                )
                level_rows.append(dt_row(location, gear, "max stress", "Pa", peaks, tolerance))
        rows.append(level_rows)
    return DamageDtCheck(dt=dt, out=out, levels=damage.levels, tolerance=tolerance, rows=rows)
