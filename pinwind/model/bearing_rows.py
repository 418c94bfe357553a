"""The rolling bearings (rows) of one shaft: each its own spring-damper in the step.

A shaft often runs in several bearings at their axial positions (a main shaft in INP-A and
INP-B, a planet in two rows; Nejad et al. 2016 Tables VI and IX), each with its own type,
rating C and stiffness, and a stiffness that differs between the two radial directions
(K_y ≠ K_z). A model file keeps every row's own data (``<row>`` in the shaft's ``<bearing>``,
read into ``BearingRow``). When the rows have stiffness and the bearing is compliant (its
slides: docs/model_format.md "Compliant bearings"), the compiled step holds the shaft in each
row (``row_springs``; ``cpp/bearing_rows.hpp``): a linear spring-damper at the row's position a
with its own axial, two radial and two tilt values,

    δ = (z,  x + a θ_w,  y − a θ_u,  θ_u,  θ_w)  for  (K_x, K_y, K_z, K_β, K_γ)

(x, y along the bearing's radial axes u, w, z along its axis k, θ_u, θ_w its tilts). K_y acts
along u and K_z along w: Nejad's axes (x axial, y, z radial) are right-handed as the bearing's
(k, u, w) are, so x → k, y → u, z → w. The rows need not sit about a stiffness centre (Σ k_i a_i
couples the radial slides with the tilts), and each row's load is a series of its own
(``row_force``, ``row_moment``).

The bearing's own stiffness and damping attributes then say which slides the shaft has (an
axial slide with ``axial_stiffness``, tilt hinges with ``tilt_stiffness``) and nothing more. The
rows' laws are linear but for a row's radial clearance c (its ``radial_clearance_mm``, the one
its reference life uses; negative with ``preload="true"``): each radial direction j then sits
between two sides, each a one-sided contact of stiffness K_j,

    L_j = −K_j [max(δ_j − c, 0) − max(−δ_j − c, 0)]

a dead band |δ_j| < c without load for a clearance, both sides pressing (2 K_j) while
|δ_j| < |c| for a preload. A roller sum (``law="roller_sum"``) or the bearing's own clearance is
for a bearing without stiff rows. ``rolling_load`` gives the load the loaded side's rolling
elements carry, preload included (what a skidding check needs). ``equivalent_bearing`` gives
the one isotropic compliant bearing at the rows' stiffness centre that stands for them (what
``pinwind build stages`` writes as the bearing's attributes, for a bearing read without its
rows):

    radial   k_r = Σ_i k_i,                   k_i = (K_y,i + K_z,i)/2
    axial    k_a = Σ_i K_x,i
    tilt     k_t = Σ_i (k_i a_i² + (K_β,i + K_γ,i)/2),   a_i = z_i − z_c

about the stiffness centre z_c = Σ k_i z_i / Σ k_i, where the radial and tilting motions of a
rigid shaft on linear springs uncouple (Σ k_i a_i = 0); the dampers likewise. The mean of K_y
and K_z keeps the trace of the radial stiffness and loses the difference between the two
directions, which the rows in the step keep.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

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
    def clearance(self) -> float:
        """Its radial clearance c [m] (negative: a preload; ``radial_clearance_mm``), or 0."""
        return self.life.clearance if self.life is not None else 0.0

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


def row_springs(compliance: Any, rows: Sequence[BearingRow]) -> list[BearingRow]:
    """The rows that are a compliant bearing's springs in the step, or [] (module docstring).

    Rows are the springs of a bearing that is compliant and not floating (``compliance``, a
    ``BearingCompliance`` or None for an ideal bearing) when any of them has stiffness; rows
    without stiffness only carry ratings.
    """
    if compliance is None or compliance.floating:
        return []
    return list(rows) if any(any(r.stiffness) for r in rows) else []


def row_name(bearing: str, row: str) -> str:
    """A row's name among the run's rows, ``<bearing>.<row>`` (``stage1_planet1.PL-A``).

    Rows are named within their bearing: the planets' bearings have rows of one name.
    """
    return f"{bearing}.{row}"


def rolling_load(force: np.ndarray, stiffness: float, clearance: float) -> np.ndarray:
    """The load the loaded side of a row's radial direction carries [N], from its net load.

    ``force`` is the row's net load along one radial direction [N] (any shape), ``stiffness``
    its K_j [N/m] and ``clearance`` its c [m] (module docstring). With a preload (c < 0) both
    sides touch while |F| < 2 K_j |c|: the shaft is then at δ = −F/(2 K_j) and the loaded side
    carries K_j (|c| + |δ|) = K_j |c| + |F|/2; beyond, and for a clearance or a linear row, one
    side carries the whole |F|. So ``max(|F|, K_j |c| + |F|/2)`` for a preload, ``|F|`` else.
    """
    magnitude = np.abs(np.asarray(force, dtype=float))
    if clearance >= 0.0:
        return magnitude
    return np.maximum(magnitude, stiffness * -clearance + 0.5 * magnitude)
