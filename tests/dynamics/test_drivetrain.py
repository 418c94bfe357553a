"""The drivetrain a run steps and a linearisation takes (``dynamics/drivetrain.py``).

The modes of a rotor on a compliant spur pair, derived by hand. Gear a (joint a, J_a) carries the
rotor (J_r); gear b (joint b, J_b) is braked by a linear-slip generator (slope c). The mesh is a
spring k along the line of action; external gears turn oppositely, so the deflection is
δ = r_a θ_a + r_b θ_b (r the base radii m z cos α / 2). Both gears feel the same force k δ:

    (J_a + J_r) θ̈_a = −k r_a δ,    J_b θ̈_b = −k r_b δ,    c on θ̇_b

so the one flexible mode has the shape φ ∝ (r_a / (J_a + J_r), r_b / J_b) and

    ω² = k (r_a² / (J_a + J_r) + r_b² / J_b),

the two-inertia formula k_t (1/J₁ + 1/J_t) with the torsional stiffness k_t = k r_a² at a and the
train's inertia J_t = J_b (r_a / r_b)² reduced to a. Its damping ratio: the generator's
ζ = c φ_b² / (2 ω φᵀ M φ) = c (r_b / J_b)² / (2 ω (r_a² / (J_a + J_r) + r_b² / J_b)), plus the
mesh dashpot's, exactly its ζ_mesh: c_mesh = 2 ζ_mesh √(k m_eq) with m_eq = 1/(r_a²/(J_a + J_r) +
r_b²/J_b), the mode's own (ω² = k / m_eq), when m_eq has the rotor in.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.dynamics.compliant import mean_mesh_stiffness
from pinwind.dynamics.drivetrain import drivetrain, generator_slope, rotor_slope
from pinwind.loads.generator import LinearSlip, VariableSpeed
from pinwind.loads.rotor import Rotor, heier_cp
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from tests.conftest import two_gear_urdf

#: The pair of ``two_gear_urdf``: 20/40 teeth, module 2 mm, 20° (the model format's default).
BASE_RADII = (
    0.002 * 20 * math.cos(math.radians(20.0)) / 2,
    0.002 * 40 * math.cos(math.radians(20.0)) / 2,
)
#: Its gears' polar inertias [kg·m²] (izz of links a and b).
INERTIA_A, INERTIA_B = 0.0015, 0.006


def _pair():
    return loads(two_gear_urdf(), "pair.urdf")


@pytest.mark.parametrize("rotor_inertia", [0.0, 0.01, 2.0])
def test_a_rotor_on_a_compliant_pair_rings_at_the_two_inertia_frequency(rotor_inertia):
    gb = _pair()
    slope = 0.05  # N·m·s/rad
    train = drivetrain(
        gb,
        meshes={"all": "compliant"},
        rotors={"a": Rotor(radius=1.0, inertia=rotor_inertia)},
        wind=0.0,  # no aerodynamic torque, no aerodynamic damping
        generators={"b": LinearSlip(slope=slope, sync_speed=0.0)},
    )
    lin = linearise(train)
    k = mean_mesh_stiffness(train.meshes[0])
    r_a, r_b = BASE_RADII
    j_1 = INERTIA_A + rotor_inertia
    omega2 = k * (r_a**2 / j_1 + r_b**2 / INERTIA_B)
    # The two-inertia form of the same: k_t (1/J₁ + 1/J_t).
    k_t, j_t = k * r_a**2, INERTIA_B * (r_a / r_b) ** 2
    np.testing.assert_allclose(omega2, k_t * (1 / j_1 + 1 / j_t), rtol=1e-12)
    (mode,) = [m for m in lin.modes() if not m.rigid]
    np.testing.assert_allclose(mode.frequency, math.sqrt(omega2) / (2 * math.pi), rtol=1e-9)
    zeta = slope * (r_b / INERTIA_B) ** 2 / (2 * math.sqrt(omega2) * omega2 / k)
    zeta += MeshCompliance().damping_ratio
    np.testing.assert_allclose(mode.damping_ratio, zeta, rtol=1e-9)
    assert lin.added_inertia == ({"a": rotor_inertia} if rotor_inertia else {})


def test_a_speed_driver_holds_its_joint_in_the_modes():
    # Gear a driven at its speed: gear b alone on the mesh spring, ω² = k r_b² / J_b.
    gb = _pair()
    train = drivetrain(gb, meshes={"all": "compliant"}, speeds={"a": 10.0})
    (mode,) = [m for m in linearise(train).modes() if not m.rigid]
    k = mean_mesh_stiffness(train.meshes[0])
    expected = math.sqrt(k * BASE_RADII[1] ** 2 / INERTIA_B) / (2 * math.pi)
    np.testing.assert_allclose(mode.frequency, expected, rtol=1e-9)


def test_the_generator_laws_slope_is_their_torque_s_derivative():
    # T = k (ω − ω_s): slope k; T = K ω² below rated, P/ω above: 2 K ω and −P/ω².
    assert generator_slope(LinearSlip(slope=123.0, sync_speed=10.0), 3.0) == 123.0
    law = VariableSpeed(gain=2.0, rated_power=1000.0)  # rated where K ω³ = P: ω = 7.94 rad/s
    np.testing.assert_allclose(generator_slope(law, 5.0), 2 * 2.0 * 5.0, rtol=1e-12)
    np.testing.assert_allclose(generator_slope(law, 10.0), -1000.0 / 10.0**2, rtol=1e-12)


def test_the_rotor_slope_is_the_derivative_of_the_power_over_the_speed():
    # T = ½ ρ π R² v³ C_p(λ) / ω, λ = ω R / v, with Heier's C_p (loads/rotor.py), by hand.
    rotor = Rotor.saleh2017()
    wind, speed = 10.0, 14.2 * math.pi / 30

    def torque(omega):
        cp = float(heier_cp(omega * rotor.radius / wind, 0.0, rotor.cp.scale))
        return 0.5 * rotor.air_density * math.pi * rotor.radius**2 * wind**3 * cp / omega

    h = 1e-4 * speed
    expected = (torque(speed + h) - torque(speed - h)) / (2 * h)
    np.testing.assert_allclose(rotor_slope(rotor, speed, wind), expected, rtol=1e-6)
    # In the linearisation it is a damper −∂T/∂ω on the rotor's joint.
    train = drivetrain(_pair(), rotors={"a": rotor}, wind=wind, initial_speeds={"a": speed})
    lin = linearise(train)
    assert lin.law_damping == {"a": pytest.approx(-expected, rel=1e-6)}
    ia = _pair().v_index("a")
    np.testing.assert_allclose(lin.damping[ia, ia], -expected, rtol=1e-6)


def test_a_run_damps_its_mesh_on_the_effective_mass_with_the_rotor_in():
    # c = 2 ζ √(k m_eq), m_eq = 1 / (r_a² / (J_a + J_r) + r_b² / J_b) (module docstring): the
    # run's mesh is the machine's, the rotor's inertia in.
    from pinwind.dynamics.simulate import simulate

    rotor_inertia = 0.01
    res = simulate(
        _pair(), duration=1e-4, dt=1e-5, meshes={"all": "compliant"},
        rotors={"a": Rotor(radius=1.0, inertia=rotor_inertia)}, wind=0.0,
    )  # fmt: skip
    mesh = res.metadata["meshes"]["m"]
    r_a, r_b = BASE_RADII
    m_eq = 1 / (r_a**2 / (INERTIA_A + rotor_inertia) + r_b**2 / INERTIA_B)
    expected = 2 * MeshCompliance().damping_ratio * math.sqrt(mesh["mean_stiffness"] * m_eq)
    np.testing.assert_allclose(mesh["damping"], expected, rtol=1e-9)
