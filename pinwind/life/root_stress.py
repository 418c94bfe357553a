"""Tooth-root bending stress of a gear of a pair along its path of contact, sample by sample.

The stress at the root fillet on the loaded flank's side (in tension) of the tooth a force
acts on, for a run's single-tooth force and contact position (docs/series.md
``mesh_single_tooth_force``, ``mesh_contact_position``), by one of two models (`RootStress`):

- `IsoRootStress`, ISO 6336-3 method B:

      σ_F = F_t / (b m_n) · Y_F Y_S Y_β,   F_t = F_n cos β_b cos α_t

  with Y_F, Y_S for the load at the outer point of single tooth contact and Y_β from
  `pinwind.gears.rating_iso` (the rating's own formulas). The standard rates the tooth at
  that point with the whole force; here the force the pair carries at each sample is applied
  with the same factors wherever it acts on the flanks, so the stress follows the force (it is
  largest in single contact) but not its lever arm. K_A, K_v, K_Fβ and K_Fα are 1: the
  simulated forces are the dynamic ones of each mesh, the face-load distribution is not
  simulated.
- `TableRootStress`, a table of stress per unit normal force against the contact position on
  the gear's flank, from a finite-element model (Jørgensen 2014
  §2.5.1, Fig. 9: "the normal single gear tooth force multiplied by the polynomial function
  describing the relationship between stresses and base circle arc length"), linear between
  its points and constant beyond its ends.

A helical pair with an overlap ratio ε_β ≥ 1 (`RootStress.mesh_stress`) is rated as
ISO 6336-3:2006 method B rates it, from the whole mesh force: its contact lines sweep the face
and the load per tooth does not jump between one and two pairs as in a spur pair
(`pinwind.life.contact_stress` module docstring), so the standard's nominal root stress

    σ_F = F_t/(b m_n) Y_F Y_S Y_β,   F_t = F_n cos β_b cos α_t

is what each tooth meets on each pass: Y_F, Y_S of the virtual spur gear (z_n, ε_αn =
ε_α/cos² β_b) loaded at its outer point of single contact, as the standard applies the load
of a helical pair, and Y_β = 1 − ε_β β/120° (ε_β taken as 1 above 1). Method B of the 2006
edition has no Y_ε: the contact-ratio factor Y_ε = 0.25 + 0.75/ε_αn belongs to the 1996
edition's method C, which loads the tooth at its tip instead (``form_factors(at_tip=True)``).
A table is a spur pair's (a stress per force against one contact point); it has no helical
form.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.rating_iso import form_factors, root_helix_factor
from pinwind.life.contact_stress import on_involutes, require_full_overlap


class RootStress(ABC):
    """A model of a gear's tooth-root stress under the force of one tooth pair.

    `stress` gives σ_F [Pa] of gear 1 or 2 of a pair per sample from the pair's normal force
    and its contact position, NaN where the position is off the involutes or a value is NaN.
    """

    @abstractmethod
    def stress(
        self, pair: GearPair, gear: int, *, force: npt.ArrayLike, position: npt.ArrayLike
    ) -> np.ndarray:
        """σ_F of ``gear`` (1 or 2) of ``pair`` [Pa].

        Args:
            pair: the mesh's gears in the model's order (as `contact_stress.contact_stress`).
            gear: 1 or 2, the gear of the pair whose root is rated.
            force: normal force on the tooth pair [N]; its sign (the flank) does not matter.
            position: roll distance of the contact from gear 1's base tangency point [m],
                broadcast against ``force``.
        """

    @abstractmethod
    def mesh_stress(self, pair: GearPair, gear: int, *, force: npt.ArrayLike) -> np.ndarray:
        """σ_F of ``gear`` (1 or 2) of a helical ``pair`` under the mesh force [Pa].

        Args:
            pair: the mesh's gears in the model's order, helical with ε_β ≥ 1.
            gear: 1 or 2, the gear of the pair whose root is rated.
            force: the mesh's force normal to the flanks F_n [N], all tooth pairs together
                (``mesh_normal`` is its transverse part F_bt = F_n cos β_b:
                `GearPair.flank_normal_force`); its sign (the flank) does not matter. NaN
                gives NaN.

        Raises:
            InputError: a spur pair or ε_β < 1, or a model without a helical form.
        """

    @abstractmethod
    def describe(self) -> str:
        """The model and its numbers in one line, for the printout and a case's inputs."""


