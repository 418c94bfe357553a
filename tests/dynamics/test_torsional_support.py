"""Torsional springs to the ground and torsional stiffness on a bearing (issue 36, item 3).

A disc of axial inertia J on a bearing on the housing, held by a torsional spring k (damping c)
to the ground, ``<torsional_spring joint1="disc"/>`` without joint2, or by the same stiffness on
its bearing, ``<bearing joint="disc" torsional_stiffness="k"/>``. Hand results:

- the torque on the joint is −k(θ − θ₀) − c ω: the element's tangent is K = k e eᵀ and its
  damping C = c e eᵀ, which central differences of the force reproduce (the force is linear);
- undamped, under a constant torque T released untwisted, ½ J ω² + ½ k θ² − T θ stays constant;
  damped, the ledger's balance Δkinetic = W_applied + W_springs − dissipated closes;
- its natural frequency is √(k/J)/2π, and a constant torque T twists it by T/k at the start.

For a planetary stage the ring is held by Lin & Parker's k_ru (Lin & Parker 1999, J. Vib.
Acoust. 121): written as ``<bearing joint="ring" torsional_stiffness>`` on the ring's fixed
mount, or as a ``<support housing="ring">`` with ``stiffness_roll`` on the ring link, the same
machine, so the same modes; with the carrier and sun torques of a turbine (T_c in, T_s = −T_c/i
out) its support holds the ring against T_c + T_s, a twist θ_r = (T_c + T_s)/k_ru.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.compliant import mesh_choices, mesh_setup
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper
from pinwind.errors import InvalidMount, MalformedModel
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from tests.conftest import MODELS

J = 0.05  # kg·m², the disc's axial inertia


def _discs(gearbox: str) -> str:
    """Two coaxial discs a and b on bearings on the housing, inertia J each; ``gearbox`` inside."""
    links = "".join(
        f"""
  <link name="{name}">
    <inertial><mass value="2.0"/>
      <inertia ixx="0.03" iyy="0.03" izz="{J!r}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="{name}" type="continuous">
    <parent link="housing"/><child link="{name}"/>
    <origin xyz="0 0 {z}"/><axis xyz="0 0 1"/>
  </joint>"""
        for name, z in (("a", 0.0), ("b", 0.4))
    )
    return f"""<?xml version="1.0"?>
<robot name="discs">
  <link name="housing"/>{links}
  <gearbox>{gearbox}</gearbox>
