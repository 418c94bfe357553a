"""Gear mesh stiffness by ISO 6336-1:2019 clause 9, method B.

ISO gives two stiffnesses per unit face width. The single stiffness c′ is the stiffness of one
tooth pair, taken at the pitch point (in the single-pair zone). The mesh stiffness c_γα is the
mean over one base pitch of the stiffness summed over all pairs in contact. Both act along the
line of action, in the transverse plane. Here both are multiplied by the face width b and given
in SI units [N/m]. ISO's own units are N/(mm·µm): c′ [N/(mm·µm)] · b [mm] is in N/µm, and
multiplying by 1e6 gives N/m.

Validity, as ISO 6336-1 states it for method B: steel/steel pairs (for other materials scale by
E/E_steel); specific load F_t K_A / b ≥ 100 N/mm (below that ISO reduces c′); spur and helical
gears with basic-rack profiles; x1 ≥ x2 and −0.5 ≤ x1 + x2 ≤ 2. c_γα = c′(0.75 ε_α + 0.25)
holds for ε_α ≥ 1.2. None of these limits is checked here.

The clause and constant values are those of ISO 6336-1 (method B, theoretical single stiffness
from the flexibility q′ with constants C1…C9). The ISO text was not available to cross-check
equation numbers, so only the clause is cited.
"""

from __future__ import annotations

import math

import numpy as np

from pinwind.errors import InputError
from pinwind.gears.contact import PathOfContact
from pinwind.gears.gear_pair import GearPair

#: ISO 6336-1 method B constants C1…C9 of the flexibility q′ [mm·µm/N].
FLEXIBILITY_CONSTANTS = (
    0.04723,
    0.15551,
    0.25791,
    -0.00635,
    -0.11654,
    -0.00193,
    -0.24188,
    0.00529,
    0.00182,
)

#: Factor from c′ b in N/(mm·µm) · m to N/m: 1e3 mm per m times 1e6 µm per m.
_ISO_TO_SI = 1e9


def single_pair_stiffness(pair: GearPair, *, rim_factor: float = 1.0, C_M: float = 0.8) -> float:
    """Single stiffness times face width, c′ b [N/m], by ISO 6336-1:2019 clause 9, method B.

    The formula, with q′ in mm·µm/N and c′ in N/(mm·µm):

        q′    = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2
                + C8 x1² + C9 x2²
        c′_th = 1/q′
        c′    = c′_th C_M C_R C_B cos β
        C_B   = [1 + 0.5 (1.2 − h_fP/m_n)] [1 − 0.02 (20° − α_n)]
        z_n   = z / (cos² β_b cos β)

    C1…C9 are `FLEXIBILITY_CONSTANTS`. The virtual tooth numbers are z_n
    (`GearPair.virtual_teeth`). Gear 1 of the formula is the pinion, the external gear with
    fewer teeth (`GearPair.pinion_first`), whichever of two external gears the pair names
    first: q′ is not symmetric in the two gears (C2 ≠ C3, C5 ≠ C7), so the NREL 5 MW stage-1
    sun (19 teeth) meshing its 17-tooth planets, or a wheel named before its pinion, would
    otherwise change c′ by 2-3 %. An internal gear 2 counts as a rack, z_n2 = ∞ (the C3 and C7
    terms vanish), as KISSsoft's ISO 6336:2006 method B reads ISO 6336-1: its reports of the
    NREL 5 MW planetary stages (Rebouças 2020) print c′ = 13.289 and 14.053 N/(mm·µm) for the
    planet–ring meshes (C_R = 0.862), which z_n2 = ∞ gives to 4e-4 and the ring's tooth count
    (−56 or +56; −93 or +93) misses by 5-15 %; their sun meshes (12.362, 12.240) also take the
    pinion as gear 1. The ISO text itself was not available to quote. The profile shifts keep
    the ISO 21771 signs (KISSsoft's x_ring = −0.5013 for stage 1 enters C6 x2 and C9 x2²).

    Args:
        pair: the pair, gear 1 external (an internal gear, if any, is gear 2); its
            face width b, normal module, pressure angle α_n of the basic rack, profile shifts,
            helix angle and dedendum coefficient h_fP/m_n (1.25 for ISO 53 profile A) enter.
        rim_factor: gear blank factor C_R [-]. It is 1 for solid gears; ISO gives
            C_R = 1 + ln(b_s/b)/(5 e^(s_R/(5 m_n))) for webbed rims.
        C_M: theoretical-to-measured correction factor [-], 0.8 for solid disc gears.

    Raises:
        InvalidGearTrain: gear 1 is internal (put the internal gear second).
    """
    pair.require_external_gear_1("ISO 6336-1 method B")
    pair = pair.pinion_first()
    z_n1 = pair.virtual_teeth(1)
    inverse_z_n2 = 0.0 if pair.internal_2 else 1.0 / pair.virtual_teeth(2)  # 0 for a ring
    x1, x2 = pair.profile_shift_1, pair.profile_shift_2
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = FLEXIBILITY_CONSTANTS
    flexibility = (
        c1
        + c2 / z_n1
        + c3 * inverse_z_n2
        + c4 * x1
        + c5 * x1 / z_n1
        + c6 * x2
        + c7 * x2 * inverse_z_n2
        + c8 * x1**2
        + c9 * x2**2
    )
    basic_rack = (1.0 + 0.5 * (1.2 - pair.dedendum_coefficient)) * (
        1.0 - 0.02 * (20.0 - math.degrees(pair.pressure_angle))
    )
    single = C_M * rim_factor * basic_rack * math.cos(pair.helix_angle) / flexibility
    return single * pair.face_width * _ISO_TO_SI


