"""AGMA 2001 rating of a gear mesh: bending and pitting (Saleh 2017 eqs. 32-37).

SI form of AGMA 2001-D04 (Shigley's Mechanical Engineering Design, 10th ed., eqs. 14-15 to 14-42):

    σ   = W_t K_o K_v K_s / (F m_t) · K_m K_B / J                  bending   (Saleh 2017 eq. 32)
    σ_c = C_p √(W_t K_o K_v K_s K_m C_f / (d_P F I))                contact   (Saleh 2017 eq. 34)
    σ_all   = s_at Y_N / (K_T K_R)                                             (Saleh 2017 eq. 33)
    σ_c,all = s_ac Z_N C_H / (K_T K_R)                                         (Saleh 2017 eq. 35)
    S_F = σ_all / σ,   S_H = σ_c,all / σ_c                               (Saleh 2017 eqs. 36-37)

Saleh 2017 writes eqs. 36-37 as stress over allowable; here they are allowable over stress, as
in AGMA 2001 and Shigley, so that S ≥ 1 passes. (S_H compares stresses; AGMA compares S_F with
S_H².)

Every factor is a field of `AgmaFactors`; None means "compute the default":

- K_v = ((A + √V)/A)^B, A = 50 + 56 (1 − B), B = 0.25 (12 − Q_v)^(2/3), V [ft/min]
  (Shigley eq. 14-27), transmission accuracy level Q_v (`quality`, default 10);
- K_s = 1 (AGMA 2001: unity when the steel is chosen for the section; `shigley_size_factor`
  gives Shigley's 1.192 (F √Y / P)^0.0535 estimate);
- K_m = 1 + C_mc (C_pf C_pm + C_ma C_e) (Shigley eq. 14-30), uncrowned (C_mc 1), straddle
  mounted (C_pm 1), C_e 1, C_ma for ``gearing`` (default ``"precision_enclosed"``);
- J (per gear) by AGMA 908-B89 (``geometry_factor="agma908"``, the default for external
  pairs; `agma_geometry_factor.agma_geometry_factors`: Lewis parabola tangent to the generated
  fillet, load at the highest point of single tooth contact, Dolan–Broghamer K_f). AGMA 908 has
  no J for internal gears, so an internal pair (and ``geometry_factor="iso"``) uses
  J = 1/(Y_F Y_S) with ISO 6336-3 method B's Y_F, Y_S (load at the outer point of single tooth
  contact, `rating_iso.form_factors`);
- I = cos φ_t sin φ_t / (2 m_N) · m_G/(m_G ± 1) (+ external, − internal; m_N = 1 for spur
  gears, p_N/(0.95 Z) for helical), at the working pressure angle (Shigley eqs. 14-23, 14-21);
- C_p from the two materials (`materials.elastic_coefficient`);
- Y_N = Z_N = 1 (10⁷ cycles), C_H = 1, K_T = 1, K_R from ``reliability_percent`` R [%]
  (Shigley eq. 14-38 with the fraction R/100; 1 at 99 %, 1.25 at 99.9 %), C_f = 1, K_B = 1,
  K_o = 1.

W_t is the tangential load at the operating pitch circle: F_t d_1/d_w1.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import TypeVar

from pinwind.errors import InputError
from pinwind.gears.agma_geometry_factor import agma_geometry_factors
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.materials import elastic_coefficient
from pinwind.gears.rating_iso import form_factors

Pair = tuple[float, float]
_T = TypeVar("_T")

#: C_ma = A + B F + C F² (F in inches) by gearing condition (Shigley Table 14-9).
MESH_ALIGNMENT = {
    "open": (0.247, 0.0167, -0.765e-4),
    "commercial_enclosed": (0.127, 0.0158, -0.930e-4),
    "precision_enclosed": (0.0675, 0.0128, -0.926e-4),
    "extra_precision_enclosed": (0.00360, 0.0102, -0.822e-4),
}
_INCH = 0.0254


@dataclass(frozen=True)
class AgmaFactors:
    """Factors of an AGMA 2001 rating; None means "compute the default" (module docstring).

    Attributes:
        K_o: overload factor.
        K_v: dynamic factor.
        K_s: (pinion, wheel) size factors.
        K_m: load distribution factor (K_H).
        K_B: rim thickness factor.
        J: (pinion, wheel) bending geometry factors (Y_J).
        I: contact geometry factor (Z_I).
        C_p: elastic coefficient [√Pa] (Z_E).
        C_f: surface condition factor (Z_R).
        Y_N, Z_N: (pinion, wheel) stress cycle factors for bending and contact.
        C_H: (pinion, wheel) hardness ratio factors (Z_W).
        K_T: temperature factor (Y_θ).
        K_R: reliability factor (Y_Z).
        quality: transmission accuracy level Q_v for the default K_v.
        gearing: condition for C_ma: ``open``, ``commercial_enclosed``, ``precision_enclosed``,
            ``extra_precision_enclosed``.
        reliability_percent: reliability R [%] for the default K_R, 50 < R ≤ 99.99 (AGMA
            2001 Table 8 and Shigley eq. 14-38 give K_R from 50 % to 99.99 %).
        geometry_factor: default J: ``"agma908"`` (AGMA 908-B89 for external pairs, ISO's
            1/(Y_F Y_S) for internal ones) or ``"iso"`` (1/(Y_F Y_S) always).
    """

    K_o: float = 1.0
    K_v: float | None = None
    K_s: Pair = (1.0, 1.0)
    K_m: float | None = None
    K_B: float = 1.0
    J: Pair | None = None
    I: float | None = None  # noqa: E741 (AGMA's name)
    C_p: float | None = None
    C_f: float = 1.0
    Y_N: Pair = (1.0, 1.0)
    Z_N: Pair = (1.0, 1.0)
    C_H: Pair = (1.0, 1.0)
    K_T: float = 1.0
    K_R: float | None = None
    quality: int = 10
    gearing: str = "precision_enclosed"
    reliability_percent: float = 99.0
    geometry_factor: str = "agma908"


@dataclass(frozen=True, kw_only=True)
class ResolvedAgmaFactors:
    """The factors an AGMA 2001 rating used: `AgmaFactors` with every default computed.

    The same fields, in the same order and with the same meaning, as `AgmaFactors`; none is
    None. `resolve_factors` makes one; `agma_rating` also accepts one and then uses it as is.
    """

    K_o: float
    K_v: float
    K_s: Pair
    K_m: float
    K_B: float
    J: Pair
    I: float  # noqa: E741 (AGMA's name)
    C_p: float
    C_f: float
    Y_N: Pair
    Z_N: Pair
    C_H: Pair
    K_T: float
    K_R: float
    quality: int
    gearing: str
    reliability_percent: float
    geometry_factor: str


@dataclass(frozen=True)
class AgmaRating:
    """AGMA 2001 stresses and safety factors of one mesh at one load (SI units).

    Attributes:
        factors: every factor used, defaults resolved.
        transmitted_load: W_t [N].
        bending_stress: σ of pinion and wheel [Pa] (Saleh 2017 eq. 32).
        bending_allowable: σ_all of pinion and wheel [Pa] (eq. 33).
        contact_stress: σ_c of pinion and wheel [Pa] (eq. 34; they differ only through K_s).
        contact_allowable: σ_c,all of pinion and wheel [Pa] (eq. 35).
        S_F: bending safety factors σ_all/σ (eq. 36, inverted so that ≥ 1 passes).
        S_H: contact safety factors σ_c,all/σ_c (eq. 37, inverted likewise).
    """

    factors: ResolvedAgmaFactors
    transmitted_load: float
    bending_stress: Pair
    bending_allowable: Pair
    contact_stress: Pair
    contact_allowable: Pair
    S_F: Pair
    S_H: Pair

    @property
    def passes(self) -> bool:
        """Every safety factor at least 1."""
        return min(self.S_F) >= 1.0 and min(self.S_H) >= 1.0

    def as_dict(self) -> dict:
        """Plain numbers for JSON and tables."""
        out = asdict(self)
        out["passes"] = self.passes
        return out


def agma_rating(
    pair: GearPair, load: MeshLoad, factors: AgmaFactors | ResolvedAgmaFactors | None = None
) -> AgmaRating:
    """Rate a pair at one load by AGMA 2001 (Saleh 2017 eqs. 32-37).

    ``factors``: overrides, every None field computed (module docstring); a
    `ResolvedAgmaFactors` (``AgmaRating.factors`` of an earlier rating) is used as is.

    Raises:
        InputError: a non-positive or non-finite force, or an unknown ``gearing``.
        InvalidGearTrain: gear 1 is internal.
    """
    pair.require_external_gear_1("the AGMA 2001 rating")
    if not (math.isfinite(load.tangential_force) and load.tangential_force > 0.0):
        raise InputError(
            f"the tangential force must be positive and finite, got {load.tangential_force} N"
        )
    if isinstance(factors, ResolvedAgmaFactors):
        f = factors
    else:
        f = resolve_factors(pair, load, factors or AgmaFactors())
    d_w1 = 2.0 * pair.geometry.working_radius_1
    w_t = load.tangential_force * pair.reference_diameter_1 / d_w1
    b, m_t = pair.face_width, pair.transverse_module
    common = _per_gear(lambda i: w_t * f.K_o * f.K_v * f.K_s[i])
    bending = _per_gear(lambda i: common[i] / (b * m_t) * f.K_m * f.K_B / f.J[i])
    contact = _per_gear(lambda i: f.C_p * math.sqrt(common[i] * f.K_m * f.C_f / (d_w1 * b * f.I)))
    materials = pair.materials
    derate = f.K_T * f.K_R
    bending_all = _per_gear(lambda i: materials[i].agma_bending_allowable * f.Y_N[i] / derate)
    contact_all = _per_gear(
        lambda i: materials[i].agma_contact_allowable * f.Z_N[i] * f.C_H[i] / derate
    )
    return AgmaRating(
        factors=f,
        transmitted_load=w_t,
        bending_stress=bending,
        bending_allowable=bending_all,
        contact_stress=contact,
        contact_allowable=contact_all,
        S_F=_per_gear(lambda i: bending_all[i] / bending[i]),
        S_H=_per_gear(lambda i: contact_all[i] / contact[i]),
    )


def resolve_factors(pair: GearPair, load: MeshLoad, given: AgmaFactors) -> ResolvedAgmaFactors:
    """Every factor of ``given``, its None fields computed for this pair and load."""
    if given.gearing not in MESH_ALIGNMENT:
        raise InputError(
            f'unknown gearing condition "{given.gearing}"; choose one of '
            f"{', '.join(MESH_ALIGNMENT)}"
        )
    k_v = _given_or(given.K_v, lambda: dynamic_factor(load.pitch_line_speed, given.quality))
    k_m = _given_or(
        given.K_m,
        lambda: load_distribution_factor(pair.face_width, pair.reference_diameter_1, given.gearing),
    )
    if given.geometry_factor not in ("agma908", "iso"):
        raise InputError(
            f'unknown geometry_factor "{given.geometry_factor}"; choose "agma908" or "iso"'
        )
    j = _given_or(given.J, lambda: _bending_geometry_factors(pair, given.geometry_factor))
    i_factor = _given_or(given.I, lambda: pitting_geometry_factor(pair))
    c_p = _given_or(given.C_p, lambda: elastic_coefficient(*pair.materials))
    k_r = _given_or(given.K_R, lambda: reliability_factor(given.reliability_percent))
    return ResolvedAgmaFactors(
        K_o=given.K_o,
        K_v=k_v,
        K_s=given.K_s,
        K_m=k_m,
        K_B=given.K_B,
        J=j,
        I=i_factor,
        C_p=c_p,
        C_f=given.C_f,
        Y_N=given.Y_N,
        Z_N=given.Z_N,
        C_H=given.C_H,
        K_T=given.K_T,
        K_R=k_r,
        quality=given.quality,
        gearing=given.gearing,
        reliability_percent=given.reliability_percent,
        geometry_factor=given.geometry_factor,
    )


def _bending_geometry_factors(pair: GearPair, method: str) -> Pair:
    """Default (J_pinion, J_wheel): AGMA 908 for an external pair, else 1/(Y_F Y_S) (ISO)."""
    if method == "agma908" and not pair.internal_2:
        return agma_geometry_factors(pair)
    forms = [form_factors(pair, gear) for gear in (1, 2)]
    return _per_gear(lambda i: 1.0 / (forms[i][0] * forms[i][1]))


def _given_or(value: _T | None, compute: Callable[[], _T]) -> _T:
    """``value`` if the user gave it, else ``compute()`` (called only then)."""
    return compute() if value is None else value


def _per_gear(value: Callable[[int], float]) -> Pair:
    """(value(0), value(1)): a per-gear quantity of pinion and wheel."""
    return value(0), value(1)


def dynamic_factor(speed: float, quality: int) -> float:
    """K_v = ((A + √V)/A)^B (Shigley eq. 14-27; V = v/0.00508 in ft/min, v [m/s], Q_v 6…11).

    Shigley's SI form writes √(200 v), a rounded 196.85 ft/min per m/s; the exact conversion is
    used here so that the US-unit examples come out as printed.
    """
    if not 3 <= quality <= 12:
        raise InputError(f"transmission accuracy level Q_v = {quality} is outside 3…12")
    b = 0.25 * (12.0 - quality) ** (2.0 / 3.0)
    a = 50.0 + 56.0 * (1.0 - b)
    return ((a + math.sqrt(speed / 0.00508)) / a) ** b


def load_distribution_factor(face_width: float, pinion_diameter: float, gearing: str) -> float:
    """K_m = 1 + C_pf + C_ma (Shigley eq. 14-30, uncrowned, straddle mounted, C_e = 1).

    C_pf = F/(10 d) − 0.025 (F ≤ 1 in), F/(10 d) − 0.0375 + 0.0125 F (≤ 17 in),
    F/(10 d) − 0.1109 + 0.0207 F − 0.000228 F² (≤ 40 in), with F/(10 d) at least 0.05;
    C_ma = A + B F + C F² (Table 14-9); F and d in inches.
    """
    f_in, d_in = face_width / _INCH, pinion_diameter / _INCH
    ratio = max(f_in / (10.0 * d_in), 0.05)
    if f_in <= 1.0:
        c_pf = ratio - 0.025
    elif f_in <= 17.0:
        c_pf = ratio - 0.0375 + 0.0125 * f_in
    else:
        c_pf = ratio - 0.1109 + 0.0207 * f_in - 0.000228 * f_in**2
    a, b, c = MESH_ALIGNMENT[gearing]
    return 1.0 + c_pf + a + b * f_in + c * f_in**2


def pitting_geometry_factor(pair: GearPair) -> float:
    """I = cos φ_t sin φ_t / (2 m_N) · m_G/(m_G ± 1) (Shigley eqs. 14-23, 14-21)."""
    phi = pair.path.working_pressure_angle
    m_g = pair.teeth_2 / pair.teeth_1
    ratio = m_g / (m_g - 1.0) if pair.internal_2 else m_g / (m_g + 1.0)
    if pair.helix_angle == 0.0:
        load_sharing = 1.0
    else:
        p_n = math.pi * pair.module * math.cos(pair.pressure_angle)
        load_sharing = p_n / (0.95 * pair.path.length)
    return math.cos(phi) * math.sin(phi) / (2.0 * load_sharing) * ratio


#: The reliabilities R [%] AGMA's K_R holds for: 50 < R ≤ 99.99 (Shigley eq. 14-38).
RELIABILITY_PERCENT_RANGE = (50.0, 99.99)


def reliability_factor(reliability_percent: float) -> float:
    """K_R [-] for a reliability R [%], 50 < R ≤ 99.99, by Shigley eq. 14-38.

    With r = R/100 the fraction: K_R = 0.658 − 0.0759 ln(1 − r) for 0.5 < r < 0.99,
    0.50 − 0.109 ln(1 − r) for 0.99 ≤ r ≤ 0.9999.

    Raises:
        InputError: R outside (50, 99.99] (a fraction such as 0.99 is one: give 99).
    """
    low, high = RELIABILITY_PERCENT_RANGE
    if not low < reliability_percent <= high:
        hint = (
            f" (a fraction? {reliability_percent:g} is {100 * reliability_percent:g} %)"
            if 0.0 < reliability_percent <= 1.0
            else ""
        )
        raise InputError(
            f"reliability {reliability_percent:g} % is outside AGMA's K_R range, "
            f"{low:g} < R ≤ {high:g} %{hint}"
        )
    r = reliability_percent / 100.0
    if r < 0.99:
        return 0.658 - 0.0759 * math.log(1.0 - r)
    return 0.50 - 0.109 * math.log(1.0 - r)


def shigley_size_factor(face_width: float, module: float, lewis_form_factor: float) -> float:
    """K_s = 1.192 (F √Y / P)^0.0535, at least 1 (Shigley §14-10; F [in], P = 25.4/m [1/in])."""
    p = _INCH / module
    return max(1.0, 1.192 * (face_width / _INCH * math.sqrt(lewis_form_factor) / p) ** 0.0535)
