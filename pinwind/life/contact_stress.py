"""Hertz contact stress of a tooth pair along its path of contact, sample by sample.

Jørgensen 2014 §2.5.2: the two flanks touch as two cylinders whose
radii are the flank radii of curvature at the contact point, the roll distances from the
gears' base tangency points (Fig. 10), as long as the face width:

    B = ½ (1/ρ1 + 1/ρ2)                                        (eq. 20)
    a = √(2/π · (m1 + m2)/B · F/L),  m_i = (1 − ν_i²)/E_i       (eq. 21)
    p_max = 2F / (π a L)                                        (eq. 22)
    σ_vM ≈ 0.65 p_max                                           (§2.5.2, after Norton 2000)

The formulas live in `pinwind.gears.hertz` and the radii in `GearPair.flank_radii`; this
module feeds them a run's single-tooth force and contact position (docs/series.md
``mesh_single_tooth_force``, ``mesh_contact_position``), which give the stress history of the
entering tooth pair of a mesh.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.hertz import VON_MISES_RATIO, hertz_pressure


@dataclass(frozen=True)
class ContactStress:
    """Hertz stress at the contact point of one tooth pair, per sample.

    Attributes:
        rho_1, rho_2: flank radii of curvature of gears 1 and 2 [m], negative for a concave
            (internal gear) flank.
        p_max: maximum Hertz pressure [Pa] (Jørgensen 2014 eq. 22).
        von_mises: σ_vM ≈ 0.65 p_max, the largest von Mises stress, below the surface [Pa].
    """

    rho_1: np.ndarray
    rho_2: np.ndarray
    p_max: np.ndarray
    von_mises: np.ndarray


def contact_stress(
    pair: GearPair, *, force: npt.ArrayLike, position: npt.ArrayLike
) -> ContactStress:
    """Hertz stress of one tooth pair from its normal force and contact position.

    Args:
        pair: the mesh's gears in the model's order, gear 1 = gear A (either may be internal):
            ``GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec, materials)``; its face
            width is the contact length L and its materials give m1, m2.
        force: normal force on the tooth pair [N] (``mesh_single_tooth_force``); its sign (the
            flank) does not matter.
        position: roll distance of the contact point from gear 1's base tangency point [m]
            (``mesh_contact_position``), broadcast against ``force``. A NaN position or force,
            or a position off the involutes (beyond a tangency point), gives NaN.

    Raises:
        InputError: a helical pair (the transverse radii and the face width are not its
            contact's; Jørgensen 2014's stage is spur), or shapes that do not broadcast.
    """
    if pair.helix_angle != 0.0:
        raise InputError(
            f"contact_stress takes spur pairs; {pair.names[0]}/{pair.names[1]} has a helix angle "
            f"of {math.degrees(pair.helix_angle):g}°, whose contact lines are inclined: rate it "
            "with ISO 6336-2 (pinwind.gears.rating_iso) instead"
        )
    try:
        load, roll = np.broadcast_arrays(
            np.asarray(force, dtype=float), np.asarray(position, dtype=float)
        )
    except ValueError as err:
        raise InputError(
            f"force {np.shape(force)} and contact position {np.shape(position)} must have the "
            "same number of samples"
        ) from err
    rho_1, rho_2, on_flanks = on_involutes(pair, roll)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = hertz_pressure(load, rho_1, rho_2, pair.face_width, *pair.materials)
    p = np.where(on_flanks & np.isfinite(load), p, np.nan)
    return ContactStress(rho_1=rho_1, rho_2=rho_2, p_max=p, von_mises=VON_MISES_RATIO * p)


def on_involutes(pair: GearPair, roll: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ρ1, ρ2, on): flank radii of curvature [m] and contact on both involutes, per roll.

    ``roll`` is the distance from gear 1's base tangency point [m] (`GearPair.flank_radii`).

    An involute starts at its base circle: past a tangency point the flank's radius changes
    sign (external flanks are convex, ρ > 0; internal ones concave, ρ < 0) and there is no
    contact there.
    """
    rho_1, rho_2 = (np.asarray(r, dtype=float) for r in pair.flank_radii(np.asarray(roll)))
    on = (np.where(pair.internal_1, -rho_1, rho_1) > 0.0) & (
        np.where(pair.internal_2, -rho_2, rho_2) > 0.0
    )
    return rho_1, rho_2, on
