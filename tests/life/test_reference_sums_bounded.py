"""A row's ISO/TS 16281 reference sums in bounded memory (``life/life_sums._ReferenceCells``).

A row with a clearance or a preload keeps its samples in a file until the history's end (its
cells are shares of the whole history's largest load) and reads them back in chunks; every row
solves its cells a chunk at a time. Both must give the sums of the whole history held in memory:
Σ P_ref,i^p n_i and Σ P_ref,i^p Δt_i of each sample's own P_ref from ``sample_distribution`` of
the whole history at once (``row_contact.load_cells`` over all the samples, ISO/TS 16281:2008),
to 1e-12 (the sums are added in another order), whatever the parts the history comes in, and
the same samples without equilibrium. The chunks are made small here so that a history of a few
thousand samples spans many.
"""

from __future__ import annotations

import gc
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind.life.life_sums as life_sums
from pinwind.life.bearing_life import load_power_sum, sample_weights
from pinwind.life.life_sums import HistoryStream, sample_distribution
from pinwind.model.bearing import bearing_rating
from pinwind.model.bearing_life_data import BearingLifeData
from tests.life.test_case_stream import random_cuts

N = 2500
SIZE = (0.30, 0.20, 0.06)
TAPERED = bearing_rating("row", "tapered_roller", dynamic_load_rating=500e3)
CYLINDER = bearing_rating("row", "cylindrical_roller", dynamic_load_rating=500e3)
#: (rating, clearance [m] (< 0: a preload), mean axial load [N]): a cylindrical row with a
#: 20 µm clearance and one without; a single tapered row with a 10 µm preload whose mean axial
#: load is negative (it faces the other way) and one without clearance.
ROWS = {
    "clearance": (CYLINDER, 20e-6, 0.0),
    "no clearance": (CYLINDER, 0.0, 0.0),
    "preloaded tapered": (TAPERED, -10e-6, -40e3),
    "tapered": (TAPERED, 0.0, -40e3),
}


def history(seed: int, axial: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time [s], speed [rad/s], W (n, 5) [N, N·m]): a seeded radial load turning about 60 kN."""
    rng = np.random.default_rng(seed)
    time = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, N))
    speed = 10.0 + rng.normal(0.0, 2.0, N)
    load = np.column_stack([
        60e3 + rng.normal(0, 12e3, N), rng.normal(0, 12e3, N), axial + rng.normal(0, 4e3, N),
        rng.normal(0, 300, N), rng.normal(0, 300, N),
    ])  # fmt: skip
    return time, speed, load


@pytest.fixture
def small_chunks(monkeypatch):
    """Chunks of 97 samples read back and 7 cells solved at a time."""
    monkeypatch.setattr(life_sums, "SAMPLE_CHUNK", 97)
    monkeypatch.setattr(life_sums, "CELL_CHUNK", 7)


@pytest.mark.parametrize("row", ROWS)
def test_reference_sums_in_random_parts_are_those_of_each_samples_own_p_ref(
    row, small_chunks, tmp_path
):
    rating, clearance, axial = ROWS[row]
    data = BearingLifeData(size=SIZE, clearance=clearance)
    time, speed, load = history(38, axial)
    rng = np.random.default_rng(281)
    for largest in (5, 400):
        stream = HistoryStream(row, rating, data=data, size=None, folder=tmp_path)
        assert stream.geometry is not None and stream.geometry.clearance == clearance
        for start, stop in random_cuts(rng, N, largest):
            stream.add(time=time[start:stop], speed=speed[start:stop], load=load[start:stop])
        kept = list(tmp_path.iterdir())
        if clearance:  # W, revolutions and seconds of every sample but the last (held)
            assert [p.stat().st_size for p in kept] == [(N - 1) * 7 * 8]
        else:
            assert kept == []
        got = stream.sums()
        assert list(tmp_path.iterdir()) == []  # the file goes with the sums
        # The whole history at once: each sample's P_ref of its cell, as the sums' docstring.
        whole = sample_distribution(stream.geometry, load)
        assert whole.failed == 0
        weights = sample_weights(time)
        turns = weights * np.abs(speed) / (2.0 * math.pi)
        p = rating.exponent
        assert_allclose(
            got.sums.reference_sum, load_power_sum(whole.reference_load, turns, p), rtol=1e-12
        )
        assert_allclose(
            got.sums.reference_time_sum,
            load_power_sum(whole.reference_load, weights, p),
            rtol=1e-12,
        )


@pytest.mark.parametrize("clearance", [10e-6, 0.0])
def test_samples_without_equilibrium_are_counted_as_the_whole_history_counts_them(
    clearance, small_chunks, tmp_path
):
    # A single tapered row whose axial load is at times below its induced thrust F_r tan α:
    # those samples have no equilibrium, and the note names as many as the whole history's
    # distribution finds, and as many below the thrust.
    data = BearingLifeData(size=SIZE, clearance=clearance)
    time, speed, load = history(16, -15e3)
    stream = HistoryStream("row", TAPERED, data=data, size=None, folder=tmp_path)
    for start, stop in random_cuts(np.random.default_rng(3), N, 300):
        stream.add(time=time[start:stop], speed=speed[start:stop], load=load[start:stop])
    got = stream.sums()
    assert stream.geometry is not None
    whole = sample_distribution(stream.geometry, load)
    assert whole.failed > 0 and whole.below_thrust > 0
    assert math.isnan(got.sums.reference_sum)
    assert any(
        f"no equilibrium at {whole.failed} of {N} samples ({whole.below_thrust} with" in note
        for note in got.notes
    ), got.notes


def test_a_rows_kept_samples_file_goes_when_the_stream_is_let_go(tmp_path):
    data = BearingLifeData(size=SIZE, clearance=20e-6)
    time, speed, load = history(7, 0.0)
    stream = HistoryStream("row", CYLINDER, data=data, size=None, folder=tmp_path)
    stream.add(time=time, speed=speed, load=load)
    assert len(list(tmp_path.iterdir())) == 1
    del stream
    gc.collect()
    assert list(tmp_path.iterdir()) == []
