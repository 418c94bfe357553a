"""Loaded static transmission error of a gear pair over a mesh cycle, with flank modifications.

The static transmission error (TE) is how far gear 2 lags the position a rigid, perfect pair
would give it, at rest under a steady load, measured along the line of action in the transverse
plane [m] (Harris 1958; Smith 2003 "Gear noise and vibration" ch. 2; ISO 6336-1's mesh stiffness
acts in the same direction). At each roll position of the mesh the tooth pairs in contact are
springs behind the gaps their modifications leave (`pinwind.gears.flank_modification`), all
pressed by one approach δ: the TE is that δ (`pinwind.gears.loaded_contact.approach`). One mesh
cycle is one transverse base pitch p_bt of roll: the reference pair's position y from A runs
over [0, p_bt), the pair j base pitches ahead sits at y + j p_bt.

Each pair is cut into N slices across the face width. A slice at axial position z of a pair at y
touches at the transverse roll position q = y − z tan β_b (the inclined contact line of a
helical pair; q = y for a spur pair) and is in contact where 0 ≤ q ≤ g_α. Its stiffness:

- spur: the pair's stiffness along the path (`mesh_stiffness.pair_stiffness_along_path`:
  ISO 6336-1's c′ b in the single-pair zone, 0.875 c′ b in the double-pair zones) times the
  slice's share of the face, 1/N;
- helical: ISO 6336-1's mean mesh stiffness per unit length of contact line, the same along the
  line, so a slice of width b/N carries c_γα b · p_bt/(g_α b) · b/N: summed over a pair's slices
  in contact it is `mesh_stiffness.contact_line_pair_stiffness`'s pair stiffness.

Its gap: both gears' profile reliefs at q, their lead modifications at z, and the misalignment
F_β z/b. The pairs' forces follow (`loaded_contact.spring_forces`). The TE's peak-to-peak
against the load is the "Harris map": a tip relief of the right amount flattens the TE at its
design load, and it grows on either side (a V); its spectrum has the mesh frequency's harmonics.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.errors import InputError
from pinwind.gears.face_load import slice_centres
from pinwind.gears.flank_modification import (
    UNMODIFIED,
    FlankModification,
    lead_gap,
    profile_gap,
)
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.loaded_contact import approach, spring_forces
from pinwind.gears.mesh_stiffness import (
    mesh_stiffness,
    pair_stiffness_along_path,
    single_pair_stiffness,
)


@dataclass(frozen=True)
class TransmissionError:
    """The loaded static TE of a pair over one mesh cycle.

    Attributes:
        roll: the reference pair's roll position from A [m], (M,), over one base pitch.
        approach: the static TE δ at each, along the transverse line of action [m], (M,).
        pair_forces: the force each pair carries [N], (M, J); pair j sits at roll + offsets[j].
        offsets: the pairs' roll offsets from the reference pair, multiples of p_bt [m], (J,).
        force: the mesh force along the transverse line of action [N].
        base_pitch: p_bt [m], one mesh cycle of roll.
        base_radius_2: r_b2 [m], to turn δ into gear 2's angle.
    """

    roll: np.ndarray
    approach: np.ndarray
    pair_forces: np.ndarray
    offsets: np.ndarray
    force: float
    base_pitch: float
    base_radius_2: float

    @property
    def peak_to_peak(self) -> float:
        """The peak-to-peak TE, max δ − min δ over the mesh cycle [m]."""
        return float(np.ptp(self.approach))

    @property
    def mean(self) -> float:
        """The mean δ over the mesh cycle [m]."""
        return float(np.mean(self.approach))

    @property
    def angle_of_gear_2(self) -> np.ndarray:
        """The TE as gear 2's angular lag, δ / r_b2 [rad], (M,)."""
        return self.approach / self.base_radius_2

    def harmonics(self, count: int = 5) -> np.ndarray:
        """Amplitudes of the first ``count`` mesh-frequency harmonics of δ [m], (count,).

        From the Fourier series over the cycle's M equally spaced positions: 2|X_h|/M.
        """
        if not 1 <= count < self.roll.size // 2:
            raise InputError(
                f"{count} harmonics from {self.roll.size} positions per mesh cycle; ask for "
                f"1 to {self.roll.size // 2 - 1}, or compute more positions"
            )
        spectrum = np.fft.rfft(self.approach)
        return 2.0 * np.abs(spectrum[1 : count + 1]) / self.roll.size


