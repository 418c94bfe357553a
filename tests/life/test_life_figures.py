"""Figures of a fatigue set's damage (``life/life_figures.py``)."""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.life.set_damage import set_damage
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import fatigue_toml
from tests.life.test_set_damage import write_cycles


def test_figures_of_a_set_are_written(tmp_path):
    from pinwind.life.life_figures import plot_damage_vs_turbulence, plot_range_cycles

    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()
    write_cycles(fset, low, [4], [500], [1.0], 2.0)
    write_cycles(fset, high, [4], [600], [1.0], 2.0)
    damage = set_damage(fset)
    for path in (
        plot_damage_vs_turbulence(damage, tmp_path / "figs" / "turbulence.png"),
        plot_range_cycles(damage, tmp_path / "figs" / "ranges.png"),
    ):
        assert path.stat().st_size > 1000


def test_damage_axis_draws_the_smallest_nonzero_damage_on_its_log_part():
    from pinwind.life.life_figures import damage_axis_threshold

    # ISO 6336 damages of 1e-44 beside Miner sums of hundreds: the linear range must end below
    # 3.1e-44, i.e. at the decade 1e-44; zeros and NaN do not move it.
    values = np.array([0.0, 641.0, 3.1e-44, 2.6e-8, np.nan])
    assert damage_axis_threshold(values) == pytest.approx(1e-44, rel=1e-12)
    assert damage_axis_threshold(np.array([0.0, 0.5])) == 1e-3
    assert damage_axis_threshold(np.zeros(3)) == 1e-3


def test_each_figure_draws_its_caption_under_the_axes_and_the_quick_mark_above(
    tmp_path, monkeypatch
):
    """The caption is drawn text (and the PNG's Description), the mark the figure's title; the
    paper is named "Jørgensen 2014" in the legend, not by its file number."""
    import re

    import matplotlib.figure
    from PIL import Image

    from pinwind.life.life_figures import plot_damage_vs_turbulence, plot_range_cycles

    drawn: list[tuple[list[str], str, list[str]]] = []
    real = matplotlib.figure.Figure.savefig

    def seen(fig, fname, *args, **kwargs):
        legends = [t.get_text() for ax in fig.axes if ax.get_legend() for t in
                   ax.get_legend().get_texts()]  # fmt: skip
        suptitle = fig._suptitle.get_text() if fig._suptitle is not None else ""
        drawn.append(([t.get_text() for t in fig.texts], suptitle, legends))
        return real(fig, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", seen)
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()
    write_cycles(fset, low, [4], [500], [1.0], 2.0)
    write_cycles(fset, high, [4], [600], [1.0], 2.0)
    damage = set_damage(fset)
    about, mark = "Set: set.toml, 2 cases x 0.04 s", "quick set (2 cases x 0.04 s): a first look"
    turbulence = plot_damage_vs_turbulence(damage, tmp_path / "t.png", about=about, mark=mark)
    plot_range_cycles(damage, tmp_path / "r.png")  # no mark: the whole set's figure
    (texts, suptitle, legends), (plain_texts, plain_suptitle, _) = drawn
    (caption,) = [t for t in texts if t != suptitle and t]
    assert suptitle == mark
    assert caption.endswith("\n" + about)
    assert "levels 10%" in caption and "Dashed: Jørgensen 2014 Table 8" in caption
    assert "sun (Jørgensen 2014 Table 8)" in legends
    assert not any(re.search(r"(?<![\w.])003(?!\w)", t) for t in [caption, *legends])
    with Image.open(turbulence) as image:
        assert image.text["Description"] == caption and image.text["Title"] == mark
    assert plain_suptitle == "" and len([t for t in plain_texts if t]) == 1


def test_the_bearing_lives_figure_draws_each_life_in_hours_on_a_log_axis(tmp_path, monkeypatch):
    """planet1's three lives (tests/life/test_life_sums.py: ISO 281 by hand) as bars whose right
    ends are the lives [h]; the site's 1250 h as a line; the caption says what is drawn."""
    import matplotlib.figure
    from PIL import Image

    from pinwind.life.life_figures import plot_bearing_lives
    from pinwind.life.set_bearing_life import set_bearing_lives
    from tests.life.test_life_sums import hand_lives, write_cases

    drawn = []
    real = matplotlib.figure.Figure.savefig

    def seen(fig, fname, *args, **kwargs):
        drawn.append(fig)
        return real(fig, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", seen)
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    write_cases(fset)
    lives = set_bearing_lives(fset)[0]
    path = plot_bearing_lives(lives, tmp_path / "lives.png", hours=1250.0, title="turbulence 10%")
    (fig,) = drawn
    (ax,) = [a for a in fig.axes if a.get_xscale() == "log"]
    ends = sorted(p.get_x() + p.get_width() for p in ax.patches)
    expected = hand_lives(fset.bearings["planet1"].dynamic_load_rating)
    np.testing.assert_allclose(ends, sorted([expected["lnmh"], expected["l10h"],
                                             expected["l10h"]]), rtol=1e-2)  # fmt: skip
    np.testing.assert_allclose(ends[0], expected["lnmh"], rtol=1e-9)
    assert ax.get_xlabel() == "life [h of operation]"
    assert any(np.allclose(line.get_xdata(), 1250.0) for line in ax.get_lines())
    with Image.open(path) as image:
        caption = image.text["Description"]
    assert "L10h" in caption and "L_nmh" in caption and "L10rh" in caption
