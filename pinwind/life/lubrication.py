"""Lubricant viscosity and cleanliness for ISO 281:2007's modified rating life, SI units.

**Viscosity grades.** ISO 3448:1992 names industrial oils by their kinematic viscosity at 40 °C
(the grade's mid-point, ±10 %): VG 2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460,
680, 1000, 1500, 2200, 3200 with mid-points 2.2, 3.2, 4.6, 6.8 mm²/s for the four lowest and the
grade's number for the others (`VG_GRADES`).

**Viscosity at the operating temperature.** ISO 281 reads the operating viscosity ν off a
viscosity-temperature chart of mineral oils with viscosity index 95 (ISO 281:2007 Figure 14). The
chart's straight lines are those of Ubbelohde-Walther's equation (ASTM D341-09 eq. 1)

    log10 log10(ν + 0.7) = A − B log10 T,          ν in mm²/s, T in K,

through two points: ν40 (the grade's mid-point) at 313.15 K and ν100 at 373.15 K. ν100 is the
oil's own (``viscosity_100C_cSt`` in a model file) or, when not given, the line has the assumed
slope ``DEFAULT_WALTHER_SLOPE`` B = 3.5, typical of mineral gear oils of viscosity index ≈ 95
(an assumption pinwind states wherever it is used: ``Lubricant.slope_assumed``). The operating
viscosity may be given outright instead (``viscosity_cSt``).

**Cleanliness.** ISO 281:2007 Table 13 gives the contamination factor e_C by cleanliness class
and mean diameter d_m (below or from 100 mm) as ranges; pinwind takes each range's mid-point
(`CONTAMINATION_CLASSES`), or a value given outright.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pinwind.model.bearing_life_data import (
    CONTAMINATION_CLASSES,
    CONTAMINATION_RANGES,
    DEFAULT_CONTAMINATION,
    DEFAULT_TEMPERATURE,
    DEFAULT_VG,
    DEFAULT_WALTHER_SLOPE,
    VG_GRADES,
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

_T40 = 313.15
_T100 = 373.15


def contamination_factor(level: str, mean_diameter: float) -> float:
    """e_C [-] of an ISO 281:2007 Table 13 cleanliness class: its range's mid-point.

    Args:
        level: a key of ``CONTAMINATION_RANGES``.
        mean_diameter: bearing mean diameter d_m = (D + d)/2 [m].
    """
    small, large = CONTAMINATION_RANGES[level]
    lo, hi = small if mean_diameter < 0.1 else large
    return 0.5 * (lo + hi)


def _walther(nu_mm2s: float) -> float:
    return math.log10(math.log10(nu_mm2s + 0.7))


@dataclass(frozen=True)
class Lubricant:
    """An oil by its ISO 3448 grade (and ν100), at an operating temperature.

    Attributes:
        grade: ISO VG grade (a key of ``VG_GRADES``).
        temperature: operating temperature of the bearing [K].
        viscosity_100: kinematic viscosity at 100 °C [m²/s], or None: Walther slope assumed.
    """

    grade: int
    temperature: float
    viscosity_100: float | None = None

    @property
    def viscosity_40(self) -> float:
        """ν40 [m²/s]: the grade's mid-point."""
        return VG_GRADES[self.grade] * 1e-6

    @property
    def slope_assumed(self) -> bool:
        """The Walther slope is ``DEFAULT_WALTHER_SLOPE``, not from the oil's ν100."""
        return self.viscosity_100 is None

    @property
    def walther_slope(self) -> float:
        """B of Walther's line [-] (module docstring)."""
        if self.viscosity_100 is None:
            return DEFAULT_WALTHER_SLOPE
        drop = _walther(self.viscosity_40 * 1e6) - _walther(self.viscosity_100 * 1e6)
        return drop / math.log10(_T100 / _T40)

    def viscosity(self, temperature: float | None = None) -> float:
        """Kinematic viscosity ν [m²/s] at ``temperature`` [K] (default: the operating one).

        Walther's equation through ν40 with slope B (ASTM D341-09 eq. 1).
        """
        t = self.temperature if temperature is None else temperature
        w = _walther(self.viscosity_40 * 1e6) - self.walther_slope * math.log10(t / _T40)
        return (10.0 ** (10.0**w) - 0.7) * 1e-6
