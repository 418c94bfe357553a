"""Geometry checks a gear designer expects: undercut, tip thickness, internal-pair interference.

Each check returns `Finding` objects (nothing wrong: an empty list) rather than raising, so that a
design sweep can record every problem of a design in one row. `check_pair` and `check_planetary`
run them all; `raise_for` turns the first error into an exception for callers that want one.

Conventions as in `pinwind.gears.involute` and `pinwind.gears.contact`: SI units, angles in
radians, ISO 21771 sign of the profile shift (an internal gear counts with a negative tooth number
inside the formulas; its tip circle is r − m_n (h_a* + x)). The transverse and overlap contact
ratios are `pinwind.gears.contact.path_of_contact`'s; this module does not recompute them.

Sources of the formulas (each repeated where it is used):

- virtual tooth number z_n = z / (cos² β_b cos β) (ISO 21771; ISO 6336-1 clause 9);
- undercut: x_min = h_a0* − ρ_a0* (1 − sin α_n) − z sin² α_t / (2 cos β) (DIN 3960 / ISO 21771,
  the tool's straight flank reaching the base circle's tangency point);
- tip thickness: s_at = d_a (s_t/d + inv α_t − inv α_at), s_t = m_t (π/2 + 2 x tan α_n)
  (ISO 21771), with d, d_a negative for an internal gear;
- internal pairs: involute interference (the ring's tip circle reaching past the planet's
  tangency point, `contact.path_of_contact`) and trochoid (tip) interference at the end of
  contact, KHK "Gear Technical Reference", internal gears: θ1 z1/z2 + inv α_w − inv α_a2 ≥ θ2.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

from pinwind.errors import InvalidGearTrain
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.involute import (
    base_radius,
    half_tooth_angle,
    involute,
    transverse_pressure_angle,
)
from pinwind.gears.involute import tip_radius as unshortened_tip_radius
from pinwind.gears.involute import virtual_teeth as virtual_teeth

#: Tool addendum h_a0* of the ISO 53 profile A hob (= basic rack dedendum h_fP*) [-].
TOOL_ADDENDUM = 1.25
#: Tool tip radius ρ_a0* of the ISO 53 profile A hob (= basic rack root radius ρ_fP*) [-].
TOOL_TIP_RADIUS = 0.38
#: Minimum tip thickness as a fraction of the normal module: 0.2 m_n for through-hardened
#: teeth, 0.4 m_n for case-hardened ones (common design practice, e.g. Niemann/Winter Vol. II).
MIN_TIP_THICKNESS = {"through_hardened": 0.2, "case_hardened": 0.4}


@dataclass(frozen=True)
class Finding:
    """One result of a geometry check.

    Attributes:
        check: what was checked: ``"undercut"``, ``"tip_thickness"``, ``"involute_interference"``,
            ``"trochoid_interference"``, ``"contact_ratio"``, ``"assembly"``,
            ``"planet_clearance"``.
        severity: ``"error"`` (the design cannot work) or ``"warning"`` (it works with a penalty).
        gear: the gear concerned (``"gear 1"``, ``"sun"``, ...) or the pair's name.
        value: the checked quantity in SI units (a profile shift, a thickness [m], ...).
        limit: the limit it was checked against, same unit.
        message: what is wrong and how to fix it.
    """

    check: str
    severity: str
    gear: str
    value: float
    limit: float
    message: str


def min_profile_shift(
    teeth: int,
    *,
    pressure_angle: float,
    helix_angle: float = 0.0,
    tool_addendum: float = TOOL_ADDENDUM,
    tool_tip_radius: float = TOOL_TIP_RADIUS,
) -> float:
    """Smallest profile shift of an external gear cut by a rack tool without undercut [-].

    x_min = h_a0* − ρ_a0* (1 − sin α_n) − z sin² α_t / (2 cos β) (DIN 3960, ISO 21771): the end of
    the tool's straight flank must not pass the tangency point of the line of action on the base
    circle. With the ISO 53 profile A tool (h_a0* 1.25, ρ_a0* 0.38) and α_n = 20° the straight
    flank ends 1.000 m_n above the datum line, so a spur gear needs 17.1 teeth (x = 0).
    """
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    straight = _straight_flank_end(pressure_angle, tool_addendum, tool_tip_radius)
    return straight - teeth * math.sin(alpha_t) ** 2 / (2.0 * math.cos(helix_angle))


def tip_thickness(
    teeth: int,
    *,
    module: float,
    pressure_angle: float,
    profile_shift: float = 0.0,
    helix_angle: float = 0.0,
    internal: bool = False,
    tip_radius: float | None = None,
    addendum_coefficient: float = 1.0,
) -> float:
    """Transverse tooth thickness on the tip circle, s_at [m] (ISO 21771).

    s_at = d_a (s_t/d + inv α_t − inv α_at) with s_t = m_t (π/2 + 2 x tan α_n) and
    cos α_at = d_b/d_a. For an internal gear d and d_a count negative (ISO sign convention), so
    s_at = |d_a| (s_t/|d| − inv α_t + inv α_at): its teeth thin towards the tip, which is the
    inner circle. A negative value means the flanks cross below the tip circle (pointed teeth).
    That is s_at = 2 r_a ψ(r_a), ψ the half tooth angle of ``involute.half_tooth_angle``.
    """
    if tip_radius is None:
        tip_radius = unshortened_tip_radius(
            teeth, module, profile_shift, helix_angle, internal, addendum_coefficient
        )
    if tip_radius <= base_radius(teeth, module, pressure_angle, helix_angle):
        return math.nan  # no involute at the tip; reported by path_of_contact
    half_angle = half_tooth_angle(
        teeth,
        module=module,
        pressure_angle=pressure_angle,
        radius=tip_radius,
        profile_shift=profile_shift,
        helix_angle=helix_angle,
        internal=internal,
    )
    return 2.0 * tip_radius * half_angle


def check_gear(
    teeth: int,
    *,
    module: float,
    pressure_angle: float,
    profile_shift: float = 0.0,
    helix_angle: float = 0.0,
    internal: bool = False,
    name: str = "gear",
    case_hardened: bool = True,
    tip_radius: float | None = None,
) -> list[Finding]:
    """Undercut (external gears) and tip thickness of one gear.

    Tip thickness below 0.4 m_n (case hardened, ``case_hardened=True``) or 0.2 m_n (through
    hardened) is a warning; a pointed tooth (≤ 0) is an error. Undercut is an error: the root is
    cut away below the base circle and the contact ratio and root strength both drop.
    """
    findings = []
    if not internal:
        x_min = min_profile_shift(teeth, pressure_angle=pressure_angle, helix_angle=helix_angle)
        if profile_shift < x_min - 1e-12:
            z_free = _teeth_without_undercut(pressure_angle, helix_angle, profile_shift)
            findings.append(
                Finding(
                    "undercut",
                    "error",
                    name,
                    profile_shift,
                    x_min,
                    f"{name} ({teeth} teeth, x = {profile_shift:+.3f}) is undercut: a rack tool "
                    f"cuts into its flank below the base circle unless x ≥ {x_min:+.3f}; use at "
                    f"least {z_free} teeth, or a profile shift of {x_min:+.3f} or more",
                )
            )
    s_at = tip_thickness(
        teeth,
        module=module,
        pressure_angle=pressure_angle,
        profile_shift=profile_shift,
        helix_angle=helix_angle,
        internal=internal,
        tip_radius=tip_radius,
    )
    s_an = s_at * math.cos(helix_angle)  # normal tip thickness (at the tip, close enough)
    limit = MIN_TIP_THICKNESS["case_hardened" if case_hardened else "through_hardened"] * module
    if math.isfinite(s_an) and s_an < limit:
        pointed = s_an <= 0.0
        need = (
            f"{limit * 1e3:.3f} mm ({limit / module:.1f} m_n"
            f"{', case hardened' if case_hardened else ''})"
        )
        verdict = (
            f"not positive: the flanks cross below the tip (pointed teeth); it needs {need}"
            if pointed
            else f"below {need}"
        )
        findings.append(
            Finding(
                "tip_thickness",
                "error" if pointed else "warning",
                name,
                s_an,
                limit,
                f"{name} ({teeth} teeth, x = {profile_shift:+.3f}): tip thickness "
                f"{s_an * 1e3:.3f} mm is {verdict}; reduce the profile shift or shorten the tip",
            )
        )
    return findings


def check_pair(pair: GearPair, *, case_hardened: bool = True) -> list[Finding]:
    """All checks of a pair: each gear (`check_gear`), path of contact, internal interference.

    The gears are named by ``pair.names`` in the findings. The path of contact comes from
    `contact.path_of_contact`; its errors (tip inside the base circle, involute interference,
    ε_α < 1) become findings. For an internal gear the trochoid (tip) interference at the end
    of contact is checked too (`trochoid_clearance`).
    """
    findings: list[Finding] = []
    for gear in (1, 2):
        teeth, shift, internal = pair.gear(gear)
        findings += check_gear(
            teeth,
            module=pair.module,
            pressure_angle=pair.pressure_angle,
            profile_shift=shift,
            helix_angle=pair.helix_angle,
            internal=internal,
            name=pair.names[gear - 1],
            case_hardened=case_hardened,
            tip_radius=pair.tip_radius(gear),
        )
    names = pair.names
    label = f"{names[0]}–{names[1]}"
    try:
        pair.path_of_contact()
    except InvalidGearTrain as err:
        kind = type(err).__name__
        check = {
            "InvoluteInterference": "involute_interference",
            "ContactRatioBelowOne": "contact_ratio",
        }.get(kind, "path_of_contact")
        value = getattr(err, "contact_ratio", math.nan)
        findings.append(Finding(check, "error", label, value, 1.0, f"{label}: {err}"))
    if pair.internal_1 or pair.internal_2:
        ring_last = pair if pair.internal_2 else pair.reversed()
        clearance = trochoid_clearance(ring_last)
        if clearance < 0.0:
            (z1, z2), (n1, n2) = (ring_last.teeth_1, ring_last.teeth_2), ring_last.names
            findings.append(
                Finding(
                    "trochoid_interference",
                    "error",
                    label,
                    clearance,
                    0.0,
                    f"{label}: the tip of {n1} ({z1} teeth) fouls the tips of "
                    f"{n2} ({z2} teeth, internal) as it leaves the mesh (trochoid "
                    f"interference, clearance {clearance:+.4f} rad < 0); the tooth numbers differ "
                    f"by only {z2 - z1}: use a larger difference, or shift the "
                    "internal gear's profile (positive ISO x) to shorten its teeth",
                )
            )
    return findings


def trochoid_clearance(pair: GearPair) -> float:
    """Trochoid interference margin of an external gear 1 in an internal gear 2 [rad].

    KHK "Gear Technical Reference" (internal gears, trochoid interference), spur gears: as the
    pinion's tip leaves the mesh it must pass clear of the ring's tips,

        θ1 z1/z2 + inv α_w − inv α_a2 − θ2 ≥ 0
        θ1 = acos((r_a2² − r_a1² − a²) / (2 a r_a1)) + inv α_a1 − inv α_w
        θ2 = acos((a² + r_a2² − r_a1²) / (2 a r_a2))

    with r_a1, r_a2 the tip radii (r_a2 the ring's inner radius), α_a the pressure angles there
    and a, α_w the working centre distance and pressure angle. The formula is for spur gears: a
    helical pair is checked as its spur equivalent (β = 0). Returns the left-hand side; below 0
    the tips collide. The tips are assumed not to overlap radially beyond the centre distance
    (r_a2 − r_a1 < a); if they do the acos arguments leave [−1, 1] and the margin is −inf.

    Raises:
        InvalidGearTrain: gear 2 is not internal.
    """
    if not pair.internal_2:
        raise InvalidGearTrain(
            f"the trochoid clearance is that of an external gear in an internal gear 2; "
            f"{pair.names[1]} is not internal (set internal_2=True)"
        )
    spur = replace(pair, helix_angle=0.0)
    geometry = spur.geometry
    a = geometry.centre_distance
    alpha_w = geometry.working_pressure_angle
    r_a1, r_a2 = spur.tip_radius(1), spur.tip_radius(2)
    r_b1, r_b2 = geometry.base_radius_1, geometry.base_radius_2
    if r_a1 <= r_b1 or r_a2 <= r_b2:
        return -math.inf
    alpha_a1 = math.acos(r_b1 / r_a1)
    alpha_a2 = math.acos(r_b2 / r_a2)
    c1 = (r_a2**2 - r_a1**2 - a**2) / (2.0 * a * r_a1)
    c2 = (a**2 + r_a2**2 - r_a1**2) / (2.0 * a * r_a2)
    if not (-1.0 <= c1 <= 1.0 and -1.0 <= c2 <= 1.0):
        return -math.inf
    theta_1 = math.acos(c1) + involute(alpha_a1) - involute(alpha_w)
    theta_2 = math.acos(c2)
    z1, z2 = pair.teeth_1, pair.teeth_2
    return theta_1 * z1 / z2 + involute(alpha_w) - involute(alpha_a2) - theta_2


def check_planetary(
    *,
    sun: int,
    planet: int,
    ring: int,
    planets: int,
    module: float,
    pressure_angle: float,
    face_width: float,
    profile_shift: tuple[float, float, float] = (0.0, 0.0, 0.0),
    helix_angle: float = 0.0,
    case_hardened: bool = True,
) -> list[Finding]:
    """Checks of a simple planetary stage: both pairs, assembly and neighbouring planets.

    Besides `check_pair` on sun–planet and planet–ring (`stage_pairs`): equally spaced
    identical planets need (z_sun + z_ring)/N whole (error otherwise), and neighbouring planets'
    tip circles must clear each other, 2 r_a,planet < 2 a sin(π/N) (error).
    """
    sun_planet, planet_ring = stage_pairs(
        sun=sun, planet=planet, ring=ring, module=module, pressure_angle=pressure_angle,
        face_width=face_width, profile_shift=profile_shift, helix_angle=helix_angle,
    )  # fmt: skip
    findings = check_pair(sun_planet, case_hardened=case_hardened)
    ring_pair = check_pair(planet_ring, case_hardened=case_hardened)
    seen = {(f.check, f.gear) for f in findings}
    findings += [f for f in ring_pair if (f.check, f.gear) not in seen]
    if (sun + ring) % planets:
        findings.append(
            Finding(
                "assembly",
                "error",
                "stage",
                (sun + ring) / planets,
                round((sun + ring) / planets),
                f"(z_sun + z_ring)/N = ({sun} + {ring})/{planets} = {(sun + ring) / planets:.4g} "
                f"is not a whole number: {planets} identical planets cannot be assembled equally "
                "spaced",
            )
        )
    a = sun_planet.geometry.centre_distance
    tip = sun_planet.tip_radius(2)
    chord = 2.0 * a * math.sin(math.pi / planets)
    if planets > 1 and 2.0 * tip >= chord:
        findings.append(
            Finding(
                "planet_clearance",
                "error",
                "planet",
                2.0 * tip,
                chord,
                f"{planets} planets of tip diameter {2 * tip * 1e3:.2f} mm collide: neighbouring "
                f"centres are only {chord * 1e3:.2f} mm apart; use fewer or smaller planets",
            )
        )
    return findings


def stage_pairs(
    *,
    sun: int,
    planet: int,
    ring: int,
    module: float,
    pressure_angle: float,
    face_width: float,
    profile_shift: tuple[float, float, float] = (0.0, 0.0, 0.0),
    helix_angle: float = 0.0,
) -> tuple[GearPair, GearPair]:
    """The sun–planet and planet–ring `GearPair` of a simple planetary stage, ring internal."""
    x_s, x_p, x_r = profile_shift
    sun_planet = GearPair(
        sun,
        planet,
        module=module,
        pressure_angle=pressure_angle,
        face_width=face_width,
        profile_shift_1=x_s,
        profile_shift_2=x_p,
        helix_angle=helix_angle,
        names=("sun", "planet"),
    )
    planet_ring = replace(
        sun_planet,
        teeth_1=planet,
        teeth_2=ring,
        profile_shift_1=x_p,
        profile_shift_2=x_r,
        internal_2=True,
        names=("planet", "ring"),
    )
    return sun_planet, planet_ring


def raise_for(findings: Iterable[Finding]) -> None:
    """Raise `InvalidGearTrain` with the message of the first error, if any."""
    for finding in findings:
        if finding.severity == "error":
            raise InvalidGearTrain(finding.message)


def errors(findings: Iterable[Finding]) -> list[Finding]:
    """The findings of severity ``"error"``."""
    return [f for f in findings if f.severity == "error"]


def _teeth_without_undercut(pressure_angle: float, helix_angle: float, shift: float) -> int:
    """Smallest tooth count without undercut at profile shift ``shift``."""
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    straight = _straight_flank_end(pressure_angle, TOOL_ADDENDUM, TOOL_TIP_RADIUS)
    return math.ceil(2.0 * math.cos(helix_angle) * (straight - shift) / math.sin(alpha_t) ** 2)


def _straight_flank_end(
    pressure_angle: float, tool_addendum: float, tool_tip_radius: float
) -> float:
    """End of a rack tool's straight flank above its datum line, h_a0* − ρ_a0* (1 − sin α_n) [-]."""
    return tool_addendum - tool_tip_radius * (1.0 - math.sin(pressure_angle))
