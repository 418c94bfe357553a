"""One precision per table column and rounding noise as 0 (``analysis/table_numbers.py``)."""

from __future__ import annotations

import numpy as np

from pinwind.analysis.table_numbers import WIDTH, column_texts


def test_a_locked_ring_s_noise_beside_a_carrier_s_speed_prints_zero():
    # 1000 rpm to 6 significant digits is 1000.00: two decimals, which 4.8e-28 rpm shares as 0.
    assert column_texts([1000.0, 4.8e-28, -3.2e-14]) == ["1000.00", "0.00", "0.00"]
    # In the exponent form (a scale of 2.5e9) the noise would print as a value: it prints 0.
    # −10 is 4e-9 of the scale, above NOISE (1e-9): a value.
    assert column_texts([2.5e9, 4.8e-28, -10.0]) == ["2.50e+09", "0", "-1.00e+01"]


def test_entries_of_a_column_share_the_decimals_of_its_largest():
    # 1199.98 kN·m has 4 integer digits: 6 significant digits leave 2 decimals for every entry.
    assert column_texts([1199.98, 44.2165, -0.5, 0.004]) == ["1199.98", "44.22", "-0.50", "0.00"]
    # 0.0123 (scale below 1): 6 significant digits are 7 decimals, 0.0123456 fits 9 characters
    # with its sign only with 6: the width wins.
    assert column_texts([0.0123456, -0.001]) == ["0.012346", "-0.001000"]


def test_a_column_of_tiny_values_shares_the_exponent_form_and_zero_is_zero():
    # a constraint residual of 1e-13 m/s is not noise beside itself: the exponent form, 3 digits
    assert column_texts([9.481e-14, 4.042e-14, 0.0]) == ["9.48e-14", "4.04e-14", "0"]


def test_any_column_fits_the_cell_and_reads_back_to_half_its_last_place():
    rng = np.random.default_rng(7)
    for exponent in range(-14, 12):
        values = list(rng.uniform(-1.0, 1.0, 6) * 10.0**exponent)
        texts = column_texts(values)
        assert all(len(t) <= WIDTH for t in texts), texts
        decimals = {len(t.split(".")[1]) if "." in t and "e" not in t else None for t in texts}
        assert len(decimals) == 1, texts  # one precision for the column
        for value, text in zip(values, texts, strict=True):
            mantissa = text.split("e")[0]
            places = len(mantissa.split(".")[1]) if "." in mantissa else 0
            scale = 10.0 ** int(text.split("e")[1]) if "e" in text else 1.0
            np.testing.assert_allclose(float(text), value, rtol=0, atol=0.5 * 10.0**-places * scale)
