"""The energy ledger keeps the work of a mesh's time-varying stiffness apart from numerical loss.

A compliant mesh stores U = ½ k δ²; its stiffness k steps as tooth pairs enter and leave the
path of contact. The bodies' kinetic energy changes by the work of the tooth force −k δ δ̇ only;
the rest of ΔU, ∫ ½ δ² dk, is put in by the stiffness's change (the parametric excitation): it is
physics and does not vanish as dt → 0. With one tooth pair of constant stiffness k₁ (a pair table
of one value), the mesh stiffness is k₁ times the pairs in contact, so the ledger's
``work_parametric`` must be Σ ½ k₁ (pairs_n − pairs_{n−1}) δ_n² over the samples, from the
recorded pairs and deflections, and the trapezoidal step (ρ∞ = 1) leaves ``numerical`` at rounding.
"""

from __future__ import annotations

import numpy as np

import pinwind
from pinwind.dynamics import Integrator
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

K_PAIR = 1e8  # one tooth pair's stiffness [N/m]


def _run(dt: float):
    gb = loads(two_gear_urdf(), "pair.urdf")
    one_pair = (np.array([0.0, 1.0]), np.array([K_PAIR, K_PAIR]))
    return pinwind.simulate(
        gb,
        duration=0.05,
        dt=dt,
        torques={"b": -60.0},  # a generator-like load on B
        speeds={"a": 100.0},  # A driven at 100 rad/s: about 32 tooth passes
        gravity=np.zeros(3),
        # Damped (ζ = 0.05 of the mesh mode) so that the teeth stay in contact: undamped, the
        # stiffness steps pump the mesh mode until the teeth rattle between flanks.
        meshes={"m": MeshCompliance(pair_stiffness=one_pair)},
        integrator=Integrator(rho_infinity=1.0),
    )


def test_parametric_work_is_half_the_stiffness_steps_times_the_squared_deflection():
    res = _run(2e-6)
    mesh = res.mesh("m")
    delta = np.maximum(mesh.deflection, 0.0)
    steps = np.diff(mesh.pairs) * K_PAIR
    expected = np.concatenate([[0.0], np.cumsum(0.5 * steps * delta[1:] ** 2)])
    assert np.count_nonzero(steps) > 20  # pairs entered and left many times
    scale = np.abs(expected).max()
    assert scale > 0.0
    np.testing.assert_allclose(res.energy["work_parametric"], expected, atol=1e-9 * scale)


def test_the_trapezoidal_step_leaves_no_numerical_loss_beside_the_parametric_work():
    res = _run(2e-6)
    e = res.energy
    parametric = np.abs(e["work_parametric"]).max()
    # Before the two were split, numerical held −work_parametric.
    assert np.abs(e["numerical"]).max() < 1e-6 * parametric


def test_parametric_work_converges_with_dt_while_numerical_loss_vanishes():
    coarse, fine = _run(4e-6), _run(2e-6)
    w_coarse = coarse.energy["work_parametric"][-1]
    w_fine = fine.energy["work_parametric"][-1]
    # Physics: the same work at both steps (to the accuracy of the run, not zero).
    np.testing.assert_allclose(w_coarse, w_fine, rtol=0.05)
    assert abs(w_fine) > 1e3 * abs(fine.energy["numerical"][-1])
