"""What a check of ``pinwind.testing`` measured: the figure it returns, or raises with."""

from __future__ import annotations

from dataclasses import dataclass

from pinwind.errors import CheckFailed


@dataclass(frozen=True)
class CheckFigure:
    """The figure of one check: what was compared, the measured value and its tolerance.

    Attributes:
        check: the check's name (``ledger_closure``, ``element_tangents``, ...).
        compared: what was compared with what, in words, with the unit of ``measured``.
        measured: the measured value (a relative error unless ``compared`` says otherwise).
        tolerance: the largest value the check accepts.
        detail: where the worst value was (the sample, joint, state or mode) and its size.
    """

    check: str
    compared: str
    measured: float
    tolerance: float
    detail: str = ""

    @property
    def passed(self) -> bool:
        """The measured value is within the tolerance (NaN never is)."""
        return bool(self.measured <= self.tolerance)

    def enforced(self) -> CheckFigure:
        """Return this figure; raise ``CheckFailed`` with its values when it is beyond tolerance."""
        if not self.passed:
            raise CheckFailed(self.check, self.compared, self.measured, self.tolerance, self.detail)
        return self

    def __str__(self) -> str:
        verdict = "within" if self.passed else "BEYOND"
        return (
            f"{self.check}: {self.compared}: {self.measured:.3g} ({verdict} {self.tolerance:.3g})"
            + (f"; {self.detail}" if self.detail else "")
        )
