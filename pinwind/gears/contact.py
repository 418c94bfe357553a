"""Path of contact of an involute gear pair in the transverse plane (ISO 21771).

The line of action is tangent to both base circles, at T1 on gear 1 and T2 on gear 2. Contact
runs along it from A, where it starts, to E, where it ends; C is the pitch point. Every length
here is a roll length along that line, which is also an arc length on the base circle
(Jørgensen 2014 Fig. 7b calls it the base circle arc length "s"). Positions are
measured from T1, or from A where the name says so. Lengths are in metres and angles in radians.

Profile shift follows ISO 21771, as in `pinwind.gears.involute`: an internal gear counts with a
negative tooth number inside the formulas, and its profile shift x keeps the ISO sign. So the
tip (inner) radius of an internal gear is r_a = r − m_n (h_a* + x) (see `path_of_contact`).
`path_of_contact` takes the pair's geometry as numbers; `GearPair.path_of_contact` gives them for
a `pinwind.gears.gear_pair.GearPair`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pinwind.errors import InvalidGearTrain
from pinwind.gears.involute import PairGeometry


@dataclass(frozen=True)
class PathOfContact:
    """Where the teeth of a pair touch along the line of action, in the transverse plane.

    A is where contact starts, B and D bound the single-pair zone, and E is where contact ends.
    When one pair is at A, the pair ahead of it is at A + p_bt. With 1 < ε_α < 2 two pairs are
    in contact on [A, B] and [D, E], and one pair on [B, D].

    Attributes:
        base_pitch: transverse base pitch p_bt = π m_t cos α_t [m].
        length: g_α, the length of the path of contact from A to E [m].
        contact_ratio: transverse contact ratio ε_α = g_α / p_bt [-].
        overlap_ratio: overlap ratio ε_β = b sin β / (π m_n) [-]; 0 for spur gears.
        start_roll_1: distance from T1 (gear 1's base-circle tangency point) to A along the line
            of action [m]. This is gear 1's base-circle roll length at the start of contact.
        pitch_roll_1: the same distance for the pitch point C, r_b1 tan α_wt [m].
        single_start: B, the start of the single-pair zone, as a distance from A:
            g_α − p_bt [m].
        single_end: D, the end of the single-pair zone, as a distance from A: p_bt [m].
        tip_radius_1: tip radius of gear 1 [m]. For an internal gear this is the inner radius.
        tip_radius_2: tip radius of gear 2 [m].
        working_pressure_angle: transverse working pressure angle α_wt [rad].
    """

    base_pitch: float
    length: float
    contact_ratio: float
    overlap_ratio: float
    start_roll_1: float
    pitch_roll_1: float
    single_start: float
    single_end: float
    tip_radius_1: float
    tip_radius_2: float
    working_pressure_angle: float


def path_of_contact(
    geometry: PairGeometry,
    *,
    tip_radius_1: float,
    tip_radius_2: float,
    base_pitch: float,
    internal_1: bool = False,
    internal_2: bool = False,
    overlap_ratio: float = 0.0,
) -> PathOfContact:
    """Path of contact of a spur or helical pair, external or internal, with profile shift.

    The working pressure angle α_wt, centre distance a_w and base radii are ``geometry``'s
    (`pinwind.gears.involute.pair_geometry`). Tip radii without tip shortening
    (`involute.tip_radius`, `GearPair.tip_radius`) are:

        external gear: r_a = r + m_n (h_a* + x)
        internal gear: r_a = r − m_n (h_a* + x)

    where r = z m_n / (2 cos β). For an internal gear x has the ISO 21771 sign. ISO 21771 (and
    DIN 3960) write d_a = d + 2 (z/|z|) m_n (h_aP* + x + k), so an internal gear's tip circle
    moves inward as x grows. The source is hanslhansl/diniso21771 `d_a` (an implementation of
    DIN ISO 21771:2014); MESYS (mesys.ag/?p=1265) notes that ISO 21771 gives internal gears
    positive diameters. Some textbooks and tools write r − m(1 − x) for an internal gear instead
    (SDP/SI D785 Table 5-1, MSC Adams); their x is the negative of ISO's. The DTU stage of
    Jørgensen 2014 (ring x = −0.840) is consistent only with the ISO sign: both meshes
    then have the same centre distance, and Table 6 is reproduced (tests/gears/test_contact.py).

    Path length (ISO 21771), with g_a,i = sqrt(r_ai² − r_bi²):

        external pair:     g_α = g_a1 + g_a2 − a_w sin α_wt
        gear 2 internal:   g_α = g_a1 − g_a2 + a_w sin α_wt
        gear 1 internal:   g_α = g_a2 − g_a1 + a_w sin α_wt

    Args:
        geometry: working geometry of the pair (either gear may be internal).
        tip_radius_1: tip radius of gear 1 [m] (its inner radius if internal).
        tip_radius_2: tip radius of gear 2 [m].
        base_pitch: transverse base pitch p_bt = π m_t cos α_t [m].
        internal_1, internal_2: gear 1 or gear 2 is an internal (ring) gear.
        overlap_ratio: ε_β = b sin β / (π m_n) [-], carried into the result.

    Raises:
        TipInsideBaseCircle: a tip circle lies inside its base circle.
        InvoluteInterference: the path leaves the part of the line of action that both involutes
            cover (a tip reaches past the mating gear's tangency point).
        ContactRatioBelowOne: ε_α < 1, so the pair cannot transmit motion continuously.
        ValueError: an internal and an external gear of equal tooth numbers
            (`involute.pair_geometry`).
    """
    base_1 = float(geometry.base_radius_1)
    base_2 = float(geometry.base_radius_2)
    for gear, tip, base in ((1, tip_radius_1, base_1), (2, tip_radius_2, base_2)):
        if tip <= base:
            raise TipInsideBaseCircle(gear, tip, base)

    alpha_wt = float(geometry.working_pressure_angle)
    line = geometry.tangency_distance  # |T1 T2|
    tip_roll_1 = math.sqrt(tip_radius_1**2 - base_1**2)  # from T1 to gear 1's tip circle
    tip_roll_2 = math.sqrt(tip_radius_2**2 - base_2**2)  # from T2 to gear 2's tip circle

    # Positions u along the line of action, measured from T1 towards the pitch point C. Contact
    # must stay where both flanks are involutes: between T1 and T2 for an external pair, and
    # beyond the nearer tangency point for an internal pair (both lie on the same side of C).
    if internal_2:
        start, end = tip_roll_2 - line, tip_roll_1
        lower, upper = 0.0, math.inf
    elif internal_1:
        start, end = tip_roll_1, line + tip_roll_2
        lower, upper = line, math.inf
    else:
        start, end = line - tip_roll_2, tip_roll_1
        lower, upper = 0.0, line
    if start < lower or end > upper:
        raise InvoluteInterference(start, end, lower, upper)

    length = end - start
    contact_ratio = length / base_pitch
    if contact_ratio < 1.0:
        raise ContactRatioBelowOne(contact_ratio, length, base_pitch)
    return PathOfContact(
        base_pitch=base_pitch,
        length=length,
        contact_ratio=contact_ratio,
        overlap_ratio=overlap_ratio,
        start_roll_1=start,
        pitch_roll_1=base_1 * math.tan(alpha_wt),
        single_start=length - base_pitch,
        single_end=base_pitch,
        tip_radius_1=float(tip_radius_1),
        tip_radius_2=float(tip_radius_2),
        working_pressure_angle=alpha_wt,
    )


def pairs_in_contact(path: PathOfContact, s: float | npt.ArrayLike) -> np.ndarray:
    """Number of tooth pairs in contact when one pair sits at roll position s.

    s is measured from A along the line of action [m] and taken modulo p_bt, so any pair can
    serve as the reference. The pairs sit at s, s + p_bt, s + 2 p_bt, ...; those with
    s + k p_bt ≤ g_α are in contact. This gives 1 or 2 pairs for 1 < ε_α < 2, and up to 3 for
    2 < ε_α < 3. Zone ends count as the zone with more pairs, up to rounding.

    Returns:
        Integer array with the shape of s.
    """
    phase = np.mod(np.asarray(s, dtype=float), path.base_pitch)
    return (np.floor((path.length - phase) / path.base_pitch) + 1.0).astype(int)


# --- errors ------------------------------------------------------------------------------------


class TipInsideBaseCircle(InvalidGearTrain):
    """A tip circle lies inside its base circle, where no involute exists."""

    def __init__(self, gear: int, tip_radius: float, base_radius: float):
        self.gear = gear
        self.tip_radius = tip_radius
        self.base_radius = base_radius
        super().__init__(
            f"gear {gear}: tip radius {tip_radius * 1e3:.4f} mm is not outside its base radius "
            f"{base_radius * 1e3:.4f} mm, so the flank has no involute to roll on; for an "
            "internal gear raise its tip radius (a more negative ISO profile shift), for an "
            "external gear check the tip radius and addendum"
        )


class InvoluteInterference(InvalidGearTrain):
    """The path of contact runs past a tangency point of the line of action."""

    def __init__(self, start: float, end: float, lower: float, upper: float):
        self.start = start
        self.end = end
        self.lower = lower
        self.upper = upper
        super().__init__(
            f"the path of contact runs from {start * 1e3:.4f} to {end * 1e3:.4f} mm from T1, "
            f"but the involutes only cover {lower * 1e3:.4f} to {upper * 1e3:.4f} mm: a tip "
            "reaches past the mating gear's base-circle tangency point (involute "
            "interference). Shift the small gear's profile positively, or shorten the tips "
            "with tip_radius_1/tip_radius_2"
        )


class ContactRatioBelowOne(InvalidGearTrain):
    """The transverse contact ratio is below 1: the teeth lose contact once per pitch."""

    def __init__(self, contact_ratio: float, length: float, base_pitch: float):
        self.contact_ratio = contact_ratio
        self.length = length
        self.base_pitch = base_pitch
        super().__init__(
            f"transverse contact ratio ε_α = {contact_ratio:.4f} < 1 (path of contact "
            f"{length * 1e3:.4f} mm, base pitch {base_pitch * 1e3:.4f} mm): one pair leaves "
            "contact before the next one enters. Lengthen the tips (addendum_coefficient or "
            "tip radii), reduce the working pressure angle (less total profile shift), or use "
            "more teeth"
        )
