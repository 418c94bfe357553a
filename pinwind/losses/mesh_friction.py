"""A gear mesh's mean coefficient of friction μ_mz and tooth-loss factor H_V (ISO/TR 14179-2).

**Mean coefficient of friction** (ISO/TR 14179-2:2001, the load-dependent gear losses; the
formula of Schlenk 1994 and Michaelis, FZG, fitted on FZG test gears with mineral oil):

    μ_mz = 0.048 (F_bt/b / (v_Σc ρ_redC))^0.2 η_oil^(−0.05) Ra^0.25 X_L

in the standard's units: F_bt the transverse tangential load on the base circle [N], b the face
width [mm], v_Σc = 2 v_t sin α_wt the sum velocity at the pitch point [m/s] (v_t the pitch-line
speed), ρ_redC the reduced radius of curvature at the pitch point, normal section [mm], η_oil the
oil's dynamic viscosity at its temperature [mPa·s], Ra = (Ra1 + Ra2)/2 the mean arithmetic
roughness [µm] and X_L the lubricant factor (``LUBRICANT_FACTORS``: 1 for mineral oil). pinwind
takes every argument in SI and converts. μ_mz grows without bound as v_Σc → 0 (the fit covers
mixed and full-film friction at speed, not start-up): ``mean_friction_coefficient`` refuses
v_Σc ≤ 0.

**Tooth-loss factor** (Ohlendorf 1958, as ISO/TR 14179-2 gives it): the load-dependent mesh loss
is P_VZP = P_in μ_mz H_V with

    H_V = π (u + 1) / (z1 u cos β_b) · (1 − ε_α + ε_1² + ε_2²),      1 ≤ ε_α < 2,

u = z2/z1 (negative for an internal wheel), ε_1, ε_2 the addendum contact ratios (the parts of
the path of contact on either side of the pitch point over the base pitch, ε_1 + ε_2 = ε_α).
The bracket is 2 ∫ s(y) |y| dy over the path y ∈ [−ε_1, ε_2] (in base pitches from the pitch
point), s = 1 where one pair is in contact and ½ in the two double-contact zones of width
ε_α − 1 at the path's ends (the load shared equally): Ohlendorf's closed form is that integral
when the pitch point lies in the single-contact zone (ε_1, ε_2 ≥ ε_α − 1). Where it does not (a
pitch point in a double-contact zone or off the path, as in the NREL 5 MW planet–ring meshes,
ε_2 = 0.04 and −0.01), ``tooth_loss_factor`` takes the integral itself, which the closed form
overstates there (by 5 % and 24 % for those meshes).
"""

from __future__ import annotations

import math

import numpy as np

from pinwind.errors import InvalidLossInput
from pinwind.gears.gear_pair import GearPair
from pinwind.losses.oil import Lubricant

#: A value or an array of values (forces, speeds, powers), SI units.
Values = float | np.ndarray

__all__ = [
    "LUBRICANT_FACTORS",
    "addendum_contact_ratios",
    "mean_friction_coefficient",
    "mesh_power_loss",
    "pair_friction_coefficient",
    "pitch_point_conditions",
    "sum_velocity_per_relative_spin",
    "tooth_loss_factor",
]

#: Lubricant factor X_L of ISO/TR 14179-2 by base oil.
LUBRICANT_FACTORS: dict[str, float] = {
    "mineral": 1.0,
    "polyalphaolefin": 0.8,
    "polyglycol": 0.7,
    "polyglycol_water_soluble": 0.6,
    "phosphate_ester": 1.3,
    "traction_fluid": 1.5,
}


