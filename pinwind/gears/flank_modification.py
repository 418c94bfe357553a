"""Micro-geometry of a gear's flanks: profile relief at tip and root, lead crowning and end relief.

A modification removes material from the involute flank; where two modified flanks meet, the
pair's teeth must deflect by the removed amount before they carry load. Every amount here is
that removed material measured in the transverse plane along the line of action (the direction
ISO 1328-1 measures profile and helix deviations in, and the direction the mesh stiffness of
ISO 6336-1 acts in), so the gap a tooth pair leaves is the sum of its two flanks' amounts.

Coordinates (ISO 21771 terms):

- the roll position y along the transverse path of contact, from A (where contact starts, gear
  2's tip on gear 1's lowest active point) to E (gear 1's tip on gear 2's lowest point),
  0 ≤ y ≤ g_α (`pinwind.gears.contact.PathOfContact`), so gear 1's tip relief acts near E and
  gear 2's near A, gear 1's root relief near A and gear 2's near E;
- the axial position z across the face width, 0 at face side I to b at side II.

Profile relief (ISO 21771 §8.2 "tip relief" C_a and its length L_Ca, root relief C_f and L_Cf,
taken along the line of action, i.e. as a roll length): the amount at a distance u into the
relieved zone, counted from where the relief starts towards the tip (or root), is C (u/L) for a
linear relief and C (u/L)² for a parabolic ("progressive") one. Lead (ISO 21771 §8.3): crowning
C_β removes C_β (2z/b − 1)² (C_β at both ends, 0 in the middle); end relief C_I over L_I at side
I removes C_I (1 − z/L_I) for z < L_I, and the same at side II; a helix slope deviation f_Hβ
removes f_Hβ z/b (a flank turned so the gap opens towards side II; only the slope matters, a
constant shifts no load).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError

#: The shapes of a profile relief and the power of u/L each removes material by.
RELIEF_SHAPES = {"linear": 1, "parabolic": 2}


@dataclass(frozen=True)
class FlankModification:
    """One gear's flank modifications, amounts of removed material [m] (module docstring).

    Attributes:
        tip_relief: C_a at the tip [m].
        tip_relief_length: L_Ca, the roll length along the line of action the tip relief spans,
            from where it starts to the tip's contact point [m].
        root_relief: C_f at the lowest active point [m].
        root_relief_length: L_Cf, the roll length the root relief spans [m].
        relief_shape: "linear" or "parabolic", of both reliefs.
        crowning: lead crowning C_β, removed at both face ends [m].
        end_relief: C_I = C_II, removed at each face end [m].
        end_relief_length: L_I = L_II, the axial length each end relief spans [m].
        helix_slope_deviation: f_Hβ over the face width, positive opening the gap towards side
            II [m] (a helix slope deviation, or a lead correction of that slope).
    """

    tip_relief: float = 0.0
    tip_relief_length: float = 0.0
    root_relief: float = 0.0
    root_relief_length: float = 0.0
    relief_shape: str = "linear"
    crowning: float = 0.0
    end_relief: float = 0.0
    end_relief_length: float = 0.0
    helix_slope_deviation: float = 0.0

    def __post_init__(self) -> None:
        if self.relief_shape not in RELIEF_SHAPES:
            raise InputError(
                f'relief_shape "{self.relief_shape}" is not one of {", ".join(RELIEF_SHAPES)}'
            )
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "relief_shape":
                continue
            if not math.isfinite(value):
                raise InputError(f"flank modification {f.name} is {value}; give a finite number")
            if f.name != "helix_slope_deviation" and value < 0.0:
                raise InputError(
                    f"flank modification {f.name} is {value * 1e6:g} µm; an amount of removed "
                    "material or a length is ≥ 0 (a negative one would add material)"
                )
        for amount, length, what in (
            (self.tip_relief, self.tip_relief_length, "tip_relief"),
            (self.root_relief, self.root_relief_length, "root_relief"),
            (self.end_relief, self.end_relief_length, "end_relief"),
        ):
            if amount > 0.0 and length <= 0.0:
                raise InputError(
                    f"{what} is {amount * 1e6:g} µm over a length of 0; give its "
                    f"{what}_length, the span it is ground over"
                )

    @property
    def is_none(self) -> bool:
        """No material removed anywhere."""
        return not (
            self.tip_relief or self.root_relief or self.crowning or self.end_relief
            or self.helix_slope_deviation
        )  # fmt: skip


#: An unmodified involute flank.
UNMODIFIED = FlankModification()


def _relief(amount: float, length: float, shape: str, u: np.ndarray) -> np.ndarray:
    """C (u/L)^n inside the relieved zone (0 ≤ u ≤ L), 0 before it [m]."""
    if amount == 0.0:
        return np.zeros_like(u)
    x = np.clip(u / length, 0.0, None)
    return amount * x ** RELIEF_SHAPES[shape]


def profile_gap(
    gear_1: FlankModification, gear_2: FlankModification, path_length: float, y: npt.ArrayLike
) -> np.ndarray:
    """Gap the two flanks' profile reliefs leave at roll position y from A [m] (module docstring).

    Gear 1's tip relief acts on [g_α − L_Ca1, g_α] and its root relief on [0, L_Cf1]; gear 2's
    tip relief on [0, L_Ca2] and its root relief on [g_α − L_Cf2, g_α]. A relief longer than
    the path stands past its start: only the part on the path counts.

    Args:
        path_length: g_α [m].
        y: roll positions, any shape [m].
    """
    y = np.asarray(y, dtype=float)
    g = path_length
    return (
        _relief(gear_1.tip_relief, gear_1.tip_relief_length, gear_1.relief_shape,
                y - (g - gear_1.tip_relief_length))
        + _relief(gear_1.root_relief, gear_1.root_relief_length, gear_1.relief_shape,
                  gear_1.root_relief_length - y)
        + _relief(gear_2.tip_relief, gear_2.tip_relief_length, gear_2.relief_shape,
                  gear_2.tip_relief_length - y)
        + _relief(gear_2.root_relief, gear_2.root_relief_length, gear_2.relief_shape,
                  y - (g - gear_2.root_relief_length))
    )  # fmt: skip


def lead_gap(
    gear_1: FlankModification, gear_2: FlankModification, face_width: float, z: npt.ArrayLike
) -> np.ndarray:
    """Gap the two flanks' lead modifications leave at axial position z [m] (module docstring).

    Crowning C_β (2z/b − 1)², end reliefs, and the helix slope deviations f_Hβ z/b of both
    gears added (z from face side I, 0 ≤ z ≤ b).
    """
    z = np.asarray(z, dtype=float)
    b = face_width
    gap = np.zeros_like(z)
    for m in (gear_1, gear_2):
        gap = gap + m.crowning * (2.0 * z / b - 1.0) ** 2 + m.helix_slope_deviation * z / b
        if m.end_relief:
            gap = gap + _relief(m.end_relief, m.end_relief_length, "linear",
                                m.end_relief_length - z)  # fmt: skip
            gap = gap + _relief(m.end_relief, m.end_relief_length, "linear",
                                z - (b - m.end_relief_length))  # fmt: skip
    return gap
