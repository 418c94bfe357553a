"""ISO 281:2007 modified rating life L_nm = a₁ a_ISO L₁₀ of a radial rolling bearing.

**Rated viscosity** ν₁ (ISO 281:2007 §9.3.3, from the mean diameter d_m [mm] and the speed n
[r/min]):

    ν₁ = 45 000 n^−0.83 d_m^−0.5       n < 1 000 r/min
    ν₁ =  4 500 n^−0.5  d_m^−0.5       n ≥ 1 000 r/min         [mm²/s]

and the **viscosity ratio** κ = ν/ν₁ of the operating viscosity ν (``life/lubrication.py``).

**Life modification factor** a_ISO (ISO 281:2007 §9.3.2 eqs. for radial roller and ball
bearings), with x = e_C C_u / P:

    roller:  a_ISO = 0.1 [1 − (1.5859 − c₂ κ^−c₃) x^0.4]^−9.185
    ball:    a_ISO = 0.1 [1 − (2.5671 − c₂ κ^−c₃)^0.83 x^(1/3)]^−9.3

in four κ regimes: 0.1 ≤ κ < 0.4 (roller c₂ = 1.3993, ball 2.2649; c₃ = 0.054381),
0.4 ≤ κ < 1 (roller 1.2348, ball 1.9987; c₃ = 0.19087), 1 ≤ κ ≤ 4 (roller 1.2348, ball 1.9987;
c₃ = 0.071739) and κ > 4, where κ = 4 is used. The standard's method does not cover κ < 0.1;
pinwind uses κ = 0.1 there and says so (``ModifiedLife.kappa_clamped``). a_ISO is capped at 50
(ISO 281:2007 §9.3.2), which is also its value where the bracket is ≤ 0. The middle regime's
exponent c₃ = 0.19087 is the one that makes a_ISO continuous at κ = 0.4 for both kinds
(some copies of the ball formula print 0.019087, which jumps by 15 % there).

**Fatigue load limit** C_u: the catalogue's, or ISO 281:2007 Annex B's simplified estimate from
the basic static load rating C₀ and the mean diameter d_m [mm] (said wherever it is used):
roller C_u = C₀/8.2 (d_m ≤ 100), C₀/8.2 · (100/d_m)^0.3 (d_m > 100); ball C_u = C₀/22
(d_m ≤ 100), C₀/22 · (100/d_m)^0.5.

**Reliability** a₁ (ISO 281:2007 §9.2, Table 12 comes from it):
a₁ = 0.95 (ln(100/R)/ln(100/90))^(2/3)
+ 0.05 for a reliability R [%] from 90 to 99.95.
"""

from __future__ import annotations

import math

import numpy as np

from pinwind.errors import InputError

#: a_ISO regimes: (κ from, c₂ roller, c₂ ball, c₃), ISO 281:2007 §9.3.2.
A_ISO_REGIMES = (
    (0.1, 1.3993, 2.2649, 0.054381),
    (0.4, 1.2348, 1.9987, 0.19087),
    (1.0, 1.2348, 1.9987, 0.071739),
)
#: The largest a_ISO ISO 281 allows.
A_ISO_CAP = 50.0
KAPPA_MIN, KAPPA_MAX = 0.1, 4.0


def rated_viscosity(speed_rpm: np.ndarray | float, mean_diameter: float) -> np.ndarray:
    """ν₁ [m²/s] at speeds n [r/min] of a bearing of mean diameter d_m [m] (module docstring).

    NaN at n = 0 (a bearing at rest builds no film; its revolutions count nothing).
    """
    n = np.abs(np.asarray(speed_rpm, dtype=float))
    dm_mm = mean_diameter * 1e3
    with np.errstate(divide="ignore"):
        slow = 45000.0 * n**-0.83 * dm_mm**-0.5
        fast = 4500.0 * n**-0.5 * dm_mm**-0.5
    nu1 = np.where(n < 1000.0, slow, fast) * 1e-6
    return np.where(n > 0.0, nu1, np.nan)