def mean_friction_coefficient(
    *,
    transverse_force: Values,
    face_width: float,
    sum_velocity: Values,
    reduced_radius: float,
    dynamic_viscosity: float,
    roughness: float,
    lubricant_factor: float = 1.0,
) -> Values:
    """μ_mz [-] of ISO/TR 14179-2 (module docstring); arrays broadcast.

    Args:
        transverse_force: F_bt, transverse tangential load on the base circle [N] (≥ 0).
        face_width: b [m].
        sum_velocity: v_Σc = 2 v_t sin α_wt at the pitch point [m/s] (> 0).
        reduced_radius: ρ_redC, normal section, at the pitch point [m].
        dynamic_viscosity: η_oil at the oil temperature [Pa·s].
        roughness: Ra = (Ra1 + Ra2)/2 [m].
        lubricant_factor: X_L [-] (``LUBRICANT_FACTORS``).

    Raises:
        InvalidLossInput: a sum velocity ≤ 0 (the fit's μ grows without bound), or a
            non-positive width, radius, viscosity or roughness, or a negative force.
    """
    force = np.asarray(transverse_force, dtype=float)
    speed = np.asarray(sum_velocity, dtype=float)
    if not np.all(np.isfinite(force)) or np.any(force < 0.0):
        raise InvalidLossInput("transverse_force", transverse_force, "give F_bt ≥ 0 [N]")
    if not np.all(np.isfinite(speed)) or np.any(speed <= 0.0):
        raise InvalidLossInput(
            "sum_velocity",
            sum_velocity,
            "ISO/TR 14179-2's μ_mz holds at speed only (it grows without bound as v_Σc → 0); "
            "give v_Σc > 0 [m/s]",
        )
    for name, value in (
        ("face_width", face_width),
        ("reduced_radius", reduced_radius),
        ("dynamic_viscosity", dynamic_viscosity),
        ("roughness", roughness),
        ("lubricant_factor", lubricant_factor),
    ):
        if not (math.isfinite(value) and value > 0.0):
            raise InvalidLossInput(name, value, "must be a finite number > 0 (SI units)")
    line_load = force / (face_width * 1e3)  # N/mm
    group = line_load / (speed * reduced_radius * 1e3)
    return (
        0.048
        * group**0.2
        * (dynamic_viscosity * 1e3) ** -0.05
        * (roughness * 1e6) ** 0.25
        * lubricant_factor
    )


def addendum_contact_ratios(pair: GearPair) -> tuple[float, float]:
    """(ε_1, ε_2) [-]: the path of contact on gear 1's and gear 2's side of the pitch point.

    ε_1 + ε_2 = ε_α (``GearPair.path``): the approach A→C and the recess C→E over p_bt; which
    is which does not matter to H_V (ε_1² + ε_2²).
    """
    path = pair.path
    approach = (path.pitch_roll_1 - path.start_roll_1) / path.base_pitch
    return approach, path.contact_ratio - approach


def tooth_loss_factor(pair: GearPair) -> float:
    """Ohlendorf's H_V [-] of the pair (module docstring); an internal gear as gear 2.

    The bracket is the integral of the sliding over the path with the load shared equally in
    the double-contact zones: Ohlendorf's 1 − ε_α + ε_1² + ε_2² where the pitch point lies in
    the single-contact zone, the integral itself where it does not.

    Raises:
        InvalidLossInput: ε_α ≥ 2 (Ohlendorf's formula holds for 1 ≤ ε_α < 2).
    """
    if pair.internal_1:
        pair = pair.reversed()
    eps_1, eps_2 = addendum_contact_ratios(pair)
    eps = eps_1 + eps_2
    if eps >= 2.0:
        raise InvalidLossInput(
            "contact_ratio", eps, "Ohlendorf's H_V holds for 1 ≤ ε_α < 2 (a high-contact pair)"
        )
    u = pair.gear_ratio
    beta_b = pair.base_helix_angle
    return math.pi * (u + 1.0) / (pair.teeth_1 * u * math.cos(beta_b)) * _loss_bracket(eps_1, eps_2)


def _loss_bracket(eps_1: float, eps_2: float) -> float:
    """2 ∫ s(y) |y| dy over the path [−ε_1, ε_2], s = ½ in the double-contact zones (module doc).

    Equals Ohlendorf's 1 − ε_α + ε_1² + ε_2² when the pitch point is in the single-contact zone.
    """

    def area(a: float, b: float) -> float:  # ∫_a^b |y| dy
        return (math.copysign(b * b, b) - math.copysign(a * a, a)) / 2.0

    double = eps_1 + eps_2 - 1.0
    whole = area(-eps_1, eps_2)
    ends = area(-eps_1, -eps_1 + double) + area(eps_2 - double, eps_2)
    return 2.0 * (whole - 0.5 * ends)


