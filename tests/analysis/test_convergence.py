"""The dt-convergence judgement: the observed order of a synthetic series, a row's verdict."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.analysis.convergence import dt_row, observed_order


@pytest.mark.parametrize("order", [1, 2])
def test_observed_order_recovers_p_of_f0_plus_c_h_to_the_p(order):
    f0, c, h = 100.0, 3.0e4, 1e-3

    def f(step: float) -> float:
        return f0 + c * step**order

    values = [f(h), f(h / 2), f(h / 4)]
    np.testing.assert_allclose(observed_order(*values), order, rtol=1e-9)
    row = dt_row("mesh", "m", "normal force max", "N", values, tolerance=0.01)
    # (f(h/2) − f(h)) / f(h/2) = −c h^p (1 − 2^−p) / f(h/2), by hand.
    np.testing.assert_allclose(
        row.change_half, -c * h**order * (1 - 2.0**-order) / f(h / 2), rtol=1e-12
    )
    np.testing.assert_allclose(
        row.change_quarter, -c * (h / 2) ** order * (1 - 2.0**-order) / f(h / 4), rtol=1e-12
    )
    np.testing.assert_allclose(row.error, c * (h**order - (h / 4) ** order) / f(h / 4), rtol=1e-12)
    assert row.converged == (row.error <= 0.01)
    assert row.verdict == (
        f"converged to {100 * row.error:.2g} %" if row.converged else "not converged: halve dt"
    )


def test_values_that_do_not_change_have_no_order_and_are_converged():
    row = dt_row("bearing", "a", "|force| RMS", "N", [5.0, 5.0, 5.0])
    assert math.isnan(row.order) and row.converged and row.error == 0.0


def test_two_values_judge_the_run_against_dt_half_without_an_order():
    # f(dt) = 1.0, f(dt/2) = 1.04: the run is 0.04 / 1.04 from its dt/2 value.
    row = dt_row("contact", "sun", "damage (limit)", "-", [1.0, 1.04], tolerance=0.05)
    np.testing.assert_allclose(row.change_half, 0.04 / 1.04, rtol=1e-12)
    np.testing.assert_allclose(row.error, 0.04 / 1.04, rtol=1e-12)
    assert math.isnan(row.order) and math.isnan(row.change_quarter)
    assert row.converged
    assert not dt_row("contact", "sun", "damage (limit)", "-", [1.0, 1.06], 0.05).converged
