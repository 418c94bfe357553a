"""Numbers of one quantity in a printed table: one precision for all, rounding noise as 0.

A table column of one quantity (the speeds of every shaft in rpm, the radial forces of every
bearing in kN) is printed with one number of decimals, chosen from the largest magnitude in it
(its scale) so that the scale shows ``SIGNIFICANT`` significant digits within ``WIDTH``
characters; a value that is rounding noise beside that scale (below ``NOISE`` times it: a locked
ring's 4.8e-28 rpm beside a carrier's 1e3 rpm, the 1e-13 kN·m a planet's bearing passes beside
the carrier's 1200 kN·m) is printed as 0. Scales outside ``FIXED`` get the exponent form, with
one mantissa precision for the column.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

#: Characters of a number cell: the printed tables fit 80 columns (``io/report.py``).
WIDTH = 9
#: Significant digits of a column's largest magnitude.
SIGNIFICANT = 6
#: A value below this fraction of its column's largest magnitude is rounding noise, printed 0:
#: float64 sums and solver residuals leave ~1e-16 to 1e-12 of the loads they balance, and
#: a value of 1e-9 of the scale would need 10 significant digits to show anyway.
NOISE = 1e-9
#: Column scales printed in fixed point (below and above: the exponent form) [display unit].
FIXED = (1e-3, 1e8)


def column_scale(values: Sequence[float]) -> float:
    """The largest finite magnitude of a column (0 when it has none)."""
    finite = [abs(v) for v in values if math.isfinite(v)]
    return max(finite, default=0.0)


def decimals(scale: float) -> int | None:
    """Decimals of a fixed-point column of this scale; None: the exponent form.

    ``SIGNIFICANT`` digits of the scale, as many as a sign, the integer digits and the point
    leave of ``WIDTH``.
    """
    if scale == 0.0:
        return 0
    if not FIXED[0] <= scale < FIXED[1]:
        return None
    integer_digits = max(1, math.floor(math.log10(scale)) + 1)
    wanted = (
        SIGNIFICANT - integer_digits
        if scale >= 1.0
        else SIGNIFICANT - 1 - math.floor(math.log10(scale))
    )
    return max(0, min(wanted, WIDTH - 2 - integer_digits))


def column_texts(values: Sequence[float], scale: float | None = None) -> list[str]:
    """The values of one column, with one precision and rounding noise as 0.

    Args:
        values: the column, in its display unit.
        scale: the column's largest magnitude, when the column is wider than ``values`` (the
            same quantity of other elements); default ``column_scale(values)``.
    """
    if scale is None:
        scale = column_scale(values)
    places = decimals(scale)
    out = []
    for value in values:
        if not math.isfinite(value):
            out.append(f"{value}")
            continue
        if abs(value) < NOISE * scale:
            value = 0.0
        if places is None:
            out.append("0" if value == 0.0 else f"{value:.2e}")
            continue
        text = f"{value:.{places}f}"
        if float(text) == 0.0:
            text = text.lstrip("-")  # no "-0.00": a value that rounds to zero has no sign
        out.append(text)
    return out
