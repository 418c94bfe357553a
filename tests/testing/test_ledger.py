"""ledger_closure: a run's ledger closes; energy a step creates or loses is caught and located."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

import pinwind
from pinwind.errors import CheckFailed, InputError, PinwindWarning
from pinwind.model.gearbox import loads
from pinwind.testing import ledger_closure
from pinwind.testing.ledger import energy_scale
from tests.dynamics.test_flank_contact import pair_urdf


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def _damped_pair(mesh: str):
    """The 20/40 pair on fixed axes, gear b held, a torque of 50 ± 20 N·m at 300 Hz on a."""
    gb = loads(pair_urdf(bearing="", mesh=mesh))
    return _run(
        gb, duration=0.01, dt=1e-5, speeds={"b": 0.0},
        torques={"a": lambda t: 50.0 + 20.0 * np.sin(2 * np.pi * 300.0 * t)},
    )  # fmt: skip


def test_a_damped_mesh_on_fixed_axes_closes_its_ledger_to_rounding():
    res = _damped_pair('stiffness_variation="constant" damping="2000"')
    assert res.energy["dissipated"][-1] > 1e-3 * energy_scale(res)  # the damper does work
    figure = ledger_closure(res, rtol=1e-9)
    assert figure.passed and figure.tolerance == 1e-9


def test_a_meshs_time_varying_stiffness_does_the_parametric_work_the_ledger_counts():
    """Gear a turns through single- and double-pair contact (path stiffness) under a torque
    that the held gear reacts: k(s) changes under a loaded mesh, and only W_parametric says
    where that energy went."""
    gb = loads(pair_urdf(bearing="", mesh='stiffness_variation="path" damping="0"'))
    res = _run(gb, duration=0.05, dt=1e-5, torques={"a": 200.0}, speeds={"b": 3.0})
    assert np.abs(res.energy["work_parametric"]).max() > 1e-6 * energy_scale(res)
    ledger_closure(res, rtol=1e-9)


def test_energy_a_step_creates_is_caught_with_its_sample_and_size():
    res = _damped_pair('stiffness_variation="constant" damping="2000"')
    scale = energy_scale(res)
    res.energy["kinetic"][700:] += 1e-4 * scale  # 1e-4 of the scale appears at sample 700
    with pytest.raises(CheckFailed) as caught:
        ledger_closure(res, rtol=1e-6)
    err = caught.value
    np.testing.assert_allclose(err.measured, 1e-4, rtol=1e-4)
    assert err.tolerance == 1e-6 and err.check == "ledger_closure"
    assert "first beyond it at sample 700" in str(err) and "created" in str(err)
    again = pickle.loads(pickle.dumps(err))
    assert (again.measured, again.tolerance, str(again)) == (err.measured, 1e-6, str(err))


def test_a_result_without_a_ledger_is_refused_naming_the_missing_terms():
    res = _damped_pair('stiffness_variation="constant"')
    del res.energy["work_parametric"]
    with pytest.raises(InputError, match="work_parametric"):
        ledger_closure(res)
