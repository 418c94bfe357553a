"""S-N (Wöhler) curve with an endurance limit, and Palmgren-Miner damage of counted cycles.

Jørgensen 2014 eqs. 2, 3 and 23:

    s(N) = s0 (N / N0)^(−1/m)   ⇔   N(s) = N0 (s0 / s)^m             (eq. 3 / eq. 23, N0 = 1)
    D = Σ n_i / N(s_i) = Σ n_i s_i^m / (N0 s0^m)                      (eq. 2)

with no damage from cycles whose stress lies below the endurance limit σ_e (Fig. 4). It
fits the curve through two points (Table 4: 3·10⁴ cycles at 1400 MPa, 10⁶ at 500 MPa), which
gives s0 = 28.9 GPa and m = 3.4 (eq. 23), and takes σ_e per gear from Table 5. Stresses in Pa.

ISO 6336's own curves are the permissible stress times its life factor, σ_Hlim Z_NT(N)
(ISO 6336-2, contact) and σ_Flim Y_ST Y_NT(N) (ISO 6336-3, root): straight lines in a log-log
plot between the knee points of the standard's tables (`IsoLifeCurve`, `iso6336_contact_curve`,
`iso6336_root_curve`).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError, InvalidSNCurve
from pinwind.gears.materials import Material, material
from pinwind.gears.rating_iso import IsoFactors
from pinwind.life.cycles import Cycles


class FatigueCurve(ABC):
    """An S-N curve: the cycles N(s) a stress s [Pa] fails the material in, and back.

    Each curve has an endurance limit below which cycles do no damage, and a line that
    continues below it for the no-limit case (``use_endurance_limit=False``).
    """

    @abstractmethod
    def stress(self, cycles: npt.ArrayLike) -> np.ndarray:
        """s(N) [Pa] on the curve without its endurance limit."""

    @abstractmethod
    def cycles_to_failure(
        self, stress: npt.ArrayLike, *, use_endurance_limit: bool = True
    ) -> np.ndarray:
        """N(s) [-]; infinite below the endurance limit (unless told not to) and for s ≤ 0."""

    @abstractmethod
    def scaled(self, factor: float) -> FatigueCurve:
        """The same curve for a stress ``factor`` times this one's: s'(N) = factor · s(N).

        E.g. a curve of the Hertz pressure read at σ_vM = 0.65 p_max: ``curve.scaled(0.65)``.
        """


@dataclass(frozen=True)
class SNCurve(FatigueCurve):
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

    def scaled(self, factor: float) -> SNCurve:
        """s0 and σ_e times ``factor`` (`FatigueCurve.scaled`)."""
        return replace(
            self,
            reference_stress=self.reference_stress * factor,
            endurance_limit=self.endurance_limit * factor,
        )


@dataclass(frozen=True)
class IsoLifeCurve(FatigueCurve):
    """s(N) = strength · f(N), f the life factor of ISO 6336 (Z_NT or Y_NT) between knee points.

    f is constant up to the first knee (the static value: the standard gives no more below it),
    a straight line in log f - log N between knees, through 1 at the endurance knee N_L, and
    beyond the last knee the last line continued. Above the static stress the first line is
    continued too (N below the first knee): the standard rates such a stress as a static
    overload, not a number of cycles, and the steeper line is the conservative choice.

    Its endurance limit is the strength: with it, f = 1 from N_L on (ISO 6336's line "with
    optimum lubrication, material, manufacturing and experience"); without it, the standard's
    falling line beyond N_L (0.85 at 10¹⁰ cycles) rates every cycle.

    Attributes:
        strength: the stress where f = 1 [Pa]: σ_Hlim (contact), σ_FE = σ_Flim Y_ST (root).
        knees: (N, f) of the standard's table row, N rising and f falling; one f is 1.
        name: the table row, for messages.

    Raises:
        InvalidSNCurve: a non-positive strength or cycle count, knees that do not fall, or no
            knee at f = 1.
    """

    strength: float
    knees: tuple[tuple[float, float], ...]
    name: str = ""

    def __post_init__(self) -> None:
        if not math.isfinite(self.strength) or self.strength <= 0.0:
            raise InvalidSNCurve(
                "strength [Pa]", self.strength, "finite and positive", "give σ_Hlim or σ_FE"
            )
        cycles = [n for n, _ in self.knees]
        factors = [f for _, f in self.knees]
        if (
            len(self.knees) < 2
            or not all(math.isfinite(v) and v > 0.0 for v in cycles + factors)
            or any(b <= a for a, b in zip(cycles[:-1], cycles[1:], strict=True))
            or any(b >= a for a, b in zip(factors[:-1], factors[1:], strict=True))
            or 1.0 not in factors
        ):
            raise InvalidSNCurve(
                "knees (N, factor)",
                self.knees,
                "two or more points, N rising, the factor falling through 1",
                "give the rows of ISO 6336-2 Table 2 or ISO 6336-3 Table 3",
            )

    @property
    def endurance_limit(self) -> float:
        """σ at the endurance knee N_L, where the life factor is 1 [Pa]."""
        return self.strength

    @property
    def endurance_cycles(self) -> float:
        """N_L, the cycles where the life factor reaches 1 [-]."""
        return next(n for n, f in self.knees if f == 1.0)

    def _log_points(self) -> tuple[np.ndarray, np.ndarray]:
        """(ln N, ln s) of the knees."""
        n, f = np.array(self.knees).T
        return np.log(n), np.log(self.strength * f)

    def stress(self, cycles: npt.ArrayLike) -> np.ndarray:
        """s(N) = strength · f(N) [Pa], f constant below the first knee (the static value)."""
        log_n, log_s = self._log_points()
        x = np.log(np.maximum(np.asarray(cycles, dtype=float), np.exp(log_n[0])))
        slope = (log_s[-1] - log_s[-2]) / (log_n[-1] - log_n[-2])
        inside = np.interp(x, log_n, log_s)
        return np.exp(np.where(x > log_n[-1], log_s[-1] + slope * (x - log_n[-1]), inside))

    def cycles_to_failure(
        self, stress: npt.ArrayLike, *, use_endurance_limit: bool = True
    ) -> np.ndarray:
        """N(s) [-] on the lines between the knees, continued at both ends (class docstring).

        Args:
            stress: cycle stress [Pa].
            use_endurance_limit: False to rate stresses below the strength on the falling
                line beyond N_L (the standard's 0.85 at 10¹⁰) instead of not at all.
        """
        s = np.asarray(stress, dtype=float)
        floor = self.strength if use_endurance_limit else 0.0
        damaging = (s > 0.0) & (s >= floor)
        log_n, log_s = self._log_points()
        x = np.log(np.where(damaging, s, self.strength))
        # ln s falls with ln N: interpolate on the reversed (rising) knees.
        inside = np.interp(x, log_s[::-1], log_n[::-1])
        first = (log_n[1] - log_n[0]) / (log_s[1] - log_s[0])
        last = (log_n[-1] - log_n[-2]) / (log_s[-1] - log_s[-2])
        log_life = np.where(
            x > log_s[0],
            log_n[0] + first * (x - log_s[0]),
            np.where(x < log_s[-1], log_n[-1] + last * (x - log_s[-1]), inside),
        )
        with np.errstate(over="ignore"):  # far below the strength N overflows to ∞: no damage
            return np.where(damaging, np.exp(log_life), np.inf)

    def scaled(self, factor: float) -> IsoLifeCurve:
        """The strength times ``factor`` (`FatigueCurve.scaled`)."""
        return replace(self, strength=self.strength * factor)


#: ISO 6336-2:2006 Table 2, life factor Z_NT for contact stress: material group → (N_L, Z_NT)
#: at its knees (the static value, the endurance knee at 1, and 0.85 at 10¹⁰). Material codes
#: of the standard: St structural steel, V through-hardened, GGG nodular and GTS black
#: malleable cast iron, Eh case-hardened, IF flame or induction hardened, GG grey cast iron,
#: NT nitrided, NV nitrocarburised.
ISO_6336_2_Z_NT: dict[str, tuple[tuple[float, float], ...]] = {
    "St, V, GGG (perl., bai.), GTS (perl.), Eh, IF; some pitting permitted": (
        (6e5, 1.6),
        (1e7, 1.3),
        (1e9, 1.0),
        (1e10, 0.85),
    ),
    "St, V, GGG (perl., bai.), GTS (perl.), Eh, IF": ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85)),
    "GG, GGG (ferr.), NT (nitr.), NV (nitr.)": ((1e5, 1.3), (2e6, 1.0), (1e10, 0.85)),
    "NV (nitrocar.)": ((1e5, 1.1), (2e6, 1.0), (1e10, 0.85)),
}
#: ISO 6336-3:2006 Table 3, life factor Y_NT for tooth-root stress, in the same form.
ISO_6336_3_Y_NT: dict[str, tuple[tuple[float, float], ...]] = {
    "St, V, GGG (perl., bai.), GTS (perl.)": ((1e4, 2.5), (3e6, 1.0), (1e10, 0.85)),
    "Eh, IF (root)": ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85)),
    "GG, GGG (ferr.), NT (nitr.), NV (nitr.)": ((1e3, 1.6), (3e6, 1.0), (1e10, 0.85)),
    "NV (nitrocar.)": ((1e3, 1.1), (3e6, 1.0), (1e10, 0.85)),
}
#: The table rows of a `Material.treatment`: (contact, root).
_ISO_6336_GROUPS = {
    "case_carburised": ("St, V, GGG (perl., bai.), GTS (perl.), Eh, IF", "Eh, IF (root)"),
    "through_hardened": (
        "St, V, GGG (perl., bai.), GTS (perl.), Eh, IF",
        "St, V, GGG (perl., bai.), GTS (perl.)",
    ),
    "nitrided": ("GG, GGG (ferr.), NT (nitr.), NV (nitr.)",) * 2,
    "nitrocarburised": ("NV (nitrocar.)",) * 2,
}
#: σ_FE of a gear loaded on both flanks (an idler, as a planet) over one loaded on one:
#: ISO 6336-5 §5.3.3, reversed bending.
REVERSED_BENDING_FACTOR = 0.7


def _groups(gear_material: Material) -> tuple[str, str]:
    """The ISO 6336-2 and -3 table rows of a material, by its treatment."""
    try:
        return _ISO_6336_GROUPS[gear_material.treatment]
    except KeyError as err:
        raise InputError(
            f'material "{gear_material.name}" has treatment "{gear_material.treatment}", which '
            f"no ISO 6336 life-factor row names; treatments are: {', '.join(_ISO_6336_GROUPS)}"
        ) from err


def iso6336_contact_curve(
    gear_material: Material | str,
    *,
    pitting_permitted: bool = False,
    sigma_H_lim: float | None = None,
) -> IsoLifeCurve:
    """σ_Hlim Z_NT(N): ISO 6336-2's S-N curve of the Hertz contact stress σ_H [Pa].

    Z_L, Z_v, Z_R, Z_W and Z_X are 1 (reference conditions). The curve is of σ_H (the Hertz
    pressure p_max); read at σ_vM = 0.65 p_max it is ``scaled(VON_MISES_RATIO)``.

    Args:
        gear_material: the gear's material (`pinwind.gears.materials`): its treatment picks the
            row of ISO 6336-2 Table 2, its σ_Hlim the strength.
        pitting_permitted: the row for "some pitting permitted" (St, V, GGG, GTS, Eh, IF only).
        sigma_H_lim: σ_Hlim [Pa] instead of the material's.

    Raises:
        InputError: ``pitting_permitted`` for a nitrided material (the standard has no such
            row), or a treatment without a row.
    """
    chosen = material(gear_material)
    row = _groups(chosen)[0]
    if pitting_permitted:
        row += "; some pitting permitted"
        if row not in ISO_6336_2_Z_NT:
            raise InputError(
                f'ISO 6336-2 has no "some pitting permitted" row for {chosen.treatment} steel '
                f'("{chosen.name}"); it has one for St, V, GGG, GTS, Eh and IF'
            )
    strength = chosen.sigma_H_lim if sigma_H_lim is None else sigma_H_lim
    return IsoLifeCurve(strength, ISO_6336_2_Z_NT[row], f"ISO 6336-2 Z_NT: {row}")


def iso6336_root_curve(
    gear_material: Material | str,
    *,
    reversed_bending: bool = False,
    sigma_F_lim: float | None = None,
) -> IsoLifeCurve:
    """σ_Flim Y_ST Y_NT(N): ISO 6336-3's S-N curve of the tooth-root stress σ_F [Pa].

    Y_ST = 2 (the reference test gear's stress correction factor); Y_δrelT, Y_RrelT and Y_X
    are 1. The strength is for a root loaded on one side (pulsating, as the cycles of one
    fillet's history are); ``reversed_bending`` takes 0.7 of it for a gear loaded on both
    flanks, an idler such as a planet (ISO 6336-5 §5.3.3).

    Args:
        gear_material: the gear's material: its treatment picks the row of ISO 6336-3
            Table 3, its σ_Flim the strength.
        reversed_bending: the gear's teeth are loaded on both flanks in turn.
        sigma_F_lim: σ_Flim [Pa] instead of the material's.
    """
    chosen = material(gear_material)
    row = _groups(chosen)[1]
    limit = chosen.sigma_F_lim if sigma_F_lim is None else sigma_F_lim
    strength = limit * IsoFactors().Y_ST * (REVERSED_BENDING_FACTOR if reversed_bending else 1.0)
    return IsoLifeCurve(strength, ISO_6336_3_Y_NT[row], f"ISO 6336-3 Y_NT: {row}")


def miner_damage(
    cycles: Cycles,
    curve: FatigueCurve,
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
