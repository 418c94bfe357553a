"""The summary table of ``pinwind simulate``: speed ratios of runs driven by wind alone."""

from __future__ import annotations

import warnings

import numpy as np

import pinwind
from pinwind.analysis.summary import summary_tables
from pinwind.loads.generator import LinearSlip
from pinwind.loads.rotor import Rotor
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf


def test_ratio_column_of_a_rotor_and_generator_run_is_the_tooth_ratio():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the pair's inertias are not steel discs
        pair = loads(two_gear_urdf(), path="pair.urdf")
    # No speed or torque load: a rotor on a in a 10 m/s wind, a generator on b.
    res = pinwind.simulate(
        pair,
        duration=0.02,
        dt=1e-3,
        initial_speeds={"a": 1.5},
        rotors={"a": Rotor(radius=1.0)},
        wind=10.0,
        generators={"b": LinearSlip(slope=0.01, sync_speed=-3.0)},
        progress=False,
    )
    table = summary_tables(res, plain=True)[0]
    header = table.columns[2].header
    assert "ratio to a" in str(header)
    ratios = dict(zip(table.columns[0]._cells, table.columns[2]._cells, strict=True))
    # External pair of 20 and 40 teeth: b turns at −20/40 of a.
    np.testing.assert_allclose(float(ratios["b"]), -20 / 40, rtol=1e-5)
    np.testing.assert_allclose(float(ratios["a"]), 1.0, rtol=1e-12)
