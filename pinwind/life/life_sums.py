"""A rolling bearing's life sums from its load history: ISO 281 basic and modified, ISO/TS 16281.

`history_sums` turns the load W = (F_u, F_w, F_a, M_u, M_w) [N, N·m] on one bearing or row (its
joint frame, axis k = F_a's) and its speed over a history into the sums
``bearing_life.BearingLoadSum`` keeps, which add over histories (a fatigue set adds its cases,
each scaled to its wind bin's hours: ``life/set_bearing_life.py``). With n_i the revolutions
and Δt_i the seconds of sample i (trapezoid rule):

- **basic** Σ P_i^p n_i of ISO 281's dynamic equivalent load P = X F_r + Y F_a
  (``bearing_life.dynamic_equivalent_load``), L10 = (C/P_eq)^p;
- **modified** Σ n_i P_i^p / a_ISO,i, a_ISO at the sample's viscosity ratio κ = ν/ν₁(n, d_m) and
  e_C C_u / P (ISO 281:2007 §9.3.4: Palmgren-Miner over the load levels,
  ``modified_life.modified_life_sum``), L_nm = a₁ C^p Σ n_i / Σ (n_i P_i^p / a_ISO,i)
  (``modified_life.modified_rating_life``); none without the mean diameter d_m (``size_mm``)
  or a fatigue load limit C_u (given, or estimated from C₀ by ISO 281 Annex B);
- **reference** Σ P_ref,i^p n_i of each sample's internal load distribution (ISO/TS
  16281:2008, ``dynamics/load_distribution.py``), L10r = (C/P_ref,eq)^p; none without an internal
  geometry (``size_mm``, or rollers and roller_mm). The distribution is solved once per cell of
  like loads (``dynamics/row_contact.cell_distribution``), which also gives each sample's
  largest element load Q_max and load-zone angle 2ψ_l (`sample_distribution`).

Every sum is revolution-weighted as ISO 281's P_eq is, so sums over a site's bins give its
lives by the same rule as L10 (``set_bearing_life``); lives in hours follow at the mean speed
(``bearing_life.life_hours``). The lubricant, cleanliness, C_u and inside are the model's
``<bearing>`` or ``<row>`` attributes (``model/bearing_life_data.py``; defaults VG 320 at
70 °C, normal cleanliness, which `history_sums` notes).
"""

from __future__ import annotations

import dataclasses
import math
import os
import tempfile
import weakref
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.dynamics.bearing_load import along_axis
from pinwind.dynamics.load_distribution import (
    InternalGeometry,
    distribute,
    reference_load,
)
from pinwind.dynamics.row_contact import (
    LOAD_CELLS,
    cell_distribution,
    cell_keys,
    geometry_of,
    life_data_of,
    oriented,
)
from pinwind.errors import InputError
from pinwind.life.bearing_life import (
    BearingLoadSum,
    dynamic_equivalent_load,
    load_sum_of_history,
    radial_and_axial,
    row_rating,
    sample_weights,
)
from pinwind.life.lubrication import Lubricant, contamination_factor
from pinwind.life.modified_life import (
    KAPPA_MAX,
    KAPPA_MIN,
    estimated_fatigue_limit,
    modified_life_sum,
    rated_viscosity,
)
from pinwind.model.bearing import BearingRating
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.model.bearing_rows import rolling_load, row_name


@dataclass(frozen=True)
class SampleDistribution:
    """A bearing's internal load distribution at each sample of a history (ISO/TS 16281).

    Attributes:
        max_element_load: Q_max per sample [N], (n,); NaN where no equilibrium was found.
        load_zone: load-zone angle 2ψ_l per sample [rad], (n,); NaN likewise.
        reference_load: P_ref per sample [N], (n,); NaN likewise.
        failed: samples without equilibrium.
        below_thrust: of those, samples whose axial load is below a single angular row's
            induced thrust F_r tan α (it needs its paired row).
        not_carried: largest axial force [N] and tilting moment [N·m] the type does not carry.
    """

    max_element_load: np.ndarray
    load_zone: np.ndarray
    reference_load: np.ndarray
    failed: int
    below_thrust: int
    not_carried: tuple[float, float]


