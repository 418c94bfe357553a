"""A shaft on two rolling bearings with Palmgren friction in the step: torque loss and ledger."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import InvalidBearingFriction
from pinwind.model.gearbox import loads
from pinwind.testing.ledger import energy_scale, ledger_residual

RPM = 2.0 * math.pi / 60.0
#: ν = 60 mm²/s outright (no Walther here), d_m: A (300 + 200)/2 = 250 mm, B (280 + 200)/2 =
#: 240 mm; loads P1 50 kN and 20 kN.
NU = 60.0


def shaft(rows: str = "", bearing: str = "") -> str:
    """A shaft (J = 5 kg·m², axis z) on an ideal bearing with two rows A and B."""
    rows = rows or (
        '      <row name="A" type="spherical_roller" size_mm="300 200 60" '
        'friction_load_kN="50"/>\n'
        '      <row name="B" type="cylindrical_roller" size_mm="280 200 50" '
        'friction_load_kN="20"/>\n'
    )
    return f"""<robot name="shaft">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="100"/>
    <inertia ixx="10" iyy="10" izz="5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
    <bearing joint="shaft" friction_model="iso_tr_14179_2" viscosity_cSt="{NU}" {bearing}>
{rows}    </bearing>
  </gearbox>
</robot>"""


def hand_moment(rpm: float) -> float:
    """M_A + M_B [N·m] by ISO/TR 14179-2 (Palmgren) at n rpm: f0 5 and 2.5, f1 0.0004, 0.000275."""
    branch = (NU * rpm) ** (2.0 / 3.0) if NU * rpm >= 2000 else 160.0  # (ν n)^(2/3)
    m_a = 1e-7 * 5.0 * branch * 250.0**3 + 0.0004 * 50e3 * 250.0  # N·mm
    m_b = 1e-7 * 2.5 * branch * 240.0**3 + 0.000275 * 20e3 * 240.0
    return (m_a + m_b) * 1e-3


@pytest.mark.parametrize("rpm", [100.0, 10.0])  # ν n = 6000 (viscous branch), 600 (constant)
def test_steady_torque_loss_of_a_shaft_on_two_bearings_is_the_sum_of_their_hand_moments(rpm):
    gb = loads(shaft(), path="shaft.urdf")
    res = pinwind.simulate(
        gb, duration=0.05, dt=1e-3, speeds={"shaft": rpm * RPM},
        initial_speeds={"shaft": rpm * RPM},
    )  # fmt: skip
    expected = hand_moment(rpm)  # 10.04 N·m at 100 rpm, 8.12 N·m at 10 rpm
    # the driver holds the speed against the friction: its torque is the friction's
    assert_allclose(res.torque[10:, 0], expected, rtol=1e-9)
    assert_allclose(res.bearing_friction_moment[10:, 0], -expected, rtol=1e-9)
    assert_allclose(res.bearing_friction_power[10:, 0], expected * rpm * RPM, rtol=1e-9)


def test_a_spinning_shaft_slows_down_stops_and_the_ledger_closes_with_the_friction_as_dissipation():
    gb = loads(shaft(), path="shaft.urdf")
    # 1 rad/s: decelerates at M/J = 8.12/5 = 1.62 rad/s² and stops after 0.62 s
    res = pinwind.simulate(gb, duration=1.0, dt=1e-3, initial_speeds={"shaft": 1.0})
    speed = res.speed[:, 0]
    # while it turns: the constant-branch moment decelerates it (ν n < 2000 all the way down)
    m = hand_moment(1.0 / RPM)
    t = res.time
    early = t < 0.2
    assert_allclose(speed[early], 1.0 - m / 5.0 * t[early], atol=2e-3)
    # stopped (within the regularised band ω_s = 0.01 rad/s) and staying there
    assert np.all(np.abs(speed[t > 0.8]) < 0.01)
    # all the kinetic energy went to the friction, and the ledger closes
    assert_allclose(res.energy["friction_loss"][-1], 0.5 * 5.0 * 1.0**2, rtol=1e-3)
    residual = ledger_residual(res)
    assert np.abs(residual).max() <= 1e-9 * energy_scale(res)


def test_a_bearing_with_friction_but_no_size_is_refused_with_the_fix():
    rows = '      <row name="A" type="spherical_roller"/>\n'
    gb = loads(shaft(rows), path="shaft.urdf")
    with pytest.raises(InvalidBearingFriction, match="size_mm"):
        pinwind.simulate(gb, duration=0.02, dt=1e-3)


def test_an_unknown_friction_model_is_refused_at_load():
    text = shaft().replace('friction_model="iso_tr_14179_2"', 'friction_model="skf"')
    with pytest.raises(InvalidBearingFriction, match="none, iso_tr_14179_2"):
        loads(text, path="shaft.urdf")
