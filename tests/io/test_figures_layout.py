"""Every figure pinwind writes keeps its artists on the page and its numbers with their units.

Each figure is built on a short run (the shared planetary log of ``tests/io/conftest.py``, the
two-gear pair's Campbell diagram, a two-case fatigue set, three designs of the sweep) and is
checked when it is saved: every legend, title, caption and axes (with its tick and axis labels)
lies inside the figure's bounding box (``io/figure_layout.outside_figure``: what lies outside is
cut from the file), and every axis says its unit in brackets.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.figure  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pinwind.io.figure_layout import caption_below, outside_figure  # noqa: E402
from pinwind.io.figures import signal_in_units  # noqa: E402

#: A unit in brackets: "[kN]", "[kN·m]", "[rpm]", "[-]" (a ratio).
UNIT = re.compile(r"\[[^\]]+\]")


class Page:
    """What a saved figure showed: its file, the artists off the page, its axes' labels."""

    def __init__(self, fig, name: str):
        self.name = name
        self.outside = outside_figure(fig)
        self.axes = [
            (ax.get_title(loc="left") or ax.get_title(), ax.get_xlabel(), ax.get_ylabel())
            for ax in fig.axes
        ]
        renderer = fig.canvas.get_renderer()
        #: Per axes with a legend: whether the legend's box overlaps the axes' (hides data).
        self.legend_over_axes = [
            ax.get_legend().get_window_extent(renderer).overlaps(ax.get_window_extent(renderer))
            for ax in fig.axes
            if ax.get_legend() is not None
        ]


def checked_pages(monkeypatch) -> list[Page]:
    """Every figure saved from now on (``Figure.savefig``), checked as it is saved."""
    seen: list[Page] = []
    real = matplotlib.figure.Figure.savefig

    def checked(fig, fname, *args, **kwargs):
        seen.append(Page(fig, Path(str(fname)).name))
        return real(fig, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", checked)
    return seen


@pytest.fixture
def pages(monkeypatch):
    """Every figure saved while the test runs, checked as it is saved."""
    return checked_pages(monkeypatch)


def on_the_page_with_units(pages: list[Page], at_least: int) -> None:
    """Every page keeps its artists, its legends off the axes, and its axes say their units."""
    _on_the_page_with_units(pages, at_least)


def _on_the_page_with_units(pages: list[Page], at_least: int) -> None:
    assert len(pages) >= at_least, [p.name for p in pages]
    for page in pages:
        assert page.outside == [], page.name
        assert not any(page.legend_over_axes), page.name
        for title, xlabel, ylabel in page.axes:
            # the unit is on the y axis or in the title beside it; an x label has its own
            assert UNIT.search(ylabel) or UNIT.search(title), (page.name, title, ylabel)
            assert not xlabel or UNIT.search(xlabel), (page.name, xlabel)


# --- the check itself ---------------------------------------------------------------------------


def test_a_legend_placed_beyond_the_right_edge_is_found_and_named():
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0, 1], [0, 1], label="sun_planet1")
    # anchored at 1.5 axes widths: its left edge is right of the figure's (axes end at ~0.9)
    ax.legend(loc="upper left", bbox_to_anchor=(1.5, 1.0))
    found = outside_figure(fig)
    plt.close(fig)
    assert any(text.startswith("Legend 'sun_planet1'") for text in found), found


def test_the_same_legend_beside_constrained_axes_stays_on_the_page():
    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.plot([0, 1], [0, 1], label="sun_planet1")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    assert outside_figure(fig) == []
    plt.close(fig)


def test_a_caption_wider_than_the_page_widens_it_and_sits_under_the_axes():
    fig, ax = plt.subplots(figsize=(3, 3), layout="constrained")
    ax.set_xlabel("time [s]")
    note = caption_below(fig, "x" * 200, fontsize=6.5)
    assert outside_figure(fig) == []
    assert fig.get_size_inches()[0] > 3.0  # 200 characters of 6.5 pt do not fit 3 inches
    renderer = fig.canvas.get_renderer()
    # the caption's top is below the lowest label of the axes (nothing overprints it)
    assert note.get_window_extent(renderer).y1 <= ax.get_tightbbox(renderer).y0 + 0.5
    plt.close(fig)


# --- every figure of the package ----------------------------------------------------------------


def test_plot_figures_keep_legends_caption_and_units_on_the_page(logged_run, tmp_path, pages):
    from pinwind.io.figures import GROUPS, plot_log

    written = plot_log(logged_run.path, tmp_path)
    assert len(written) >= len(GROUPS) - 2  # no rotor; the rest of the groups
    _on_the_page_with_units(pages, len(written))


def test_spectrum_figure_keeps_its_markers_and_caption_on_the_page(logged_run, tmp_path, pages):
    from pinwind.io.log_spectrum import spectrum_of_log, write_figure

    write_figure(spectrum_of_log(logged_run.path, segment=0.1), tmp_path / "spectrum.png")
    _on_the_page_with_units(pages, 1)


def test_campbell_figure_keeps_its_legend_off_the_axes(tmp_path, pages):
    from pinwind.modes.campbell import write_figure
    from tests.modes.test_campbell import _diagram

    write_figure(_diagram(0.0, 200.0), str(tmp_path / "campbell.png"))
    _on_the_page_with_units(pages, 1)
    (page,) = pages
    assert page.legend_over_axes == [False]  # beside the axes, it hides no crossing
    assert "[rpm]" in page.axes[0][1]  # the speed axis in rpm, as the command line's


