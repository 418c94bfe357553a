"""The rotor's thrust, weight and wind-shear moment on its hub in a run (loads/rotor.py)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import dblquad

import pinwind
from pinwind.errors import InputError, PinwindWarning
from pinwind.loads.rotor import CpTable, CtTable, Rotor, RotorHub
from pinwind.loads.signals import Sine
from pinwind.model.gearbox import loads

#: The shaft's bearing centre in the world [m], the rotor centre's distance from it along the
#: shaft [m], the shaft's mass [kg]; gravity along world −y.
CENTRE, OVERHANG, SHAFT_MASS, G = (0.1, 0.2, 0.0), 1.5, 10.0, 9.81
#: A rotor: R [m], mass [kg], tilt [rad], hub height H [m], shear exponent α, air density.
RADIUS, MASS, TILT, HEIGHT, ALPHA, RHO = 40.0, 2.0e4, math.radians(5.0), 60.0, 0.2, 1.225
#: The hub axes in the world (columns x, y, z): x along the shaft (world z), z up (world y).
HUB_IN_WORLD = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])


def shaft_urdf(bearing: str = 'type="spherical_roller" rating_c_kN="2200"') -> str:
    """A shaft on bearing "shaft" (axis world z) at CENTRE, gravity along world −y."""
    return f"""<robot name="shaft">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="{SHAFT_MASS!r}"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.2" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <origin xyz="{CENTRE[0]!r} {CENTRE[1]!r} {CENTRE[2]!r}"/><axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 {-G!r} 0">
    <bearing joint="shaft" {bearing}/>
  </gearbox>
