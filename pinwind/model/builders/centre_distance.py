"""Working geometry of the builders' pairs, and the profile shift that gives a centre distance."""

from __future__ import annotations

import math

from scipy.optimize import brentq

from pinwind.errors import InvalidGearTrain
from pinwind.gears.involute import (
    PairGeometry,
    involute,
    pair_geometry,
    pitch_radius,
    transverse_pressure_angle,
)


def shift_sum_for_centre_distance(
    teeth_1: int,
    teeth_2: int,
    *,
    module: float,
    pressure_angle: float,
    centre_distance: float,
    internal_2: bool = False,
    helix_angle: float = 0.0,
) -> float:
    """Total profile shift x1 + x2 that gives a pair exactly ``centre_distance`` [m].

    Solves ``pair_geometry(...).centre_distance = centre_distance`` for x1 + x2 (ISO 21771; for
    an internal gear 2 the ISO sign convention of ``gears/involute.py``); ``helix_angle`` β
    [rad] of a helical pair.
    """

    def excess(x_sum: float) -> float:
        geo = pair_geometry(
            teeth_1,
            teeth_2,
            module=module,
            pressure_angle=pressure_angle,
            profile_shift_1=x_sum,
            internal_2=internal_2,
            helix_angle=helix_angle,
        )
        return geo.centre_distance - centre_distance

    reference = pitch_radius(
        abs(teeth_1 + (-teeth_2 if internal_2 else teeth_2)), module, helix_angle
    )
    span = 2.0 * abs(centre_distance - reference) / module + 0.1
    low, high = -span, span
    # inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2) must stay positive (ISO 21771)
    z_sum = teeth_1 - teeth_2 if internal_2 else teeth_1 + teeth_2
    alpha_t = transverse_pressure_angle(pressure_angle, helix_angle)
    limit = -involute(alpha_t) * z_sum / (2.0 * math.tan(pressure_angle)) * (1.0 - 1e-9)
    if z_sum > 0:
        low = max(low, limit)
    else:
        high = min(high, limit)
    try:
        return float(brentq(excess, low, high, xtol=1e-14))
    except ValueError as err:
        raise InvalidGearTrain(
            f"no profile shift puts {teeth_1} and {teeth_2} teeth of module {module * 1e3:g} mm "
            f"at {centre_distance * 1e3:g} mm (reference {reference * 1e3:g} mm)"
        ) from err


def working_pair(
    z1: int,
    z2: int,
    *,
    module: float,
    alpha: float,
    x1: float,
    x2: float,
    internal: bool = False,
    helix_angle: float = 0.0,
) -> PairGeometry:
    """``pair_geometry`` of a pair, or ``InvalidGearTrain`` when it has no working geometry.

    Args:
        z1, z2: tooth counts (gear 2 internal when ``internal``).
        module: module [m].
        alpha: pressure angle [rad].
        x1, x2: profile shifts, ISO sign convention.
        internal: gear 2 is an internal gear.
        helix_angle: helix angle β [rad] (0: spur).
    """
    try:
        return pair_geometry(
            z1,
            z2,
            module=module,
            pressure_angle=alpha,
            profile_shift_1=x1,
            profile_shift_2=x2,
            internal_2=internal,
            helix_angle=helix_angle,
        )
    except ValueError as err:
        kind = "internal" if internal else "external"
        raise InvalidGearTrain(
            f"an {kind} pair of {z1} and {z2} teeth with profile shifts {x1:g} and {x2:g} has no "
            f"working geometry: {err}"
        ) from err
