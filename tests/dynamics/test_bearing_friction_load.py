"""Bearing friction whose load P1 follows the bearing's load in the step (cpp/bearing_friction.hpp).

A rigid shaft on two compliant rows A and B (no tilt stiffness) under a radial force F at p on
its axis, or a thrust T: the statics give the rows' radial loads by the lever rule,
R_B = F (p − a_A)/(a_B − a_A), R_A = F − R_B, and the thrust goes to B alone (A has no axial
spring). (Both at once are not the lever rule to 1e-9: the thrust's line moves with the shaft's
deflection, a moment T x of ~1 N·m.) ISO/TR 14179-2 (Palmgren 1959) then gives each row's
moment by hand, in the standard's units (N·mm, ν mm²/s, n rpm, d_m mm, P1 N):

    M = 10⁻⁷ f0 (ν n)^(2/3) d_m³ + f1 P1 d_m,   P1 = F_r (cylindrical), max(0.8 F_a cot α, F_r)
                                                     (spherical roller, α = 10°)

The driver that holds the shaft's speed carries the sum. P1 is the step before's load: the first
sample has M1 = 0 (M0 alone).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics import _native
from pinwind.errors import PinwindWarning
from pinwind.loads.hub_loads import constant_hub_load
from pinwind.losses.bearing_friction import LOAD_RULES, PALMGREN_FACTORS, friction_load
from pinwind.model.gearbox import loads
from pinwind.testing.ledger import energy_scale, ledger_residual

RPM = 2.0 * math.pi / 60.0
N_RPM = 100.0
NU = 60.0  # mm²/s, given outright
A, B = -0.3, 0.1  # row positions along the axis [m]
# radial force [N] at P [m] on the axis, thrust [N]; P is the rows' stiffness centre
# (k_A a_A + k_B a_B)/(k_A + k_B) = 0: the shaft moves without tilting (a tilted axis would turn
# a little of the friction moment into radial loads, ~1e-8 of them)
F, P, T = 50e3, 0.0, 30e3


def shaft(rows: bool = True, row_b: str = "") -> str:
    """The shaft (axis z) on bearing "shaft": two compliant rows, or an ideal spherical bearing."""
    friction = f'friction_model="iso_tr_14179_2" viscosity_cSt="{NU}"'
    if rows:
        bearing = f"""    <bearing joint="shaft" radial_stiffness="1" axial_stiffness="1" tilt_stiffness="1" {friction}>
      <row name="A" type="cylindrical_roller" position_mm="{A * 1e3}" size_mm="300 200 60"
           stiffness="0 1e9 1e9 0 0" damping="0 0 0 0 0" rating_c_kN="1000"/>
      <row name="B" type="spherical_roller" position_mm="{B * 1e3}" size_mm="280 200 50"
           stiffness="1e9 3e9 3e9 0 0" damping="0 0 0 0 0" rating_c_kN="1000" {row_b}/>
    </bearing>"""  # noqa: E501
    else:
        bearing = (
            f'    <bearing joint="shaft" type="spherical_roller" size_mm="280 200 50" '
            f'rating_c_kN="1000" {friction}/>'
        )
    return f"""<robot name="shaft">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="100"/>
    <inertia ixx="10" iyy="10" izz="5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
{bearing}
  </gearbox>
</robot>"""


def run(text: str, point: float = P, force: float = F, thrust: float = T):
    gb = loads(text, path="shaft.urdf")
    # hub frame: x the axis (world z), y world x, z world y; F at 30° from u towards w
    angle = math.radians(30.0)
    load = constant_hub_load(
        "shaft", [thrust, force * math.cos(angle), force * math.sin(angle), 0, 0, 0],
        point=(0, 0, point), up=(0, 1, 0),
    )  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gb, duration=0.02, dt=1e-3, speeds={"shaft": N_RPM * RPM},
            initial_speeds={"shaft": N_RPM * RPM}, hub_loads=[load],
        )  # fmt: skip
    return res


def m0(f0: float, d_m_mm: float) -> float:
    """Palmgren's M0 [N·m] at ν n = 6000 mm²/s·rpm (the viscous branch)."""
    return 1e-7 * f0 * (NU * N_RPM) ** (2.0 / 3.0) * d_m_mm**3 * 1e-3