def static_transmission_error(
    pair: GearPair,
    force: float,
    *,
    gear_1: FlankModification = UNMODIFIED,
    gear_2: FlankModification = UNMODIFIED,
    misalignment: float = 0.0,
    positions: int = 128,
    slices: int | None = None,
    single_pair: float | None = None,
    roll: np.ndarray | None = None,
) -> TransmissionError:
    """The loaded static TE of ``pair`` under ``force`` over one mesh cycle (module docstring).

    Args:
        pair: the pair, external gear 1 (`GearPair.from_mesh` puts a ring second).
        force: F_bt, the mesh force along the transverse line of action [N] (T1 / r_b1).
        gear_1, gear_2: the gears' flank modifications.
        misalignment: F_β across the face, positive loading side I [m].
        positions: M roll positions over the cycle, at (m + ½) p_bt / M.
        slices: N slices of the face width; default 1 for a spur pair with no lead modification
            and no misalignment, else 40.
        single_pair: c′ b [N/m] of a spur pair, default ISO 6336-1 method B's
            (`single_pair_stiffness`); a helical pair takes `mesh_stiffness`'s c_γα b.
        roll: the reference pair's roll positions from A [m], in [0, p_bt), instead of the M
            equally spaced ones (`TransmissionError.harmonics` needs those).

    Raises:
        InputError: a negative force, positions < 4, slices < 1.
        InvalidGearTrain: gear 1 internal.
    """
    pair.require_external_gear_1("the static transmission error")
    if not (isinstance(positions, int) and positions >= 4):
        raise InputError(f"positions = {positions!r}; give at least 4 per mesh cycle")
    path = pair.path
    g, p, b = path.length, path.base_pitch, pair.face_width
    spur = pair.helix_angle == 0.0
    lead_free = all(
        m.crowning == 0.0 and m.end_relief == 0.0 and m.helix_slope_deviation == 0.0
        for m in (gear_1, gear_2)
    )
    if slices is None:
        slices = 1 if spur and lead_free and misalignment == 0.0 else 40
    z = slice_centres(b, slices)
    skew = z * math.tan(pair.base_helix_angle)  # q = y − z tan β_b
    if spur:
        s, k = pair_stiffness_along_path(
            path, single_pair if single_pair is not None else single_pair_stiffness(pair)
        )

        def stiffness(q: np.ndarray) -> np.ndarray:
            inside = (q >= 0.0) & (q <= g)
            return np.where(inside, np.interp(q, s, k), 0.0) / slices
    else:
        per_slice = mesh_stiffness(pair) * p / (g * slices)

        def stiffness(q: np.ndarray) -> np.ndarray:
            return np.where((q >= 0.0) & (q <= g), per_slice, 0.0)

    first = -math.ceil(float(skew[-1]) / p) - 1
    offsets = np.arange(first, math.ceil(g / p) + 1) * p
    if roll is None:
        roll = (np.arange(positions) + 0.5) * p / positions
    else:
        roll = np.asarray(roll, dtype=float)
        if roll.ndim != 1 or np.any((roll < 0.0) | (roll >= p)):
            raise InputError(f"roll positions must lie in one mesh cycle, [0, {p:.6g}) m from A")
        positions = roll.size
    lead = lead_gap(gear_1, gear_2, b, z) + misalignment * z / b
    deltas = np.empty(positions)
    forces = np.empty((positions, offsets.size))
    for m, y in enumerate(roll):
        q = y + offsets[:, None] - skew[None, :]  # (J, N)
        k_q = stiffness(q)
        gap = profile_gap(gear_1, gear_2, g, np.clip(q, 0.0, g)) + lead[None, :]
        deltas[m] = approach(k_q, gap, force)
        forces[m] = spring_forces(k_q, gap, deltas[m]).sum(axis=1)
    return TransmissionError(
        roll, deltas, forces, offsets, float(force), p, pair.geometry.base_radius_2
    )


def transmission_error_map(
    pair: GearPair, forces: Sequence[float] | np.ndarray, **options: Any
) -> list[TransmissionError]:
    """`static_transmission_error` at each force [N]: the Harris map's points."""
    return [static_transmission_error(pair, float(f), **options) for f in forces]