def test_fatigue_figures_keep_legends_and_units_on_the_page(logged_run, planetary, tmp_path, pages):
    from pinwind.life.life_figures import (
        plot_damage_vs_turbulence,
        plot_load_spectra,
        plot_range_cycles,
    )
    from pinwind.life.load_spectrum import shaft_spectra
    from pinwind.life.set_damage import set_damage
    from pinwind.runs.fatigue_set_file import load_fatigue_set
    from tests.conftest import fatigue_toml
    from tests.life.test_set_damage import write_cycles

    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()
    write_cycles(fset, low, [4], [500], [1.0], 2.0)
    write_cycles(fset, high, [4], [600], [1.0], 2.0)
    damage = set_damage(fset)
    plot_damage_vs_turbulence(damage, tmp_path / "turbulence.png")
    plot_range_cycles(damage, tmp_path / "ranges.png")
    plot_load_spectra(shaft_spectra(logged_run.result, planetary), tmp_path / "spectra.png")
    _on_the_page_with_units(pages, 3)


def test_sweep_figures_keep_labels_and_legend_on_the_page(tmp_path, pages):
    from pinwind.analysis.sweep_plots import plot_sweep
    from pinwind.runs.sweep import SweepSettings, run_sweep
    from tests.runs.test_sweep import _designs

    rows = run_sweep(_designs()[:3], SweepSettings(), workers=1).rows
    written = plot_sweep(rows, tmp_path)
    _on_the_page_with_units(pages, len(written))


# --- what the figures say -----------------------------------------------------------------------


def test_campbell_lines_differ_in_colour_or_dash_and_none_is_grey_or_red():
    from pinwind.modes.campbell import Excitation, excitation_styles

    # 20 sources (more than the colours) with 3 harmonics each: 60 lines, no two alike
    lines = [Excitation(f"mesh m{k}" + (f" ×{h}" if h > 1 else ""), h, float(k * h + 1))
             for k in range(20) for h in (1, 2, 3)]  # fmt: skip
    styles = excitation_styles(lines)
    assert len(set(map(str, styles))) == len(lines)
    for colour, _, _ in styles:
        r, g, b = matplotlib.colors.to_rgb(colour)
        # grey (the modes) has r = g = b; the crossings' crimson is red over green and blue
        assert max(r, g, b) - min(r, g, b) > 0.1, colour
        assert not (r > 0.7 and g < 0.3 and b < 0.35), colour


def test_caption_gives_torques_in_kn_m_and_speeds_in_rpm_as_the_axes():
    # 1e6 N·m = 1000 kN·m; 2π rad/s = 60 rpm; 10π rad/s = 300 rpm
    assert signal_in_units("1e6", "N·m") == "1000 kN·m"
    assert signal_in_units(repr(2 * math.pi), "rad/s") == "60 rpm"
    ramp = f"ramp(start_value=0, end_value={10 * math.pi!r}, start_time=0, end_time=5)"
    assert signal_in_units(ramp, "rad/s") == (
        "ramp(start_value=0, end_value=300, start_time=0, end_time=5) rpm"
    )
    # a table's values are in its file's unit: given as they are, with their SI unit
    assert (
        signal_in_units('csv(file="t.csv", column=1)', "N·m") == 'csv(file="t.csv", column=1) [N·m]'
    )


def test_bearing_figure_draws_no_world_moment_holding_the_shaft_torque(logged_run, tmp_path):
    import pinwind.io.figures as figures

    titles: list[str] = []
    real = figures._draw

    def record(ax, kept):
        real(ax, kept)
        titles.append(kept.panel.title)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(figures, "_draw", record)
        figures.plot_log(logged_run.path, tmp_path, groups=["bearings"])
    assert titles and not any("|M|" in title for title in titles), titles
    np.testing.assert_equal(sum("not a bearing load" in title for title in titles), 1)


def test_spectrum_legend_draws_each_series_or_says_it_is_zero(logged_run, tmp_path, monkeypatch):
    # A bearing's z force (0 on a spur stage) stood in the legend with no line on the log axis;
    # the mesh marker read "mesh sun_planet1 +5".
    from pinwind.io.log_spectrum import spectrum_of_log, write_figure

    seen = []
    real = matplotlib.figure.Figure.savefig

    def keep(fig, fname, *args, **kwargs):
        for ax in fig.axes:
            drawn = {line.get_label(): len(line.get_xdata()) for line in ax.get_lines()}
            legend = ax.get_legend()
            labels = [t.get_text() for t in legend.get_texts()] if legend else []
            seen.append((labels, drawn, [t.get_text() for t in ax.texts]))
        return real(fig, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", keep)
    report = spectrum_of_log(logged_run.path, series=["bearing_force"], segment=0.1)
    zero = [s.label for s in report.spectra if not np.any(s.density[1:] > 0.0)]
    assert zero, "the run should have a bearing force component that stays 0"
    write_figure(report, tmp_path / "spectrum.png")
    ((labels, drawn, markers),) = seen
    for label in labels:
        name = label.split(" (0:", 1)[0]
        assert (name in zero) == (label != name), label
        assert drawn[label] == (0 if name in zero else len(report.spectra[0].frequency) - 1)
    assert not any(" +" in text for text in markers), markers
