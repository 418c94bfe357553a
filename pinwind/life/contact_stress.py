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
entering tooth pair of a spur mesh.

A helical pair (`helical_contact_stress`) is rated as ISO 6336-2:2006 rates it, from the
whole mesh force: its contact lines are inclined across the face at the base helix angle
β_b, so a tooth pair's line grows, runs and shrinks over the roll span g_α + ε_β p_bt, and
with an overlap ratio ε_β = b sin β/(π m_n) ≥ 1 the lines in contact always span the face:
their total length stays near its mean b ε_α / cos β_b (`pinwind.gears.mesh_stiffness.
contact_line_pair_stiffness`; constant for a whole-number ε_β) and the load per unit length
of line near F_n cos β_b / (b ε_α), with no jump between one and two pairs in contact as in
a spur pair. The standard's nominal contact stress of the pair carries that:

    σ_H = Z_H Z_E Z_ε Z_β √(F_t/(d1 b) · (u + 1)/u),   F_t = F_n cos β_b cos α_t
    Z_H = √(2 cos β_b cos α_wt / (cos² α_t sin α_wt)),  Z_E = √(1/(π Σ (1 − ν_i²)/E_i))
    Z_ε = √(1/ε_α)  (ε_β ≥ 1),   Z_β = 1/√cos β  (the 2006 edition; 1996: √cos β)

with Z_B = Z_D = 1 for ε_β ≥ 1 and the load factors K 1 (the simulated force is the dynamic
one). The formulas are `pinwind.gears.rating_iso`'s (`nominal_contact_stress`, `zone_factor`,
`contact_ratio_factor`, `helix_factor`). At the pitch point of a spur pair Z_H Z_E √(...) is
the Hertz p_max above with the whole force on one pair (Z_ε = Z_β = 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.hertz import VON_MISES_RATIO, hertz_pressure
from pinwind.gears.materials import elastic_coefficient
from pinwind.gears.rating_iso import (
    contact_ratio_factor,
    helix_factor,
    nominal_contact_stress,
    zone_factor,
)


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
            contact's; Jørgensen 2014's stage is spur: use `helical_contact_stress`), or shapes
            that do not broadcast.
    """
    if pair.helix_angle != 0.0:
        raise InputError(
            f"contact_stress takes spur pairs; {pair.names[0]}/{pair.names[1]} has a helix angle "
            f"of {math.degrees(pair.helix_angle):g}°, whose contact lines are inclined: rate it "
            "with helical_contact_stress (ISO 6336-2 from the mesh force) instead"
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


def helical_contact_stress(pair: GearPair, *, force: npt.ArrayLike) -> np.ndarray:
    """ISO 6336-2 contact stress σ_H [Pa] of a helical pair under the mesh force, per sample.

    σ_H = Z_H Z_E Z_ε Z_β √(F_t/(d1 b) · (u + 1)/u) with F_t = F_n cos β_b cos α_t (module
    docstring): the Hertz pressure on the contact lines, the same on every tooth pair in
    contact (ε_β ≥ 1), so each tooth meets it on each pass through the mesh.

    Args:
        pair: the mesh's gears in either order, either of them internal (rated pinion first,
            the internal gear second, as ISO 6336-2 numbers them).
        force: the mesh's force normal to the flanks F_n [N], all tooth pairs together (a
            run logs its transverse part F_bt = F_n cos β_b as ``mesh_normal``:
            `GearPair.flank_normal_force`); its sign (the flank) does not matter. NaN gives
            NaN.

    Raises:
        InputError: a spur pair or an overlap ratio below 1 (`require_full_overlap`).
    """
    require_full_overlap(pair, "helical_contact_stress")
    rated = pair.pinion_first()
    eps_alpha, eps_beta = rated.path.contact_ratio, rated.path.overlap_ratio
    load = rated.tangential_force(np.abs(np.asarray(force, dtype=float)))
    return nominal_contact_stress(
        rated,
        load,
        Z_H=zone_factor(rated),
        Z_E=elastic_coefficient(*rated.materials),
        Z_eps=contact_ratio_factor(eps_alpha, eps_beta),
        Z_beta=helix_factor(rated.helix_angle),
    )


def require_full_overlap(pair: GearPair, method: str) -> None:
    """Raise `InputError` unless ``pair`` is helical with an overlap ratio ε_β ≥ 1.

    ``method`` rates a tooth of a helical pair at the mesh force, which holds where the contact
    lines span the face (`helical_contact_stress`); below ε_β = 1 the load per tooth still
    jumps as the pairs in contact change, partly as in a spur pair.
    """
    eps_beta = pair.path.overlap_ratio
    if eps_beta < 1.0:
        kind = "a spur pair" if pair.helix_angle == 0.0 else f"ε_β = {eps_beta:.4g}"
        raise InputError(
            f"{method} rates helical pairs whose overlap ratio ε_β = b sin β/(π m_n) is 1 or "
            f"more; {pair.names[0]}/{pair.names[1]} has {kind} (b {pair.face_width * 1e3:g} mm, "
            f"β {math.degrees(pair.helix_angle):g}°, m_n {pair.module * 1e3:g} mm): rate a "
            "spur pair along its path (contact_stress), or widen the face or raise β until "
            "ε_β ≥ 1"
        )
