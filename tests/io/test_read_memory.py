"""A read into the memory of an earlier read: the same arrays, bit for bit, and nothing held reused.

``read_memory`` keeps the allocation of a read whose arrays have all been dropped and gives it
to the next read, which then writes every value (the memory holds the old ones). These tests
fill the first read's arrays with a value no run gives before dropping them, so that any value
the second read did not write shows; the run steps its torques on halfway, so that whole arrays
are +0.0 over the first blocks (those a read into new memory never writes).
"""

from __future__ import annotations

import gc

import numpy as np
import pytest

import pinwind
from pinwind.io import read_memory
from pinwind.io.log_reader import read_log
from pinwind.io.read_memory import read_arrays, release, written
from pinwind.loads.signals import Step
from pinwind.units import rpm_to_rad_s
from tests.io.conftest import DT
from tests.io.test_log_writer import assert_same_arrays

#: The torques step on at half the run: 20 001 samples of 1 ms, arrays of 50 MB (huge pages).
DURATION = 20.0
TORQUES = {
    "carrier": Step(time=DURATION / 2, before=0.0, after=1.0e6),
    "sun": Step(time=DURATION / 2, before=0.0, after=-1.0e6 / 6.0),
}
#: A value no array of the run holds.
SCRIBBLE = 7.25


@pytest.fixture(scope="module")
def long_run(planetary, tmp_path_factory):
    path = tmp_path_factory.mktemp("memory") / "long.mcap"
    result = pinwind.simulate(planetary, duration=DURATION, dt=DT, torques=TORQUES, log=path)
    return result, path


@pytest.fixture(scope="module")
def steady_run(planetary, tmp_path_factory):
    """Turning at 14.2 rpm and loaded throughout: the arrays zero over the first block (the
    spur meshes' axial force, the rigid bearings' displacements, friction) stay zero, so a read
    leaves their rows, laid out last, at +0.0."""
    path = tmp_path_factory.mktemp("memory") / "steady.mcap"
    torques = {"carrier": 1.0e6, "sun": -1.0e6 / 6.0}
    speeds = {"carrier": rpm_to_rad_s(14.2)}
    result = pinwind.simulate(
        planetary, duration=DURATION, dt=DT, torques=torques, initial_speeds=speeds, log=path
    )
    return result, path


def _address(array: np.ndarray) -> int:
    return array.__array_interface__["data"][0]


def _scribbled_read(path) -> int:
    """Reads the log, overwrites every array with SCRIBBLE, drops them: the time's address."""
    read = read_log(path)
    for name in read.ARRAYS:
        getattr(read, name)[...] = SCRIBBLE
    return _address(read.time)


def test_a_read_into_an_earlier_reads_memory_equals_the_run_bit_for_bit(long_run):
    result, path = long_run
    release()
    first = _scribbled_read(path)
    gc.collect()
    again = read_log(path)
    assert _address(again.time) == first  # the same memory, used again
    assert not np.any(again.mesh_normal[: len(again) // 4])  # unloaded: written as +0.0
    assert_same_arrays(again, result)


@pytest.mark.parametrize("scribbled", [False, True])
def test_rows_left_at_zero_by_a_read_read_back_as_zeros_the_next_time(
    steady_run, long_run, scribbled
):
    """The steady run's zero arrays: the second read leaves their rows alone unless the
    caller wrote into them; either way they read back as the run's +0.0. Then the other run's
    log, whose arrays lie otherwise in the same memory, and the steady one again."""
    result, path = steady_run
    release()
    if scribbled:
        _scribbled_read(path)
    else:
        read_log(path)
    gc.collect()
    # the first read left a fifth of the memory or more at +0.0 (the case under test)
    kept = read_memory._kept[0]
    assert kept.zero_from < kept.arena.ctypes.data + 0.8 * kept.arena.nbytes
    again = read_log(path)
    assert not again.mesh_axial.any() and not again.bearing_displacement.any()
    assert_same_arrays(again, result)
    memory = _address(again.time)
    del again
    gc.collect()
    other_result, other_path = long_run
    other = read_log(other_path)
    assert _address(other.time) == memory
    assert_same_arrays(other, other_result)
    del other
    gc.collect()
    assert_same_arrays(read_log(path), result)


def test_memory_a_caller_still_holds_is_not_used_again(long_run):
    result, path = long_run
    release()
    read = read_log(path)
    held = read.mesh_normal[::3]  # a view
    buffer = memoryview(read.bearing_force)
    del read
    gc.collect()
    again = read_log(path)
    for name in again.ARRAYS:
        assert not np.shares_memory(held, getattr(again, name)), name
        assert not np.shares_memory(np.asarray(buffer), getattr(again, name)), name
    np.testing.assert_array_equal(held, result.mesh_normal[::3])
    np.testing.assert_array_equal(np.asarray(buffer), result.bearing_force)
    assert_same_arrays(again, result)


def test_only_an_allocation_nobody_refers_to_is_given_again():
    release()
    rows, columns = 64, 20_001  # 10 MB
    first, first_zero = read_arrays(rows, columns)
    assert first_zero == 0  # new memory: zeros
    first[...] = SCRIBBLE
    second, first_zero = read_arrays(rows, columns)  # the first is still held
    assert first_zero == 0 and not np.shares_memory(first, second)
    assert not second[:, ::997].any()
    second[...] = SCRIBBLE
    del first, second
    third, first_zero = read_arrays(rows, columns)  # the second's, kept when it was made
    assert first_zero == rows and (third == SCRIBBLE).all()  # nothing known: all written
    smaller, first_zero = read_arrays(rows // 2, columns)  # the kept one is in use
    assert first_zero == 0
    del third, smaller
    release()
    fourth, first_zero = read_arrays(rows, columns)
    assert first_zero == 0 and not fourth[:, ::997].any()


def test_rows_a_read_left_at_zero_are_left_alone_until_someone_writes_them():
    release()
    rows, columns = 64, 20_001
    array, _ = read_arrays(rows, columns)
    array[:10] = SCRIBBLE  # a read that gave rows 0-9 values and left 10-63 at +0.0
    written(array, 9, complete=True)
    del array
    again, first_zero = read_arrays(rows, columns)
    assert first_zero == 10
    written(again, 63, complete=False)  # stopped: nothing known
    del again
    again, first_zero = read_arrays(rows, columns)
    assert first_zero == rows
    written(again, 9, complete=True)
    again[40, 7] = -0.0  # the caller's write after the read: -0.0 is not +0.0
    del again
    again, first_zero = read_arrays(rows, columns)
    assert first_zero == rows
    again[10:] = 0.0  # the read writes every value: rows 10-63 are given +0.0
    written(again, 9, complete=True)
    del again
    fewer, first_zero = read_arrays(rows // 2, columns)  # the same memory, fewer rows
    assert first_zero == 10
    fewer[4:10] = 0.0  # a read that gives rows 0-3 values and rows 4-9 +0.0
    written(fewer, 3, complete=True)
    del fewer
    # rows 32-63 of the 64-row view lie past the last read's and still hold 0: rows 4-63 zero
    again, first_zero = read_arrays(rows, columns)
    assert first_zero == 4
