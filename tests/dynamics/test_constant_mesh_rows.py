"""Mesh rows taken once when they are constant (cpp/stepper_assembly.cpp fixed_mesh_frames).

Two gears on revolute joints about parallel axes whose centres and joint axes one frame holds
(sun and planet on a carrier, two gears on fixed axes) have a row J in joint coordinates that
does not depend on q: each entry is the moment arm of a joint's axis about the line of action.
So γ = J̇ v = 0. The step takes such rows once; these tests check the rows it takes against the
general path (``MeshSet.evaluate``, every mesh evaluated in full from Pinocchio's J and J̇) at
random states, that the general path's γ is zero to rounding there, and that a gear on a crank
swinging about another axis (its centre distance varies) is not taken for constant.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pinwind.dynamics.mesh import MeshSet
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, load_model
from tests.dynamics.test_constant_mass import _stepper
from tests.dynamics.test_mesh_rows import SWING_ARM

#: The swing arm with the arm's pivot on gear a's axis and b 60 mm out on it (the centre
#: distance of 20 and 40 teeth of module 2 mm): a sun and a planet on a carrier.
CARRIER_ARM = SWING_ARM.replace(
    '<origin xyz="0.06 -0.05 0"/><axis xyz="0 0 1"/>', '<origin xyz="0 0 0"/><axis xyz="0 0 1"/>'
).replace(
    '<origin xyz="0 0.05 0"/><axis xyz="0 0 1"/>', '<origin xyz="0.06 0 0"/><axis xyz="0 0 1"/>'
)


def _general_rows(gb, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """J and γ of every mesh on its front flank by the general path at (q, v)."""
    data = gb.model.createData()
    pin.computeJointJacobiansTimeVariation(gb.model, data, q, v)
    ms = MeshSet(gb)
    ms.set_velocity(v)
    rows = ms.evaluate(gb.model, data)
    return ms.combine(rows, np.ones(len(gb.meshes)))


def _assert_rows_are_the_general_paths(gb, seed: int, fixed: bool) -> None:
    """The step's J and γ at random (q, v), after a first assembly at the neutral pose, against
    the general path's at each state; a fixed mesh's γ is exactly 0, the general path's is 0 to
    rounding (the scale of its terms: |J| |v|², J in m, v in rad/s)."""
    model = gb.model
    stepper = _stepper(gb)
    stepper.assemble(gb.neutral(), np.zeros(model.nv))
    rng = np.random.default_rng(seed)
    first = None
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        v = rng.uniform(-5.0, 5.0, model.nv)
        jac, gamma = _general_rows(gb, q, v)
        step = stepper.assemble(q, v)
        scale = abs(jac).max()
        np.testing.assert_allclose(step.jac, jac, rtol=0, atol=1e-14 * scale)
        if fixed:
            assert np.all(step.gamma == 0.0)
            np.testing.assert_allclose(gamma, 0.0, atol=1e-14 * scale * abs(v).max() ** 2)
            first = jac if first is None else first
            np.testing.assert_allclose(jac, first, rtol=0, atol=1e-14 * scale)
        else:
            np.testing.assert_allclose(step.gamma, gamma, rtol=1e-12, atol=1e-14 * scale)


def test_planetary_meshes_are_fixed_in_the_carrier_and_their_rows_are_the_general_paths():
    """Sun–planet and planet–ring: the sun's and the ring's axes are the carrier's, each
    planet turns on the carrier: every mesh's figure turns with the carrier."""
    gb = load_model(MODELS / "saleh2017_planetary.urdf")
    carrier = gb.model.getJointId("carrier")
    assert _stepper(gb).mesh_frames == [carrier] * 6
    _assert_rows_are_the_general_paths(gb, seed=11, fixed=True)


def test_parallel_stages_are_fixed_in_the_world():
    """The drivetrain's two parallel stages turn on the housing (frame 0); its planetary
    meshes on the carrier."""
    gb = load_model(MODELS / "saleh2017_drivetrain.urdf")
    carrier = gb.model.getJointId("carrier")
    frames = dict(zip([m.name for m in gb.meshes], _stepper(gb).mesh_frames, strict=True))
    assert frames["stage1"] == 0 and frames["stage2"] == 0
    assert [frames[f"sun_planet{i}"] for i in (1, 2, 3)] == [carrier] * 3
    assert [frames[f"planet{i}_ring"] for i in (1, 2, 3)] == [carrier] * 3
    _assert_rows_are_the_general_paths(gb, seed=12, fixed=True)


def test_an_arm_about_the_suns_axis_is_a_carrier():
    """The arm pivoting on gear a's axis: b is a planet on it, the mesh is fixed in the arm."""
    gb = loads(CARRIER_ARM, path="carrier_arm.urdf")
    assert _stepper(gb).mesh_frames == [gb.model.getJointId("arm")]
    _assert_rows_are_the_general_paths(gb, seed=13, fixed=True)


def test_a_gear_on_a_crank_about_another_axis_is_evaluated_at_every_step():
    """The swing arm pivots 78 mm from gear a's axis: the centre distance changes with the
    arm's angle, so J does (by more than rounding between two angles), and the step must
    evaluate it in full: its J and γ are the general path's at every state."""
    gb = loads(SWING_ARM, path="swing_arm.urdf")
    assert _stepper(gb).mesh_frames == [-1]
    model = gb.model
    q0, q1 = gb.neutral(), gb.neutral()
    q1[model.idx_qs[model.getJointId("arm")]] = 0.5
    v = np.zeros(model.nv)
    j0, j1 = _general_rows(gb, q0, v)[0], _general_rows(gb, q1, v)[0]
    assert abs(j1 - j0).max() > 1e-3 * abs(j0).max()
    _assert_rows_are_the_general_paths(gb, seed=14, fixed=False)