@pytest.mark.parametrize(("force", "thrust"), [(F, 0.0), (0.0, T)])
def test_each_rows_friction_moment_takes_its_load_from_the_statics_reactions(force, thrust):
    res = run(shaft(), force=force, thrust=thrust)
    r_b = force * (P - A) / (B - A)  # 37.5 kN: moments about A
    r_a = force - r_b  # 12.5 kN
    cot = 1.0 / math.tan(math.radians(10.0))
    p1_b = max(0.8 * thrust * cot, r_b)  # the thrust alone: 0.8 T cot 10° = 136 kN
    m_a = m0(2.5, 250.0) + 0.000275 * abs(r_a) * 0.250
    m_b = m0(5.0, 240.0) + 0.0004 * p1_b * 0.240
    # the rows carry the statics' loads (so P1 is theirs)
    scale = 1e-9 * (force + thrust)
    assert_allclose(res.row("shaft.B").radial, r_b, rtol=1e-9, atol=scale)
    assert_allclose(res.row("shaft.B").axial, -thrust, rtol=1e-9, atol=scale)
    # step 0 has no step before it: M1 = 0; from step 1 on M1 at the step before's load
    assert_allclose(res.bearing("shaft").friction_moment[0], -(m0(2.5, 250.0) + m0(5.0, 240.0)))
    bearing = res.bearing("shaft")
    assert_allclose(bearing.friction_moment[1:], -(m_a + m_b), rtol=1e-9)
    assert_allclose(res.joint("shaft").torque[1:], m_a + m_b, rtol=1e-9)
    assert_allclose(bearing.friction_power[1:], (m_a + m_b) * N_RPM * RPM, rtol=1e-9)
    residual = ledger_residual(res)
    assert np.abs(residual).max() <= 1e-9 * energy_scale(res)
    assert res.energy["friction_loss"][-1] > 0.0


def test_friction_load_kN_keeps_a_fixed_load_for_its_row():
    res = run(shaft(row_b='friction_load_kN="10"'), thrust=0.0)
    m_a = m0(2.5, 250.0) + 0.000275 * (F - F * (P - A) / (B - A)) * 0.250
    m_b = m0(5.0, 240.0) + 0.0004 * 10e3 * 0.240
    assert_allclose(res.bearing("shaft").friction_moment[1:], -(m_a + m_b), rtol=1e-9)


@pytest.mark.parametrize("thrust", [5e3, T])  # 0.8 T cot 10° = 22.7 kN < F; 136 kN > F
def test_an_ideal_bearings_moment_takes_its_load_from_the_joints_reaction(thrust):
    # the bearing carries F and T itself (the reaction of the joint); F at the bearing centre
    res = run(shaft(rows=False), point=0.0, thrust=thrust)
    cot = 1.0 / math.tan(math.radians(10.0))
    m = m0(5.0, 240.0) + 0.0004 * max(0.8 * thrust * cot, F) * 0.240
    assert_allclose(res.bearing("shaft").radial, F, rtol=1e-9)
    assert_allclose(res.bearing("shaft").friction_moment[1:], -m, rtol=1e-9)
    assert_allclose(res.joint("shaft").torque[1:], m, rtol=1e-9)


def test_the_steps_load_rule_is_friction_load():
    rng = np.random.default_rng(41)
    radial, axial = rng.uniform(0.0, 2e5, 50), rng.uniform(-2e5, 2e5, 50)
    for kind, factors in PALMGREN_FACTORS.items():
        cot = 1.0 / math.tan(factors.contact_angle) if factors.contact_angle > 0.0 else 0.0
        compiled = [
            _native.bearing_friction_load(LOAD_RULES[factors.axial], cot, r, a)
            for r, a in zip(radial, axial, strict=True)
        ]
        assert_allclose(compiled, friction_load(kind, radial, axial), rtol=1e-15, err_msg=kind)
