"""The static start (``simulate(initial_deflection="static")``, the default).

A compliant run starts with its meshes and springs deflected under the loads of t = 0, so that
the first sample carries the forces that rigid meshes and locked springs carry under the same
loads, with the whole train accelerating as one. The expectations are closed forms of the free
pair of ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, 20°, J_A = 0.0015 and
J_B = 0.006 kg·m², no gravity):

- balanced torques F r_b,A on A and F r_b,B on B: tooth force F, deflection F/k, no motion;
- a torque T on A alone: the pair accelerates as one, θ̈_A = T / (J_A + J_B (r_b,A/r_b,B)²), and
  the teeth carry what gear B needs to follow, F = J_B θ̈_B / r_b,B with θ̈_B = θ̈_A r_b,A/r_b,B;
- planets of a planetary with constant mesh stiffness k_s (sun) and k_r (ring) share the sun's
  torque in proportion to the series stiffness k_s k_r / (k_s + k_r) of their two meshes (the
  planet's moment balance makes both of its tooth forces equal).
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.stepper import EQUILIBRIUM_DIVERGED, EQUILIBRIUM_LOAD_STEPS
from pinwind.errors import (
    EquilibriumNotReached,
    InputError,
    StaticStartDiverged,
    StepTooCoarse,
    TorquesUnbalanced,
)
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, load_model, two_gear_urdf
from tests.dynamics.test_time_stepping import K_MESH, K_SINGLE

MODULE, ALPHA = 0.002, math.radians(20.0)
Z_A, Z_B = 20, 40
J_A, J_B = 0.0015, 0.006
R_BA = Z_A * MODULE * math.cos(ALPHA) / 2
R_BB = Z_B * MODULE * math.cos(ALPHA) / 2
#: Single-pair stiffness [N/m] and the constant mesh stiffness it gives, ISO 6336-1's mean
#: c_γα = c′ (0.75 ε_α + 0.25) (derived in test_time_stepping).
K = K_SINGLE


def _pair(**kw):
    return pinwind.simulate(loads(two_gear_urdf(), "pair.urdf"), gravity=np.zeros(3), **kw)


def _constant(k: float = K, **kw) -> MeshCompliance:
    return MeshCompliance(stiffness=k, variation="constant", damping=0.0, **kw)


def test_a_loaded_pair_starts_at_its_static_deflection_and_does_not_vibrate():
    force = 1000.0
    res = _pair(duration=0.01, dt=1e-5, torques={"a": force * R_BA, "b": force * R_BB},
                meshes={"m": _constant()})  # fmt: skip
    mesh = res.mesh("m")
    np.testing.assert_allclose(mesh.normal[0], force, rtol=1e-6)
    np.testing.assert_allclose(mesh.deflection[0], force / K_MESH, rtol=1e-6)
    # In equilibrium from the start: no start-up vibration, the force stays.
    np.testing.assert_allclose(mesh.normal, force, rtol=1e-6)
    start = res.metadata["initial_deflection"]
    assert start["converged"] and start["residual"] < 1e-12


def test_the_static_start_deflects_the_teeth_without_rolling_the_pair():
    # The loads fix the deflection δ = r_b,A θ_A + r_b,B θ_B, not where the pair has rolled to:
    # the start has no part along the rolling (r_b,B, −r_b,A), so θ_A r_b,B = θ_B r_b,A, and
    # θ_A = δ r_b,A / (r_b,A² + r_b,B²), θ_B = δ r_b,B / (r_b,A² + r_b,B²).
    force = 1000.0
    res = _pair(duration=1e-3, dt=1e-5, torques={"a": force * R_BA, "b": force * R_BB},
                meshes={"m": _constant()})  # fmt: skip
    theta = np.array([res.joint("a").angle[0], res.joint("b").angle[0]])
    deflection = R_BA * theta[0] + R_BB * theta[1]
    np.testing.assert_allclose(abs(deflection), force / K_MESH, rtol=1e-6)
    expected = deflection * np.array([R_BA, R_BB]) / (R_BA**2 + R_BB**2)
    np.testing.assert_allclose(theta, expected, rtol=1e-9)


def test_the_undeflected_start_keeps_the_model_pose_and_rings():
    force = 1000.0
    res = _pair(duration=0.01, dt=1e-5, torques={"a": force * R_BA, "b": force * R_BB},
                meshes={"m": _constant()}, initial_deflection="none")  # fmt: skip
    np.testing.assert_allclose(res.mesh("m").deflection[0], 0.0, atol=1e-15)
    # Released undeflected, the teeth overshoot to twice the static force.
    np.testing.assert_allclose(res.mesh("m").normal.max(), 2 * force, rtol=0.02)
    assert res.metadata["initial_deflection"] == {"mode": "none"}


def test_an_accelerating_pair_starts_with_the_rigid_tooth_force():
    torque = 50.0
    accel_a = torque / (J_A + J_B * (R_BA / R_BB) ** 2)
    force = J_B * (accel_a * R_BA / R_BB) / R_BB
    with pytest.warns(TorquesUnbalanced):  # nothing brakes b: the pair accelerates
        compliant = _pair(duration=1e-3, dt=1e-5, torques={"a": torque}, meshes={"m": _constant()})
    with pytest.warns(TorquesUnbalanced):
        rigid = _pair(duration=1e-3, dt=1e-5, torques={"a": torque}, meshes={"m": "rigid"})
    np.testing.assert_allclose(rigid.mesh("m").normal[0], force, rtol=1e-9)
    np.testing.assert_allclose(compliant.mesh("m").normal[0], rigid.mesh("m").normal[0], rtol=1e-6)
    np.testing.assert_allclose(compliant.joint("a").acceleration[0], accel_a, rtol=1e-6)


def test_a_load_on_the_back_flank_closes_the_backlash_first():
    force, backlash = 800.0, 1e-4
    res = _pair(duration=1e-3, dt=1e-5, torques={"a": -force * R_BA, "b": -force * R_BB},
                meshes={"m": _constant(backlash=backlash)})  # fmt: skip
    mesh = res.mesh("m")
    assert mesh.flank[0] == -1
    np.testing.assert_allclose(mesh.normal[0], force, rtol=1e-6)
    np.testing.assert_allclose(mesh.deflection[0], force / K_MESH, rtol=1e-6)
    assert res.metadata["initial_deflection"]["flank_switches"] >= 1


def _iso_mean_factor(z_1: int, z_2: int, *, internal: bool) -> float:
    """0.75 ε_α + 0.25, ISO 6336-1's mean over one pair's stiffness c′ ("constant" variation),
    with ε_α of Saleh 2017's standard gears (module 15 mm, 24.5°, no profile shift) by hand:
    (√(r_a1² − r_b1²) ± √(r_a2² − r_b2²) ∓ a sin α)/p_b, the ring's tip circle inside."""
    module, alpha = 0.015, math.radians(24.5)
    r_1, r_2 = z_1 * module / 2, z_2 * module / 2
    rb_1, rb_2 = r_1 * math.cos(alpha), r_2 * math.cos(alpha)
    pitch = math.pi * module * math.cos(alpha)
    a = r_2 - r_1 if internal else r_1 + r_2
    path_1 = math.sqrt((r_1 + module) ** 2 - rb_1**2)
    if internal:
        length = path_1 - math.sqrt((r_2 - module) ** 2 - rb_2**2) + a * math.sin(alpha)
    else:
        length = path_1 + math.sqrt((r_2 + module) ** 2 - rb_2**2) - a * math.sin(alpha)
    return 0.75 * length / pitch + 0.25