</robot>
"""


def _ground_spring(k: float, c: float = 0.0, preload: float = 0.0, joint: str = "a") -> str:
    return (
        f'<torsional_spring name="arm" joint1="{joint}" stiffness="{k!r}" damping="{c!r}" '
        f'preload_angle="{preload!r}"/>'
    )


def _bearing_torsion(k: float, c: float = 0.0, joint: str = "b") -> str:
    return f'<bearing joint="{joint}" torsional_stiffness="{k!r}" torsional_damping="{c!r}"/>'


def _stepper(gb: pinwind.Gearbox) -> CompiledStepper:
    return CompiledStepper(
        gb, 2, gb.neutral(), np.zeros(gb.model.nv), dt=1e-3, gravity=np.zeros(3),
        driver_index=[], driver_names=[], settings=SolverSettings(),
        meshes=mesh_setup(gb, mesh_choices(gb, None), driver_index=[], dt=1e-3),
    )  # fmt: skip


def _central_difference(f, x: np.ndarray, h: float) -> np.ndarray:
    """∂f/∂x by central differences, one column per coordinate."""
    cols = []
    for j in range(len(x)):
        step = np.zeros_like(x)
        step[j] = h
        cols.append((f(x + step) - f(x - step)) / (2 * h))
    return np.array(cols).T


def test_each_torsional_element_s_tangent_matches_central_differences_of_its_force():
    # A spring a–b, a spring from a to the ground (preloaded), b's bearing in torsion: each with
    # its own stiffness and damping, so that a wrong entry of any one shows.
    gb = loads(
        _discs(
            '<torsional_spring name="shaft" joint1="a" joint2="b" stiffness="700.0" '
            'damping="3.0" preload_angle="0.1"/>'
            + _ground_spring(1100.0, 5.0, preload=-0.3)
            + _bearing_torsion(1900.0, 7.0)
        )
    )
    stepper = _stepper(gb)
    rng = np.random.default_rng(36)
    q, v = rng.uniform(-1, 1, 2), rng.uniform(-5, 5, 2)

    def force_q(x):
        return np.array(stepper.element_forces(x, v).force)

    def force_v(x):
        return np.array(stepper.element_forces(q, x).force)

    def potential(x):
        return stepper.element_forces(x, v).potential

    terms = stepper.element_forces(q, v)
    stiffness, damping = np.array(terms.stiffness), np.array(terms.damping)
    expected_k = np.array([[700 + 1100, -700], [-700, 700 + 1900]])
    expected_c = np.array([[3 + 5, -3], [-3, 3 + 7]])
    assert_allclose(stiffness, expected_k, rtol=1e-12)  # the hand sums
    assert_allclose(damping, expected_c, rtol=1e-12)
    assert_allclose(-_central_difference(force_q, q, 1e-6), stiffness, rtol=1e-6, atol=1e-6)
    assert_allclose(-_central_difference(force_v, v, 1e-6), damping, rtol=1e-6, atol=1e-6)
    # The forces themselves, by hand: joint a takes the shaft's and the arm's torques.
    twist = q[0] - q[1] - 0.1
    shaft = -700 * twist - 3 * (v[0] - v[1])
    arm = -1100 * (q[0] + 0.3) - 5 * v[0]
    torsion = -1900 * q[1] - 7 * v[1]
    assert_allclose(force_q(q), [shaft + arm, -shaft + torsion], rtol=1e-12)
    # Each spring is conservative: its elastic force is −∂U/∂q, U = Σ ½ k twist².
    elastic = np.array(stepper.element_forces(q, np.zeros(2)).force)
    energy = 0.5 * (700 * twist**2 + 1100 * (q[0] + 0.3) ** 2 + 1900 * q[1] ** 2)
    assert_allclose(potential(q), energy, rtol=1e-12)
    gradient = np.array([(potential(q + h) - potential(q - h)) / 2e-6 for h in np.eye(2) * 1e-6])
    assert_allclose(-gradient, elastic, rtol=1e-6)
    # The modes see the same K and C (modes/linearisation.py).
    lin = linearise(gb)
    assert_allclose(lin.stiffness, stiffness, rtol=1e-12)
    assert_allclose(lin.damping, damping, rtol=1e-12)


@pytest.mark.parametrize("spelling", ["spring", "bearing"])
def test_an_undamped_disc_on_a_spring_to_the_ground_keeps_its_energy(spelling):
    k, torque = 400.0, 20.0
    text = _ground_spring(k) if spelling == "spring" else _bearing_torsion(k, joint="a")
    res = pinwind.simulate(
        loads(_discs(text)), duration=1.0, dt=1e-3, torques={"a": torque},
        gravity=np.zeros(3), initial_deflection="none",
    )  # fmt: skip
    theta, omega = res.joint("a").angle, res.joint("a").speed
    assert theta.max() > 1.9 * torque / k  # released untwisted: it swings to 2 T/k
    energy = 0.5 * J * omega**2 + 0.5 * k * theta**2 - torque * theta
    scale = 0.5 * k * (2 * torque / k) ** 2
    assert_allclose(energy, 0.0, atol=1e-9 * scale)
    assert_allclose(res.energy["potential_spring"], 0.5 * k * theta**2, rtol=1e-12, atol=1e-15)
    # The ledger: the spring's work is the change of its energy; the step loses none.
    e = res.energy
    assert_allclose(e["work_springs"], -e["potential_spring"], atol=1e-9 * scale)
    assert_allclose(e["numerical"], 0.0, atol=1e-9 * scale)


@pytest.mark.parametrize("spelling", ["spring", "bearing"])
def test_the_ledger_of_a_damped_disc_on_a_torsional_support_closes(spelling):
    k, c, torque = 400.0, 1.5, 20.0
    text = _ground_spring(k, c) if spelling == "spring" else _bearing_torsion(k, c, joint="a")
    res = pinwind.simulate(
        loads(_discs(text)), duration=1.0, dt=1e-3, torques={"a": torque},
        gravity=np.zeros(3), initial_deflection="none",
    )  # fmt: skip
    e = res.energy
    scale = 0.5 * k * (2 * torque / k) ** 2
    assert e["dissipated"][-1] > 0.1 * scale  # the damper takes a good part of the swing
    change = e["kinetic"] - e["kinetic"][0]
    assert_allclose(
        change, e["work_applied"] + e["work_springs"] - e["dissipated"], atol=1e-9 * scale
    )
    assert_allclose(e["work_springs"], -e["potential_spring"], atol=1e-9 * scale)
    # The dissipated energy is ∫ c ω² dt (trapezoidal over the mid-step speeds).
    omega = res.joint("a").speed
    mid = 0.5 * (omega[1:] + omega[:-1])
    assert_allclose(e["dissipated"][-1], np.sum(c * mid**2) * 1e-3, rtol=1e-9)


def test_a_disc_on_a_spring_to_the_ground_starts_twisted_and_vibrates_at_sqrt_k_over_j():
    k, torque = 400.0, 20.0
    gb = loads(_discs(_ground_spring(k, preload=0.25)))
    res = pinwind.simulate(gb, duration=0.05, dt=1e-3, torques={"a": torque}, gravity=np.zeros(3))
    assert_allclose(res.joint("a").angle, 0.25 + torque / k, rtol=1e-12)
    found = [m.frequency for m in linearise(gb).modes() if m.frequency > 0]
    assert_allclose(found, [math.sqrt(k / J) / (2 * math.pi)], rtol=1e-12)


def _planetary(extra: str) -> pinwind.Gearbox:
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    return loads(text.replace("</gearbox>", extra + "</gearbox>"))


def test_a_ring_on_a_support_roll_has_the_modes_of_a_ring_on_a_torsional_bearing():
    k = 2e9  # N·m/rad, the ring's torsional support k_ru
    support = _planetary(f'<support housing="ring"><mount stiffness_roll="{k!r}"/></support>')
    bearing = _planetary(_bearing_torsion(k, joint="ring"))
    assert "ring" not in support.locked_joints and "ring" not in bearing.locked_joints
    for meshes in ({"all": "compliant"}, {"all": "rigid"}):
        modes = [
            [m.frequency for m in linearise(gb, meshes=meshes, held=["carrier"]).modes()]
            for gb in (support, bearing)
        ]
        assert len(modes[0]) == len(modes[1]) >= 1
        assert_allclose(modes[0], modes[1], rtol=1e-9)
    # Rigid meshes, the carrier held: the one mode left is the train (ring, planets, sun) on
    # k_ru, of inertia J_r + J_s (Z_r/Z_s)² + Σ J_p (Z_r/Z_p)², ratios with the carrier still.
    inertia = 1083.485 + 4.8370 * (120 / 24) ** 2 + 3 * 77.78 * (120 / 48) ** 2
    rigid = linearise(bearing, meshes={"all": "rigid"}, held=["carrier"]).modes()
    assert_allclose(rigid[-1].frequency, math.sqrt(k / inertia) / (2 * math.pi), rtol=1e-9)


@pytest.mark.parametrize("spelling", ["support", "bearing"])
def test_a_ring_on_its_torsional_support_starts_twisted_by_the_ring_torque(spelling):
    k, t_carrier = 2e9, 1e6
    extra = (
        f'<support housing="ring"><mount stiffness_roll="{k!r}"/></support>'
        if spelling == "support"
        else _bearing_torsion(k, joint="ring")
    )
    gb = _planetary(extra)
    joint = "support_mount_roll" if spelling == "support" else "ring"
    res = pinwind.simulate(
        gb, duration=0.01, dt=1e-3, torques={"carrier": t_carrier, "sun": -t_carrier / 6},
        gravity=np.zeros(3),
    )  # fmt: skip
    # The stage's external torques balance: T_c + T_s − k θ_r = 0 (the support's on the ring).
    twist = (t_carrier - t_carrier / 6) / k
    assert_allclose(res.joint(joint).angle[0], twist, rtol=1e-9)
    assert_allclose(res.joint(joint).angle, twist, rtol=1e-6)


def test_a_spring_to_the_ground_on_a_joint_whose_parent_turns_is_refused():
    text = _discs(_ground_spring(100.0, joint="b")).replace(
        '<parent link="housing"/><child link="b"/>', '<parent link="a"/><child link="b"/>'
    )
    with pytest.raises(MalformedModel, match=r'parent link "a" turns on joint "a".*joint2'):
        loads(text)


def test_torsional_stiffness_on_a_weld_or_negative_is_refused_with_its_value():
    ring = (MODELS / "saleh2017_planetary.urdf").read_text()
    with pytest.raises(MalformedModel, match="fixed joint that carries no gear"):
        loads(ring.replace("</gearbox>", _bearing_torsion(1e9, joint="pin1") + "</gearbox>"))
    with pytest.raises(InvalidMount, match="torsional_stiffness -5 N·m/rad"):
        loads(_discs(_bearing_torsion(-5.0, joint="a")))


def test_a_bearing_held_in_torsion_alone_is_not_rated():
    gb = loads(_discs(_bearing_torsion(100.0, joint="a")))
    assert gb.source.bearings == {}
    assert [s.name for s in gb.springs] == ["a_torsion"]
