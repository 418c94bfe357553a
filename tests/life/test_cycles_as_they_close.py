"""Rainflow cycles counted as a history comes, and a case's cycles written as they close.

Counting a history in parts is counting it whole when the stack of points not yet closed (the
residue) is carried from part to part and only the last residue is counted as half cycles
(ASTM E1049-85 §5.4.4, the three-point rule; the ``rainflow`` package's ``extract_cycles`` is
such a loop over a stream). The reference is the ``rainflow`` package itself. The residue of a
history whose values are the integers 0..L has strictly decreasing ranges, each an integer of
0..L, so it holds at most L + 2 points: the memory of the count does not grow with the
history. A case whose cycles go to files as they close writes the ``.npz`` of the case whose
cycles were held in memory: the same arrays, bit for bit.
"""

from __future__ import annotations

import json
import warnings
from collections import Counter

import numpy as np
import rainflow
from numpy.testing import assert_array_equal

import pinwind
from pinwind.life.case_cycles import CaseCycles, case_cycles
from pinwind.life.cycles import CycleStream
from pinwind.runs.case_runner import (
    CASE_SERIES,
    case_reduction,
    case_scenario,
    reduced_case,
    save_reduced_case,
)
from pinwind.runs.fatigue_set_file import load_fatigue_set
from pinwind.runs.scenario import run
from tests.conftest import fatigue_toml


def counted_in_parts(history: np.ndarray, rng: np.random.Generator, largest: int) -> list:
    """(range, mean, count) of each cycle of ``history`` fed to a `CycleStream` in random
    parts of 1 to ``largest`` samples, in the order given."""
    stream = CycleStream()
    found = []
    start = 0
    while start < history.size:
        stop = min(history.size, start + int(rng.integers(1, largest + 1)))
        part = stream.add(history[start:stop])
        found += zip(part.ranges, part.means, part.counts, strict=True)
        start = stop
    last = stream.end()
    return found + list(zip(last.ranges, last.means, last.counts, strict=True))


def test_cycles_of_a_history_in_parts_are_the_rainflow_packages_cycles_of_the_whole():
    """Random walks (rounded: plateaus and repeated levels) and bounded random levels, cut at
    random: the cycles, half cycles of the last residue included, are those
    ``rainflow.extract_cycles`` finds in the whole history, in its order, to 1e-12, and their
    counts per (range, count) are ``rainflow.count_cycles``' counts per range."""
    rng = np.random.default_rng(3812)
    for trial in range(120):
        n = int(rng.integers(1, 600))
        if trial % 3 == 0:
            history = rng.integers(0, 6, size=n).astype(float)
        else:
            history = np.round(rng.normal(size=n).cumsum(), trial % 3)
        got = counted_in_parts(history, rng, (2, 7, 50)[trial % 3])
        want = [(r, m, c) for r, m, c, _, _ in rainflow.extract_cycles(history)]
        assert len(got) == len(want), trial
        if want:
            np.testing.assert_allclose(np.array(got), np.array(want), rtol=1e-12, atol=1e-12)
        halves = sum(1 for *_, c in want if c == 0.5)
        assert sum(1 for *_, c in got if c == 0.5) == halves
        per_range = Counter()
        for r, _, c in got:
            per_range[r] += c
        assert sorted(per_range.items()) == sorted(rainflow.count_cycles(history))


def test_the_count_holds_a_residue_bounded_by_the_levels_not_the_history():
    """200 000 samples of the levels 0..20 given 1000 at a time: the points held never exceed
    the residue's bound, 20 + 2 (its ranges strictly decrease through 20..0), plus the two
    last reversals; and the cycles closed on the way and at the end are all the package's."""
    rng = np.random.default_rng(7)
    history = rng.integers(0, 21, size=200_000).astype(float)
    stream = CycleStream()
    held, closed = 0, 0.0
    for start in range(0, history.size, 1000):
        closed += float(np.sum(stream.add(history[start : start + 1000]).counts))
        held = max(held, stream.held)
    last = stream.end()
    assert held <= 22 + 2
    # the last two points close a few cycles of the residue, at most, and halve the rest
    assert last.counts.size <= 22 + 2 and np.sum(last.counts == 0.5) >= 1
    total = sum(c for _, c in rainflow.count_cycles(history))
    assert closed + float(np.sum(last.counts)) == total


def test_a_case_saved_from_its_cycle_files_is_the_case_saved_from_memory(tmp_path):
    """The DTU 500 kW case's run fed in random blocks to a reduction whose cycles go to files,
    saved from them (`save_reduced_case`), and the same blocks reduced and held in memory,
    saved by `CaseCycles.save`: the same array names, dtypes and values bit for bit, the same
    record; `CaseCycles.load` reads it; its flanks are `case_cycles` of the whole run (cycles
    exactly, in their order); and the reduction's folder of files is gone."""
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    case = fset.cases()[0]
    scenario = case_scenario(case, fset)
    gearbox = pinwind.load(scenario.model_path())
    fset.out.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run(scenario, gearbox=gearbox, progress=False, statistics=False,
                     keep_series=CASE_SERIES)  # fmt: skip
    first = int(np.searchsorted(result.time, fset.skip_start - 1e-12))
    counted = result.rows(first, len(result))
    rng = np.random.default_rng(38)
    on_disk, in_memory = case_reduction(fset, gearbox), case_reduction(fset, gearbox)
    start = 0
    while start < len(counted):
        stop = min(len(counted), start + int(rng.integers(1, 200)))
        on_disk.add(counted.rows(start, stop))
        in_memory.add(counted.rows(start, stop))
        start = stop
    folder = on_disk.folder
    assert any(folder.iterdir())  # cycles went to files as they closed
    path = save_reduced_case(case, fset, on_disk, wall_time=1.5)
    assert not folder.exists()
    memory_path = tmp_path / "memory.npz"
    reduced_case(case, fset, in_memory, wall_time=1.5).save(memory_path)
    with np.load(path) as got, np.load(memory_path) as want:
        assert list(got.keys()) == list(want.keys())
        assert len(got.keys()) > 20
        for key in want.keys():
            if key == "meta":
                assert str(got[key]) == str(want[key])  # the same record, NaN times too
                assert json.loads(str(got[key]))["wall_time"] == 1.5
            else:
                assert got[key].dtype == want[key].dtype, key
                assert_array_equal(got[key], want[key], err_msg=key)
    loaded = CaseCycles.load(path)
    whole = case_cycles(result.rows(first, len(result)), gearbox, fset.gears,
                        materials=fset.materials)  # fmt: skip
    assert len(loaded.flanks) == len(whole) > 5
    assert sum(f.counts.sum() for f in loaded.flanks) > 100
    for got_flank, want_flank in zip(loaded.flanks, whole, strict=True):
        assert (got_flank.gear, got_flank.flank) == (want_flank.gear, want_flank.flank)
        assert_array_equal(got_flank.tooth, want_flank.tooth)
        assert_array_equal(got_flank.ranges, want_flank.ranges)
        assert_array_equal(got_flank.counts, want_flank.counts)
        assert_array_equal(got_flank.peaks, want_flank.peaks)