def pitch_point_conditions(pair: GearPair, speed_1: float) -> tuple[float, float]:
    """(v_Σc [m/s], ρ_redC [m]) at the pitch point, gear 1 at speed ω1 [rad/s] (carrier frame).

    v_Σc = 2 |ω1| r_w1 sin α_wt; ρ_redC = ρ1 ρ2 / (ρ1 + ρ2) / cos β_b with ρ_i = r_wi sin α_wt
    (ρ2 < 0 for an internal gear 2, concave).
    """
    if pair.internal_1:
        pair = pair.reversed()
    g = pair.geometry
    sin_w = math.sin(float(g.working_pressure_angle))
    rho_1 = g.working_radius_1 * sin_w
    rho_2 = (-1.0 if pair.internal_2 else 1.0) * g.working_radius_2 * sin_w
    reduced = rho_1 * rho_2 / (rho_1 + rho_2) / math.cos(pair.base_helix_angle)
    return 2.0 * abs(speed_1) * g.working_radius_1 * sin_w, reduced


def sum_velocity_per_relative_spin(pair: GearPair) -> float:
    """c_v [m]: the sum velocity at the pitch point per relative spin, v_Σc = c_v |ω2 − ω1|.

    Rolling at the pitch point, |ω1| r_w1 = |ω2| r_w2, so an external pair's relative spin is
    |ω1| + |ω2| = |ω1| (r_w1 + r_w2)/r_w2 and an internal one's |ω1| (r_w2 − r_w1)/r_w2; with
    v_Σc = 2 |ω1| r_w1 sin α_wt (``pitch_point_conditions``)

        c_v = 2 sin α_wt r_w1 r_w2 / (r_w2 ± r_w1),

    + external, − internal (gear 2 the ring). The relative spin does not depend on the frame
    (a carrier's turn cancels), so the step reads v_Σc from the gears' spins alone.
    """
    if pair.internal_1:
        pair = pair.reversed()
    g = pair.geometry
    r_1, r_2 = g.working_radius_1, g.working_radius_2
    per_speed_1, _ = pitch_point_conditions(pair, 1.0)
    return per_speed_1 * r_2 / (r_2 - r_1 if pair.internal_2 else r_2 + r_1)


def pair_friction_coefficient(
    pair: GearPair,
    *,
    transverse_force: Values,
    pitch_line_speed: Values,
    oil: Lubricant,
    roughness: float,
    lubricant_factor: float = 1.0,
) -> Values:
    """μ_mz [-] of ``pair`` at an operating point: what a model sets as a mesh's μ.

    ``mean_friction_coefficient`` at the pair's pitch point (``pitch_point_conditions``):
    v_Σc = 2 v_t sin α_wt, ρ_redC from the working pitch radii, η the oil's at its temperature.

    Args:
        pair: the gear pair (its face width, working geometry and base helix angle).
        transverse_force: F_bt, the mesh's force along the line of action in the transverse
            plane [N] (a run's ``mesh_normal``).
        pitch_line_speed: v_t at the working pitch circle, relative to the carrier [m/s] (> 0).
        oil: the gear oil at its temperature (``Lubricant``).
        roughness: Ra = (Ra1 + Ra2)/2 of the flanks [m].
        lubricant_factor: X_L [-] (``LUBRICANT_FACTORS``).
    """
    sin_w = math.sin(float(pair.geometry.working_pressure_angle))
    _, reduced = pitch_point_conditions(pair, 1.0)
    return mean_friction_coefficient(
        transverse_force=transverse_force,
        face_width=pair.face_width,
        sum_velocity=2.0 * np.abs(np.asarray(pitch_line_speed, dtype=float)) * sin_w,
        reduced_radius=abs(reduced),
        dynamic_viscosity=oil.dynamic_viscosity(),
        roughness=roughness,
        lubricant_factor=lubricant_factor,
    )


def mesh_power_loss(
    input_power: Values, friction_coefficient: Values, loss_factor: float
) -> Values:
    """P_VZP = P_in μ_mz H_V [W] (ISO/TR 14179-2): the load-dependent loss of one mesh."""
    return np.abs(np.asarray(input_power, dtype=float)) * friction_coefficient * loss_factor
