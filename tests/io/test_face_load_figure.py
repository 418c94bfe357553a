"""The face load figure of a sliced mesh: line load over face position and time, K_Hβ beside it.

A short run of the sliced pair of ``tests/dynamics/test_slice_series.py`` (6 slices lifting and
landing), logged: ``pinwind plot`` writes its figure after the group figures, every artist on
the page and every axis with its unit; the map it draws keeps each span's largest line load.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from numpy.testing import assert_array_equal  # noqa: E402

import pinwind  # noqa: E402
from pinwind.io.face_load_figures import FaceLoadMap, sliced_meshes  # noqa: E402
from pinwind.io.figures import FACE_LOAD, GROUPS, plot_log  # noqa: E402
from tests.dynamics.test_slice_series import turning  # noqa: E402
from tests.io.test_figures_layout import _on_the_page_with_units, checked_pages  # noqa: E402


@pytest.fixture(scope="module")
def sliced_log(tmp_path_factory):
    path = tmp_path_factory.mktemp("face") / "sliced.mcap"
    res = turning(6, log=path)
    return path, res


def test_plot_writes_the_face_load_figure_with_its_artists_and_units_on_the_page(
    sliced_log, tmp_path, monkeypatch
):
    path, _ = sliced_log
    pages = checked_pages(monkeypatch)
    written = plot_log(path, tmp_path, groups=[FACE_LOAD])
    assert [p.name for p in written] == [f"{len(GROUPS) + 1:02d}_face_load_m.png"]
    _on_the_page_with_units(pages, 1)
    (page,) = pages
    labels = " ".join(" ".join(axes) for axes in page.axes)
    assert "[mm]" in labels and "[s]" in labels and "K_Hβ" in labels


def test_an_unsliced_run_has_no_face_load_figure(logged_run, tmp_path):
    assert plot_log(logged_run.path, tmp_path, groups=[FACE_LOAD]) == []


def test_the_map_keeps_each_spans_largest_line_load_and_k_range_whatever_the_blocks(sliced_log):
    """One span per sample: the map is the series itself. Fewer spans: each holds the max of
    its samples, the same folded block by block as at once."""
    path, res = sliced_log
    assert sliced_meshes(res) == ["m"]
    _, w = res.slice_line_loads("m")
    factor = res.mesh("m").face_load_factor
    n = len(res)
    # n spans of (t_n−1 − t_0)/n: sample k < n − 1 at k + k/(n − 1) spans, in span k; the last
    # at n, kept in the last
    whole = FaceLoadMap.of(res, "m", spans=n)
    assert_array_equal(whole.line_load, w)
    assert_array_equal(whole.factor_low, factor)
    assert_array_equal(whole.factor_high, factor)
    assert_array_equal(whole.time_low, res.time)
    coarse = FaceLoadMap.of(res, "m", spans=7)
    edges = np.clip(((res.time - res.time[0]) / (res.time[-1] - res.time[0]) * 7).astype(int), 0, 6)
    for span in range(7):
        inside = edges == span
        assert_array_equal(coarse.line_load[span], w[inside].max(axis=0))
        assert coarse.factor_low[span] == factor[inside].min()
        assert coarse.factor_high[span] == factor[inside].max()
    by_blocks = FaceLoadMap("m", whole.positions, float(res.time[0]), float(res.time[-1]), 7)
    for start in range(0, n, 37):
        by_blocks.add(res.rows(start, start + 37))
    assert_array_equal(by_blocks.line_load, coarse.line_load)
    assert_array_equal(by_blocks.factor_low, coarse.factor_low)
    back = pinwind.read_log(path)
    assert_array_equal(FaceLoadMap.of(back, "m", spans=7).line_load, coarse.line_load)
