"""The byte planes of a log's columns (docs/log_format.md, "Columns", layout 3), and the sink.

The compiled kernels (``dynamics/cpp/byte_planes.hpp``) against the definition written with
numpy: byte b (little-endian) of value i of a run of n values is at b · n + i.
"""

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_array_equal

import pinwind
from pinwind.dynamics._native import fill_rows, shuffle_series, unshuffle_series
from pinwind.io import mcap_file
from pinwind.io.log_channels import CHANNELS
from pinwind.io.log_columns import ColumnSink, decode_chunk
from pinwind.io.log_reader import LogReader
from tests.io.conftest import DT, TORQUES

#: Lengths below, at and past the 16 values of one vector step, and long runs with a tail.
LENGTHS = [1, 2, 15, 16, 17, 31, 33, 1003]


def _planes_by_definition(values: np.ndarray) -> np.ndarray:
    """Byte b of every value, b = 0..7, for the values in order (little-endian float64)."""
    raw = np.ascontiguousarray(values, dtype="<f8").reshape(-1).view(np.uint8)
    return raw.reshape(-1, 8).T.reshape(-1)


def _awkward_values(rng: np.random.Generator, shape: tuple[int, int]) -> np.ndarray:
    """Random values with the bit patterns a log must keep: signed zeros, infinities, NaN
    payloads, subnormals."""
    values = rng.normal(size=shape) * 10.0 ** rng.integers(-300, 300, size=shape)
    flat = values.reshape(-1)
    special = [0.0, -0.0, np.inf, -np.inf, 5e-324, -2.2e-308]
    for i, value in enumerate(special):
        flat[(7 * i) % flat.size] = value
    flat.view(np.uint64)[(11 * 5) % flat.size] = 0x7FF8_0000_DEAD_BEEF  # a NaN with a payload
    return values


@pytest.mark.parametrize("m", LENGTHS)
def test_byte_planes_of_chosen_rows_are_byte_b_of_every_value_in_turn(m):
    rng = np.random.default_rng(m)
    values = _awkward_values(rng, (6, m))
    rows = np.array([4, 0, 5, 2], dtype=np.int64)
    planes = np.empty(8 * len(rows) * m, np.uint8)
    shuffle_series(values, rows, planes)
    assert_array_equal(planes, _planes_by_definition(values[rows]))


@pytest.mark.parametrize("m", LENGTHS)
@pytest.mark.parametrize("stream", [False, True])
def test_series_from_byte_planes_are_the_values_bit_for_bit_in_their_rows(m, stream):
    rng = np.random.default_rng(100 + m)
    values = _awkward_values(rng, (3, m))
    planes = _planes_by_definition(values)
    out = np.full((5, m + 7), 1.25)
    # every series to another row, from an odd sample: stores that do not start on 16 bytes
    unshuffle_series(planes, m, 0, m, np.array([3, -1, 0]), out, 5, stream)
    assert_array_equal(out[3, 5 : 5 + m].view(np.uint64), values[0].view(np.uint64))
    assert_array_equal(out[0, 5 : 5 + m].view(np.uint64), values[2].view(np.uint64))
    untouched = np.ones(out.shape, dtype=bool)
    untouched[[3, 0], 5 : 5 + m] = False
    assert (out[untouched] == 1.25).all()  # the skipped series, other rows and samples


@pytest.mark.parametrize("stream", [False, True])
def test_a_window_of_samples_from_byte_planes_lands_at_its_place(stream):
    rng = np.random.default_rng(7)
    m = 1000
    values = rng.normal(size=(2, m))
    out = np.zeros((2, 900))
    unshuffle_series(_planes_by_definition(values), m, 37, 851, np.array([1, 0]), out, 40, stream)
    assert_array_equal(out[1, 40:891], values[0, 37:888])
    assert_array_equal(out[0, 40:891], values[1, 37:888])
    assert not out[:, :40].any() and not out[:, 891:].any()


@pytest.mark.parametrize("count", [0, 1, 3, 32, 1001])
@pytest.mark.parametrize("stream", [False, True])
def test_fill_rows_sets_each_chosen_row_over_the_samples_and_nothing_else(count, stream):
    out = np.zeros((4, 1010))
    fill_rows(np.array([np.nan, -0.0, 3.5]), np.array([2, -1, 0]), out, 3, count, stream)
    assert np.isnan(out[2, 3 : 3 + count]).all()
    assert_array_equal(out[0, 3 : 3 + count], 3.5)
    rest = np.ones(out.shape, dtype=bool)
    rest[[2, 0], 3 : 3 + count] = False
    assert_array_equal(out[rest].view(np.uint64), 0)  # +0.0 bit for bit: -0.0 went nowhere


