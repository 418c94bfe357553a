"""Torsional spring-dampers and viscous bearing damping (``cpp/torsional_spring.hpp``).

Two coaxial shafts ``a`` and ``b`` on a housing, each of axial inertia J, no gears: a torsional
spring (stiffness k, damping c_s, preload angle θ₀) between them and, on ``a``, a viscous bearing
damping c_b. Hand results:

- the spring stores U = ½ k (θ_a − θ_b − θ₀)² at every sample, whatever the motion;
- a shaft of inertia J under a constant torque T against its bearing damping c, stepped with the
  trapezoidal rule (ρ∞ = 1: the damping torque at the mid-step speed, taken implicitly), follows
  ω_{n+1} = g ω_n + (T h / J) / (1 + r/2) with r = c h / J and g = (1 − r/2)/(1 + r/2), so
  ω_n = (T/c) (1 − gⁿ) from rest: |g| < 1 at any step, however stiff the damping. Taking the
  damping explicitly instead gives g = 1 − r, which grows without bound for r > 2.
"""

from __future__ import annotations

from contextlib import nullcontext

import numpy as np
import pytest

import pinwind
from pinwind.dynamics import Integrator
from pinwind.errors import TorquesUnbalanced
from pinwind.model.gearbox import loads

J = 0.02


def _shafts_urdf(
    *, stiffness: float = 0.0, spring_damping: float = 0.0, preload: float = 0.0,
    bearing_damping: float = 0.0,
) -> str:  # fmt: skip
    """Two coaxial shafts a and b (axial inertia J each) joined by a torsional spring-damper."""
    dynamics = f'<dynamics damping="{bearing_damping!r}"/>' if bearing_damping else ""
    links = "".join(
        f"""
  <link name="{name}">
    <inertial><mass value="1.0"/>
      <inertia ixx="0.01" iyy="0.01" izz="{J!r}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="{name}" type="continuous">
    <parent link="housing"/><child link="{name}"/>
    <origin xyz="0 0 {z}"/><axis xyz="0 0 1"/>{dynamics if name == "a" else ""}
  </joint>"""
        for name, z in (("a", 0.0), ("b", 0.5))
    )
    return f"""<?xml version="1.0"?>
<robot name="shafts">
  <link name="housing"/>{links}
  <gearbox>
    <torsional_spring name="shaft" joint1="a" joint2="b" stiffness="{stiffness!r}"
                      damping="{spring_damping!r}" preload_angle="{preload!r}"/>
  </gearbox>
</robot>
"""


def test_spring_energy_is_half_k_twist_squared_at_every_sample():
    """Guards ``TorsionalSprings::potential`` (U = ½ k t², t = θ₁ − θ₂ − θ₀): with k t² the
    ledger's ``potential_spring`` doubles."""
    k, preload, torque = 500.0, 0.2, 30.0
    res = pinwind.simulate(
        loads(_shafts_urdf(stiffness=k, preload=preload), "shafts.urdf"),
        duration=0.5,
        dt=1e-3,
        torques={"a": torque, "b": -torque},
        gravity=np.zeros(3),
        initial_deflection="none",  # released untwisted: the twist swings over the run
    )
    twist = res.joint("a").angle - res.joint("b").angle - preload
    expected = 0.5 * k * twist**2
    assert expected.max() > 1.0  # the shafts twist: a few joules are at stake
    np.testing.assert_allclose(res.energy["potential_spring"], expected, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    ("model", "inertia", "torques"),
    [
        (dict(bearing_damping=40.0), J, {"a": 8.0}),
        # The spring's dashpot acts on the twist, u = θ_a − θ_b: J u'' = 2 T − 2 c u'
        (dict(spring_damping=20.0), J / 2, {"a": 4.0, "b": -4.0}),
    ],
    ids=["bearing damping", "spring damping"],
)
def test_stiffly_damped_shaft_follows_the_implicit_trapezoidal_response_at_a_coarse_step(
    model, inertia, torques
):
    """Guards the damping's share of the implicit weight (``BearingDamping::add_implicit``
    ``speed_gain * damping_`` and ``TorsionalSprings::add_implicit`` ``damping * speed_gain``):
    without it the damping is explicit and the speed at r = c h / J = 4 grows as (−3)ⁿ."""
    c = model.get("bearing_damping", 0.0) + model.get("spring_damping", 0.0)
    torque = torques["a"]
    h = 4.0 * inertia / c  # r = 4: twice the explicit stability limit
    steps = 30
    # A damped bearing holds its shaft's motion (dynamics/torque_balance.py); the spring's
    # dashpot acts on the twist only, and the run says what nothing holds.
    said = pytest.warns(TorquesUnbalanced) if "spring_damping" in model else nullcontext()
    with said:
        res = pinwind.simulate(
            loads(_shafts_urdf(**model), "shafts.urdf"),
            duration=steps * h,
            dt=h,
            torques=torques,
            gravity=np.zeros(3),
            integrator=Integrator(rho_infinity=1.0),
        )
    speed = res.joint("a").speed - (res.joint("b").speed if "b" in torques else 0.0)
    r = c * h / inertia
    g = (1 - r / 2) / (1 + r / 2)
    np.testing.assert_allclose(g, -1 / 3, rtol=1e-15)
    expected = torque / c * (1 - g ** np.arange(steps + 1))
    np.testing.assert_allclose(speed, expected, rtol=1e-9, atol=1e-12)
