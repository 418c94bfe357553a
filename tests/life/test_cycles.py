"""Rainflow cycles: the ASTM E1049-85 example and the range × mean matrix."""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.errors import InputError, NonFiniteInput
from pinwind.life.cycles import rainflow_cycles

#: The load history of ASTM E1049-85 Fig. 6 (rainflow counting example), in load units.
ASTM_HISTORY = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0]


def counts_by_range(cycles) -> dict[float, float]:
    """Cycles summed per range, as the standard's table lists them."""
    table: dict[float, float] = {}
    for value, count in zip(cycles.ranges, cycles.counts, strict=True):
        table[float(value)] = table.get(float(value), 0.0) + float(count)
    return table


def test_astm_example_gives_the_published_counts_per_range():
    """ASTM E1049-85 Fig. 6 / its table of the rainflow example: range 3 → 0.5 cycle, 4 → 1.5,
    6 → 0.5, 8 → 1.0, 9 → 0.5 (the same table is quoted in iamlikeme/rainflow issue #4)."""
    table = counts_by_range(rainflow_cycles(ASTM_HISTORY))
    assert sorted(table) == [3.0, 4.0, 6.0, 8.0, 9.0]
    np.testing.assert_allclose(
        [table[r] for r in (3.0, 4.0, 6.0, 8.0, 9.0)], [0.5, 1.5, 0.5, 1.0, 0.5], rtol=0, atol=0
    )


def test_astm_example_cycle_means_follow_from_its_peaks_and_valleys():
    """By hand, ASTM E1049-85 §5.4.4 on the example: half cycles -2→1, 1→-3, -3→5, 5→-4, -4→4,
    4→-2 and the full cycle -1↔3, each with mean (peak + valley) / 2."""
    cycles = rainflow_cycles(ASTM_HISTORY)
    found = sorted(zip(cycles.ranges, cycles.means, cycles.counts, strict=True))
    expected = sorted(
        [
            (3.0, (-2 + 1) / 2, 0.5),
            (4.0, (1 - 3) / 2, 0.5),
            (8.0, (-3 + 5) / 2, 0.5),
            (9.0, (5 - 4) / 2, 0.5),
            (8.0, (-4 + 4) / 2, 0.5),
            (6.0, (4 - 2) / 2, 0.5),
            (4.0, (-1 + 3) / 2, 1.0),
        ]
    )
    np.testing.assert_allclose(np.array(found), np.array(expected), rtol=0, atol=1e-12)


def test_total_cycles_of_the_astm_example_is_four_and_a_half():
    """0.5 + 1.5 + 0.5 + 1.0 + 0.5 = 4 cycles in the standard's table."""
    np.testing.assert_allclose(rainflow_cycles(ASTM_HISTORY).total, 4.0, rtol=0, atol=0)


def test_cosine_history_counts_one_cycle_per_period_of_its_peak_to_peak_range():
    """10 − 3 cos(2πt) over 5 whole periods, from valley to valley: every cycle spans valley 7
    to peak 13, range 6 and mean 10, and 5 periods hold 5 cycles."""
    t = np.linspace(0.0, 5.0, 5001)
    cycles = rainflow_cycles(10.0 - 3.0 * np.cos(2.0 * np.pi * t))
    np.testing.assert_allclose(cycles.ranges, 6.0, rtol=1e-9)
    np.testing.assert_allclose(cycles.means, 10.0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cycles.total, 5.0, rtol=0, atol=1e-12)


def test_scaled_cycles_multiply_every_count():
    cycles = rainflow_cycles(ASTM_HISTORY).scaled(1000.0)
    np.testing.assert_allclose(cycles.total, 4000.0, rtol=1e-12)


def test_matrix_bins_every_cycle_by_range_and_mean():
    """Edges 0-5-10 (range) and -1-0-1 (mean) put, by the hand list above: range < 5 with mean
    < 0 → 0.5 + 0.5; range < 5, mean ≥ 0 → 1.0 (the full 4-cycle, mean 1); range ≥ 5, mean < 0
    → none; range ≥ 5, mean ≥ 0 → four half cycles."""
    matrix = rainflow_cycles(ASTM_HISTORY).matrix(range_bins=[0, 5, 10], mean_bins=[-1, 0, 1])
    np.testing.assert_allclose(matrix.counts, [[1.0, 1.0], [0.0, 2.0]], rtol=0, atol=0)
    np.testing.assert_allclose(matrix.range_centres, [2.5, 7.5], rtol=0, atol=0)
    np.testing.assert_allclose(matrix.mean_centres, [-0.5, 0.5], rtol=0, atol=0)


def test_matrix_with_bin_counts_keeps_all_cycles():
    """Equal bins span 0 to the largest range (9) and the smallest to the largest mean."""
    matrix = rainflow_cycles(ASTM_HISTORY).matrix(range_bins=3, mean_bins=4)
    assert matrix.counts.shape == (3, 4)
    np.testing.assert_allclose(matrix.range_edges, [0.0, 3.0, 6.0, 9.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(matrix.mean_edges[[0, -1]], [-1.0, 1.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(matrix.counts.sum(), 4.0, rtol=0, atol=1e-12)


def test_non_finite_history_raises():
    with pytest.raises(NonFiniteInput, match="index 2"):
        rainflow_cycles([0.0, 1.0, np.nan, 2.0])


def test_two_dimensional_history_raises():
    with pytest.raises(InputError, match="shape"):
        rainflow_cycles(np.zeros((3, 4)))


def test_decreasing_bin_edges_raise():
    with pytest.raises(InputError, match="increasing"):
        rainflow_cycles(ASTM_HISTORY).matrix(range_bins=[5.0, 1.0])


def test_cycles_equal_those_the_package_counts_on_every_sample():
    """The compiled count of the reversals (found with numpy) gives the same cycles, bit for bit
    and in the same order, as ``rainflow.extract_cycles`` on the whole history: plateaus, a
    history without a reversal (a ramp), one whose start is counted 10 000 times and a long
    random one included."""
    import rainflow

    rng = np.random.default_rng(7)
    histories = [
        np.repeat(rng.integers(-2, 3, size=40), rng.integers(1, 4, size=40)).astype(float),
        np.concatenate([[0.0], np.abs(rng.normal(size=300)) * (rng.random(300) > 0.3), [0.0]]),
        rng.normal(size=500),
        np.array([1.0, 1.0, 1.0]),
        np.array([0.0, 1.0, 2.0]),
        np.array([0.0, 2.0]),
        # a growing oscillation: every start is counted as a half cycle (10 000 of them)
        np.arange(1, 10_001) * (-1.0) ** np.arange(10_000),
        # and a long random one (about 650 000 reversals, as a 30 s tooth history has)
        rng.normal(size=1_000_000),
    ]
    for history in histories:
        cycles = rainflow_cycles(history)
        expected = [(r, m, c) for r, m, c, _, _ in rainflow.extract_cycles(history)]
        found = list(zip(cycles.ranges, cycles.means, cycles.counts, strict=True))
        np.testing.assert_allclose(
            np.array(found).reshape(-1, 3), np.array(expected).reshape(-1, 3), rtol=0, atol=0
        )
