"""Runs stream block by block: the Result keeps what is asked, memory does not grow with length."""

from __future__ import annotations

import importlib
import tracemalloc

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.errors import InputError, TorquesUnbalanced
from tests.conftest import MODELS

# the module, not the function pinwind.dynamics exports under its name
simulate = importlib.import_module("pinwind.dynamics.simulate")

RUN = dict(dt=1e-3, torques={"carrier": 1e5, "sun": lambda t: -1e4 * (1 + np.sin(t))})


def accelerating(planetary, **options) -> Result:
    """The run of ``RUN``: its torques do not balance (1e5 N·m against about 6 · 1e4), the
    train accelerates, and the run says so (``TorquesUnbalanced``, asserted)."""
    with pytest.warns(TorquesUnbalanced, match='referred to joint "carrier"'):
        return pinwind.simulate(planetary, **options, **RUN)


@pytest.fixture(scope="module")
def planetary():
    return pinwind.load(MODELS / "saleh2017_planetary.urdf")


@pytest.fixture(scope="module")
def everything(planetary):
    return accelerating(planetary, duration=2.5, keep="all")


def _same_rows(res: Result, full: Result, rows: np.ndarray, posed: np.ndarray | None = None):
    """``res`` holds samples ``rows`` of ``full``, with the poses of its samples ``posed``
    (default: all)."""
    posed = np.arange(len(rows)) if posed is None else posed
    np.testing.assert_array_equal(res.pose_rows, posed)
    for name in Result.ARRAYS:
        expected = getattr(full, name)[rows]
        if name in POSE_ARRAYS:
            expected = expected[posed]
        np.testing.assert_array_equal(getattr(res, name), expected, err_msg=name)
    for name, values in full.energy.items():
        np.testing.assert_array_equal(res.energy[name], values[rows], err_msg=name)


def test_keeping_every_nth_sample_gives_those_samples_of_the_whole_run(planetary, everything):
    res = accelerating(planetary, duration=2.5, keep=7, chunk=300)
    rows = np.append(np.arange(0, len(everything), 7), len(everything) - 1)
    _same_rows(res, everything, rows)
    assert res.metadata["keep_stride"] == 7
    assert res.metadata["samples_simulated"] == len(everything)


@pytest.mark.parametrize("keep", [7, 600, "last"])
def test_without_statistics_the_kept_samples_equal_those_of_the_whole_run(
    planetary, everything, keep
):
    # No observer reads the blocks: the step loop records the kept samples alone (keep=600:
    # some blocks of 300 keep none) and the bearing loads, derived in Python, are derived for
    # them alone; all equal the whole run's at those samples.
    res = accelerating(planetary, duration=2.5, keep=keep, chunk=300, statistics=False)
    n = len(everything)
    rows = np.array([n - 1]) if keep == "last" else np.append(np.arange(0, n, keep), n - 1)
    _same_rows(res, everything, rows)
    assert res.statistics is None
    assert res.metadata["samples_simulated"] == n


def test_keeping_the_last_sample_gives_the_final_state(planetary, everything):
    res = accelerating(planetary, duration=2.5, keep="last")
    _same_rows(res, everything, np.array([len(everything) - 1]))


def test_the_log_holds_every_sample_whatever_the_result_keeps(planetary, everything, tmp_path):
    path = tmp_path / "run.mcap"
    accelerating(planetary, duration=2.5, keep="last", log=path)
    back = pinwind.read_log(path)
    # link poses are logged at 100 Hz (every 10th sample of 1 ms)
    _same_rows(back, everything, np.arange(len(everything)), np.arange(0, len(everything), 10))


@pytest.mark.parametrize("keep", ["some", 0, -3, 2.5, True])
def test_an_unknown_keep_is_refused(planetary, keep):
    with pytest.raises(InputError, match="keep is"):
        pinwind.simulate(planetary, duration=0.01, keep=keep, **RUN)


class _BlockSizes:
    def __init__(self) -> None:
        self.sizes: list[int] = []

    def begin(self, gearbox, result) -> None:
        pass

    def samples(self, block: Result, start: int) -> None:
        self.sizes.append(len(block))

    def end(self, result, status) -> None:
        pass


@pytest.mark.parametrize(
    ("duration", "block"),
    [(5.0, 1000), (30.0, 1500), (200.0, 5000)],  # 5001, 30 001, 200 001 samples at 1 ms
)
def test_blocks_are_a_twentieth_of_the_run_from_1000_to_5000_samples(planetary, duration, block):
    blocks = _BlockSizes()
    accelerating(planetary, duration=duration, keep="last", observer=blocks)
    samples = round(duration / RUN["dt"]) + 1
    assert sum(blocks.sizes) == samples
    assert set(blocks.sizes[:-1]) == {block}
    assert blocks.sizes[-1] == samples - block * (len(blocks.sizes) - 1)


@pytest.mark.parametrize("chunk", [0, -5, 2.5, True])
def test_a_block_of_no_whole_positive_number_of_samples_is_refused(planetary, chunk):
    with pytest.raises(InputError, match=f"chunk={chunk!r}: give a whole number"):
        pinwind.simulate(planetary, duration=0.01, chunk=chunk, **RUN)


def _peak_bytes(planetary, duration: float) -> int:
    tracemalloc.start()
    try:
        accelerating(planetary, duration=duration, keep="last", chunk=1000)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_peak_memory_does_not_grow_with_the_run_length(planetary):
    short, long = _peak_bytes(planetary, 3.0), _peak_bytes(planetary, 30.0)
    # Ten times the samples (30 001 of ~1.6 KB: 48 MB if kept), the same memory: one block of
    # 1000 samples and the kept last sample, a few MB either way.
    assert long < 1.2 * short + 1e6, (short, long)
    assert long < 20e6


class _UnreadBlockSizes(_BlockSizes):
    reads = False  # told of each block, reads none: the run may take them longer


def test_blocks_no_observer_reads_grow_after_the_first_and_equal_the_whole_run(
    planetary, everything
):
    # 2501 samples kept whole: the first block is the run's chunk (1000), the later ones last
    # about UNWATCHED_BLOCK_S at the step's measured cost, within [chunk, UNWATCHED_BLOCK_MAX];
    # blocks of any length step the same samples as 300-sample blocks.
    blocks = _UnreadBlockSizes()
    res = accelerating(planetary, duration=2.5, keep="all", observer=blocks)
    assert blocks.sizes[0] == 1000
    assert sum(blocks.sizes) == len(everything)
    assert all(1000 <= n <= simulate.UNWATCHED_BLOCK_MAX for n in blocks.sizes[1:-1])
    short = accelerating(planetary, duration=2.5, keep="all", chunk=300)
    _same_rows(res, short, np.arange(len(short)))


@pytest.mark.parametrize(
    ("per_sample", "samples"),
    [(1e-6, simulate.UNWATCHED_BLOCK_MAX), (4e-6, 25_000), (1e-3, 1000), (0.0, 50_000)],
)
def test_an_unread_block_lasts_a_tenth_of_a_second_within_its_bounds(per_sample, samples):
    assert simulate._unwatched_block(per_sample, 1000) == samples
