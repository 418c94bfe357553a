"""S-N (Wöhler) curve with an endurance limit, and Palmgren-Miner damage of counted cycles.

Jørgensen 2014 (003_83d3049daebcd276.txt) eqs. 2, 3 and 23:

    s(N) = s0 (N / N0)^(−1/m)   ⇔   N(s) = N0 (s0 / s)^m             (eq. 3 / eq. 23, N0 = 1)
    D = Σ n_i / N(s_i) = Σ n_i s_i^m / (N0 s0^m)                      (eq. 2)

with no damage from cycles whose stress lies below the endurance limit σ_e (Fig. 4). It
fits the curve through two points (Table 4: 3·10⁴ cycles at 1400 MPa, 10⁶ at 500 MPa), which
gives s0 = 28.9 GPa and m = 3.4 (eq. 23), and takes σ_e per gear from Table 5. Stresses in Pa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError, InvalidSNCurve
from pinwind.life.cycles import Cycles


@dataclass(frozen=True)
class SNCurve:
    """N(s) = N0 (s0 / s)^m above the endurance limit, no failure below it (Jørgensen 2014 eq. 23).

    Attributes:
        reference_stress: s0, the stress that fails the material in N0 cycles [Pa].
        slope_exponent: m, the negative inverse slope of the curve in a log-log plot [-]
            (3-3.5 for steel, Jørgensen 2014 §1.3).
        reference_cycles: N0, the cycles to failure at s0 [-]; 1 in eq. 23.
        endurance_limit: σ_e, the stress below which cycles do no damage [Pa]; 0 for none.

    Raises:
        InvalidSNCurve: a parameter is not finite, s0, m or N0 is not positive, or σ_e < 0.
    """

    reference_stress: float
    slope_exponent: float
    reference_cycles: float = 1.0
    endurance_limit: float = 0.0

    def __post_init__(self) -> None:
        checks = (
            ("reference stress s0 [Pa]", self.reference_stress, "positive", "e.g. 28.9e9"),
            ("slope exponent m", self.slope_exponent, "positive", "3 to 3.5 for steel"),
            ("reference cycles N0", self.reference_cycles, "positive", "1 when s0 is at N = 1"),
        )
        for name, value, requirement, example in checks:
            if not math.isfinite(value) or value <= 0.0:
                raise InvalidSNCurve(
                    name,
                    value,
                    f"finite and {requirement}",
                    f"give a {requirement} value ({example})",
                )
        if not math.isfinite(self.endurance_limit) or self.endurance_limit < 0.0:
            raise InvalidSNCurve(
                "endurance limit [Pa]",
                self.endurance_limit,
                "finite and zero or positive",
                "give 0 for a curve without an endurance limit",
            )

    @classmethod
    def through_points(
        cls,
        *,
        cycles_1: float,
        stress_1: float,
        cycles_2: float,
        stress_2: float,
        endurance_limit: float = 0.0,
    ) -> SNCurve:
        """The curve through (N1, s1) and (N2, s2), with N0 = 1.

        This is how Jørgensen 2014 gets eq. 23 from the two points of its Table 4:
        m = ln(N2 / N1) / ln(s1 / s2) and s0 = s1 N1^(1/m).

        Raises:
            InvalidSNCurve: the points do not give a falling curve (N2 > N1 with s2 < s1).
        """
        for name, value in (
            ("cycles_1", cycles_1),
            ("stress_1 [Pa]", stress_1),
            ("cycles_2", cycles_2),
            ("stress_2 [Pa]", stress_2),
        ):
            if not math.isfinite(value) or value <= 0.0:
                raise InvalidSNCurve(
                    name, value, "finite and positive", "give a point of the curve"
                )
        if (cycles_2 - cycles_1) * (stress_1 - stress_2) <= 0.0:
            raise InvalidSNCurve(
                "point 2 (cycles, stress)",
                (cycles_2, stress_2),
                f"more cycles at a lower stress than point 1 ({cycles_1:g}, {stress_1:g})",
                "give two points of a falling curve",
            )
        slope = math.log(cycles_2 / cycles_1) / math.log(stress_1 / stress_2)
        return cls(
            reference_stress=stress_1 * cycles_1 ** (1.0 / slope),
            slope_exponent=slope,
            reference_cycles=1.0,
            endurance_limit=endurance_limit,
        )

    def stress(self, cycles: npt.ArrayLike) -> np.ndarray:
        """s(N) = s0 (N / N0)^(−1/m) [Pa] without the endurance limit (Jørgensen 2014 eq. 3)."""
        n = np.asarray(cycles, dtype=float)
        return self.reference_stress * (n / self.reference_cycles) ** (-1.0 / self.slope_exponent)

    def cycles_to_failure(
        self, stress: npt.ArrayLike, *, use_endurance_limit: bool = True
    ) -> np.ndarray:
        """N(s) = N0 (s0 / s)^m [-]; infinite below the endurance limit and for s ≤ 0.

        Args:
            stress: cycle stress [Pa].
            use_endurance_limit: False to extend the sloped line below σ_e.
        """
        s = np.asarray(stress, dtype=float)
        floor = self.endurance_limit if use_endurance_limit else 0.0
        damaging = (s > 0.0) & (s >= floor)
        with np.errstate(divide="ignore"):
            n = self.reference_cycles * (self.reference_stress / np.where(damaging, s, 1.0)) ** (
                self.slope_exponent
            )
        return np.where(damaging, n, np.inf)


def miner_damage(
    cycles: Cycles,
    curve: SNCurve,
    *,
    stress: Literal["range", "amplitude"] = "range",
    use_endurance_limit: bool = True,
) -> float:
    """Palmgren-Miner damage D = Σ n_i / N(s_i) of counted cycles (Jørgensen 2014 eq. 2) [-].

    Failure is expected at D ≥ 1. Cycles below the curve's endurance limit add nothing unless
    ``use_endurance_limit`` is False.

    Args:
        cycles: rainflow cycles of a stress history [Pa], counts already multiplied by any time
            factor (`Cycles.scaled`).
        curve: the S-N curve.
        stress: which stress of a cycle the curve is read at: its range (peak − valley, as Jørgensen
            2014 Fig. 14 counts them) or its amplitude (half the range).
        use_endurance_limit: False to count every cycle on the sloped line (the no-limit case of
            issue 23).

    Raises:
        InputError: ``stress`` is neither "range" nor "amplitude".
    """
    if stress == "range":
        levels = cycles.ranges
    elif stress == "amplitude":
        levels = cycles.amplitudes
    else:
        raise InputError(f'the cycle stress must be "range" or "amplitude", got {stress!r}')
    life = curve.cycles_to_failure(levels, use_endurance_limit=use_endurance_limit)
    return float(np.sum(cycles.counts / life))


#: Jørgensen 2014 Table 5: endurance limits of the contact (von Mises) stress per gear [Pa].
_JORGENSEN_2014_ENDURANCE = {"sun": 800e6, "planet": 800e6, "ring": 550e6}


def jorgensen_2014_curve(gear: str, *, location: str = "contact") -> SNCurve:
    """Jørgensen 2014's S-N curve of a sun, planet or ring tooth (eq. 23 and Table 5).

    s0 = 28.9 GPa, m = 3.4 (eq. 23) and σ_e from Table 5: sun 800, planet 800, ring 550 MPa.
    Jørgensen 2014 gives one curve and applies it to both the contact (von Mises, §4.2) and the root
    (§4.1, "clearly below the endurance limit") stress, so ``location`` "contact" and "root"
    return the same curve; it is kept so that callers name the stress they rate.

    Raises:
        InputError: an unknown gear or location.
    """
    if location not in ("contact", "root"):
        raise InputError(f'unknown stress location "{location}"; locations are: contact, root')
    if gear not in _JORGENSEN_2014_ENDURANCE:
        raise InputError(
            f'Jørgensen 2014 gives no S-N curve for a "{gear}" gear; gears are: '
            f"{', '.join(_JORGENSEN_2014_ENDURANCE)}"
        )
    return SNCurve(
        reference_stress=28.9e9,
        slope_exponent=3.4,
        reference_cycles=1.0,
        endurance_limit=_JORGENSEN_2014_ENDURANCE[gear],
    )
