"""The step takes M once when the model says it is constant (cpp/joint_algorithms.hpp
mass_is_constant): the taken M must equal Pinocchio's CRBA at any configuration, and a model
whose M does vary must not be taken for constant."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.dynamics.compliant import mesh_setup
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, load_model
from tests.dynamics.test_mesh_rows import SWING_ARM

#: The swing arm with gear b's centre of mass 10 mm off its own axis: b's path then has two
#: levers (its axis 50 mm from the arm's, its centre of mass off its axis), so its M depends on
#: b's angle (the m d₁·d₂ cos θ_b term of a double pendulum).
OFF_AXIS = SWING_ARM.replace(
    '<link name="b"><inertial><mass value="2"/>',
    '<link name="b"><inertial><origin xyz="0.01 0 0"/><mass value="2"/>',
)


def _stepper(gb: pinwind.Gearbox) -> CompiledStepper:
    return CompiledStepper(
        gb,
        2,
        gb.neutral(),
        np.zeros(gb.model.nv),
        dt=1e-3,
        gravity=gb.gravity,
        driver_index=[],
        driver_names=[],
        settings=SolverSettings(),
        meshes=mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-3),
    )


def _crba(model: pin.Model, q: np.ndarray) -> np.ndarray:
    m = pin.crba(model, model.createData(), q)
    return np.triu(m) + np.triu(m, 1).T


def _assert_step_mass_is_crba(gb: pinwind.Gearbox, stepper: CompiledStepper, seed: int) -> None:
    """The step's M at random (q, v), after a first assembly at the neutral pose, against
    Pinocchio's CRBA recomputed at each q."""
    model = gb.model
    stepper.assemble(gb.neutral(), np.zeros(model.nv))
    rng = np.random.default_rng(seed)
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        v = rng.uniform(-5.0, 5.0, model.nv)
        expected = _crba(model, q)
        atol = 1e-13 * abs(expected).max()
        np.testing.assert_allclose(stepper.assemble(q, v).mass, expected, rtol=0, atol=atol)
        np.testing.assert_allclose(stepper.mass_matrix(q), expected, rtol=0, atol=atol)


@pytest.mark.parametrize(
    "name", ["saleh2017_planetary.urdf", "saleh2017_drivetrain.urdf", "dtu500_planetary.urdf"]
)
def test_gear_trains_on_parallel_axes_take_m_once_and_it_is_crbas_everywhere(name):
    """Planets on a carrier and gears on fixed axes: one lever on every body's path."""
    gb = load_model(MODELS / name)
    stepper = _stepper(gb)
    assert stepper.constant_mass
    _assert_step_mass_is_crba(gb, stepper, seed=3)


def test_one_lever_per_path_is_constant_with_an_off_axis_centre_of_mass():
    """The swing arm: the arm's centre of mass 30 mm off its axis, b's axis 50 mm off the
    arm's, b's centre of mass on its axis: M is constant, and Pinocchio agrees at any q."""
    gb = loads(SWING_ARM, path="swing_arm.urdf")
    stepper = _stepper(gb)
    assert stepper.constant_mass
    _assert_step_mass_is_crba(gb, stepper, seed=5)


def test_two_levers_on_a_path_vary_and_the_step_follows_them():
    """Gear b's centre of mass off its axis on the swinging arm: M varies with b's angle, so
    the step must not take it once, and its M is CRBA's at every q."""
    gb = loads(OFF_AXIS, path="swing_arm_off_axis.urdf")
    model = gb.model
    stepper = _stepper(gb)
    assert not stepper.constant_mass
    q0, q1 = gb.neutral(), gb.neutral()
    q1[model.idx_qs[model.getJointId("b")]] = np.pi / 2
    arm = model.idx_vs[model.getJointId("arm")]
    # b's share of M_arm,arm is m |d₁ + d₂|² + I_b: d₁ = (0, 0.05) m in the arm, d₂ = (0.01, 0) m
    # in b, perpendicular at θ_b = 0 and parallel at π/2, where it is larger by 2 m d₁ d₂ with
    # m = 2 kg: 2 · 2 · 0.05 · 0.01 = 2e-3 kg·m².
    rise = _crba(model, q1)[arm, arm] - _crba(model, q0)[arm, arm]
    assert rise == pytest.approx(2e-3, rel=1e-9)
    _assert_step_mass_is_crba(gb, stepper, seed=9)


def test_constant_m_has_no_velocity_terms_and_follows_an_off_axis_centre_of_mass():
    """With M constant, b = C(q, v) v + g(q) is g(q) alone (C v = Ṁ v − ½ ∂(vᵀ M v)/∂q = 0):
    the step's b at random (q, v) must equal Pinocchio's RNEA at zero acceleration, which
    computes the velocity terms, on the swing arm whose centre of mass, 30 mm off its world
    axis, moves with the arm's angle under gravity in the plane (a body whose world inertia were
    taken once would keep the first pose's weight lever)."""
    gb = loads(SWING_ARM, path="swing_arm.urdf")
    model = gb.model.copy()
    model.gravity = pin.Motion(np.asarray(gb.gravity, dtype=float), np.zeros(3))
    stepper = _stepper(gb)
    assert stepper.constant_mass
    stepper.assemble(gb.neutral(), np.zeros(model.nv))
    rng = np.random.default_rng(21)
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        v = rng.uniform(-30.0, 30.0, model.nv)
        expected = pin.rnea(model, model.createData(), q, v, np.zeros(model.nv))
        assert abs(expected).max() > 0.1  # weights about the arm axis: arm 30 mm, gear b 50 mm off
        bias = stepper.assemble(q, v).bias
        np.testing.assert_allclose(bias, expected, rtol=0, atol=1e-12 * abs(expected).max())