def test_planets_share_the_sun_torque_by_the_series_stiffness_of_their_meshes():
    gb = pinwind.load("models/saleh2017_planetary.urdf")
    k_sun = {"planet1": 3e9, "planet2": 2e9, "planet3": 1e9}
    k_ring = {"planet1": 4e9, "planet2": 4e9, "planet3": 2e9}
    sun_mesh, ring_mesh, meshes = {}, {}, {}
    for m in gb.meshes:
        names = {m.gear_a.name, m.gear_b.name}
        (planet,) = names - {"sun", "ring"}
        if "sun" in names:
            sun_mesh[planet] = m.name
            meshes[m.name] = _constant(k_sun[planet])
        else:
            ring_mesh[planet] = m.name
            meshes[m.name] = _constant(k_ring[planet])
    planets = sorted(k_sun)
    # Balanced: the carrier's torque over the ratio 1 + z_ring/z_sun held at the sun.
    torques = {"carrier": 1e6, "sun": -1e6 / (1 + 120 / 24)}
    rigid = pinwind.simulate(gb, duration=1e-3, dt=1e-4, torques=torques, meshes={"all": "rigid"})
    with pytest.warns(StepTooCoarse):  # 10 steps for the static start: the mesh mode unresolved
        res = pinwind.simulate(gb, duration=1e-3, dt=1e-4, torques=torques, meshes=meshes)
    f_sun = _iso_mean_factor(24, 48, internal=False)
    f_ring = _iso_mean_factor(48, 120, internal=True)
    series = np.array([1 / (1 / (f_sun * k_sun[p]) + 1 / (f_ring * k_ring[p])) for p in planets])
    sun_forces = np.array([res.mesh(sun_mesh[p]).normal[0] for p in planets])
    rigid_total = sum(rigid.mesh(sun_mesh[p]).normal[0] for p in planets)
    np.testing.assert_allclose(sun_forces.sum(), rigid_total, rtol=1e-6)
    np.testing.assert_allclose(sun_forces / sun_forces.sum(), series / series.sum(), rtol=1e-6)
    # Each planet's two tooth forces are equal (its moment balance; equal base radii).
    ring_forces = np.array([res.mesh(ring_mesh[p]).normal[0] for p in planets])
    np.testing.assert_allclose(ring_forces, sun_forces, rtol=1e-6)


