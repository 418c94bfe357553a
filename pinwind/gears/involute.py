"""Involute spur and helical gear geometry (ISO 21771 / ISO 53 basic rack).

Internal gears follow the ISO sign convention inside the formulas: the tooth number of an internal
gear counts as negative, so one formula serves external and internal pairs. Every length is in
metres and every angle in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def involute(angle: float) -> float:
    """Inv α = tan α − α [rad]."""
    return float(np.tan(angle) - angle)


def inverse_involute(value: float) -> float:
    """The angle α in (0, π/2) whose involute is ``value`` [rad].

    Newton's method on f(α) = tan α − α − value, f′ = tan² α, from α₀ = min(∛(3 value),
    atan(value + π/2)), which lies at or above the root (inv α ≥ α³/3, and tan α = value + α <
    value + π/2): f is increasing and convex on (0, π/2), so the iterates fall monotonically onto
    the root, to rounding, in a few steps. (Without scipy.optimize, whose import costs more than
    a ``pinwind modes`` run.)

    Raises:
        ValueError: ``value`` not finite or ≤ 0 (no angle in (0, π/2) has that involute).
    """
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"no pressure angle in (0, 90)° has the involute {value:g}")
    alpha = min(math.cbrt(3.0 * value), math.atan(value + math.pi / 2))
    for _ in range(100):
        step = (math.tan(alpha) - alpha - value) / math.tan(alpha) ** 2
        if step <= 4.0 * math.ulp(alpha):
            break
        alpha -= step
    return alpha


def transverse_pressure_angle(pressure_angle: float, helix_angle: float) -> float:
    """α_t = atan(tan α_n / cos β) [rad] (ISO 21771 eq. 4)."""
    return float(np.arctan(np.tan(pressure_angle) / np.cos(helix_angle)))


def pitch_radius(teeth: int, module: float, helix_angle: float = 0.0) -> float:
    """Reference pitch radius r = z m_n / (2 cos β) [m]."""
    return float(teeth * module / (2.0 * np.cos(helix_angle)))


def base_helix_angle(pressure_angle: float, helix_angle: float) -> float:
    """β_b = atan(tan β cos α_t) [rad] (ISO 21771)."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    return math.atan(math.tan(helix_angle) * math.cos(alpha_t))


def virtual_teeth(teeth: int, helix_angle: float = 0.0, pressure_angle: float = 0.0) -> float:
    """Virtual tooth number z_n = z / (cos² β_b cos β) [-] (ISO 21771; ISO 6336-1 clause 9).

    β_b is the base helix angle (`base_helix_angle`); for spur gears z_n = z.
    """
    beta_b = base_helix_angle(pressure_angle, helix_angle)
    return teeth / (math.cos(beta_b) ** 2 * math.cos(helix_angle))


def tip_radius(
    teeth: int,
    module: float,
    profile_shift: float,
    helix_angle: float,
    internal: bool,
    addendum_coefficient: float,
    tip_alteration: float = 0.0,
) -> float:
    """Tip radius [m], with the tip alteration k·m_n (0: no tip shortening).

    r ± (m_n (h_a* + x) + k m_n), − for an internal gear (its inner radius), x with the ISO
    21771 sign (ISO 21771: d_a = d + 2 (z/|z|) (h_aP* m_n + x m_n + k m_n)). The tip alteration
    ``tip_alteration`` = k m_n [m] is negative for a shortened tip (Nejad et al. 2016 Table V:
    −10.861 mm on the stage-1 sun and planets). Sign convention of x on an internal gear (ISO
    21771, signed tooth numbers): a positive x moves its tip circle towards the axis (a smaller
    inner tip diameter) and thickens its teeth on the reference circle, as a positive x thickens
    an external gear's; Nejad et al. 2016's stage-1 ring, x = −0.501, has
    d_a = 2520 − 2 · 45 (1 − 0.501) = 2475.09 mm, the paper's 2475.087 mm. The one
    implementation, used by `GearPair.tip_radius` (so ``GearPair.path_of_contact``) and
    ``checks.tip_thickness``.
    """
    r = pitch_radius(teeth, module, helix_angle)
    addendum = module * (addendum_coefficient + profile_shift) + tip_alteration
    return float(r - addendum if internal else r + addendum)