def mesh_stiffness(
    pair: GearPair,
    *,
    rim_factor: float = 1.0,
    C_M: float = 0.8,
    tip_radius_1: float | None = None,
    tip_radius_2: float | None = None,
) -> float:
    """Mean mesh stiffness times face width, c_γα b = c′ b (0.75 ε_α + 0.25) [N/m].

    ISO 6336-1:2019 clause 9, method B. ε_α is the pair's (`GearPair.path`), or that of
    `GearPair.path_of_contact` with the tip radii given, so tip radii and addendum matter here.
    The other arguments are those of `single_pair_stiffness`. ISO states the formula for
    ε_α ≥ 1.2.
    """
    if tip_radius_1 is None and tip_radius_2 is None:
        path = pair.path
    else:
        path = pair.path_of_contact(tip_radius_1=tip_radius_1, tip_radius_2=tip_radius_2)
    single = single_pair_stiffness(pair, rim_factor=rim_factor, C_M=C_M)
    return single * (0.75 * path.contact_ratio + 0.25)


def pair_stiffness_along_path(
    path: PathOfContact, single_pair: float
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness of one tooth pair as it runs along the path of contact, from A to E.

    The curve is piecewise constant. It is chosen so that the summed mesh stiffness is k_s = c′ b
    in the single-pair zone [B, D], and its mean over one base pitch is ISO's c_γα b. Over one
    base pitch two pairs are in contact for a fraction ε − 1 and one pair for 2 − ε. Let k_d be
    the summed stiffness while two pairs are in contact:

        (ε − 1) k_d + (2 − ε) k_s = k_s (0.75 ε + 0.25)
        ⇒ k_d (ε − 1) = k_s (1.75 ε − 1.75)  ⇒  k_d = 1.75 k_s

    So each of the two pairs carries 0.875 c′ b on [A, B] and [D, E]. A check: the mean summed
    stiffness is ∫₀^g k(s) ds / p_bt. Here that is
    [2 (g − p_bt) 0.875 + (2 p_bt − g)] k_s / p_bt = k_s (0.75 ε + 0.25).

    Args:
        path: the pair's path of contact, with 1 ≤ ε_α ≤ 2.
        single_pair: c′ b [N/m], e.g. from `single_pair_stiffness`.

    Returns:
        (s, k): roll distance from A [m] and pair stiffness [N/m], six breakpoints
        s = (0, B, B, D, D, g_α). Each jump repeats its abscissa, so `np.interp(s_query, s, k)`
        gives the step curve. Exactly at a jump, np.interp returns one of the two values; use
        `pairs_in_contact` where the zone matters. Outside [0, g_α] the pair is not in contact
        and its stiffness is 0.

    Raises:
        InputError: ε_α outside [1, 2]. Above 2 there is no single-pair zone to anchor c′ on.
    """
    if not 1.0 <= path.contact_ratio <= 2.0:
        raise InputError(
            f"pair_stiffness_along_path needs 1 ≤ ε_α ≤ 2, got ε_α = {path.contact_ratio:.4f}: "
            "above 2 there is no single-pair zone where ISO's c′ applies; use the mean "
            "c_γα b from mesh_stiffness instead"
        )
    double = 0.875 * single_pair
    b, d, g = path.single_start, path.single_end, path.length
    s = np.array([0.0, b, b, d, d, g])
    k = np.array([double, double, single_pair, single_pair, double, double])
    return s, k


def contact_line_pair_stiffness(
    path: PathOfContact, mean_stiffness: float
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness of one helical tooth pair as it rolls, proportional to its contact-line length.

    The tooth pairs of a helical mesh touch along straight lines in the plane of action, the
    rectangle g_α long (transverse) and b wide (axial), each line inclined at the base helix
    angle β_b to the axis. A pair whose contact point in the front face section sits at y from A
    touches, at axial position z ∈ [0, b], at y − z tan β_b; it is in contact where that lies in
    [0, g_α]. So one pair stays in contact over the roll span g_α + Δ, Δ = b tan β_b = ε_β p_bt
    (total contact ratio ε_γ = ε_α + ε_β), and its contact line is

        ℓ(y) = [min(y, Δ) − max(0, y − g_α)] / sin β_b,   0 ≤ y ≤ g_α + Δ

    long: a trapezoid that rises while the line enters the face, stays flat and falls as it
    leaves. The mesh stiffness follows the total length L(y) = Σ_j ℓ(y + j p_bt) of the lines in
    contact (ISO 6336-1 takes the mesh stiffness per unit contact length); its mean over a base
    pitch is ∫ℓ dy / p_bt = g_α b / (p_bt cos β_b). The pair stiffness is ℓ scaled so that the
    summed stiffness has the mean ``mean_stiffness``:

        k(y) = mean_stiffness · p_bt · [min(y, Δ) − max(0, y − g_α)] / (g_α Δ)

    With ε_β a whole number L is constant; for a spur pair (Δ → 0) it becomes the count of pairs
    in contact. Stiffness along the transverse line of action, like `mesh_stiffness`.

    Args:
        path: the pair's path of contact, with its overlap ratio ε_β > 0.
        mean_stiffness: mean mesh stiffness [N/m], e.g. c_γα b from `mesh_stiffness`.

    Returns:
        (y, k): roll position of the pair from A in the front face section [m] and its stiffness
        [N/m] at the four corners of the trapezoid, exact under linear interpolation; 0 outside
        [0, g_α + Δ].

    Raises:
        InputError: ε_β ≤ 0 (a spur pair has no inclined contact lines).
    """
    if not path.overlap_ratio > 0.0:
        raise InputError(
            f"contact_line_pair_stiffness needs a helical pair (ε_β > 0), got ε_β = "
            f"{path.overlap_ratio:g}; use pair_stiffness_along_path for spur gears"
        )
    g, p = path.length, path.base_pitch
    overlap = path.overlap_ratio * p
    y = np.array([0.0, min(g, overlap), max(g, overlap), g + overlap])
    height = min(g, overlap)
    k = np.array([0.0, height, height, 0.0]) * mean_stiffness * p / (g * overlap)
    return y, k
