"""The recorded kinetic energy is ½ vᵀ M(q) v with M Pinocchio's CRBA at each sample's (q, v).

The step forms M v from its own M (mirrored lower triangle, read by columns): here M is
recomputed by ``pinocchio.crba`` from the recorded angles, independently of the step, on a
train whose M varies (every turning bearing compliant: slides and tilts under the bodies) and
on one whose M is constant (rigid bearings, M taken once).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from tests.conftest import MODELS, load_model
from tests.dynamics.test_stepper import _all_bearings_compliant


def _kinetic_from_crba(gb: pinwind.Gearbox, res) -> np.ndarray:
    model = gb.model
    data = model.createData()
    out = np.empty(len(res.time))
    for k in range(len(res.time)):
        mass = pin.crba(model, data, res.angle[k])
        mass = np.triu(mass) + np.triu(mass, 1).T
        out[k] = 0.5 * res.speed[k] @ mass @ res.speed[k]
    return out


@pytest.mark.parametrize("compliant", [True, False])
def test_kinetic_energy_is_half_v_m_v_at_every_sample(compliant):
    name = "saleh2017_planetary.urdf"
    gb = _all_bearings_compliant(name) if compliant else load_model(MODELS / name)
    assert gb.model.nq == gb.model.nv  # the recorded angles are Pinocchio's q
    res = pinwind.simulate(
        gb,
        duration=40 * 2e-5,
        dt=2e-5,
        torques={"carrier": 1e6},
        speeds={"sun": 8.92},
        meshes={"all": "compliant"},
        progress=False,
    )
    expected = _kinetic_from_crba(gb, res)
    assert expected[-1] > 1e3  # the train turns: a kinetic energy of kJ, not rounding
    np.testing.assert_allclose(res.energy["kinetic"], expected, rtol=1e-12, atol=0)