def test_byte_planes_refuse_sizes_and_rows_that_do_not_fit():
    planes = np.zeros(8 * 2 * 10, np.uint8)
    out = np.zeros((3, 10))
    with pytest.raises(ValueError, match="planes hold 160 bytes, not 8 · 3 · 10"):
        unshuffle_series(planes, 10, 0, 10, np.array([0, 1, 2]), out, 0)
    with pytest.raises(ValueError, match="samples 5 \\+ 10 of 10"):
        unshuffle_series(planes, 10, 5, 10, np.array([0, 1]), out, 0)
    with pytest.raises(ValueError, match="row 3 of out \\(3, 10\\)"):
        unshuffle_series(planes, 10, 0, 10, np.array([0, 3]), out, 0)
    with pytest.raises(ValueError, match="row 6 of values \\(2, 10\\)"):
        shuffle_series(np.zeros((2, 10)), np.array([6]), np.zeros(80, np.uint8))
    with pytest.raises(ValueError, match="2 values for 1 rows"):
        fill_rows(np.zeros(2), np.array([0]), out, 0, 1)


def test_samples_placed_one_by_one_equal_the_same_samples_of_a_whole_read(planetary, tmp_path):
    """A window whose samples are not consecutive in a block (a foreign file's times) takes
    the per-sample path of ``ColumnSink.place``; it must give what the whole read gives."""
    path = tmp_path / "run.mcap"
    pinwind.simulate(planetary, duration=0.2, dt=DT, torques=TORQUES, log=path, chunk=100)
    whole = pinwind.read_log(path)
    picked = np.array([0, 3, 4, 50, 99])  # of the second block: samples 100 + picked
    with LogReader(path) as log:
        keys = log._layout.keys(tuple(CHANNELS))
        block = decode_chunk(
            mcap_file.read_chunk(log._fd, log._sample_chunks(None)[1]), log._columns
        )[0]
        sink = ColumnSink(log._columns, log._layout.shapes, keys, len(picked))
        sink.place(block, picked, len(picked), 0)
        sink.n = len(picked)
        part = sink.result(log.names, log._layout.terms)
    for name in ("time", "mesh_normal", "mesh_axial", "bearing_force_local"):
        assert_array_equal(getattr(part, name), getattr(whole, name)[100 + picked], err_msg=name)
    # poses every 10th sample (100 Hz at 1 ms): samples 100 and 150 of those picked
    assert_array_equal(part.pose_rows, [0, 3])
    assert_array_equal(part.body_position, whole.body_position[[10, 15]])
    assert_array_equal(whole.pose_rows[[10, 15]], [100, 150])


def test_constant_series_read_bit_for_bit_including_signed_zeros(planetary, tmp_path):
    """Series constant over a block are filled (+0.0 by the zeroed array, not written); -0.0,
    NaN and other constants keep their bits. The constants are set by hand: +0.0, -0.0, NaN and
    1.5 in turn over the block's constant series."""
    path = tmp_path / "run.mcap"
    pinwind.simulate(planetary, duration=0.1, dt=DT, torques=TORQUES, log=path, chunk=100)
    pattern = np.array([0.0, -0.0, np.nan, 1.5])
    with LogReader(path) as log:
        keys = log._layout.keys(tuple(CHANNELS))
        block = decode_chunk(
            mcap_file.read_chunk(log._fd, log._sample_chunks(None)[0]), log._columns
        )[0]
        constant = np.flatnonzero(block.same)
        assert len(constant) > 8  # the run has many series constant over a block
        # the time (series 0) varies: every constant series is a sample's value of some array
        assert not block.same[0]
        values = np.resize(pattern, len(constant))
        block = dataclasses.replace(block, constants=values)
        sink = ColumnSink(log._columns, log._layout.shapes, keys, block.samples)
        sink.place(block, slice(0, block.samples), block.samples, 0)
    for series, value in zip(constant, values, strict=True):
        row = sink.row_of[series]
        if row < 0:  # not a series a read copies
            continue
        expected = np.full(block.samples, value)
        assert_array_equal(sink.base[row].view(np.uint64), expected.view(np.uint64))
