"""The load across the face width of a mesh: slices, misalignment, lead modifications, K_Hβ.

The contact line across the face width b is cut into N slices of equal width b/N, each a spring
of the mesh stiffness per unit width c_γ times its width, behind the gap at its centre: the
relative misalignment of the two flanks F_β z/b (ISO 6336-1's effective mesh misalignment F_βy,
or a gear's tilt in a run) plus the lead modifications of both gears
(`pinwind.gears.flank_modification.lead_gap`). The force F pushes all of them by one approach
(`pinwind.gears.loaded_contact.approach`); the slice's line load w_i = c_γ max(0, δ − e_i).
This is the spring bed of constant stiffness behind ISO 6336-1's face load factor, and the
slicing of SIMPACK's and Romax's gear pairs.

The face load factor K_Hβ = w_max / w_m, w_m = F/b (ISO 6336-1 §7: the maximum load per unit face
width over the mean). For a linear gap F_β z/b (no modification) the spring bed has ISO 6336-1's
closed form (ISO 6336-1 §7, the form `pinwind.gears.rating_iso.face_load_factor` rates with):

    K_Hβ = 1 + F_β c_γ / (2 w_m)        where F_β c_γ / (2 w_m) ≤ 1 (the whole face carries),
    K_Hβ = √(2 F_β c_γ / w_m)           where part of the face lifts off.

With slices the peak is that of the slice at the loaded end, half a slice in, so K_Hβ of N slices
approaches the closed form as 1/N; the line load at each slice centre is the closed form's there,
exactly where the whole face carries (a linear gap, sampled at slice centres, has the same mean).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinwind.errors import InputError
from pinwind.gears.flank_modification import UNMODIFIED, FlankModification, lead_gap
from pinwind.gears.loaded_contact import approach


@dataclass(frozen=True)
class FaceLoad:
    """The line load across the face width of one loaded contact line.

    Attributes:
        z: slice centres from face side I [m], (N,).
        line_load: load per unit face width of each slice [N/m], (N,).
        approach: δ, the flanks' approach along the line of action [m].
        face_width: b [m].
    """

    z: np.ndarray
    line_load: np.ndarray
    approach: float
    face_width: float

    @property
    def force(self) -> float:
        """Σ w_i b/N, the force the slices carry [N]."""
        return float(np.sum(self.line_load) * self.face_width / self.z.size)

    @property
    def face_load_factor(self) -> float:
        """K_Hβ = w_max / w_m, w_m = F/b [-] (ISO 6336-1 §7)."""
        return float(np.max(self.line_load) * self.face_width / self.force)

    @property
    def load_centre(self) -> float:
        """Where the resultant acts across the face, from side I [m]: Σ w_i z_i / Σ w_i."""
        return float(np.sum(self.line_load * self.z) / np.sum(self.line_load))

    @property
    def loaded_width(self) -> float:
        """The width of the slices that carry load [m]."""
        return float(np.count_nonzero(self.line_load > 0.0) * self.face_width / self.z.size)


def slice_centres(face_width: float, slices: int) -> np.ndarray:
    """Centres of N equal slices of the face width, from side I [m], (N,)."""
    if not (isinstance(slices, int | np.integer) and slices >= 1):
        raise InputError(f"slices = {slices!r}; cut the face width into a whole number ≥ 1")
    return (np.arange(slices) + 0.5) * face_width / slices


def face_load(
    force: float,
    *,
    face_width: float,
    stiffness_per_width: float,
    misalignment: float = 0.0,
    slices: int = 50,
    gear_1: FlankModification = UNMODIFIED,
    gear_2: FlankModification = UNMODIFIED,
) -> FaceLoad:
    """The line load across the face of a contact line carrying ``force`` (module docstring).

    Args:
        force: F along the line of action, transverse plane [N], ≥ 0.
        face_width: b [m].
        stiffness_per_width: c_γ, the mesh stiffness per unit face width [N/m²] (ISO 6336-1
            c_γβ = 0.85 c_γα for K_Hβ; `pinwind.gears.mesh_stiffness` gives c_γα b).
        misalignment: F_β, the gap the flanks leave at side II when they touch at side I [m]
            (positive: loaded at side I; negative: at side II).
        slices: N.
        gear_1, gear_2: the gears' lead modifications.

    Raises:
        InputError: a non-positive face width or stiffness, a negative force, N < 1.
    """
    if not (face_width > 0.0 and np.isfinite(face_width)):
        raise InputError(f"face width {face_width!r} m; it must be positive")
    if not (stiffness_per_width > 0.0 and np.isfinite(stiffness_per_width)):
        raise InputError(f"mesh stiffness per width {stiffness_per_width!r} N/m²; must be positive")
    if not np.isfinite(misalignment):
        raise InputError(f"misalignment {misalignment!r} m; give a finite number")
    z = slice_centres(face_width, slices)
    gap = misalignment * z / face_width + lead_gap(gear_1, gear_2, face_width, z)
    width = face_width / slices
    delta = approach(np.full(z.size, stiffness_per_width * width), gap, force)
    return FaceLoad(z, stiffness_per_width * np.maximum(0.0, delta - gap), delta, face_width)


#: The most slices `slice_count` gives.
MOST_SLICES = 50

#: The line load [N/m] at which ``slices="auto"`` takes the rule's mean deflection δ_m: 100
#: N/mm, a light load for a wind-turbine gear (rated loads are several times it). δ_m grows with
#: the load, so N from it resolves the misalignment at the heavier loads too.
AUTO_LINE_LOAD = 100e3

#: The misalignment [m] ``slices="auto"`` adds for what the model file does not give (the shafts'
#: and bearings' deflections, the gears' tilt in the run): the rating's default effective
#: misalignment F_βy (`pinwind.gears.rating_iso.IsoFactors.misalignment`).
UNMODELLED_MISALIGNMENT = 10e-6


def expected_misalignment(
    gear_1: FlankModification, gear_2: FlankModification, face_width: float
) -> float:
    """F_β for `slice_count` [m]: b times the lead gap's steepest slope, plus the unmodelled part.

    `UNMODELLED_MISALIGNMENT` is added for what the model does not give. The lead gap of both
    gears (`pinwind.gears.flank_modification.lead_gap`: f_Hβ z/b, crowning
    C_β (2z/b − 1)², end relief) changes fastest where its slope is steepest: b max|de/dz| is
    |f_Hβ,1 + f_Hβ,2| for the slope deviations alone, 4 C_β + |f_Hβ| with crowning (its slope at
    the ends is 4 C_β/b), C_I b/L_I with an end relief. Taken as the steepest chord over 2000
    intervals across the face: exact for f_Hβ and end relief (linear pieces whose corners are
    kinks), 1/2000 short of crowning's 4 C_β at the ends.

    Raises:
        InputError: a face width ≤ 0.
    """
    if not (face_width > 0.0 and np.isfinite(face_width)):
        raise InputError(
            f"expected_misalignment: face width {face_width!r} m; it must be positive (the rule "
            "cuts the face width into slices)"
        )
    z = np.linspace(0.0, face_width, 2001)
    slope = np.diff(lead_gap(gear_1, gear_2, face_width, z)) / np.diff(z)
    return float(face_width * np.max(np.abs(slope)) + UNMODELLED_MISALIGNMENT)


def slice_count(misalignment: float, deflection: float, *, most: int = MOST_SLICES) -> int:
    """The number of slices that resolves a misalignment's change of the overlap across the face.

    A misalignment F_β across the face b changes the overlap by F_β/b per unit width; the slices
    resolve the length over which it changes by a tenth of the mean deflection δ_m (the overlap
    the mean line load takes, F/c̄), b δ_m/(10 F_β): N = ⌈10 F_β/δ_m⌉, clamped to [1, most]. So
    K_Hβ of the slices is within (K_Hβ − 1)/N of the closed form where the whole face carries
    (the peak half a slice in, module docstring): within 10 % of K_Hβ − 1 at N = 10.

    Args:
        misalignment: F_β, the expected misalignment across the face [m] (|f_Hβ|, the gears'
            relative tilt times b, 2 C_β of crowning; ≥ 0).
        deflection: δ_m, the mesh's mean deflection F/c̄ [m] (> 0).
        most: the largest N returned (≥ 1).

    Raises:
        InputError: a deflection ≤ 0, a negative or non-finite misalignment, or most < 1.
    """
    if not (deflection > 0.0 and most >= 1):
        raise InputError(
            f"slice_count: the mean deflection {deflection!r} m must be > 0 and most = {most!r} "
            "≥ 1; give δ_m = F/c̄ of the mesh's mean load"
        )
    if not (0.0 <= misalignment < float("inf")):
        raise InputError(
            f"slice_count: misalignment F_β = {misalignment!r} m must be finite and ≥ 0"
        )
    return int(min(most, max(1, int(np.ceil(10.0 * misalignment / deflection - 1e-12)))))
