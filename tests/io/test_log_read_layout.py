"""Where a log read puts its arrays: one allocation, laid out from the first chunk, at a huge page.

``ColumnSink`` keeps every series of a read in one allocation and puts the destinations that are
+0.0 throughout the first chunk after the others (``zero_destinations``), so that the pages of
arrays that stay zero are never touched. The layout is a guess from the first chunk: these tests
load the gearbox only after the first chunk, so that arrays zero there are not zero later, and
check the read against the run bit for bit, and that the arrays of a read behave as separate
arrays (writing, pickling).
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import pinwind
from pinwind.io.log_columns import zero_destinations
from pinwind.io.log_reader import LogReader, read_log
from pinwind.io.read_memory import HUGE_PAGE, read_arrays, release
from pinwind.loads.signals import Step
from tests.io.conftest import DT
from tests.io.test_log_writer import assert_same_arrays

#: Samples per chunk; the torques step on at 0.15 s, in the second chunk.
CHUNK = 100
ON = 0.15
#: Balanced on the planetary stage (sun ÷ carrier = −1/6, as the shared run's torques).
TORQUES = {
    "carrier": Step(time=ON, before=0.0, after=1.0e6),
    "sun": Step(time=ON, before=0.0, after=-1.0e6 / 6.0),
}


@pytest.fixture(scope="module")
def stepped(planetary, tmp_path_factory):
    """A 0.3 s run of the planetary stage at rest until the torques step on, and its log."""
    path = tmp_path_factory.mktemp("layout") / "stepped.mcap"
    result = pinwind.simulate(
        planetary, duration=0.3, dt=DT, torques=TORQUES, log=path, chunk=CHUNK
    )
    return result, path


def _zero(values: np.ndarray) -> bool:
    """Every value +0.0 (all bits zero; -0.0 is not)."""
    return not np.ascontiguousarray(values).view(np.uint64).any()


def _first_address(array: np.ndarray) -> int:
    return array.__array_interface__["data"][0]


def test_arrays_zero_in_the_first_chunk_but_not_after_read_bit_for_bit(stepped):
    result, path = stepped
    # which arrays are zero over the first chunk, from the run itself
    columns = [n for n in result.ARRAYS if n not in ("body_position", "body_quaternion")]
    zero_first = {
        n for n in columns if getattr(result, n).size and _zero(getattr(result, n)[:CHUNK])
    }
    loaded_later = {n for n in zero_first if not _zero(getattr(result, n))}
    assert {"mesh_normal_front", "bearing_moment"} <= loaded_later  # the case under test
    with LogReader(path) as log:
        first = log._load_columns(log._sample_chunks(None)[0], None)[1]
        assert zero_destinations(first, log._columns) & set(columns) == zero_first
    read = read_log(path)
    assert_same_arrays(read, result)
    # laid out after the others: the rows of every destination zero in the first chunk come
    # after those of every other one
    last = min(_first_address(getattr(read, n)) for n in zero_first)
    others = [n for n in columns if getattr(read, n).size and n not in zero_first]
    assert max(_first_address(getattr(read, n)) for n in others) < last


def test_arrays_of_one_read_are_independent_writable_and_pickle_their_own_bytes(stepped):
    _, path = stepped
    read = read_log(path)
    names = [n for n in read.ARRAYS if getattr(read, n).size]
    before = {n: getattr(read, n).copy() for n in names}
    # one array zero throughout (laid out last), one that varies, a pose array
    for written in ("mesh_axial", "mesh_normal", "body_position"):
        array = getattr(read, written)
        assert array.flags.writeable
        array[...] = 7.25
        for n in names:
            if n != written:
                np.testing.assert_array_equal(getattr(read, n), before[n], err_msg=n)
        array[...] = before[written]
    for n in ("mesh_axial", "mesh_normal", "time"):
        array = getattr(read, n)
        data = pickle.dumps(array)
        # its own bytes and a header, not the allocation the read shares (~80 arrays' worth)
        assert array.nbytes <= len(data) < array.nbytes + 1000, n
        np.testing.assert_array_equal(pickle.loads(data), array)
    grown = np.resize(read.mesh_normal, (2 * len(read), read.mesh_normal.shape[1]))
    np.testing.assert_array_equal(grown[len(read) :], read.mesh_normal)


def test_large_arrays_start_at_a_huge_page_and_small_ones_are_plain():
    rows, columns = 64, 20_001  # 10 MB: the kernel backs it with huge pages
    release()  # new memory, not an earlier read's
    big, first_zero = read_arrays(rows, columns)
    assert first_zero == 0 and big.shape == (rows, columns)
    assert big.flags.c_contiguous and big.flags.writeable
    assert _first_address(big) % (2 << 20) == 0 == HUGE_PAGE % (2 << 20)
    assert _zero(big[:, ::997])  # pages touched only here
    small, first_zero = read_arrays(3, 10)
    assert first_zero == 0 and small.shape == (3, 10) and _zero(small) and small.base is None


def test_a_long_read_on_huge_pages_equals_the_run(planetary, tmp_path):
    """20 001 samples: arrays of 50 MB, starting at a huge page (the short logs above give
    arrays under the 4 MiB from which the read aligns them), placed by both reading threads."""
    path = tmp_path / "long.mcap"
    torques = {"carrier": 1.0e6, "sun": -1.0e6 / 6.0}
    result = pinwind.simulate(planetary, duration=20.0, dt=DT, torques=torques, log=path)
    read = read_log(path)
    assert _first_address(read.time) % (2 << 20) == 0
    assert_same_arrays(read, result)