def _load_and_roll(force: npt.ArrayLike, position: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """|force| and position as float arrays of one shape."""
    try:
        load, roll = np.broadcast_arrays(
            np.abs(np.asarray(force, dtype=float)), np.asarray(position, dtype=float)
        )
    except ValueError as err:
        raise InputError(
            f"force {np.shape(force)} and contact position {np.shape(position)} must have the "
            "same number of samples"
        ) from err
    return load, roll


def _check_gear(gear: int) -> None:
    if gear not in (1, 2):
        raise InputError(f"a gear pair has gears 1 and 2, not {gear!r}")


@dataclass(frozen=True)
class IsoRootStress(RootStress):
    """ISO 6336-3 method B: σ_F = F_t/(b m_n) Y_F Y_S Y_β (module docstring)."""

    def factor(self, pair: GearPair, gear: int) -> float:
        """σ_F per newton of normal force, cos β_b cos α_t /(b m_n) Y_F Y_S Y_β [Pa/N]."""
        _check_gear(gear)
        y_f, y_s = form_factors(pair, gear)
        y_beta = root_helix_factor(pair.path.overlap_ratio, pair.helix_angle)
        return pair.tangential_force(1.0) / (pair.face_width * pair.module) * y_f * y_s * y_beta

    def stress(
        self, pair: GearPair, gear: int, *, force: npt.ArrayLike, position: npt.ArrayLike
    ) -> np.ndarray:
        """σ_F [Pa] (`RootStress.stress`)."""
        load, roll = _load_and_roll(force, position)
        _, _, on = on_involutes(pair, roll)
        return np.where(on & np.isfinite(load), self.factor(pair, gear) * load, np.nan)

    def mesh_stress(self, pair: GearPair, gear: int, *, force: npt.ArrayLike) -> np.ndarray:
        """σ_F = F_t/(b m_n) Y_F Y_S Y_β of a helical pair at F_n [Pa] (module docstring)."""
        require_full_overlap(pair, "the helical root stress")
        return self.factor(pair, gear) * np.abs(np.asarray(force, dtype=float))

    def describe(self) -> str:
        """`RootStress.describe`."""
        return "ISO 6336-3 method B (Y_F, Y_S at the outer point of single contact)"


@dataclass(frozen=True)
class TableRootStress(RootStress):
    """Stress per unit normal force against the contact position on the gear's flank.

    Attributes:
        position: the table's positions, rising: the roll distance of the contact from the
            gear's own base tangency point (its base-circle arc length s, Jørgensen 2014
            Fig. 9) [m], or with ``fraction`` the share of the gear's active flank in the mesh,
            0 at its lowest point of contact and 1 at its highest (the tip, unless the mate's
            tip ends the contact first).
        stress_per_force: σ per newton of normal force at each position [Pa/N].
        fraction: whether ``position`` is a fraction of the active flank.

    Raises:
        InputError: fewer than two points, positions not rising, or values not finite.
    """

    position: tuple[float, ...]
    stress_per_force: tuple[float, ...]
    fraction: bool = False

    def __post_init__(self) -> None:
        x, y = np.asarray(self.position, dtype=float), np.asarray(self.stress_per_force, float)
        if x.ndim != 1 or x.shape != y.shape or x.size < 2:
            raise InputError(
                f"a root-stress table needs two or more positions and as many stresses; got "
                f"{x.size} positions and {y.size} stresses"
            )
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y)) and np.all(np.diff(x) > 0)):
            raise InputError(
                f"a root-stress table needs finite values and rising positions; got positions "
                f"{list(self.position)}"
            )

    def flank_position(self, pair: GearPair, gear: int, roll: npt.ArrayLike) -> np.ndarray:
        """The table's position of contacts at roll distances from gear 1's tangency point.

        The gear's |ρ| (its roll distance) [m], or with ``fraction`` its share of the active
        flank between the ends of the path of contact (an internal gear's root is at the
        larger |ρ|).
        """
        _check_gear(gear)
        rho = np.abs(on_involutes(pair, roll)[gear - 1])
        if not self.fraction:
            return rho
        path = pair.path
        ends = np.abs(
            on_involutes(pair, [path.start_roll_1, path.start_roll_1 + path.length])[gear - 1]
        )
        low, high = float(np.min(ends)), float(np.max(ends))
        internal = pair.internal_1 if gear == 1 else pair.internal_2
        share = (rho - low) / (high - low)
        return 1.0 - share if internal else share

    def stress(
        self, pair: GearPair, gear: int, *, force: npt.ArrayLike, position: npt.ArrayLike
    ) -> np.ndarray:
        """σ_F [Pa] (`RootStress.stress`): the force times the table at the contact."""
        load, roll = _load_and_roll(force, position)
        _, _, on = on_involutes(pair, roll)
        per_force = np.interp(
            self.flank_position(pair, gear, roll), self.position, self.stress_per_force
        )
        return np.where(on & np.isfinite(load), per_force * load, np.nan)

    def mesh_stress(self, pair: GearPair, gear: int, *, force: npt.ArrayLike) -> np.ndarray:
        """Not defined: a table rates a spur pair's tooth at one contact point (`RootStress`)."""
        _check_gear(gear)
        raise InputError(
            f"a root-stress table gives a spur tooth's stress against its contact position; "
            f"{pair.names[gear - 1]} is in a helical pair ({pair.names[0]}/{pair.names[1]}, "
            f"β {math.degrees(pair.helix_angle):g}°) whose contact lines cross the face: drop "
            "its root_stress table to rate it by ISO 6336-3"
        )

    def describe(self) -> str:
        """`RootStress.describe`."""
        unit = "fraction of the active flank" if self.fraction else "mm of roll"
        scale = 1.0 if self.fraction else 1e3
        points = ", ".join(
            f"{x * scale:g}: {y * 1e-3:g}"
            for x, y in zip(self.position, self.stress_per_force, strict=True)
        )
        return f"table of MPa per kN against {unit} ({points})"


#: The model of every gear without a table.
ISO_ROOT_STRESS = IsoRootStress()


def table_root_stress(
    *,
    mpa_per_kn: npt.ArrayLike,
    position_mm: npt.ArrayLike | None = None,
    fraction: npt.ArrayLike | None = None,
) -> TableRootStress:
    """A `TableRootStress` from the units of a scenario file: MPa/kN against mm or fraction.

    Raises:
        InputError: neither or both of ``position_mm`` and ``fraction``, or a bad table.
    """
    if (position_mm is None) == (fraction is None):
        raise InputError("give the table's positions as position_mm or fraction (one of them)")
    per_force = tuple(float(v) * 1e3 for v in np.atleast_1d(mpa_per_kn))  # MPa/kN = 1e3 Pa/N
    if fraction is None:
        positions = tuple(float(v) * 1e-3 for v in np.atleast_1d(np.asarray(position_mm)))
        return TableRootStress(positions, per_force)
    shares = tuple(float(v) for v in np.atleast_1d(np.asarray(fraction)))
    return TableRootStress(shares, per_force, True)
