"""A site's wind as mean-speed bins with operating hours, and the time factors of a fatigue run.

Jørgensen 2014 §1.1 and §3.1. The hours a turbine runs in each bin
over its design life T follow from the Weibull distribution of the mean wind speed (eq. 1):

    F(v) = 1 − exp(−(v / A)^k),    h = T · a · [F(v_hi) − F(v_lo)]

(A the scale [m/s], k the shape, a the availability; the bin clipped to [cut-in, cut-out]).
Table 1 is this with A = 6.62 m/s, k = 2.19, T = 20 · 365 · 24 h, a = 1 and bins 2 m/s wide
centred on 6, 8, ..., 20 m/s. A simulated history of T_sim seconds then stands for the bin's
h · 3600 s (Table 2), and one tooth sees a share of it set by its gear's teeth and meshes
(Table 3, `ToothExposure`). Speeds in m/s, hours in h, times in s.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError, InvalidWindSite

#: Hours in a year as Jørgensen 2014 §1.1 counts them (20 years ≈ 20 · 365 · 24 = 175200 h).
HOURS_PER_YEAR = 365.0 * 24.0

#: IEC 61400-1 ed. 3 §6.2 reference turbulence intensity I_ref (expected at 15 m/s) per class;
#: A+ is edition 4's class for very high turbulence.
TURBULENCE_CLASSES = {"A+": 0.18, "A": 0.16, "B": 0.14, "C": 0.12}


@dataclass(frozen=True)
class WindBin:
    """One bin of mean wind speed at hub height.

    Attributes:
        speed: the bin's mean wind speed, the one its load case is simulated at [m/s].
        low, high: the bin's edges [m/s].
        hours: operating hours in the bin over the design life [h].
        turbulence: turbulence intensity σ_u / U of the bin's load case [-], None if not given.
    """

    speed: float
    low: float
    high: float
    hours: float
    turbulence: float | None = None


@dataclass(frozen=True)
class WindSite:
    """A site's wind as bins with operating hours (Jørgensen 2014 Table 1).

    Attributes:
        bins: the bins, by increasing speed.
    """

    bins: tuple[WindBin, ...]

    @property
    def speeds(self) -> np.ndarray:
        """Mean wind speed of each bin [m/s], (n,)."""
        return np.array([b.speed for b in self.bins])

    @property
    def hours(self) -> np.ndarray:
        """Operating hours of each bin over the design life [h], (n,)."""
        return np.array([b.hours for b in self.bins])

    @property
    def total_hours(self) -> float:
        """Operating hours over the design life, all bins [h]."""
        return float(np.sum(self.hours))

    def time_factors(self, *, simulated_seconds: float) -> np.ndarray:
        """`time_factor` of each bin for a simulated history of this length [-], (n,)."""
        return time_factor(hours=self.hours, simulated_seconds=simulated_seconds)


def weibull_cdf(speed: npt.ArrayLike, *, scale: float, shape: float) -> np.ndarray:
    """F(v) = 1 − exp(−(v / A)^k), the probability of a mean wind speed below v [-].

    Jørgensen 2014 eq. 1 with P(v ≥ 0) = 1.

    Args:
        speed: wind speed v [m/s].
        scale: A [m/s].
        shape: k [-].

    Raises:
        InvalidWindSite: A or k is not finite and positive.
    """
    _require_weibull(scale, shape)
    v = np.clip(np.asarray(speed, dtype=float), 0.0, None)
    return 1.0 - np.exp(-((v / scale) ** shape))


def weibull_site(
    *,
    scale: float,
    shape: float,
    edges: npt.ArrayLike,
    design_life_years: float = 20.0,
    availability: float = 1.0,
    cut_in: float | None = None,
    cut_out: float | None = None,
    turbulence: float | Sequence[float] | str | None = None,
) -> WindSite:
    """Bins with hours h = T · a · [F(v_hi) − F(v_lo)] from a Weibull distribution.

    Each bin's speed is the middle of its edges; the part of a bin below cut-in or above
    cut-out has no operating hours.

    Args:
        scale: Weibull scale A [m/s] (Jørgensen 2014: 6.62).
        shape: Weibull shape k [-] (Jørgensen 2014: 2.19).
        edges: increasing bin edges [m/s], (n + 1,) (Jørgensen 2014: 5, 7, ..., 21).
        design_life_years: T / `HOURS_PER_YEAR` [years].
        availability: a, the fraction of the time in the operating range that the turbine runs.
        cut_in: start of the operating range [m/s]; the first edge if None.
        cut_out: end of the operating range [m/s]; the last edge if None.
        turbulence: see `bin_turbulence`.

    Raises:
        InvalidWindSite: A, k or the design life not positive, edges not increasing,
            availability outside (0, 1], cut-in not below cut-out, or a bad turbulence.
    """
    _require_weibull(scale, shape)
    bounds = np.asarray(edges, dtype=float)
    if bounds.ndim != 1 or bounds.size < 2 or not np.all(np.isfinite(bounds)):
        raise InvalidWindSite(
            "bin edges [m/s]", bounds.tolist(), "at least two finite speeds", "e.g. 5, 7, ..., 21"
        )
    if bounds[0] < 0.0 or np.any(np.diff(bounds) <= 0.0):
        raise InvalidWindSite(
            "bin edges [m/s]",
            bounds.tolist(),
            "increasing and not negative",
            "sort the edges and remove repeated ones",
        )
    if not math.isfinite(design_life_years) or design_life_years <= 0.0:
        raise InvalidWindSite(
            "design life [years]", design_life_years, "finite and positive", "e.g. 20"
        )
    if not math.isfinite(availability) or not 0.0 < availability <= 1.0:
        raise InvalidWindSite(
            "availability", availability, "in (0, 1]", "give the running fraction, e.g. 0.97"
        )
    low = float(bounds[0]) if cut_in is None else cut_in
    high = float(bounds[-1]) if cut_out is None else cut_out
    if not (math.isfinite(low) and math.isfinite(high)) or low >= high:
        raise InvalidWindSite(
            "cut-in, cut-out [m/s]",
            (low, high),
            "finite with cut-in below cut-out",
            "e.g. cut_in=4, cut_out=25",
        )
    clipped = np.clip(bounds, low, high)
    probability = np.diff(weibull_cdf(clipped, scale=scale, shape=shape))
    hours = design_life_years * HOURS_PER_YEAR * availability * probability
    speeds = 0.5 * (bounds[:-1] + bounds[1:])
    return _site(speeds, bounds, hours, turbulence)


def site_from_hours(
    *,
    speeds: npt.ArrayLike,
    hours: Sequence[float | None] | np.ndarray,
    turbulence: float | Sequence[float] | str | None = None,
) -> WindSite:
    """Bins with given hours (a measured table, or Jørgensen 2014 Table 1 as printed).

    The edges are half-way between neighbouring speeds; the outer ones lie half a spacing out
    (a single bin has both edges at its speed).

    Args:
        speeds: increasing mean wind speed of each bin [m/s], (n,).
        hours: operating hours of each bin over the design life [h], (n,).
        turbulence: see `bin_turbulence`.

    Raises:
        InvalidWindSite: a bin without hours (None or NaN), negative hours, speeds not
            increasing, lengths that differ, or a bad turbulence.
    """
    centres = np.asarray(speeds, dtype=float)
    if centres.ndim != 1 or centres.size < 1 or not np.all(np.isfinite(centres)):
        raise InvalidWindSite(
            "bin speeds [m/s]", centres.tolist(), "one finite speed per bin", "e.g. 6, 8, ..., 20"
        )
    if np.any(np.diff(centres) <= 0.0) or centres[0] < 0.0:
        raise InvalidWindSite(
            "bin speeds [m/s]", centres.tolist(), "increasing and not negative", "sort the bins"
        )
    if len(hours) != centres.size:
        raise InvalidWindSite(
            "hours per bin",
            list(hours),
            f"one value per bin ({centres.size} bins)",
            "give the hours of every bin",
        )
    values = np.empty(centres.size)
    for i, (speed, value) in enumerate(zip(centres, hours, strict=True)):
        if value is None or not math.isfinite(value):
            raise InvalidWindSite(
                f"the hours of the {speed:g} m/s bin",
                value,
                "a finite number",
                "give the operating hours of every bin (0 for a bin the turbine does not run in)",
            )
        if value < 0.0:
            raise InvalidWindSite(
                f"the hours of the {speed:g} m/s bin", value, "zero or positive", "fix its sign"
            )
        values[i] = value
    if centres.size == 1:
        bounds = np.array([centres[0], centres[0]])
    else:
        middle = 0.5 * (centres[:-1] + centres[1:])
        first = centres[0] - (middle[0] - centres[0])
        last = centres[-1] + (centres[-1] - middle[-1])
        bounds = np.concatenate([[max(first, 0.0)], middle, [last]])
    return _site(centres, bounds, values, turbulence)


def ntm_turbulence(speed: npt.ArrayLike, *, turbulence_class: str) -> np.ndarray:
    """Turbulence intensity of IEC 61400-1's normal turbulence model at hub-height speed V [-].

    σ1 = I_ref (0.75 V + 5.6 m/s) (IEC 61400-1 ed. 3 §6.3.1.3), intensity σ1 / V.

    Args:
        speed: mean wind speed V [m/s], positive.
        turbulence_class: "A+", "A", "B" or "C" (`TURBULENCE_CLASSES`).

    Raises:
        InvalidWindSite: an unknown class or a speed that is not positive.
    """
    if turbulence_class not in TURBULENCE_CLASSES:
        raise InvalidWindSite(
            "turbulence class",
            turbulence_class,
            f"one of {', '.join(TURBULENCE_CLASSES)}",
            "give the IEC 61400-1 class of the site",
        )
    v = np.asarray(speed, dtype=float)
    if not np.all(np.isfinite(v)) or np.any(v <= 0.0):
        raise InvalidWindSite(
            "wind speed for the NTM [m/s]", v.tolist(), "finite and positive", "drop the 0 bin"
        )
    return TURBULENCE_CLASSES[turbulence_class] * (0.75 * v + 5.6) / v


def bin_turbulence(
    speeds: npt.ArrayLike, turbulence: float | Sequence[float] | str | None
) -> list[float | None]:
    """Turbulence intensity of each bin [-].

    Args:
        speeds: the bins' mean wind speeds [m/s], (n,).
        turbulence: None (not given), one intensity for every bin, one per bin, or an IEC
            61400-1 class ("A+", "A", "B", "C") for the normal turbulence model
            (`ntm_turbulence`).

    Raises:
        InvalidWindSite: an intensity not finite and positive, a count that is not one per bin,
            or an unknown class.
    """
    centres = np.asarray(speeds, dtype=float)
    if turbulence is None:
        return [None] * centres.size
    if isinstance(turbulence, str):
        return [float(t) for t in ntm_turbulence(centres, turbulence_class=turbulence)]
    if np.ndim(turbulence) and np.size(turbulence) != centres.size:
        raise InvalidWindSite(
            "turbulence intensity per bin",
            list(np.ravel(turbulence)),
            f"one value, or one per bin ({centres.size})",
            "give one intensity per bin",
        )
    values = np.broadcast_to(np.asarray(turbulence, dtype=float), centres.shape)
    for speed, value in zip(centres, values, strict=True):
        if not math.isfinite(value) or value <= 0.0:
            raise InvalidWindSite(
                f"the turbulence intensity of the {speed:g} m/s bin",
                float(value),
                "finite and positive",
                "give σ_u / U as a fraction, e.g. 0.10 for 10 %",
            )
    return [float(v) for v in values]


def time_factor(*, hours: npt.ArrayLike, simulated_seconds: float) -> np.ndarray:
    """Life seconds per simulated second, h · 3600 / T_sim (Jørgensen 2014 Table 2) [-].

    Multiplying the cycles counted in a history of T_sim seconds by it gives the cycles over
    the h hours it stands for, if the history is representative of them.

    Raises:
        InputError: T_sim not finite and positive.
    """
    _require_simulated(simulated_seconds)
    return np.asarray(hours, dtype=float) * 3600.0 / simulated_seconds


@dataclass(frozen=True)
class ToothExposure:
    """How a gear's simulated mesh histories map onto one of its teeth (Jørgensen 2014 §3.1).

    In T_sim the gear turns n revolutions relative to its mesh positions (relative to the
    carrier in a planetary stage). Each of its ``meshes`` meshes sees z · n tooth passes, so the
    histories of all its meshes joined end to end, ``meshes`` · T_sim long, hold z · meshes · n
    passes; one tooth passes the meshes meshes · n times, 1/z of them. The cycles one tooth
    takes in h hours are therefore the cycles counted in the joined history times

        h · 3600 / (T_sim · z)        (Table 3; its "90 sec" is the sun's joined history)

    and, when only one mesh's history is counted (the planets load alike), times ``meshes``
    once more.

    Attributes:
        teeth: z, teeth on the gear.
        meshes: meshes a tooth passes per relative revolution: the planets for a sun or a
            ring, 2 for a planet (sun and ring).
    """

    teeth: int
    meshes: int

    def __post_init__(self) -> None:
        if self.teeth < 1 or self.meshes < 1:
            raise InputError(
                f"a tooth exposure needs at least one tooth and one mesh, got teeth = "
                f"{self.teeth}, meshes = {self.meshes}"
            )

    def history_seconds(self, simulated_seconds: float) -> float:
        """Length of the gear's mesh histories joined, meshes · T_sim [s]."""
        _require_simulated(simulated_seconds)
        return self.meshes * simulated_seconds

    def time_factor(self, *, hours: npt.ArrayLike, simulated_seconds: float) -> np.ndarray:
        """Cycles of one tooth in ``hours`` per cycle counted in the joined history [-]."""
        return time_factor(hours=hours, simulated_seconds=simulated_seconds) / self.teeth

    def single_mesh_time_factor(
        self, *, hours: npt.ArrayLike, simulated_seconds: float
    ) -> np.ndarray:
        """Cycles of one tooth in ``hours`` per cycle counted in one mesh's history [-]."""
        return self.meshes * self.time_factor(hours=hours, simulated_seconds=simulated_seconds)


def planetary_exposures(
    *, sun_teeth: int, planet_teeth: int, ring_teeth: int, planets: int
) -> dict[str, ToothExposure]:
    """Tooth exposures of a planetary stage's sun, planets and ring (Jørgensen 2014 §3.1).

    A sun or ring tooth passes every planet once per revolution relative to the carrier; a
    planet tooth passes the sun and the ring once each.
    """
    return {
        "sun": ToothExposure(teeth=sun_teeth, meshes=planets),
        "planet": ToothExposure(teeth=planet_teeth, meshes=2),
        "ring": ToothExposure(teeth=ring_teeth, meshes=planets),
    }


def _site(
    speeds: np.ndarray,
    bounds: np.ndarray,
    hours: np.ndarray,
    turbulence: float | Sequence[float] | str | None,
) -> WindSite:
    """The site of bins with these speeds, edges (n + 1,), hours and turbulence."""
    intensity = bin_turbulence(speeds, turbulence)
    return WindSite(
        tuple(
            WindBin(
                speed=float(speeds[i]),
                low=float(bounds[i]),
                high=float(bounds[i + 1]),
                hours=float(hours[i]),
                turbulence=intensity[i],
            )
            for i in range(speeds.size)
        )
    )


def _require_weibull(scale: float, shape: float) -> None:
    """Raise `InvalidWindSite` unless A and k are finite and positive."""
    if not math.isfinite(scale) or scale <= 0.0:
        raise InvalidWindSite(
            "Weibull scale A [m/s]", scale, "finite and positive", "e.g. A = 6.62 m/s"
        )
    if not math.isfinite(shape) or shape <= 0.0:
        raise InvalidWindSite("Weibull shape k", shape, "finite and positive", "e.g. k = 2.19")


def _require_simulated(simulated_seconds: float) -> None:
    """Raise `InputError` unless the simulated length is finite and positive."""
    if not math.isfinite(simulated_seconds) or simulated_seconds <= 0.0:
        raise InputError(
            f"the simulated length must be finite and positive, got {simulated_seconds!r} s; "
            "give the length of the history the cycles were counted in"
        )
