"""Rows that fix one coordinate each (a speed driver, a lock) hold their joints' torque balance.

The step solves such rows by eliminating the coordinates they fix (``cpp/constrained_qp.hpp``
``solve_fixed``): the driven or locked joint's acceleration is the row's target and its torque
λ the residual of its own equation of motion. Checked on Saleh 2017's planetary stage with every
mesh compliant and every turning bearing compliant (the ring locked, the sun driven at a constant
speed): the sun and the ring each turn on their own axis with their centre of mass on it, so
their rotation's equation is I ā = τ + Σ τ_mesh, with no bias term and no coupling to the slides
that carry them. The tooth force F on a flank acts along the base circles' common tangent, at
the arm r_b of each gear whatever the centre distance. Front flank (s = +1): A turning
positively drives B (the ``flank`` series' convention), so the force resists A's positive turn,
τ_A = −r_b,A F, and turns B the way A's positive turn does: negatively across an external mesh,
τ_B = −r_b,B F, positively inside a ring, τ_B = +r_b,B F; the back flank's force turns each the
other way. With ā = 0 the driver's or lock's torque is −Σ τ_mesh:

    sun (gear A of its three meshes):       τ = +r_b,sun Σ (F_front − F_back),
    ring (internal gear B of its three):    τ = −r_b,ring Σ (F_front − F_back).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import pinwind
from pinwind.errors import PinwindWarning
from pinwind.model.gearbox import loads
from tests.conftest import MODELS

BEARING = 'radial_stiffness="2e9" radial_damping="1e4"'
SUN_SPEED = 8.92  # rad/s, held by the driver


@pytest.fixture(scope="module")
def run():
    ideal = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    turning = [j for j in ideal.joint_names if j not in ideal.locked_joints]
    lines = "".join(f'  <bearing joint="{j}" {BEARING}/>\n' for j in turning)
    gb = loads(ideal.source_text.replace("</gearbox>", lines + "</gearbox>"), str(ideal.path))
    assert sorted(gb.compliant_bearings) == sorted(turning)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)  # the driver balances the carrier
        res = pinwind.simulate(
            gb,
            duration=200 * 2e-5,
            dt=2e-5,
            torques={"carrier": 1e6},
            speeds={"sun": SUN_SPEED},
            meshes={"all": "compliant"},
        )
    return gb, res


def _balance(gb, res, joint: str) -> np.ndarray:
    """−Σ τ_mesh on ``joint``'s gear (module docstring) [N·m]: the torque that holds it."""
    total = np.zeros(len(res.time))
    for mesh in gb.meshes:
        series = res.mesh(mesh.name)
        front_less_back = series.normal_front - series.normal_back
        if mesh.gear_a.spec.name == joint:
            total += mesh.base_radius_a * front_less_back
        elif mesh.gear_b.spec.name == joint:
            sign = -1.0 if mesh.gear_b.spec.internal else 1.0
            total += sign * mesh.base_radius_b * front_less_back
    return total


def test_the_driven_sun_turns_at_its_speed_and_its_driver_takes_its_meshes_torque(run):
    gb, res = run
    sun = res.joint("sun")
    # The row's target, exactly: the fixed coordinate is not solved for (main's Schur
    # complement left 1e-11 rad/s² of rounding here).
    assert_array_equal(sun.acceleration, 0.0)
    assert_allclose(sun.speed, SUN_SPEED, rtol=1e-12)
    expected = _balance(gb, res, "sun")
    assert np.abs(expected).min() > 1e4  # loaded at every sample
    assert_allclose(sun.torque, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def test_the_locked_ring_stays_still_and_its_lock_takes_its_meshes_torque(run):
    gb, res = run
    ring = res.joint("ring")
    assert_array_equal(ring.acceleration, 0.0)
    assert_allclose(ring.speed, 0.0, atol=1e-12)  # from rest, to the start's rounding
    expected = _balance(gb, res, "ring")
    assert np.abs(expected).min() > 1e4
    assert_allclose(ring.torque, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