</robot>"""


def shear_arm_polar(radius: float, height: float, alpha: float) -> float:
    """ℓ = (1/πR²) ∬ z (1 + z/H)^{2α} dA by a quadrature in polar coordinates."""
    moment, _ = dblquad(
        lambda r, phi: r * math.sin(phi) * (1 + r * math.sin(phi) / height) ** (2 * alpha) * r,
        0.0, 2 * math.pi, 0.0, radius, epsabs=0.0, epsrel=1e-12,
    )  # fmt: skip
    return moment / (math.pi * radius**2)


def rotor(ct: CtTable, **changes) -> Rotor:
    """The test rotor, its C_p zero (no torque: the shaft's speed is the driver's)."""
    values = dict(
        radius=RADIUS, air_density=RHO, mass=MASS, shaft_tilt=TILT, hub_height=HEIGHT,
        shear_exponent=ALPHA, ct=ct, cp=CpTable(tsr=(0.1, 30.0), cp=((0.0,), (0.0,))),
        hub=RotorHub("shaft", (0.0, 0.0, OVERHANG)),
    )  # fmt: skip
    return Rotor(**{**values, **changes})


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def test_the_bearing_carries_the_rotors_thrust_weight_and_shear_moment_as_statics_says():
    # C_t(λ) = 0.1 λ; at ω = 1.5 rad/s in 10 m/s, λ = ω R / v = 6 and T = ½ ρ π R² v² 0.6. In the
    # hub axes the loads are (T + m g sin τ, 0, −m g cos τ) at the rotor centre and M_y = ℓ T;
    # the ideal bearing's reaction on the shaft is −f − m_shaft g and −(M + r × f), r = OVERHANG
    # along the shaft (world z).
    omega, wind = 1.5, 10.0
    linear = CtTable(tsr=(1.0, 20.0), ct=((0.1,), (2.0,)))
    res = _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, speeds={"shaft": omega},
               rotors={"shaft": rotor(linear)}, wind=wind)  # fmt: skip
    thrust = 0.5 * RHO * math.pi * RADIUS**2 * wind**2 * 0.1 * (omega * RADIUS / wind)
    weight = MASS * G * np.array([math.sin(TILT), 0.0, -math.cos(TILT)])
    force = HUB_IN_WORLD @ (weight + [thrust, 0.0, 0.0])
    moment = HUB_IN_WORLD @ [0.0, shear_arm_polar(RADIUS, HEIGHT, ALPHA) * thrust, 0.0]
    r = np.array([0.0, 0.0, OVERHANG])
    bearing = res.bearing("shaft")
    n = len(res.time)
    scale = thrust * OVERHANG
    assert_allclose(bearing.force, [-force - SHAFT_MASS * np.array([0.0, -G, 0.0])] * n,
                    rtol=0, atol=1e-12 * thrust)  # fmt: skip
    assert_allclose(bearing.moment[:, :2], [(-(moment + np.cross(r, force)))[:2]] * n, rtol=0,
                    atol=1e-12 * scale)  # fmt: skip
    assert_allclose(res.rotor("shaft").thrust, thrust, rtol=1e-13)
    assert_allclose(res.rotor("shaft").thrust_coefficient, 0.6, rtol=1e-13)


def test_without_a_hub_the_thrust_is_recorded_but_loads_nothing():
    omega, wind = 1.5, 10.0
    constant = CtTable(tsr=(1.0, 20.0), ct=((0.8,), (0.8,)))
    res = _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, speeds={"shaft": omega},
               rotors={"shaft": rotor(constant, hub=None)}, wind=wind)  # fmt: skip
    assert_allclose(res.rotor("shaft").thrust, 0.5 * RHO * math.pi * RADIUS**2 * wind**2 * 0.8,
                    rtol=1e-13)  # fmt: skip
    assert_allclose(res.bearing("shaft").force, [[0.0, SHAFT_MASS * G, 0.0]] * len(res.time),
                    rtol=0, atol=1e-9)  # fmt: skip


@pytest.mark.parametrize("damping", [0.0, 40.0])
def test_the_energy_ledger_closes_with_the_rotor_loading_a_compliant_bearing_in_gusts(damping):
    # A shaft in a compliant bearing, not turning (the rotor's C_p is 0), under a gusting wind:
    # the thrust, the shear moment (∝ v²) and the weight move the shaft in its bearing; their
    # work is the ledger's applied work, and the ledger closes to round-off.
    from pinwind.testing import ledger_closure

    bearing = (
        f'radial_stiffness="1e8" radial_damping="{damping}" axial_stiffness="5e7" '
        f'axial_damping="{damping}" tilt_stiffness="1e7" tilt_damping="{damping}"'
    )
    constant = CtTable(tsr=(0.05, 20.0), ct=((0.8,), (0.8,)))
    res = _run(loads(shaft_urdf(bearing)), duration=0.5, dt=1e-4,
               rotors={"shaft": rotor(constant, radius=10.0, mass=300.0, hub_height=30.0)},
               wind=Sine(10.0, 3.0, 7.0))  # fmt: skip
    assert np.ptp(res.rotor("shaft").thrust) > 1e3  # the gusts changed the load
    assert np.max(np.abs(res.energy["work_applied"])) > 1e-2  # and it did work
    ledger_closure(res, rtol=1e-12)


def test_a_rotor_hub_on_a_body_the_model_does_not_have_names_the_bodies():
    constant = CtTable(tsr=(1.0, 20.0), ct=((0.8,), (0.8,)))
    bad = rotor(constant, hub=RotorHub("main_shaft", (0.0, 0.0, 1.0)))
    message = r'rotor on "shaft": its hub_body: .*"main_shaft": no such body; bodies are: .*shaft'
    with pytest.raises(InputError, match=message):
        _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, rotors={"shaft": bad}, wind=10.0)


def test_a_rotor_mass_without_gravity_is_refused_with_the_fix():
    constant = CtTable(tsr=(1.0, 20.0), ct=((0.8,), (0.8,)))
    weightless = shaft_urdf().replace(f'gravity="0 {-G!r} 0"', 'gravity="0 0 0"')
    with pytest.raises(InputError, match=r"mass 20000.0 kg has no weight: the model has no grav"):
        _run(loads(weightless), duration=0.01, dt=1e-3,
             rotors={"shaft": rotor(constant, hub=RotorHub("shaft", up=(0.0, 1.0, 0.0)))},
             wind=10.0)  # fmt: skip
