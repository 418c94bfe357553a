"""The rolling bearings (rows) of one shaft and the one compliant bearing that stands for them.

A shaft often runs in several bearings at their axial positions (a main shaft in INP-A and
INP-B, a planet in two rows; Nejad et al. 2016 Tables VI and IX), each with its own type,
rating C and stiffness, and a stiffness that differs between the two radial directions
(K_y ≠ K_z). The compiled step holds a shaft in one compliant bearing at its joint, with one
radial stiffness for both radial axes (docs/model_format.md "Compliant bearings"). A model file
keeps every row's own data (``<row>`` in the shaft's ``<bearing>``, read into ``BearingRow``)
and gives the step their equivalent (`equivalent_bearing`):

    radial   k_r = Σ_i k_i,                   k_i = (K_y,i + K_z,i)/2
    axial    k_a = Σ_i K_x,i
    tilt     k_t = Σ_i (k_i a_i² + (K_β,i + K_γ,i)/2),   a_i = z_i − z_c

about the stiffness centre z_c = Σ k_i z_i / Σ k_i, where the radial and tilting motions of a
rigid shaft on linear springs uncouple (Σ k_i a_i = 0); the dampers likewise. The mean of K_y
and K_z keeps the trace of the radial stiffness (the mean of the two radial frequencies' squares)
and loses the difference between the two directions.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pinwind.model.bearing_life_data import BearingLifeData


@dataclass(frozen=True)
class BearingRow:
    """One rolling bearing of a shaft, in SI units; axes as Nejad et al. 2016 (x axial).

    Attributes:
        name: the bearing's name in its source (``INP-A``).
        kind: the type (a key of ``model.bearing.BEARING_TYPES``).
        position: axial position from the shaft's bearing centre (its joint) [m].
        rating: basic dynamic load rating C [N], or None when not given.
        stiffness: (K_x axial [N/m], K_y, K_z radial [N/m], K_β, K_γ tilting [N·m/rad]).
        damping: (c_x [N·s/m], c_y, c_z [N·s/m], c_β, c_γ [N·m·s/rad]).
        load_factors: ISO 281 (e, Y1, X2, Y2) of this bearing, or None: the type's.
        size: (outer diameter D, bore d, width B) [m], or None.
        life: its lubrication, cleanliness and inside (``model/bearing_life_data.py``), or
            None: pinwind's defaults.
    """

    name: str
    kind: str
    position: float
    rating: float | None
    stiffness: tuple[float, float, float, float, float]
    damping: tuple[float, float, float, float, float]
    load_factors: tuple[float, float, float, float] | None = None
    size: tuple[float, float, float] | None = None
    life: BearingLifeData | None = None

    @property
    def radial_stiffness(self) -> float:
        """(K_y + K_z)/2 [N/m]: the mean of the two radial directions."""
        return 0.5 * (self.stiffness[1] + self.stiffness[2])

    @property
    def radial_damping(self) -> float:
        """(c_y + c_z)/2 [N·s/m]."""
        return 0.5 * (self.damping[1] + self.damping[2])


@dataclass(frozen=True)
class EquivalentBearing:
    """One compliant bearing for several rows, about their stiffness centre (module docstring).

    Attributes:
        centre: stiffness centre z_c, from the same origin as the rows' positions [m].
        radial_stiffness, axial_stiffness: [N/m].
        tilt_stiffness: [N·m/rad] about each radial axis.
        radial_damping, axial_damping: [N·s/m].
        tilt_damping: [N·m·s/rad].
    """

    centre: float
    radial_stiffness: float
    axial_stiffness: float
    tilt_stiffness: float
    radial_damping: float
    axial_damping: float
    tilt_damping: float


def equivalent_bearing(rows: Sequence[BearingRow]) -> EquivalentBearing:
    """The compliant bearing at the rows' stiffness centre that stands for them all.

    Sums of the rows' radial (mean of K_y, K_z), axial and tilting stiffness, the radial ones
    moved to the centre with the parallel-axis term k_i a_i² (module docstring).

    Raises:
        ValueError: no rows, or rows without radial stiffness.
    """
    if not rows:
        raise ValueError("a shaft's equivalent bearing needs at least one row")
    k = [r.radial_stiffness for r in rows]
    c = [r.radial_damping for r in rows]
    if sum(k) <= 0.0:
        raise ValueError(f"rows {[r.name for r in rows]} have no radial stiffness")
    centre = sum(ki * r.position for ki, r in zip(k, rows, strict=True)) / sum(k)
    arms = [r.position - centre for r in rows]
    return EquivalentBearing(
        centre=centre,
        radial_stiffness=sum(k),
        axial_stiffness=sum(r.stiffness[0] for r in rows),
        tilt_stiffness=sum(
            ki * a**2 + 0.5 * (r.stiffness[3] + r.stiffness[4])
            for ki, a, r in zip(k, arms, rows, strict=True)
        ),
        radial_damping=sum(c),
        axial_damping=sum(r.damping[0] for r in rows),
        tilt_damping=sum(
            ci * a**2 + 0.5 * (r.damping[3] + r.damping[4])
            for ci, a, r in zip(c, arms, rows, strict=True)
        ),
    )
