"""A fatigue set at dt/2: the same cases at half the step, read at the same times, compared."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pinwind.analysis.convergence import dt_row
from pinwind.errors import InputError
from pinwind.life.damage_convergence import (
    HALF_STEP_SUFFIX,
    NEGLIGIBLE_DAMAGE,
    DamageDtCheck,
    half_step_set,
)
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import fatigue_toml


def test_half_step_set_halves_dt_and_reads_the_histories_at_the_same_times(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    half = half_step_set(fset)
    np.testing.assert_allclose(half.dt, fset.dt / 2, rtol=1e-15)
    assert half.out == fset.out.parent / (fset.out.name + HALF_STEP_SUFFIX)
    for case, half_case in zip(fset.cases(), half.cases(), strict=True):
        assert half_case == case
        # The stress histories' sample period, keep · dt, is the set's: 1 / sample_rate.
        period = fset.case_values(case)["keep"] * fset.dt
        half_period = half.case_values(case)["keep"] * half.dt
        np.testing.assert_allclose(half_period, 1.0 / fset.sample_rate, rtol=1e-12)
        np.testing.assert_allclose(period, 1.0 / fset.sample_rate, rtol=1e-12)


@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ("sample_rate = 50000.0", "sample_rate = 20000.0", "sample_rate = 20000 Hz"),  # 2.5 steps
        ("log_rate = 1000.0", "log_rate = 1500.0", "log_rate = 1500 Hz"),  # 33.3 steps of 20 µs
    ],
)
def test_a_rate_that_is_no_whole_number_of_steps_is_refused_naming_it(tmp_path, old, new, key):
    path = fatigue_toml(tmp_path)
    assert old in path.read_text()
    path.write_text(path.read_text().replace(old, new))
    with pytest.raises(InputError, match=key):
        half_step_set(load_fatigue_set(path))


def _check(values: list[tuple[float, float]], unit: str = "-") -> DamageDtCheck:
    rows = [
        dt_row("contact", f"g{i}", "damage (limit)", unit, v, 0.05) for i, v in enumerate(values)
    ]
    return DamageDtCheck(dt=2e-5, out=Path("x"), levels=("10%",), tolerance=0.05, rows=[rows])


def test_a_damage_negligible_at_both_steps_does_not_decide_the_verdict():
    tiny = 1e-3 * NEGLIGIBLE_DAMAGE
    check = _check([(1.0, 1.01), (tiny, 2 * tiny)])
    assert check.converged
    assert check.verdict.startswith("converged within 0.99 %")
    rows = check.as_dict()["levels"][0]["rows"]
    assert [r["judged"] for r in rows] == [True, False]


def test_a_damage_that_changes_beyond_the_tolerance_asks_for_a_smaller_dt():
    check = _check([(1.0, 1.01), (1.0, 1.2)])
    assert not check.converged
    assert "1 of 2 judged figures" in check.verdict
    assert "dt = 1e-05 s or less" in check.verdict
    # The largest change is g1's: (1.2 − 1.0) / 1.2.
    label, row = check.largest()
    assert (label, row.element) == ("10%", "g1")
    np.testing.assert_allclose(row.change_half, 0.2 / 1.2, rtol=1e-12)
