"""The rigid meshes' contact position over many turns, from the gear angles without atan2.

A mesh fixed in a frame (``Stepper.mesh_frames``) whose gear A and frame hang from the world by
joints about the mesh's axis has gear A's angle from the centre line, ψ_A, as an affine function
of q: A's joint angles less the frame's (cpp/stepper_assembly.cpp fixed_mesh_angles). The
recorded contact position x is the entering tooth pair's roll position, which moves with A's
base circle: x advances by s r_b,A Δψ_A on flank s and wraps by the base pitch p_b (Jørgensen
2014 §2.4). With gear a (20 teeth, module 2 mm, 20°, no profile shift) as A on the arm that
carries b, ψ_A = θ_a − θ_arm + const, and

    x_k − x_0 = s r_b,A ((θ_a − θ_arm)_k − (θ_a − θ_arm)_0)   (mod p_b),

r_b,A = m z cos α / 2 and p_b = π m cos α from the gear data (ISO 21771), not from pinwind.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.model.gearbox import loads
from tests.dynamics.test_constant_mass import _stepper
from tests.dynamics.test_constant_mesh_rows import CARRIER_ARM

MODULE, TEETH_A, ALPHA = 0.002, 20, math.radians(20.0)
BASE_RADIUS_A = 0.5 * MODULE * TEETH_A * math.cos(ALPHA)
BASE_PITCH = math.pi * MODULE * math.cos(ALPHA)


@pytest.mark.parametrize("torque", [5.0, -5.0])
def test_contact_position_follows_gear_a_relative_to_the_arm_over_many_turns(torque):
    """27 turns of a relative to the arm (4 s at 50 and 7 rad/s), both flanks: every sample's
    x lies on the closed form to 1e-10 of a base pitch. Leaving out the arm's angle or turning
    its sign would move x by r_b,A θ_arm (0.5 m here), not a whole number of base pitches."""
    gb = loads(CARRIER_ARM, path="carrier_arm.urdf")
    assert _stepper(gb).mesh_frames == [gb.model.getJointId("arm")]
    res = pinwind.simulate(
        gb,
        duration=4.0,
        dt=1e-3,
        speeds={"a": 50.0, "arm": 7.0},
        torques={"b": torque},
        progress=False,
    )
    assert res.status == "completed"
    flank = res.mesh_flank[:, 0]
    assert np.all(flank == flank[0])
    names = list(res.joint_names)
    psi = res.angle[:, names.index("a")] - res.angle[:, names.index("arm")]
    assert psi[-1] - psi[0] > 2.0 * math.pi * 27
    x = res.mesh_contact_position[:, 0]
    cycles = (x - x[0] - flank[0] * BASE_RADIUS_A * (psi - psi[0])) / BASE_PITCH
    assert np.abs(cycles - np.round(cycles)).max() < 1e-10
    # x moves with ψ_A: the relation is not met trivially by a constant x
    assert np.ptp(x) > 0.5 * BASE_PITCH
