"""Lubricant and cleanliness for ISO 281:2007's modified rating life, SI units.

**Viscosity.** The oil's grade and its viscosity at the operating temperature (ISO 3448 grades,
Walther's line, ASTM D341) are ``losses/oil.py``'s ``Lubricant``, re-exported here: ISO 281's
κ and the losses read the one implementation.

**Cleanliness.** ISO 281:2007 Table 13 gives the contamination factor e_C by cleanliness class
and mean diameter d_m (below or from 100 mm) as ranges; pinwind takes each range's mid-point
(`CONTAMINATION_CLASSES`), or a value given outright.
"""

from __future__ import annotations

from pinwind.losses.oil import DEFAULT_WALTHER_SLOPE, VG_GRADES, Lubricant
from pinwind.model.bearing_life_data import (
    CONTAMINATION_CLASSES,
    CONTAMINATION_RANGES,
    DEFAULT_CONTAMINATION,
    DEFAULT_TEMPERATURE,
    DEFAULT_VG,
)

__all__ = [
    "CONTAMINATION_CLASSES",
    "DEFAULT_CONTAMINATION",
    "DEFAULT_TEMPERATURE",
    "DEFAULT_VG",
    "DEFAULT_WALTHER_SLOPE",
    "VG_GRADES",
    "Lubricant",
    "contamination_factor",
]


def contamination_factor(level: str, mean_diameter: float) -> float:
    """e_C [-] of an ISO 281:2007 Table 13 cleanliness class: its range's mid-point.

    Args:
        level: a key of ``CONTAMINATION_RANGES``.
        mean_diameter: bearing mean diameter d_m = (D + d)/2 [m].
    """
    small, large = CONTAMINATION_RANGES[level]
    lo, hi = small if mean_diameter < 0.1 else large
    return 0.5 * (lo + hi)
