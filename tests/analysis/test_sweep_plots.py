"""Sweep plots: design labels that would overprint share one."""

from __future__ import annotations

from pinwind.analysis.sweep_plots import LABEL_GAP, design_labels


def test_designs_on_top_of_each_other_share_one_label():
    # #11-#14 at module 10 within 3 % of the y span of each other; #15 alone at module 12.
    labels = design_labels([11, 12, 13, 14, 15], [10, 10, 10, 10, 12], [1.0, 1.01, 1.02, 1.03, 2.0])
    assert labels == [("#11–#14", 10, 1.03), ("#15", 12, 2.0)]


def test_labels_at_one_module_are_apart_by_more_than_the_gap():
    numbers = [3, 7, 9, 20, 21]
    y = [0.5, 0.505, 0.9, 0.95, 1.5]
    labels = design_labels(numbers, [8] * 5, y)
    assert [text for text, _, _ in labels] == ["#3, #7", "#9", "#20", "#21"]
    heights = sorted(b for _, _, b in labels)
    gap = LABEL_GAP * (max(y) - min(y))
    assert all(b - a > gap for a, b in zip(heights, heights[1:], strict=False))