def life_modification_factor(
    kappa: np.ndarray | float, ratio: np.ndarray | float, *, ball: bool
) -> np.ndarray:
    """a_ISO [-] at viscosity ratios κ and x = e_C C_u / P (module docstring); ≤ 50.

    κ outside [0.1, 4] is taken at the nearer end (``ModifiedLife.kappa_clamped`` says when).
    """
    k = np.clip(np.asarray(kappa, dtype=float), KAPPA_MIN, KAPPA_MAX)
    x = np.maximum(np.asarray(ratio, dtype=float), 0.0)
    c2 = np.zeros_like(k)
    c3 = np.zeros_like(k)
    for start, roller, ball_c2, exponent in A_ISO_REGIMES:
        at = k >= start
        c2 = np.where(at, ball_c2 if ball else roller, c2)
        c3 = np.where(at, exponent, c3)
    if ball:
        inner = np.maximum(2.5671 - c2 * k**-c3, 0.0)
        bracket = 1.0 - inner**0.83 * x ** (1.0 / 3.0)
        exponent = -9.3
    else:
        bracket = 1.0 - (1.5859 - c2 * k**-c3) * x**0.4
        exponent = -9.185
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(bracket > 0.0, 0.1 * np.abs(bracket) ** exponent, A_ISO_CAP)
    return np.minimum(a, A_ISO_CAP)


#: The reliabilities R [%] ISO 281:2007 §9.2 gives a₁ for: 90 ≤ R ≤ 99.95.
RELIABILITY_PERCENT_RANGE = (90.0, 99.95)


def reliability_factor(reliability_percent: float) -> float:
    """a₁ [-] for a reliability R [%] (90 … 99.95): ISO 281:2007 §9.2 (module docstring).

    Raises:
        InputError: R outside 90 … 99.95, where ISO 281 gives no a₁ (a fraction such as 0.9
            is one: give 90).
    """
    low, high = RELIABILITY_PERCENT_RANGE
    if not low <= reliability_percent <= high:
        hint = (
            f" (a fraction? {reliability_percent:g} is {100 * reliability_percent:g} %)"
            if 0.0 < reliability_percent <= 1.0
            else ""
        )
        raise InputError(
            f"reliability {reliability_percent:g} %: ISO 281 gives a₁ from {low:g} to "
            f"{high:g} %{hint}"
        )
    ratio = math.log(100.0 / reliability_percent) / math.log(100.0 / 90.0)
    return 0.95 * ratio ** (2.0 / 3.0) + 0.05


def estimated_fatigue_limit(static_rating: float, mean_diameter: float, *, ball: bool) -> float:
    """C_u [N] from C₀ [N] and d_m [m]: ISO 281:2007 Annex B's simplified rule (module doc)."""
    dm_mm = mean_diameter * 1e3
    base = static_rating / (22.0 if ball else 8.2)
    if dm_mm <= 100.0:
        return base
    return base * (100.0 / dm_mm) ** (0.5 if ball else 0.3)


def modified_life_sum(
    loads: np.ndarray,
    turns: np.ndarray,
    kappa: np.ndarray,
    *,
    exponent: float,
    contamination: float,
    fatigue_limit: float,
    ball: bool,
) -> tuple[float, float]:
    """(Σ n_i P_i^p / a_ISO,i , Σ n_i): the sums of a varying load's modified life.

    ISO 281:2007 §9.3.4 (Palmgren-Miner over the load levels): each level i of n_i revolutions
    at equivalent load P_i [N] and viscosity ratio κ_i uses up n_i / (a_ISO,i (C/P_i)^p) of the
    life, so L_nm = a₁ Σ n_i / Σ (n_i P_i^p / (a_ISO,i C^p)). Levels at P = 0 or at rest count
    nothing. Sums add over histories, as ``BearingLoadSum``'s do.
    """
    loads = np.asarray(loads, dtype=float)
    turns = np.asarray(turns, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(loads > 0.0, contamination * fatigue_limit / loads, np.inf)
    a = life_modification_factor(kappa, ratio, ball=ball)
    moving = (turns > 0.0) & (loads > 0.0)
    used = np.sum(np.where(moving, turns * loads**exponent / a, 0.0))
    return float(used), float(np.sum(turns))


def modified_rating_life(
    rating: float, exponent: float, used: float, revolutions: float, *, a1: float = 1.0
) -> float:
    """L_nm [10⁶ rev] from the sums of `modified_life_sum` (``used`` [N^p·rev], revolutions).

    ISO 281:2007 §9.3.4: L_nm = a₁ C^p Σ n_i / Σ (n_i P_i^p / a_ISO,i), C [N] the basic dynamic
    load rating and p its life exponent (at a_ISO = 1 it is (C/P_eq)^p, ISO 281's L10 in 10⁶
    rev: the revolutions cancel); inf when nothing was used (no load), NaN when the sums are (no
    modified life) or nothing turned.
    """
    if math.isnan(used) or not revolutions > 0.0:
        return math.nan
    if used <= 0.0:
        return math.inf
    return a1 * revolutions / used * rating**exponent