def base_radius(
    teeth: int, module: float, pressure_angle: float, helix_angle: float = 0.0
) -> float:
    """Base circle radius r_b = r cos α_t [m]."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    return pitch_radius(teeth, module, helix_angle) * float(np.cos(alpha_t))


def half_tooth_angle(
    teeth: int,
    *,
    module: float,
    pressure_angle: float,
    radius: float,
    profile_shift: float = 0.0,
    helix_angle: float = 0.0,
    internal: bool = False,
) -> float:
    """Half the transverse tooth thickness at ``radius`` [m], as an angle about the axis [rad].

    ISO 21771: s_t = m_t (π/2 + 2 x tan α_n) on the reference circle d = z m_t, and at radius r

        ψ(r) = s_t/d ± (inv α_t − inv α(r)),   cos α(r) = r_b / r,

    + for an external gear (its teeth thin outwards), − for an internal one (its teeth thin
    inwards, towards its tip; x with the ISO sign convention). At or inside the base circle
    α(r) = 0. The tooth thickness on the circle of radius r is 2 r ψ(r).
    """
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    r_base = base_radius(teeth, module, pressure_angle, helix_angle)
    alpha_r = math.acos(min(1.0, r_base / radius))
    reference = (0.5 * math.pi + 2.0 * profile_shift * math.tan(pressure_angle)) / teeth
    sign = -1.0 if internal else 1.0
    return reference + sign * (involute(alpha_t) - involute(alpha_r))


@dataclass(frozen=True)
class PairGeometry:
    """Working geometry of a gear pair.

    Attributes:
        centre_distance: working centre distance a_w [m] (positive).
        working_pressure_angle: transverse working pressure angle α_wt [rad].
        working_radius_1: working pitch radius of gear 1 [m].
        working_radius_2: working pitch radius of gear 2 [m].
        base_radius_1: base radius of gear 1 [m].
        base_radius_2: base radius of gear 2 [m].
    """

    centre_distance: float
    working_pressure_angle: float
    working_radius_1: float
    working_radius_2: float
    base_radius_1: float
    base_radius_2: float

    @property
    def tangency_distance(self) -> float:
        """|T1 T2| = a_w sin α_wt, between the base-circle tangency points [m] (ISO 21771)."""
        return self.centre_distance * math.sin(float(self.working_pressure_angle))


def pair_geometry(
    teeth_1: int,
    teeth_2: int,
    *,
    module: float,
    pressure_angle: float,
    profile_shift_1: float = 0.0,
    profile_shift_2: float = 0.0,
    helix_angle: float = 0.0,
    internal_1: bool = False,
    internal_2: bool = False,
) -> PairGeometry:
    """Working centre distance and pressure angle of a pair with profile shift.

    ISO 21771 eqs. for a pair with signed tooth numbers (internal gear negative):

        inv α_wt = inv α_t + 2 tan α_n (x1 + x2) / (z1 + z2)
        a_w = m_t (z1 + z2) / 2 · cos α_t / cos α_wt

    Without profile shift this is the reference centre distance m (z1 ± z2)/2 of
    Saleh et al. 2017 eq. 38 (r3 = r2 + r5).
    """
    z1 = -teeth_1 if internal_1 else teeth_1
    z2 = -teeth_2 if internal_2 else teeth_2
    if z1 + z2 == 0:
        raise ValueError("a gear pair with equal internal and external tooth numbers cannot mesh")
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    inv_w = involute(alpha_t) + 2.0 * np.tan(pressure_angle) * (
        profile_shift_1 + profile_shift_2
    ) / (z1 + z2)
    alpha_wt = inverse_involute(inv_w)
    m_t = module / np.cos(helix_angle)
    a_w = abs(m_t * (z1 + z2) / 2.0 * np.cos(alpha_t) / np.cos(alpha_wt))
    return PairGeometry(
        centre_distance=float(a_w),
        working_pressure_angle=alpha_wt,
        working_radius_1=float(a_w * teeth_1 / abs(z1 + z2)),
        working_radius_2=float(a_w * teeth_2 / abs(z1 + z2)),
        base_radius_1=base_radius(teeth_1, module, pressure_angle, helix_angle),
        base_radius_2=base_radius(teeth_2, module, pressure_angle, helix_angle),
    )
