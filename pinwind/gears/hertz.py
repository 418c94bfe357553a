"""Hertz contact stress along the path of contact (Jørgensen 2014 eqs. 20-22).

Two cylinders of radii ρ1, ρ2 (the flank radii of curvature, i.e. the roll distances from the
tangency points T1, T2 to the contact point, Jørgensen 2014 Fig. 10) and length L pressed by F:

    B = ½ (1/ρ1 + 1/ρ2)                                  (eq. 20; ρ2 < 0 for an internal gear)
    a = √(2/π · (m1 + m2)/B · F/L),  m_i = (1 − ν_i²)/E_i   (eq. 21, contact half-width)
    p_max = 2F/(π a L)                                    (eq. 22)
    σ_vM ≈ 0.65 p_max                      (Jørgensen 2014 §2.5.2, after Norton 2000)

which is the classical p_max = √(F E*/(π L R)), 1/R = 1/ρ1 + 1/ρ2, 1/E* = m1 + m2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError
from pinwind.gears.contact import pairs_in_contact
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.materials import Material

#: σ_vM / p_max: the mean of Norton's static (0.57) and sliding (0.73) coefficients
#: (Jørgensen 2014).
VON_MISES_RATIO = 0.65


def hertz_pressure(
    force: npt.ArrayLike,
    rho_1: npt.ArrayLike,
    rho_2: npt.ArrayLike,
    length: float,
    material_1: Material,
    material_2: Material,
) -> np.ndarray:
    """Maximum Hertz pressure p_max [Pa] of two cylinders (Jørgensen 2014 eqs. 20-22).

    Args:
        force: normal force F on the pair of teeth [N].
        rho_1, rho_2: radii of curvature [m]; ρ2 negative for a concave (internal) flank.
        length: contact length L [m].
        material_1, material_2: the two gears' materials (E, ν).
    """
    if length <= 0.0:
        raise InputError(f"the contact length must be positive, got {length} m")
    force = np.asarray(force, dtype=float)
    curvature = 0.5 * (1.0 / np.asarray(rho_1, dtype=float) + 1.0 / np.asarray(rho_2, dtype=float))
    m_sum = (1.0 - material_1.poisson_ratio**2) / material_1.youngs_modulus + (
        1.0 - material_2.poisson_ratio**2
    ) / material_2.youngs_modulus
    half_width = np.sqrt(2.0 / math.pi * m_sum / curvature * np.abs(force) / length)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(half_width > 0.0, 2.0 * np.abs(force) / (math.pi * half_width * length), 0.0)
    return p


@dataclass(frozen=True)
class HertzAlongPath:
    """Hertz stress of one tooth pair as it runs from A to E.

    Attributes:
        roll: position from A along the line of action [m], (n,).
        rho_1, rho_2: flank radii of curvature of gears 1 and 2 [m] (ρ2 < 0 internal), (n,).
        pairs: tooth pairs in contact, (n,).
        force: force on this pair [N] (the mesh force shared equally between the pairs in
            contact), (n,).
        p_max: maximum Hertz pressure [Pa], (n,).
        von_mises: σ_vM ≈ 0.65 p_max [Pa], (n,).
    """

    roll: np.ndarray
    rho_1: np.ndarray
    rho_2: np.ndarray
    pairs: np.ndarray
    force: np.ndarray
    p_max: np.ndarray
    von_mises: np.ndarray

    @property
    def largest(self) -> float:
        """Largest p_max along the path [Pa]."""
        return float(np.max(self.p_max))


def hertz_along_path(pair: GearPair, normal_force: float, *, points: int = 201) -> HertzAlongPath:
    """Hertz pressure along the path of contact of a pair carrying the mesh force ``normal_force``.

    Where two pairs are in contact each carries half the force (equal pair stiffness, the rigid
    mesh's sharing); in the single-pair zone one pair carries all of it. ρ1 is the roll distance
    from T1; ρ2 = T1T2 − ρ1 for an external pair and −(T1T2 + ρ1) for an internal gear 2
    (concave flank), T1T2 = a_w sin α_wt (`GearPair.flank_radii`).

    Args:
        pair: the pair, external gear 1: its path of contact (`GearPair.path`), face width
            (the contact length L) and materials.
        normal_force: mesh normal force F_n [N].
        points: evenly spaced samples from A to E; the zone ends B and D are added to them.

    Raises:
        InvalidGearTrain: gear 1 is internal, or the pair has no valid path of contact.
    """
    pair.require_external_gear_1("hertz_along_path")
    path = pair.path
    # The samples include the zone ends B and D: over each zone the pair's force is constant and
    # the curvature 1/ρ1 + 1/ρ2 = T1T2/(ρ1 |ρ2|) is largest at an end of it (ρ1 |ρ2| has no
    # interior minimum: concave in ρ1 for an external pair, increasing for an internal one), so
    # the largest pressure sits at A, B, D or E and `largest` is exact, not a sample's near B.
    ends = [s for s in (path.single_start, path.single_end) if 0.0 < s < path.length]
    roll = np.unique(np.concatenate([np.linspace(0.0, path.length, points), ends]))
    rho_1, rho_2 = pair.flank_radii(path.start_roll_1 + roll)
    # Pairs in contact at each position of this pair: round half a nanometre towards the zone
    # with fewer pairs so that the zone ends B and D belong to the single-pair zone.
    pairs = np.minimum(
        pairs_in_contact(path, np.clip(roll - 1e-9, 0.0, None)),
        pairs_in_contact(path, np.minimum(roll + 1e-9, path.length)),
    )
    force = normal_force / np.maximum(pairs, 1)
    p = hertz_pressure(force, rho_1, rho_2, pair.face_width, *pair.materials)
    return HertzAlongPath(roll, rho_1, rho_2, pairs, force, p, VON_MISES_RATIO * p)
