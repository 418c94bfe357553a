"""A Result that keeps some series only: the same numbers, the log every series."""

from __future__ import annotations

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError
from pinwind.io.log_reader import read_log
from pinwind.model.gearbox import load
from tests.conftest import MODELS

MODEL = MODELS / "saleh2017_planetary.urdf"
RUN = dict(duration=5e-3, dt=2e-5, initial_speeds={"carrier": 1.487}, keep=25,
           torques={"carrier": 1e6, "sun": -1e6 / 6}, meshes={"all": "compliant"})  # fmt: skip
KEPT = ("mesh_normal", "speed", "bearing_force_local")


def test_the_kept_series_are_the_full_runs_and_the_log_holds_them_all(tmp_path):
    gearbox = load(MODEL)
    full = pinwind.simulate(gearbox, log=tmp_path / "full.mcap", **RUN)
    some = pinwind.simulate(gearbox, log=tmp_path / "some.mcap", keep_series=KEPT, **RUN)
    assert len(some) == len(full) == 11  # samples 0, 25, ..., 250
    for name in KEPT:  # the same steps: bit for bit
        np.testing.assert_array_equal(getattr(some, name), getattr(full, name))
    np.testing.assert_array_equal(some.time, full.time)
    assert set(some.ARRAYS) == {"time", *KEPT, "body_position", "body_quaternion"}
    assert len(some.body_position) == 0  # no poses asked for: none kept
    with pytest.raises(AttributeError):
        _ = some.mesh_tangential
    assert some.energy["kinetic"].shape == full.energy["kinetic"].shape
    # The log of the run that kept a few series has every series, as the full run's.
    logged_full, logged_some = read_log(tmp_path / "full.mcap"), read_log(tmp_path / "some.mcap")
    for name in full.ARRAYS:
        np.testing.assert_array_equal(getattr(logged_some, name), getattr(logged_full, name))


def test_an_unknown_series_to_keep_is_refused_naming_the_series():
    with pytest.raises(InputError, match=r"keep_series: no series \['mesh_force'\]; the series"):
        pinwind.simulate(load(MODEL), keep_series=("mesh_force",), **RUN)