def sample_distribution(geometry: InternalGeometry, load: np.ndarray) -> SampleDistribution:
    """The distribution of the load W (n, 5) = (F_u, F_w, F_a, M_u, M_w) [N, N·m] on the bearing.

    A single angular row faces the way its mean axial load pushes it; only what the type
    carries is distributed (``InternalGeometry.carries_tilt``, ``axially_free``), once per
    cell of like loads (``dynamics/row_contact.cell_distribution``).
    """
    w, dist, inverse, magnitude = cell_distribution(geometry, load)
    not_carried = (
        float(np.max(np.abs(w[:, 2]), initial=0.0)) if geometry.axially_free else 0.0,
        float(np.max(np.hypot(w[:, 3], w[:, 4]), initial=0.0))
        if not geometry.carries_tilt
        else 0.0,
    )
    failed_at = ~dist.converged[inverse]
    below = 0
    if failed_at.any() and geometry.contact_angle > 0.0 and geometry.rows == 1:
        thrust = np.hypot(w[:, 0], w[:, 1]) * math.tan(geometry.contact_angle)
        below = int(np.sum(failed_at & (w[:, 2] < thrust)))
    p_ref = reference_load(geometry, dist.slice_loads)
    return SampleDistribution(
        dist.max_element_load[inverse] * magnitude, dist.load_zone[inverse],
        p_ref[inverse] * magnitude, int(np.sum(failed_at)), below, not_carried,
    )  # fmt: skip


@dataclass(frozen=True)
class HistorySums:
    """A bearing's life sums over a history and what its modified and reference lives used.

    Attributes:
        sums: the sums that add over histories (basic, modified and reference).
        kappa_mean: revolution-weighted mean viscosity ratio κ [-] (NaN: no modified life).
        contamination: e_C [-]; fatigue_limit: C_u [N] (NaN: none).
        distribution: each sample's internal load distribution, or None without a geometry.
        notes: defaults and estimates used, and why a life is missing.
    """

    sums: BearingLoadSum
    kappa_mean: float
    contamination: float
    fatigue_limit: float
    distribution: SampleDistribution | None = field(repr=False)
    notes: tuple[str, ...]


def history_sums(
    name: str,
    rating: BearingRating,
    *,
    data: BearingLifeData | None,
    size: tuple[float, float, float] | None,
    time: np.ndarray,
    speed: np.ndarray,
    load: np.ndarray,
    rolling: np.ndarray | None = None,
) -> HistorySums:
    """A bearing's (or row's) life sums from its load W and speed (module docstring).

    The whole history as one part of a `HistoryStream`, with each sample's internal load
    distribution (`HistorySums.distribution`).

    Args:
        name: the bearing or row (``BEARING.ROW``), the sums' name.
        rating: its ISO 281 data (type and load factors; C is not needed for the sums).
        data: its lubricant, cleanliness, C_u and inside (None: pinwind's defaults).
        size: (D, d, B) [m] when the element has one besides ``data`` (a ``<row>``), or None.
        time: sample times [s], (n,).
        speed: its joint's speed relative to the parent [rad/s], (n,).
        load: W (n, 5) = (F_u, F_w, F_a, M_u, M_w) on the bearing, joint frame [N, N·m].
        rolling: the radial load its loaded rolling elements carry [N], (n,), for the skidding
            check (`preloaded_rolling_load`); None: its radial load.
    """
    stream = HistoryStream(name, rating, data=data, size=size)
    stream.add(time=time, speed=speed, load=load, rolling=rolling)
    sums = stream.sums()
    if stream.geometry is None:
        return sums
    dist = sample_distribution(stream.geometry, np.asarray(load, dtype=float).reshape(-1, 5))
    return dataclasses.replace(sums, distribution=dist)


