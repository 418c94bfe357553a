"""Gear oil: its ISO 3448 grade, kinematic viscosity at temperature (Walther), density, SI units.

**Viscosity grades.** ISO 3448:1992 names industrial oils by their kinematic viscosity at 40 °C
(the grade's mid-point, ±10 %): VG 2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460,
680, 1000, 1500, 2200, 3200 with mid-points 2.2, 3.2, 4.6, 6.8 mm²/s for the four lowest and the
grade's number for the others (``VG_GRADES``).

**Viscosity at the operating temperature.** Ubbelohde-Walther's equation (ASTM D341-09 eq. 1)

    log10 log10(ν + 0.7) = A − B log10 T,          ν in mm²/s, T in K,

through two points: ν40 (the grade's mid-point) at 313.15 K and ν100 at 373.15 K. ν100 is the
oil's own (``viscosity_100C_cSt`` in a model file) or, when not given, the line has the assumed
slope ``DEFAULT_WALTHER_SLOPE`` B = 3.5, typical of mineral gear oils of viscosity index ≈ 95
(an assumption pinwind states wherever it is used: ``Lubricant.slope_assumed``). This is the one
viscosity of pinwind: ISO 281's κ (``life/lubrication.py``) and the losses (``losses/``) read it.

**Density and dynamic viscosity.** ISO/TR 14179-2:2001's mesh friction takes the dynamic
viscosity η = ν ρ at the oil temperature. The density falls linearly with temperature from its
value at 15 °C (DIN 51757:2011's linear approximation for mineral oils)

    ρ(θ) = ρ15 (1 − 0.00065 (θ − 15 °C)),

ρ15 = 880 kg/m³ unless given (a typical mineral gear oil of VG 220-320; the oil's data sheet
gives its own).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: ISO 3448 viscosity grades → mid-point kinematic viscosity at 40 °C [mm²/s].
VG_GRADES: dict[int, float] = {
    2: 2.2, 3: 3.2, 5: 4.6, 7: 6.8, 10: 10.0, 15: 15.0, 22: 22.0, 32: 32.0, 46: 46.0,
    68: 68.0, 100: 100.0, 150: 150.0, 220: 220.0, 320: 320.0, 460: 460.0, 680: 680.0,
    1000: 1000.0, 1500: 1500.0, 2200: 2200.0, 3200: 3200.0,
}  # fmt: skip

#: Walther slope B [-] assumed when the oil's ν100 is not given (``Lubricant``,
#: ``life/lubrication.py``).
DEFAULT_WALTHER_SLOPE = 3.5

__all__ = [
    "DEFAULT_DENSITY_15",
    "DENSITY_EXPANSION",
    "Lubricant",
]

_T40 = 313.15
_T100 = 373.15
_T15 = 288.15

#: Density of a mineral gear oil at 15 °C [kg/m³] when the model gives none (module docstring).
DEFAULT_DENSITY_15 = 880.0
#: Relative fall of the density per kelvin [1/K] (DIN 51757 linear approximation).
DENSITY_EXPANSION = 0.00065


def _walther(nu_mm2s: float) -> float:
    return math.log10(math.log10(nu_mm2s + 0.7))


@dataclass(frozen=True)
class Lubricant:
    """An oil by its ISO 3448 grade (and ν100), at an operating temperature.

    Attributes:
        grade: ISO VG grade (a key of ``VG_GRADES``).
        temperature: operating temperature of the bearing [K].
        viscosity_100: kinematic viscosity at 100 °C [m²/s], or None: Walther slope assumed.
        density_15: density at 15 °C [kg/m³].
    """

    grade: int
    temperature: float
    viscosity_100: float | None = None
    density_15: float = DEFAULT_DENSITY_15

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

    def density(self, temperature: float | None = None) -> float:
        """Density ρ [kg/m³] at ``temperature`` [K] (default: the operating one; DIN 51757)."""
        t = self.temperature if temperature is None else temperature
        return self.density_15 * (1.0 - DENSITY_EXPANSION * (t - _T15))

    def dynamic_viscosity(self, temperature: float | None = None) -> float:
        """Dynamic viscosity η = ν ρ [Pa·s] at ``temperature`` [K] (default: the operating one)."""
        return self.viscosity(temperature) * self.density(temperature)