def test_an_accelerating_planetary_starts_with_the_rigid_forces_when_its_meshes_are_alike():
    gb = pinwind.load("models/saleh2017_planetary.urdf")
    torques = {"carrier": 1e6}  # nothing holds the sun: the train accelerates
    with pytest.warns(TorquesUnbalanced):
        rigid = pinwind.simulate(
            gb, duration=1e-3, dt=1e-4, torques=torques, meshes={"all": "rigid"}
        )
    with pytest.warns(TorquesUnbalanced), pytest.warns(StepTooCoarse):
        res = pinwind.simulate(gb, duration=1e-3, dt=1e-4, torques=torques,
                               meshes={"all": _constant(2e9)})  # fmt: skip
    for mesh in gb.meshes:
        np.testing.assert_allclose(
            res.mesh(mesh.name).normal[0], rigid.mesh(mesh.name).normal[0], rtol=1e-6
        )


def test_shaft_springs_start_twisted_by_the_torque_they_carry():
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    spring = {s.name: s for s in gb.springs}["input_spring"]
    torque = 20.0
    torques = {"input_shaft": torque, "output_shaft": torque * _ratio(gb)}
    res = pinwind.simulate(gb, duration=1e-3, dt=1e-5, torques=torques, meshes={"all": "rigid"})
    j1, j2 = res.joint(spring.joint_1), res.joint(spring.joint_2)
    twist = j1.angle[0] - j2.angle[0]
    np.testing.assert_allclose(spring.stiffness * twist, torque, rtol=1e-6)


def _ratio(gb) -> float:
    """Output over input torque of the Cai pair at rest, the tooth counts' ratio (the gears
    turn opposite ways, so equal signs balance)."""
    return gb.gears["gear2"].spec.teeth / gb.gears["gear1"].spec.teeth


def test_an_unknown_start_is_refused_naming_the_choices():
    with pytest.raises(InputError, match="'static', 'none'"):
        _pair(duration=1e-3, dt=1e-5, meshes={"m": _constant()}, initial_deflection="relaxed")


#: The NREL 5 MW gearbox's rated rotor torque [N·m] (5 MW at 12.1 rpm, Jonkman et al. 2009).
RATED_5MW = 3.946e6


def _standing_5mw(torque: float) -> pinwind.Result:
    """The NREL 5 MW gearbox standing: ``torque`` on the rotor, the generator held at rest."""
    gearbox = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    return pinwind.simulate(
        gearbox, duration=0.002, dt=1e-4, torques={"rotor": torque}, speeds={"generator": 0.0}
    )


def test_a_load_beyond_newtons_reach_is_taken_in_steps_to_static_equilibrium(monkeypatch):
    """3 times rated torque on the NREL 5 MW gearbox: Newton from the undeflected pose does
    not converge (its planets' tilts and contacts change too much), the same load taken in steps
    does, and the run then starts at rest in static equilibrium: no acceleration at its first
    sample, where the undeflected start accelerates at once."""
    torque = 3.0 * RATED_5MW
    simulate_module = sys.modules["pinwind.dynamics.simulate"]  # the package's name is a function
    monkeypatch.setattr(simulate_module, "EQUILIBRIUM_LOAD_STEPS", ())
    with pytest.warns(EquilibriumNotReached):
        whole = _standing_5mw(torque)
    assert not whole.metadata["initial_deflection"]["converged"]
    monkeypatch.undo()
    stepped = _standing_5mw(torque)
    start = stepped.metadata["initial_deflection"]
    assert start["converged"] and start["load_steps"] > 1
    undeflected = pinwind.simulate(
        pinwind.load(MODELS / "nrel5mw_gearbox.urdf"), duration=0.002, dt=1e-4,
        torques={"rotor": torque}, speeds={"generator": 0.0}, initial_deflection="none",
    )  # fmt: skip
    jolt = np.abs(undeflected.acceleration[0]).max()
    assert np.abs(stepped.acceleration[0]).max() < 1e-6 * jolt
    # The held generator takes the rotor torque back at the train's ratio (its teeth: Nejad et
    # al. 2016), to the order of the deflections over the radii (the centres move).
    ratio = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
    np.testing.assert_allclose(stepped.joint("generator").torque[0], torque / ratio, rtol=1e-4)


def test_a_static_start_that_diverges_is_refused_naming_the_joint():
    """Six times rated torque: the planets' soft rows (Nejad et al. 2016 Table VI) let no static
    start near the model's pose be found even in 64 steps: refused before any step."""
    with pytest.raises(StaticStartDiverged, match=r'largest at joint "stage\d_planet\d"') as info:
        _standing_5mw(6.0 * RATED_5MW)
    assert info.value.correction > EQUILIBRIUM_DIVERGED * info.value.displacement
    assert info.value.load_steps == max(EQUILIBRIUM_LOAD_STEPS)