class HistoryStream:
    """A bearing's (or row's) life sums over a history given in consecutive parts.

    Each sample is summed once its next one is known (its trapezoid weight spans both sides,
    `bearing_life.sample_weights`), so the sums of the parts are those of the whole history
    (`history_sums`) but for the order of the additions. The ISO/TS 16281 reference loads are
    solved once per cell of like loads (``dynamics/row_contact.cell_distribution``) at the end:
    without clearance the cells are of the load's direction alone, whatever the other samples
    (``row_contact.cell_keys``), so each part adds to its cells' sums and the memory does not
    grow with the history; with a clearance or a preload the cells are a share of the largest
    load of the whole history, so the loads of every sample are kept until the end, in a file
    (`_ReferenceCells`; removed by `sums` or `close`).

    Args:
        name: the bearing or row (``BEARING.ROW``), the sums' name.
        rating: its ISO 281 data (None: not rated; its revolutions and seconds only).
        data: its lubricant, cleanliness, C_u and inside (None: pinwind's defaults).
        size: (D, d, B) [m] when the element has one besides ``data`` (a ``<row>``), or None.
        folder: where a row with a clearance keeps its samples' file (None: the system's
            temporary folder; `_ReferenceCells`).
    """

    def __init__(
        self,
        name: str,
        rating: BearingRating | None,
        *,
        data: BearingLifeData | None,
        size: tuple[float, float, float] | None,
        folder: Path | None = None,
    ) -> None:
        data = data or BearingLifeData()
        self.name, self.rating, self.data = name, rating, data
        self.exponent = math.nan if rating is None else rating.exponent
        self.ball = rating is not None and rating.kind.endswith("_ball")
        oil_defaults = [d for d in data.defaults if d != "rotating_ring"]
        self._oil_notes = (
            ["default " + ", ".join(oil_defaults) + " (VG 320, 70 °C, normal cleanliness)"]
            if oil_defaults
            else []
        )
        notes: list[str] = []
        self.geometry = None if rating is None else geometry_of(rating.kind, data, size)
        size_used = data.size or size
        self.dm = 0.5 * (size_used[0] + size_used[1]) if size_used and rating else None
        nan = math.nan
        self.contamination = self.fatigue_limit = self.viscosity = nan
        if self.dm is None:
            notes.append("no modified life: no size_mm (the mean diameter d_m sets ν₁)")
        else:
            self.contamination = (
                data.contamination
                if data.contamination is not None
                else contamination_factor(data.contamination_class, self.dm)
            )
            if data.fatigue_limit is not None:
                self.fatigue_limit = data.fatigue_limit
            elif data.static_rating is not None:
                self.fatigue_limit = estimated_fatigue_limit(
                    data.static_rating, self.dm, ball=self.ball
                )
                notes.append("C_u estimated from C₀ (ISO 281 Annex B)")
            else:
                notes.append("no modified life: give fatigue_limit_kN (C_u) or rating_c0_kN (C₀)")
            if data.viscosity is not None:
                self.viscosity = data.viscosity
            else:
                oil = Lubricant(data.grade, data.temperature, data.viscosity_100)
                self.viscosity = oil.viscosity()
                if oil.slope_assumed:
                    notes.append("ν(T) with the assumed Walther slope 3.5 (no viscosity_100C_cSt)")
        self._life_notes = notes
        self._geometry_notes = []
        if self.geometry is None:
            self._geometry_notes.append("no reference life: no size_mm or internal geometry")
        elif self.geometry.estimated:
            self._geometry_notes.append("internal geometry estimated from size_mm")
        self._rolling: bool | None = None  # whether the parts give a rolling load
        self._sums: BearingLoadSum | None = None
        self._modified = 0.0
        self._kappa_turns = 0.0
        self._kappa_low = self._kappa_high = False
        self._held: tuple[np.ndarray, ...] | None = None  # the last sample, not summed yet
        self._time_before: float | None = None  # the time of the last sample summed
        self._cells = (
            None
            if self.geometry is None
            else _ReferenceCells(self.geometry, self.exponent, name=name, folder=folder)
        )
        self._samples = 0

    def add(
        self,
        *,
        time: np.ndarray,
        speed: np.ndarray,
        load: np.ndarray,
        rolling: np.ndarray | None = None,
    ) -> None:
        """The next samples of the history, each argument as for `history_sums`.

        Raises:
            InputError: a rolling load given in some parts only.
        """
        has_rolling = rolling is not None
        if self._rolling is None:
            self._rolling = has_rolling
        elif self._rolling != has_rolling:
            raise InputError(
                f"{self.name}: a rolling load was given for some parts of the history only; "
                "give it with every part or with none"
            )
        n = len(np.asarray(time))
        parts: tuple[np.ndarray, ...] = (
            np.asarray(time, dtype=float).reshape(n),
            np.asarray(speed, dtype=float).reshape(n),
            np.asarray(load, dtype=float).reshape(n, 5),
            np.zeros(n) if rolling is None else np.asarray(rolling, dtype=float).reshape(n),
        )
        if self._held is not None:
            parts = tuple(np.concatenate((h, p)) for h, p in zip(self._held, parts, strict=True))
        if len(parts[0]) < 2:
            self._held = parts
            return
        self._sum_samples(parts, len(parts[0]) - 1)
        self._held = tuple(p[-1:] for p in parts)

    def close(self) -> None:
        """Removes the file of a row with a clearance (`sums` does; or when it is let go)."""
        if self._cells is not None:
            self._cells.close()

    def sums(self) -> HistorySums:
        """The sums of the history given so far (its end: no part may follow)."""
        try:
            return self._history_sums()
        finally:
            self.close()

    def _history_sums(self) -> HistorySums:
        if self._held is not None:
            self._sum_samples(self._held, len(self._held[0]))
            self._held = None
        notes = list(self._oil_notes)
        if self._rolling:
            notes.append("skidding checked on the preloaded rolling elements' load")
        notes += self._life_notes
        rating, p = self.rating, self.exponent
        basic = self._sums or load_sum_of_history(
            self.name, rating, time=np.zeros(0), force_in_joint=np.zeros((0, 3)),
            speed=np.zeros(0), axis=np.array([0.0, 0.0, 1.0]),
        )  # fmt: skip
        revolutions = basic.revolutions
        nan = math.nan
        kappa_mean = modified = nan
        if self.dm is not None and revolutions > 0:
            kappa_mean = self._kappa_turns / revolutions
        if self._kappa_low:
            notes.append("κ < 0.1 at some samples: ISO 281 does not cover it; κ = 0.1 used")
        if self._kappa_high:
            notes.append("κ > 4 at some samples: κ = 4 used (ISO 281)")
        notes += self._geometry_notes
        if self.dm is not None and not math.isnan(self.fatigue_limit):
            modified = self._modified
        reference = reference_time = nan
        if self._cells is not None:
            found = self._cells.sums(p)
            if found.failed:
                notes.append(
                    f"no reference life: no equilibrium at {found.failed} of {self._samples} "
                    "samples"
                    + (
                        f" ({found.below_thrust} with the axial load below the single angular "
                        "row's induced thrust F_r tan α: rate it with its paired row)"
                        if found.below_thrust
                        else " (a moment beyond what the rollers' length holds)"
                    )
                )
            else:
                reference, reference_time = found.turns_sum, found.time_sum
        sums = dataclasses.replace(
            basic, modified_sum=modified, reference_sum=reference,
            reference_time_sum=reference_time,
        )  # fmt: skip
        return HistorySums(
            sums, kappa_mean, self.contamination, self.fatigue_limit, None, tuple(notes)
        )

    def _sum_samples(self, parts: tuple[np.ndarray, ...], count: int) -> None:
        """Sums the first ``count`` samples of ``parts`` (time, speed, W, rolling)."""
        time, speed, load, rolling = (p[:count] for p in parts)
        rating, p = self.rating, self.exponent
        # Each sample's trapezoid weight: the sample before (summed in a part before) and
        # the one after (the next of ``parts``, or none at the history's end).
        span = parts[0][: count + 1]
        if self._time_before is not None:
            weights = sample_weights(np.concatenate(([self._time_before], span)))[1 : count + 1]
        else:
            weights = sample_weights(span)[:count]
        self._time_before = float(time[-1])
        self._samples += count
        force = np.column_stack([np.hypot(load[:, 0], load[:, 1]), np.zeros(count), load[:, 2]])
        basic = load_sum_of_history(
            self.name, rating, time=time, force_in_joint=force, speed=speed,
            axis=np.array([0.0, 0.0, 1.0]), rolling=rolling if self._rolling else None,
            weights=weights,
        )  # fmt: skip
        self._sums = basic if self._sums is None else self._sums.plus(basic)
        turns = weights * np.abs(speed) / (2.0 * math.pi)
        if self.dm is not None and rating is not None:
            equivalent = dynamic_equivalent_load(rating, force[:, 0], np.abs(force[:, 2]))
            with np.errstate(invalid="ignore"):
                kappa = self.viscosity / rated_viscosity(
                    np.abs(speed) * 60.0 / (2.0 * math.pi), self.dm
                )
            moving = turns > 0
            self._kappa_turns += float(np.sum(np.where(moving, kappa, 0.0) * turns))
            self._kappa_low |= bool(np.any(moving & (kappa < KAPPA_MIN)))
            self._kappa_high |= bool(np.any(moving & (kappa > KAPPA_MAX)))
            if not math.isnan(self.fatigue_limit):
                used, _ = modified_life_sum(
                    equivalent, turns, np.where(moving, kappa, 1.0), exponent=p,
                    contamination=self.contamination, fatigue_limit=self.fatigue_limit,
                    ball=self.ball,
                )  # fmt: skip
                self._modified += used
        if self._cells is not None:
            self._cells.add(load, turns, weights)


