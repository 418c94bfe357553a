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
