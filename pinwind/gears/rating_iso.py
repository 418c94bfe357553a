"""ISO 6336 rating of a gear mesh: pitting (ISO 6336-2) and tooth-root bending (ISO 6336-3).

Method B where the standard gives one and it needs no data beyond the geometry and the material:
the zone factor Z_H, single-pair factors Z_B / Z_D, contact-ratio factor Z_ε, helix factors, the
tooth form and stress-correction factors Y_F and Y_S (load at the outer point of single tooth
contact, 30° tangent to the root fillet). Every factor is a field of `IsoFactors`; a field left
None is computed as its docstring says, a number given replaces it, so a published example can
be reproduced factor by factor. SI inside (Pa, N, m); ISO's N/mm² are MPa.

    σ_H0 = Z_H Z_E Z_ε Z_β √(F_t/(d1 b) · (u + 1)/u)                          (ISO 6336-2)
    σ_H1,2 = Z_B,D σ_H0 √(K_A K_γ K_v K_Hβ K_Hα)
    S_H = σ_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X / σ_H
    σ_F0 = F_t/(b m_n) Y_F Y_S Y_β Y_B Y_DT                                    (ISO 6336-3)
    σ_F = σ_F0 K_A K_γ K_v K_Fβ K_Fα
    S_F = σ_Flim Y_ST Y_NT Y_δrelT Y_RrelT Y_X / σ_F

u = z2/z1 is negative for an internal wheel, so (u + 1)/u = (z2 − z1)/z2.

Defaults that are choices, not standard results (override them with real data):

- K_v: ISO 6336-1:1996 method C, K_v = 1 + (K1/(K_A F_t/b) + K2) (z1 v/100) √(u²/(1 + u²)),
  F_t/b in N/mm (at least 100), v in m/s (``MeshLoad.pitch_line_speed``: in the carrier's
  frame for a planetary mesh, `pinwind.analysis.rating`), K1 and K2 for the ISO 1328 accuracy
  grade (`accuracy_grade`, default 6).
- K_Hβ: ISO 6336-1 closed form from an effective mesh misalignment F_βy (`misalignment`,
  default 10 µm after running-in) and c_γβ = 0.85 c_γα (`pinwind.gears.mesh_stiffness`):
  K_Hβ = 1 + c_γβ F_βy /(2 F_m/b) up to 2, else √(2 c_γβ F_βy/(F_m/b)); F_m = F_t K_A K_v.
  K_Fβ = K_Hβ^N_F, N_F = (b/h)²/(1 + b/h + (b/h)²), h = (h_aP* + h_fP*) m_n + k m_n the
  deeper tooth's depth with its tip alteration, b/h ≥ 3.
- K_Hα = K_Fα = 1 unless a base pitch deviation f_pb is given (`base_pitch_deviation`), then
  ISO 6336-1 method B: (ε_γ/2)(0.9 + 0.4 c_γα (f_pb − y_α)/(F_tH/b)) for ε_γ ≤ 2, limited to
  [1, ε_γ/(ε_α Z_ε²)] (K_Hα) and [1, ε_γ/(ε_α Y_ε)] (K_Fα).
- Life, lubrication, roughness, speed, work-hardening and size factors Z_NT, Z_L, Z_v, Z_R, Z_W,
  Z_X, Y_NT, Y_δrelT, Y_RrelT are 1 (reference test conditions, long life); Y_X follows
  ISO 6336-3 for the module (case hardened: 1.05 − 0.01 m_n, ≥ 0.8; through hardened:
  1.03 − 0.006 m_n, ≥ 0.85; m_n in mm; 1 up to 5 mm).
- An internal wheel's Y_F and Y_S are those of the rack (z_n → ∞) with its profile shift,
  which is conservative: an internal tooth is thicker at the root than a rack tooth.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import TypeVar

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError
from pinwind.gears.face_load import UNMODELLED_MISALIGNMENT
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.involute import involute
from pinwind.gears.materials import elastic_coefficient
from pinwind.gears.mesh_stiffness import mesh_stiffness

#: K1 of ISO 6336-1 method C by ISO 1328 accuracy grade 3…12: (spur, helical).
_K1 = {
    3: (2.1, 1.9),
    4: (3.9, 3.5),
    5: (7.5, 6.7),
    6: (14.9, 13.3),
    7: (26.8, 23.9),
    8: (39.1, 34.8),
    9: (52.8, 47.0),
    10: (76.6, 68.2),
    11: (102.6, 91.4),
    12: (146.3, 130.3),
}
#: Stand-in virtual tooth number of the rack that models an internal wheel's tooth.
_RACK_TEETH = 1.0e4

Pair = tuple[float, float]
_T = TypeVar("_T")


@dataclass(frozen=True)
class IsoFactors:
    """Influence factors of an ISO 6336 rating; None means "compute the default".

    Per-gear factors are (pinion, wheel) tuples. Dimensionless unless a unit is given.

    Attributes:
        K_A: application factor (default 1: the simulated loads are the actual ones).
        K_gamma: mesh load factor (default 1: pinwind's forces are already per mesh).
        K_v: dynamic factor.
        K_Hbeta, K_Fbeta: face load factors.
        K_Halpha, K_Falpha: transverse load factors.
        Z_H, Z_E [√Pa], Z_eps, Z_beta: zone, elasticity, contact-ratio, helix factors.
        Z_B, Z_D: single pair tooth contact factors of pinion and wheel.
        Z_NT, Z_L, Z_v, Z_R, Z_W, Z_X: (pinion, wheel) life, lubricant, velocity, roughness,
            work-hardening and size factors for pitting.
        Y_F, Y_S: (pinion, wheel) tooth form and stress correction factors.
        Y_beta, Y_B, Y_DT: helix, rim thickness and deep tooth factors.
        Y_ST: stress correction factor of the reference test gears (2.0).
        Y_NT, Y_delta, Y_R, Y_X: (pinion, wheel) life, relative notch sensitivity, relative
            surface and size factors for bending.
        S_H_min, S_F_min: minimum safety factors for the permissible stresses.
        accuracy_grade: ISO 1328 grade for the default K_v (3…12).
        misalignment: effective mesh misalignment F_βy [m] for the default K_Hβ.
        base_pitch_deviation: f_pb [m] for K_Hα by method B; None: K_Hα = 1.
    """

    K_A: float = 1.0
    K_gamma: float = 1.0
    K_v: float | None = None
    K_Hbeta: float | None = None
    K_Fbeta: float | None = None
    K_Halpha: float | None = None
    K_Falpha: float | None = None
    Z_H: float | None = None
    Z_E: float | None = None
    Z_eps: float | None = None
    Z_beta: float | None = None
    Z_B: float | None = None
    Z_D: float | None = None
    Z_NT: Pair = (1.0, 1.0)
    Z_L: Pair = (1.0, 1.0)
    Z_v: Pair = (1.0, 1.0)
    Z_R: Pair = (1.0, 1.0)
    Z_W: Pair = (1.0, 1.0)
    Z_X: Pair = (1.0, 1.0)
    Y_F: Pair | None = None
    Y_S: Pair | None = None
    Y_beta: float | None = None
    Y_B: Pair = (1.0, 1.0)
    Y_DT: float = 1.0
    Y_ST: float = 2.0
    Y_NT: Pair = (1.0, 1.0)
    Y_delta: Pair = (1.0, 1.0)
    Y_R: Pair = (1.0, 1.0)
    Y_X: Pair | None = None
    S_H_min: float = 1.0
    S_F_min: float = 1.0
    accuracy_grade: int = 6
    misalignment: float = UNMODELLED_MISALIGNMENT
    base_pitch_deviation: float | None = None


@dataclass(frozen=True, kw_only=True)
class ResolvedIsoFactors:
    """The factors an ISO 6336 rating used: `IsoFactors` with every default computed.

    The same fields, in the same order and with the same meaning, as `IsoFactors`; none of
    the factors is None (``base_pitch_deviation`` is an input, not a factor, and stays as
    given). `resolve_factors` makes one; `iso_rating` also accepts one and then uses it as is.
    """

    K_A: float
    K_gamma: float
    K_v: float
    K_Hbeta: float
    K_Fbeta: float
    K_Halpha: float
    K_Falpha: float
    Z_H: float
    Z_E: float
    Z_eps: float
    Z_beta: float
    Z_B: float
    Z_D: float
    Z_NT: Pair
    Z_L: Pair
    Z_v: Pair
    Z_R: Pair
    Z_W: Pair
    Z_X: Pair
    Y_F: Pair
    Y_S: Pair
    Y_beta: float
    Y_B: Pair
    Y_DT: float
    Y_ST: float
    Y_NT: Pair
    Y_delta: Pair
    Y_R: Pair
    Y_X: Pair
    S_H_min: float
    S_F_min: float
    accuracy_grade: int
    misalignment: float
    base_pitch_deviation: float | None


@dataclass(frozen=True)
class IsoRating:
    """ISO 6336 stresses and safety factors of one mesh at one load (SI units).

    Attributes:
        factors: every factor used, defaults resolved.
        tangential_force: F_t [N].
        sigma_H0: nominal contact stress [Pa].
        sigma_H: contact stress of pinion and wheel (Z_B, Z_D applied) [Pa].
        sigma_H_permissible: σ_HP = σ_HG/S_H,min of pinion and wheel [Pa].
        S_H: pitting safety factors σ_HG/σ_H of pinion and wheel.
        sigma_F0: nominal root stresses [Pa].
        sigma_F: root stresses [Pa].
        sigma_F_permissible: σ_FP = σ_FG/S_F,min [Pa].
        S_F: bending safety factors σ_FG/σ_F of pinion and wheel.
    """

    factors: ResolvedIsoFactors
    tangential_force: float
    sigma_H0: float
    sigma_H: Pair
    sigma_H_permissible: Pair
    S_H: Pair
    sigma_F0: Pair
    sigma_F: Pair
    sigma_F_permissible: Pair
    S_F: Pair

    @property
    def passes(self) -> bool:
        """Every safety factor at least its minimum."""
        f = self.factors
        return min(self.S_H) >= f.S_H_min and min(self.S_F) >= f.S_F_min

    def as_dict(self) -> dict:
        """Plain numbers for JSON and tables."""
        out = asdict(self)
        out["passes"] = self.passes
        return out


def iso_rating(
    pair: GearPair, load: MeshLoad, factors: IsoFactors | ResolvedIsoFactors | None = None
) -> IsoRating:
    """Rate a pair at one load by ISO 6336-2 (pitting) and ISO 6336-3 (bending).

    Args:
        pair: geometry and materials, pinion first.
        load: nominal tangential force at the reference circle and pitch-line speed.
        factors: overrides; every None field is computed (see the module docstring). A
            `ResolvedIsoFactors` (``IsoRating.factors`` of an earlier rating) is used as is.

    Raises:
        InputError: a non-positive or non-finite force.
        InvalidGearTrain: the pair has no valid path of contact, or gear 1 is internal.
    """
    pair.require_external_gear_1("the ISO 6336 rating")
    f_t = load.tangential_force
    if not (math.isfinite(f_t) and f_t > 0.0):
        raise InputError(f"the tangential force must be positive and finite, got {f_t} N")
    if isinstance(factors, ResolvedIsoFactors):
        f = factors
    else:
        f = resolve_factors(pair, load, factors or IsoFactors())
    b = pair.face_width
    sigma_h0 = float(
        nominal_contact_stress(pair, f_t, Z_H=f.Z_H, Z_E=f.Z_E, Z_eps=f.Z_eps, Z_beta=f.Z_beta)
    )
    load_h = math.sqrt(f.K_A * f.K_gamma * f.K_v * f.K_Hbeta * f.K_Halpha)
    sigma_h = (f.Z_B * sigma_h0 * load_h, f.Z_D * sigma_h0 * load_h)
    materials = pair.materials

    def pitting_strength(i: int) -> float:
        """σ_HG = σ_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X of gear i [Pa]."""
        m = materials[i]
        return m.sigma_H_lim * f.Z_NT[i] * f.Z_L[i] * f.Z_v[i] * f.Z_R[i] * f.Z_W[i] * f.Z_X[i]

    sigma_hg = _per_gear(pitting_strength)
    nominal = f_t / (b * pair.module)
    sigma_f0 = _per_gear(lambda i: nominal * f.Y_F[i] * f.Y_S[i] * f.Y_beta * f.Y_B[i] * f.Y_DT)
    load_f = f.K_A * f.K_gamma * f.K_v * f.K_Fbeta * f.K_Falpha
    sigma_f = _per_gear(lambda i: sigma_f0[i] * load_f)
    sigma_fg = _per_gear(
        lambda i: materials[i].sigma_F_lim * f.Y_ST * f.Y_NT[i] * f.Y_delta[i] * f.Y_R[i] * f.Y_X[i]
    )
    return IsoRating(
        factors=f,
        tangential_force=f_t,
        sigma_H0=sigma_h0,
        sigma_H=sigma_h,
        sigma_H_permissible=_per_gear(lambda i: sigma_hg[i] / f.S_H_min),
        S_H=_per_gear(lambda i: sigma_hg[i] / sigma_h[i]),
        sigma_F0=sigma_f0,
        sigma_F=sigma_f,
        sigma_F_permissible=_per_gear(lambda i: sigma_fg[i] / f.S_F_min),
        S_F=_per_gear(lambda i: sigma_fg[i] / sigma_f[i]),
    )


def resolve_factors(pair: GearPair, load: MeshLoad, given: IsoFactors) -> ResolvedIsoFactors:
    """Every factor of ``given``, its None fields computed for this pair and load."""
    path = pair.path
    eps_a, eps_b = path.contact_ratio, path.overlap_ratio
    beta, beta_b = pair.helix_angle, pair.base_helix_angle

    z_h = _given_or(given.Z_H, lambda: zone_factor(pair))
    z_e = _given_or(given.Z_E, lambda: elastic_coefficient(*pair.materials))
    z_eps = _given_or(given.Z_eps, lambda: contact_ratio_factor(eps_a, eps_b))
    z_beta = _given_or(given.Z_beta, lambda: helix_factor(beta))
    m1, m2 = single_pair_ratios(pair)
    z_b = _given_or(given.Z_B, lambda: _single_pair_factor(m1, eps_b))
    z_d = _given_or(given.Z_D, lambda: 1.0 if pair.internal_2 else _single_pair_factor(m2, eps_b))
    k_v = _given_or(given.K_v, lambda: dynamic_factor(pair, load, given.K_A, given.accuracy_grade))
    c_gamma_alpha = _mesh_stiffness_per_width(pair)
    k_hb = _given_or(
        given.K_Hbeta,
        lambda: face_load_factor(
            c_gamma_alpha,
            given.misalignment,
            load.tangential_force * given.K_A * k_v / pair.face_width,
        ),
    )
    k_fb = _given_or(given.K_Fbeta, lambda: k_hb ** root_face_load_exponent(pair))
    eps_gamma = eps_a + eps_b
    eps_an = eps_a / math.cos(beta_b) ** 2
    y_eps = 0.25 + 0.75 / eps_an

    def transverse(limit: float) -> float:
        return transverse_load_factor(pair, load, given, c_gamma_alpha, k_v, k_hb, eps_gamma, limit)

    k_ha = _given_or(given.K_Halpha, lambda: transverse(eps_gamma / (eps_a * z_eps**2)))
    k_fa = _given_or(given.K_Falpha, lambda: transverse(eps_gamma / (eps_a * y_eps)))
    forms = [form_factors(pair, gear) for gear in (1, 2)]
    y_f = _given_or(given.Y_F, lambda: (forms[0][0], forms[1][0]))
    y_s = _given_or(given.Y_S, lambda: (forms[0][1], forms[1][1]))
    y_beta = _given_or(given.Y_beta, lambda: root_helix_factor(eps_b, beta))
    y_x = _given_or(
        given.Y_X,
        lambda: _per_gear(lambda i: size_factor(pair.module, pair.materials[i].case_hardened)),
    )
    return ResolvedIsoFactors(
        K_A=given.K_A,
        K_gamma=given.K_gamma,
        K_v=k_v,
        K_Hbeta=k_hb,
        K_Fbeta=k_fb,
        K_Halpha=k_ha,
        K_Falpha=k_fa,
        Z_H=z_h,
        Z_E=z_e,
        Z_eps=z_eps,
        Z_beta=z_beta,
        Z_B=z_b,
        Z_D=z_d,
        Z_NT=given.Z_NT,
        Z_L=given.Z_L,
        Z_v=given.Z_v,
        Z_R=given.Z_R,
        Z_W=given.Z_W,
        Z_X=given.Z_X,
        Y_F=y_f,
        Y_S=y_s,
        Y_beta=y_beta,
        Y_B=given.Y_B,
        Y_DT=given.Y_DT,
        Y_ST=given.Y_ST,
        Y_NT=given.Y_NT,
        Y_delta=given.Y_delta,
        Y_R=given.Y_R,
        Y_X=y_x,
        S_H_min=given.S_H_min,
        S_F_min=given.S_F_min,
        accuracy_grade=given.accuracy_grade,
        misalignment=given.misalignment,
        base_pitch_deviation=given.base_pitch_deviation,
    )


def _given_or(value: _T | None, compute: Callable[[], _T]) -> _T:
    """``value`` if the user gave it, else ``compute()`` (called only then)."""
    return compute() if value is None else value


def _per_gear(value: Callable[[int], float]) -> Pair:
    """(value(0), value(1)): a per-gear quantity of pinion and wheel."""
    return value(0), value(1)


def nominal_contact_stress(
    pair: GearPair,
    tangential_force: npt.ArrayLike,
    *,
    Z_H: float,
    Z_E: float,
    Z_eps: float,
    Z_beta: float,
) -> np.ndarray:
    """σ_H0 = Z_H Z_E Z_ε Z_β √(F_t/(d1 b) · (u + 1)/u) [Pa] (ISO 6336-2), per force.

    Args:
        pair: pinion first (d1 its reference diameter, u = z2/z1 negative for an internal
            wheel).
        tangential_force: F_t at the reference circle [N], a float or an array.
        Z_H, Z_E, Z_eps, Z_beta: zone [-], elasticity [√Pa], contact-ratio and helix factors.
    """
    b, d1, u = pair.face_width, pair.reference_diameter_1, pair.gear_ratio
    return (
        Z_H
        * Z_E
        * Z_eps
        * Z_beta
        * np.sqrt(np.asarray(tangential_force, dtype=float) / (d1 * b) * (u + 1.0) / u)
    )


def zone_factor(pair: GearPair) -> float:
    """Z_H = √(2 cos β_b cos α_wt / (cos² α_t sin α_wt)) (ISO 6336-2) [-]."""
    alpha_t, alpha_wt = pair.transverse_pressure_angle, pair.path.working_pressure_angle
    return math.sqrt(
        2.0
        * math.cos(pair.base_helix_angle)
        * math.cos(alpha_wt)
        / (math.cos(alpha_t) ** 2 * math.sin(alpha_wt))
    )


def helix_factor(helix_angle: float) -> float:
    """Z_β = 1/√cos β (ISO 6336-2:2006; the 1996 edition had √cos β) [-]."""
    return 1.0 / math.sqrt(math.cos(helix_angle))


def contact_ratio_factor(eps_alpha: float, eps_beta: float) -> float:
    """Z_ε (ISO 6336-2): √((4 − ε_α)/3 (1 − ε_β) + ε_β/ε_α) for ε_β < 1, √(1/ε_α) above."""
    if eps_beta >= 1.0:
        return math.sqrt(1.0 / eps_alpha)
    return math.sqrt((4.0 - eps_alpha) / 3.0 * (1.0 - eps_beta) + eps_beta / eps_alpha)


def single_pair_ratios(pair: GearPair) -> tuple[float, float]:
    """(M1, M2) of ISO 6336-2: relative curvature at the pitch point over that at B and D.

    M1 = √(ρ_C1 ρ_C2 / (ρ_B1 ρ_B2)) with ρ the flank radii of curvature (roll distances from
    the tangency points T1, T2) at the pitch point C and at the pinion's inner point of single
    contact B (a base pitch inside the end of contact E); M2 the same at the wheel's inner point
    D (a base pitch beyond the start A). This is ISO's
    M1 = tan α_wt / √([√(d_a1²/d_b1² − 1) − 2π/z1][√(d_a2²/d_b2² − 1) − (ε_α − 1) 2π/z2]),
    written with roll distances (`GearPair.flank_radii`) so that it holds for an internal wheel
    (ρ2 = −(u + T1T2); the signs cancel in the ratio).
    """
    path = pair.path

    def curvature_product(u: float) -> float:
        rho_1, rho_2 = pair.flank_radii(u)
        return rho_1 * rho_2

    c = curvature_product(path.pitch_roll_1)
    m1 = math.sqrt(c / curvature_product(path.start_roll_1 + path.length - path.base_pitch))
    m2 = math.sqrt(c / curvature_product(path.start_roll_1 + path.base_pitch))
    return m1, m2


def _single_pair_factor(m: float, eps_beta: float) -> float:
    """Z_B or Z_D from M (ISO 6336-2): spur max(1, M); ε_β ≥ 1: 1; between: M − ε_β (M − 1)."""
    if eps_beta >= 1.0:
        return 1.0
    return max(1.0, m - eps_beta * (m - 1.0))


def dynamic_factor(pair: GearPair, load: MeshLoad, K_A: float, grade: int) -> float:
    """K_v by ISO 6336-1:1996 method C (see the module docstring)."""
    if grade not in _K1:
        raise InputError(f"accuracy grade {grade} is outside ISO 1328 grades 3…12")
    helical = pair.path.overlap_ratio >= 1.0
    k1 = _K1[grade][1 if helical else 0]
    k2 = 0.0087 if helical else 0.0193
    specific = max(K_A * load.tangential_force / (pair.face_width * 1e3), 100.0)  # N/mm
    u = pair.gear_ratio
    return 1.0 + (k1 / specific + k2) * pair.teeth_1 * load.pitch_line_speed / 100.0 * math.sqrt(
        u * u / (1.0 + u * u)
    )


def face_load_factor(c_gamma_alpha: float, misalignment: float, line_load: float) -> float:
    """K_Hβ from F_βy, c_γβ = 0.85 c_γα [N/m²] and F_m/b [N/m] (ISO 6336-1 closed form)."""
    x = 0.85 * c_gamma_alpha * misalignment / line_load
    return 1.0 + x / 2.0 if x <= 2.0 else math.sqrt(2.0 * x)


def root_face_load_exponent(pair: GearPair) -> float:
    """N_F of K_Fβ = K_Hβ^N_F [-] (ISO 6336-1).

    N_F = (b/h)²/(1 + b/h + (b/h)²), b/h taken as at least 3, h the tooth depth
    (h_aP* + h_fP*) m_n + k m_n with the gear's tip alteration k m_n (DIN 3990's
    h = h_aP + k m_n + h_fP), the deeper tooth's of the two (the smaller b/h).
    """
    tip = max(pair.tip_alteration_1, pair.tip_alteration_2)
    h = (pair.addendum_coefficient + pair.dedendum_coefficient) * pair.module + tip
    b_h = max(pair.face_width / h, 3.0)
    return b_h**2 / (1.0 + b_h + b_h**2)


def transverse_load_factor(
    pair: GearPair,
    load: MeshLoad,
    given: IsoFactors,
    c_gamma_alpha: float,
    k_v: float,
    k_hb: float,
    eps_gamma: float,
    limit: float,
) -> float:
    """K_Hα or K_Fα by ISO 6336-1 method B with the running-in allowance y_α (ISO 6336-1).

    1 when ``given.base_pitch_deviation`` is None (no f_pb, no method B).
    """
    f_pb = given.base_pitch_deviation
    if f_pb is None:
        return 1.0
    m1 = pair.materials[0]
    if m1.case_hardened:
        y_alpha = min(0.075 * f_pb, 3e-6)
    else:
        y_alpha = min(160e6 / m1.sigma_H_lim * f_pb, 6e-6)
    f_th = load.tangential_force * given.K_A * given.K_gamma * k_v * k_hb / pair.face_width
    if eps_gamma <= 2.0:
        k = eps_gamma / 2.0 * (0.9 + 0.4 * c_gamma_alpha * (f_pb - y_alpha) / f_th)
    else:
        k = (
            0.9
            + 0.4
            * math.sqrt(2.0 * (eps_gamma - 1.0) / eps_gamma)
            * c_gamma_alpha
            * (f_pb - y_alpha)
            / f_th
        )
    return min(max(k, 1.0), limit)


def root_helix_factor(overlap_ratio: float, helix_angle: float) -> float:
    """Y_β = 1 − ε_β β/120° (ISO 6336-3), ε_β taken as 1 above 1 and β as 30° above 30°."""
    return 1.0 - min(overlap_ratio, 1.0) * min(math.degrees(helix_angle), 30.0) / 120.0


def size_factor(module: float, case_hardened: bool) -> float:
    """Y_X of ISO 6336-3 for long life (m_n in mm inside)."""
    m = module * 1e3
    if case_hardened:
        return min(1.0, max(0.8, 1.05 - 0.01 * m))
    return min(1.0, max(0.85, 1.03 - 0.006 * m))


def form_factors(pair: GearPair, gear: int, *, at_tip: bool = False) -> tuple[float, float]:
    """(Y_F, Y_S) by ISO 6336-3 method B of gear 1 or 2 of ``pair``, cut by its basic-rack tool.

    Load at the outer point of single tooth contact (``at_tip``: at the tip, which gives ISO's
    Y_Fa, Y_Sa of method C); critical section where the 30° tangent touches the root fillet:

        E = π m_n/4 − h_fP tan α_n − (1 − sin α_n) ρ_fP / cos α_n
        G = ρ_fP/m_n − h_fP/m_n + x,  H = 2/z_n (π/2 − E/m_n) − π/3
        θ = 2G/z_n tan θ − H  (fixed point from π/6)
        s_Fn/m_n = z_n sin(π/3 − θ) + √3 (G/cos θ − ρ_fP/m_n)
        ρ_F/m_n = ρ_fP/m_n + 2G²/(cos θ (z_n cos² θ − 2G))
        d_en = 2 √((√(r_an² − r_bn²) − π m_n cos α_n (ε_αn − 1))² + r_bn²)
        α_en = acos(d_bn/d_en),  γ_e = (π/2 + 2 x tan α_n)/z_n + inv α_n − inv α_en
        α_Fen = α_en − γ_e
        h_Fe/m_n = ½ [(cos γ_e − sin γ_e tan α_Fen) d_en/m_n − z_n cos(π/3 − θ)
                     − G/cos θ + ρ_fP/m_n]
        Y_F = 6 (h_Fe/m_n) cos α_Fen / ((s_Fn/m_n)² cos α_n)
        Y_S = (1.2 + 0.13 L) q_s^(1/(1.21 + 2.3/L)),  L = s_Fn/h_Fe,  q_s = s_Fn/(2 ρ_F)

    with z_n the virtual tooth number, d_n = m_n z_n, d_an = d_n + d_a − d, ε_αn = ε_α/cos² β_b.
    No protuberance (s_pr = 0). An internal gear is modelled as a rack (z_n → ∞, see the module
    docstring) whose tip lies the same distance beyond its reference line.
    """
    teeth, profile_shift, internal = pair.gear(gear)
    tip_diameter = pair.tip_diameter(gear)
    m_n, alpha_n = pair.module, pair.pressure_angle
    h_fp = pair.dedendum_coefficient * m_n
    rho_fp = pair.root_radius_coefficient * m_n
    z_n = _RACK_TEETH if internal else pair.virtual_teeth(gear)
    d = teeth * pair.transverse_module
    addendum = (d - tip_diameter) / 2.0 if internal else (tip_diameter - d) / 2.0
    e = (
        math.pi / 4.0 * m_n
        - h_fp * math.tan(alpha_n)
        - (1.0 - math.sin(alpha_n)) * rho_fp / math.cos(alpha_n)
    )
    g = rho_fp / m_n - h_fp / m_n + profile_shift
    h = 2.0 / z_n * (math.pi / 2.0 - e / m_n) - math.pi / 3.0
    theta = math.pi / 6.0
    for _ in range(200):
        new = 2.0 * g / z_n * math.tan(theta) - h
        if abs(new - theta) < 1e-14:
            theta = new
            break
        theta = new
    s_fn = m_n * (
        z_n * math.sin(math.pi / 3.0 - theta)
        + math.sqrt(3.0) * (g / math.cos(theta) - rho_fp / m_n)
    )
    rho_f = m_n * (
        rho_fp / m_n + 2.0 * g * g / (math.cos(theta) * (z_n * math.cos(theta) ** 2 - 2.0 * g))
    )
    d_n = m_n * z_n
    d_bn = d_n * math.cos(alpha_n)
    d_an = d_n + 2.0 * addendum
    eps_an = 1.0 if at_tip else pair.path.contact_ratio / math.cos(pair.base_helix_angle) ** 2
    roll = math.sqrt((d_an / 2.0) ** 2 - (d_bn / 2.0) ** 2) - math.pi * m_n * math.cos(alpha_n) * (
        eps_an - 1.0
    )
    d_en = 2.0 * math.sqrt(roll**2 + (d_bn / 2.0) ** 2)
    alpha_en = math.acos(d_bn / d_en)
    gamma_e = (
        (math.pi / 2.0 + 2.0 * profile_shift * math.tan(alpha_n)) / z_n
        + involute(alpha_n)
        - involute(alpha_en)
    )
    alpha_fen = alpha_en - gamma_e
    h_fe = (
        0.5
        * m_n
        * (
            (math.cos(gamma_e) - math.sin(gamma_e) * math.tan(alpha_fen)) * d_en / m_n
            - z_n * math.cos(math.pi / 3.0 - theta)
            - g / math.cos(theta)
            + rho_fp / m_n
        )
    )
    y_f = 6.0 * (h_fe / m_n) * math.cos(alpha_fen) / ((s_fn / m_n) ** 2 * math.cos(alpha_n))
    ratio = s_fn / h_fe
    q_s = s_fn / (2.0 * rho_f)
    y_s = (1.2 + 0.13 * ratio) * q_s ** (1.0 / (1.21 + 2.3 / ratio))
    return y_f, y_s


def _mesh_stiffness_per_width(pair: GearPair) -> float:
    """c_γα [N/m per m of face width] from `mesh_stiffness` (ISO 6336-1 method B)."""
    return mesh_stiffness(pair) / pair.face_width