#: Cells whose distributions are solved at once at a history's end (`_ReferenceCells.sums`):
#: the solve's arrays, (cells, elements, slices), stay a few MB whatever the history's length.
CELL_CHUNK = 512
#: Samples of a row with a clearance read back at once from its file at the end.
SAMPLE_CHUNK = 65_536
#: Floats a kept sample takes in its file: W (5), revolutions, seconds.
_KEPT_COLUMNS = 7


@dataclass(frozen=True)
class _CellSums:
    """The reference sums of a history (`_ReferenceCells.sums`).

    Attributes:
        turns_sum: Σ P_ref,i^p n_i [N^p·rev]; time_sum: Σ P_ref,i^p Δt_i [N^p·s].
        failed: samples without equilibrium; below_thrust: of those, below the single angular
            row's induced thrust (`SampleDistribution`).
    """

    turns_sum: float
    time_sum: float
    failed: int
    below_thrust: int


class _ReferenceCells:
    """The ISO/TS 16281 reference sums of a history given in parts (`HistoryStream`).

    Without clearance each sample's cell is its load's direction (``row_contact.cell_keys``)
    and P_ref,i = P_ref(cell) s_i, s_i its size, so each cell keeps its samples' count, the sum
    of their directions (its mean, where it is solved) and Σ s_i^p n_i, Σ s_i^p Δt_i. A single
    angular row faces the way the whole history's mean axial load pushes it
    (``row_contact.oriented``): the cells are kept as given and turned at the end, a cell's
    key and mean changing sign along the axis exactly as its samples' do.

    With a clearance or a preload the cells are 1/``LOAD_CELLS`` of the whole history's
    largest load wide (``row_contact.load_cells``), known at its end only: each sample's W,
    revolutions and seconds are appended to a file of its own (``folder``, or the system's
    temporary folder) as they come, with the largest load so far, and read back at the end in
    chunks of `SAMPLE_CHUNK` samples, twice: the cells met, then each cell's count, sum of
    loads (added in the samples' order, as ``np.bincount`` adds them: the cells' means are
    those of ``load_cells`` of the whole history, bit for bit), revolutions and seconds. The
    memory holds the cells, not the samples. The file goes with `sums`, `close` or the object.

    Either way the cells are solved `CELL_CHUNK` at a time (``load_distribution.distribute``
    iterates each load on its own: the same solves, to an ulp of its matrix products).
    """

    def __init__(
        self,
        geometry: InternalGeometry,
        exponent: float,
        *,
        name: str = "row",
        folder: Path | None = None,
    ) -> None:
        self.geometry, self.exponent = geometry, exponent
        self.homogeneous = geometry.clearance == 0.0
        self.faces = geometry.contact_angle > 0.0 and geometry.rows == 1
        self.arm = 0.5 * geometry.pitch_diameter
        self.unit = np.array([1.0, 1.0, 1.0, self.arm, self.arm])
        _, self.carried = oriented(geometry, np.zeros((1, 5)))  # the mask only
        self._axial = 0.0  # Σ F_a, for the mean's sign
        # Each cell's key (k, 5) and [count, Σ direction (5), Σ s^p n, Σ s^p Δt, below thrust,
        # below when turned] (k, 10), in arrays: a dict of them took 500 bytes a cell, and a
        # turbulent run's main bearing meets a hundred new cells a second.
        self._keys = np.zeros((0, 5), dtype=np.int16)
        self._rows = np.zeros((0, 10))
        # With a clearance: the samples' file (made at the first sample), their count and
        # the largest |W| measured as ``cell_keys`` measures it.
        self._name, self._folder = name, folder
        self._file: Path | None = None
        self._remove: weakref.finalize | None = None
        self._kept = 0
        self._largest = 0.0

    def add(self, load: np.ndarray, turns: np.ndarray, weights: np.ndarray) -> None:
        """Samples W (n, 5) [N, N·m] with their revolutions (n,) and seconds (n,)."""
        self._axial += float(np.sum(load[:, 2]))
        if not self.homogeneous:
            self._keep(load, turns, weights)
            return
        key, measured, size = cell_keys(load * self.carried, homogeneous=True, arm=self.arm)
        powered = size**self.exponent
        columns = [np.ones(len(load)), *measured.T, powered * turns, powered * weights]
        if self.faces:
            thrust = np.hypot(load[:, 0], load[:, 1]) * math.tan(self.geometry.contact_angle)
            columns += [load[:, 2] < thrust, -load[:, 2] < thrust]
        else:
            columns += [np.zeros(len(load))] * 2
        keys = np.concatenate((self._keys, key.astype(np.int16)))  # |key| ≤ LOAD_CELLS
        rows = np.concatenate((self._rows, np.column_stack(columns)))
        self._keys, inverse = np.unique(keys, axis=0, return_inverse=True)
        inverse = inverse.reshape(-1)
        self._rows = np.stack(
            [np.bincount(inverse, weights=c, minlength=len(self._keys)) for c in rows.T], axis=1
        )

    def _keep(self, load: np.ndarray, turns: np.ndarray, weights: np.ndarray) -> None:
        """Appends samples to the file (class docstring), and notes the largest load."""
        if not len(load):
            return
        if self._file is None:
            handle, path = tempfile.mkstemp(
                prefix=f"{self._name}-", suffix=".kept.f8", dir=self._folder
            )
            os.close(handle)
            self._file = Path(path)
            self._remove = weakref.finalize(self, self._file.unlink, missing_ok=True)
        # |W| as `cell_keys` measures it; the axial sign (the row's facing) does not change it.
        norm = np.linalg.norm(load * self.carried / self.unit, axis=1)
        self._largest = max(self._largest, float(np.max(norm)))
        with self._file.open("ab") as f:
            np.column_stack((load, turns, weights)).astype(float).tofile(f)
        self._kept += len(load)

    def _chunks(self) -> Iterator[np.ndarray]:
        """The kept samples (n, 7) in order, `SAMPLE_CHUNK` at a time."""
        if self._file is None:
            return
        with self._file.open("rb") as f:
            while True:
                part = np.fromfile(f, dtype=float, count=SAMPLE_CHUNK * _KEPT_COLUMNS)
                if not part.size:
                    return
                yield part.reshape(-1, _KEPT_COLUMNS)

    def close(self) -> None:
        """Removes the kept samples' file (done by `sums`, or when it is let go)."""
        if self._remove is not None:
            self._remove()

    def sums(self, exponent: float) -> _CellSums:
        """The reference sums over the samples given (each cell solved once)."""
        if not self.homogeneous:
            try:
                return self._kept_sums(exponent)
            finally:
                self.close()
        if not len(self._keys):
            return _CellSums(0.0, 0.0, 0, 0)
        keys, rows = self._keys.astype(np.int64), self._rows.copy()
        below = rows[:, 8]
        if self.faces and self._axial < 0.0:  # the row faces the other way: turned
            keys[:, 2] *= -1
            rows[:, 3] *= -1.0
            below = rows[:, 9]
        order = np.lexsort(keys.T[::-1])  # np.unique's order, as `load_cells`
        keys, rows, below = keys[order], rows[order], below[order]
        count = rows[:, 0]
        scale, failed = _solved(self.geometry, rows[:, 1:6] / count[:, None] * self.unit, exponent)
        return _CellSums(
            float(np.sum(scale * rows[:, 6])),
            float(np.sum(scale * rows[:, 7])),
            int(np.sum(count[failed])),
            int(np.sum(below[failed])),
        )

    def _kept_sums(self, exponent: float) -> _CellSums:
        """The sums of a row with a clearance from its file (class docstring).

        The cells of ``row_contact.load_cells`` of the whole history, oriented as
        ``row_contact.oriented`` orients it (by the sign of Σ F_a); each sample's P_ref is
        its cell's (`sample_distribution`), so Σ P_ref,i^p n_i = Σ_cells P_ref^p Σ n_i.
        """
        if not self._kept:
            return _CellSums(0.0, 0.0, 0, 0)
        turned = self.faces and self._axial < 0.0
        scale = max(self._largest, 1e-300)  # `cell_keys`'s
        tan_alpha = math.tan(self.geometry.contact_angle)

        def measured_and_codes(chunk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            w = chunk[:, :5].copy()
            if turned:
                w[:, 2] *= -1.0
            measured = w * self.carried / self.unit
            key = np.round(measured / scale * LOAD_CELLS).astype(np.int64)
            # One integer per key, ordered as the keys' rows (np.unique's order): |key| ≤ 200.
            codes = np.zeros(len(key), dtype=np.int64)
            for j in range(5):
                codes = codes * (2 * LOAD_CELLS + 1) + (key[:, j] + LOAD_CELLS)
            return measured, codes

        met = np.zeros(0, dtype=np.int64)
        for chunk in self._chunks():
            met = np.union1d(met, measured_and_codes(chunk)[1])
        count = np.zeros(len(met), dtype=np.int64)
        totals = np.zeros((5, len(met)))
        turns = np.zeros(len(met))
        seconds = np.zeros(len(met))
        below = np.zeros(len(met), dtype=np.int64)
        for chunk in self._chunks():
            measured, codes = measured_and_codes(chunk)
            cell = np.searchsorted(met, codes)
            np.add.at(count, cell, 1)
            for j in range(5):  # in the samples' order, as np.bincount adds
                np.add.at(totals[j], cell, measured[:, j])
            np.add.at(turns, cell, chunk[:, 5])
            np.add.at(seconds, cell, chunk[:, 6])
            if self.faces:
                axial = -chunk[:, 2] if turned else chunk[:, 2]
                thrust = np.hypot(chunk[:, 0], chunk[:, 1]) * tan_alpha
                np.add.at(below, cell, axial < thrust)
        cells = np.stack([totals[j] / count for j in range(5)], axis=1) * self.unit
        powered, failed = _solved(self.geometry, cells, exponent)
        return _CellSums(
            float(np.sum(powered * turns)),
            float(np.sum(powered * seconds)),
            int(np.sum(count[failed])),
            int(np.sum(below[failed])),
        )


def _solved(
    geometry: InternalGeometry, cells: np.ndarray, exponent: float
) -> tuple[np.ndarray, np.ndarray]:
    """(P_ref^p (k,) [N^p], 0 where no equilibrium; no equilibrium (k,)) of cells' loads (k, 5).

    Solved `CELL_CHUNK` cells at a time (each load is iterated on its own by
    ``load_distribution.distribute``), so the solve's arrays stay bounded whatever the number
    of cells.
    """
    powered = np.zeros(len(cells))
    failed = np.zeros(len(cells), dtype=bool)
    for start in range(0, len(cells), CELL_CHUNK):
        part = slice(start, start + CELL_CHUNK)
        dist = distribute(geometry, cells[part])
        failed[part] = ~dist.converged
        p_ref = reference_load(geometry, dist.slice_loads)
        with np.errstate(invalid="ignore"):
            powered[part] = np.where(failed[part], 0.0, p_ref**exponent)
    return powered, failed


def run_load_sums(
    result: Any, gearbox: Any, *, life: Mapping[str, BearingLifeData] | None = None
) -> list[BearingLoadSum]:
    """The life sums of every bearing of a run, then of every row, each named as rated.

    Bearings in the order of ``result.bearing_names``: W = (F_r, 0, F_a, 0, 0) of the
    bearing force (``bearing_force_local``, joint frame; its tilting moment is left to its
    rows, ``bearing_life.tilt_refusal``), sums named by the joint. Rows in the order of
    ``analysis.bearing_rows.row_loads``: W the opposite of the row's force and tilt moment on
    the shaft, named ``BEARING.ROW`` (`row_rating`). Revolutions are the joint's speed relative
    to its parent (a planet's rows turn at the planet's speed relative to the carrier). The
    lubricant and inside of each are the model's (`life_data_of`). The whole run is one block
    of `RunLoadSums`.

    Args:
        result: the run (``Result``: time, joint speeds, bearing forces and the row series).
        gearbox: the model it ran (its ``<bearing>`` and ``<row>`` elements).
        life: each bearing's and row's life data by its rated name, instead of the model's
            (`bearing_life_data`; a fatigue set's, with its ``[fatigue.bearings]``).
    """
    sums = RunLoadSums(gearbox, life=life)
    sums.add(result)
    return sums.sums()


class RunLoadSums:
    """`run_load_sums` of a run given in blocks of consecutive samples (`add`).

    Each bearing and row is a `HistoryStream`, so the sums of the blocks are those of the
    whole run and the memory does not grow with it (rows with a clearance or preload keep
    their samples in a file until the end, `HistoryStream`).

    Args:
        gearbox: the model of the run (its ``<bearing>`` and ``<row>`` elements).
        life: each bearing's and row's life data by its rated name (None: the model's).
        folder: where rows with a clearance keep their samples' files (None: the system's
            temporary folder).
    """

    def __init__(
        self,
        gearbox: Any,
        *,
        life: Mapping[str, BearingLifeData] | None = None,
        folder: Path | None = None,
    ):
        self.gearbox = gearbox
        self.folder = folder
        self.life = bearing_life_data(gearbox) if life is None else life
        self._bearings: list[HistoryStream] | None = None
        self._rows: list[HistoryStream] = []

    def add(self, result: Any) -> None:
        """The next samples of the run (a Result with the series `run_load_sums` reads)."""
        from pinwind.analysis.bearing_rows import row_loads

        gearbox, life = self.gearbox, self.life
        ratings = gearbox.source.bearings
        rows = {(b, r.name): r for b, rs in gearbox.source.bearing_rows.items() for r in rs}
        loads = row_loads(result, gearbox)
        if self._bearings is None:
            self._bearings = [
                HistoryStream(
                    name, ratings.get(name), data=life.get(name), size=None, folder=self.folder
                )
                for name in result.bearing_names
            ]
            self._rows = [
                HistoryStream(
                    row_name(load.bearing, load.name),
                    row_rating(load.bearing, rows[(load.bearing, load.name)]),
                    data=life.get(row_name(load.bearing, load.name)),
                    size=rows[(load.bearing, load.name)].size,
                    folder=self.folder,
                )
                for load in loads
            ]
        for i, (name, stream) in enumerate(zip(result.bearing_names, self._bearings, strict=True)):
            speed = result.speed[:, result.joint_names.index(name)]
            axis = np.asarray(gearbox.joint_axis(name), dtype=float)
            force = np.asarray(result.bearing_force_local[:, i], dtype=float)
            w = np.zeros((len(force), 5))
            if stream.rating is not None:
                radial, _ = radial_and_axial(force, axis)
                k = (axis / np.linalg.norm(axis)).reshape(1, 3)
                w[:, 0], w[:, 2] = radial, along_axis(force[:, None, :], k)[:, 0]
            stream.add(time=result.time, speed=speed, load=w)
        for load, stream in zip(loads, self._rows, strict=True):
            row = rows[(load.bearing, load.name)]
            stream.add(
                time=result.time,
                speed=result.speed[:, result.joint_names.index(load.bearing)],
                load=-np.column_stack([load.radial, load.axial, load.tilting]),
                rolling=preloaded_rolling_load(gearbox, load.bearing, row, load.radial),
            )

    def sums(self) -> list[BearingLoadSum]:
        """The sums of every bearing, then of every row (the run's end: no block may follow)."""
        try:
            return [s.sums().sums for s in [*(self._bearings or []), *self._rows]]
        finally:
            self.close()

    def close(self) -> None:
        """Removes the files of rows with a clearance (`sums` does; or when let go)."""
        for stream in [*(self._bearings or []), *self._rows]:
            stream.close()


def preloaded_rolling_load(
    gearbox: Any, bearing: str, row: Any, radial: np.ndarray
) -> np.ndarray | None:
    """The radial load a preloaded row's loaded rolling elements carry [N], (n,), or None.

    For a row in the step (its bearing's springs) with a preload (``radial_clearance_mm`` < 0):
    each radial direction's loaded side carries ``model/bearing_rows.rolling_load`` of the
    row's net load along it (``radial`` (n, 2) along u, w [N]), K_j |c| + |F_j|/2 while both
    sides press, combined as the radial load is; None for any other row (its net load is what
    its rollers carry).
    """
    bearing_in_step = gearbox.compliant_bearings.get(bearing)
    in_step = bearing_in_step is not None and any(r.name == row.name for r in bearing_in_step.rows)
    if not in_step or row.clearance >= 0.0:
        return None
    return np.hypot(
        rolling_load(radial[:, 0], row.stiffness[1], row.clearance),
        rolling_load(radial[:, 1], row.stiffness[2], row.clearance),
    )


def bearing_life_data(gearbox: Any) -> dict[str, BearingLifeData]:
    """The life data `run_load_sums` uses for each bearing and row, by its rated name.

    The model's ``<bearing>`` data (and rotating ring, `life_data_of`), and each row's with the
    row's own size when its data gives none: what its modified and reference sums depend on
    besides the loads (a fatigue set's case key, ``life/fatigue_set.py``).
    """
    given = gearbox.source.bearing_life
    out = {
        name: life_data_of(gearbox, name, given.get(name))
        for name in dict.fromkeys([*gearbox.source.bearings, *given])
    }
    for bearing, rows in gearbox.source.bearing_rows.items():
        for row in rows:
            data = life_data_of(gearbox, bearing, row.life)
            if data.size is None and row.size is not None:
                data = dataclasses.replace(data, size=row.size)
            out[row_name(bearing, row.name)] = data
    return out
