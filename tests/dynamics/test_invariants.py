"""Invariants of every run: the constraints hold, and energy is accounted for."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import TorquesUnbalanced
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, load_model


def _balance(res):
    e = res.energy
    supplied = e["work_applied"] + e["work_drivers"] + e["work_springs"] + e["work_gravity"]
    return e["kinetic"] - e["kinetic"][0], supplied - e["dissipated"]


def test_constraints_hold_to_1e_10_after_ten_thousand_steps():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with pytest.warns(TorquesUnbalanced):  # 1.1 MN·m against 6 · 1e6/6: it accelerates
        res = pinwind.simulate(
            gb, duration=10.0, dt=1e-3, torques={"carrier": 1.1e6, "sun": -1e6 / 6}
        )
    assert len(res) == 10_001
    assert res.constraint_residual.max() < 1e-10
    # Transmission error: the rigid meshes do not drift apart along their lines of action.
    assert np.abs(res.transmission_error).max() < 1e-10


def test_work_of_torques_equals_kinetic_energy_plus_damper_losses():
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    # Viscous bearing damping on the carrier and the sun [N·m·s/rad].
    text = text.replace(
        '<joint name="carrier" type="continuous">',
        '<joint name="carrier" type="continuous"><dynamics damping="2000"/>',
    ).replace(
        '<joint name="sun" type="continuous">',
        '<joint name="sun" type="continuous"><dynamics damping="50"/>',
    )
    gb = loads(text, path="saleh_damped.urdf")
    res = pinwind.simulate(
        gb,
        duration=3.0,
        dt=1e-3,
        torques={"carrier": lambda t: 1e6 * (1 + 0.3 * math.sin(3 * t)), "sun": -1e5},
    )
    assert res.energy["dissipated"][-1] > 0.01 * res.energy["work_applied"][-1]
    change, supplied = _balance(res)
    scale = np.abs(res.energy["work_applied"]).max()
    assert_allclose(change, supplied, rtol=0, atol=1e-6 * scale)
    # Constraint forces do no work.
    assert_allclose(res.energy["work_constraints"], 0.0, atol=1e-9 * scale)


def test_energy_balance_holds_with_springs_and_a_speed_driver():
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    omega = 200 * 2 * math.pi / 60  # Kelso 2011: 200 rpm driver, 49 N·m brake
    res = pinwind.simulate(
        gb,
        duration=1.0,
        dt=1e-4,
        speeds={"input_shaft": lambda t: omega * min(1.0, t / 0.2)},
        torques={"output_shaft": -49.0},
    )
    change, supplied = _balance(res)
    scale = np.abs(res.energy["work_drivers"]).max()
    assert_allclose(change, supplied, rtol=0, atol=1e-6 * scale)
    assert res.constraint_residual.max() < 1e-10


def _rotate(quaternion_xyzw: np.ndarray, vector: np.ndarray) -> np.ndarray:
    """Rotate ``vector`` by each unit quaternion (x, y, z, w) of an (n, 4) array."""
    xyz, w = quaternion_xyzw[:, :3], quaternion_xyzw[:, 3:]
    t = 2.0 * np.cross(xyz, vector)
    return vector + w * t + np.cross(xyz, t)


def test_gravity_work_in_the_ledger_equals_weight_times_the_drop_of_an_unbalanced_gear():
    from tests.conftest import two_gear_urdf

    # Gear a's centre of mass 10 mm off its shaft, level with it at t = 0: released from rest
    # under the default gravity (the pair model gives none: 9.81 m/s² along −y), it swings down.
    mass, offset = 1.0, 0.01
    text = two_gear_urdf().replace(
        '<inertial><mass value="1.0"/>',
        f'<inertial><origin xyz="{offset} 0 0"/><mass value="{mass}"/>',
        1,
    )
    gb = loads(text, path="unbalanced_pair.urdf")
    dt = 1e-4
    res = pinwind.simulate(gb, duration=1.0, dt=dt)
    body = res.body("a")
    centre_of_mass = body.position + _rotate(body.quaternion, np.array([offset, 0.0, 0.0]))
    drop = centre_of_mass[0, 1] - centre_of_mass[:, 1]
    assert drop.max() > 0.99 * offset  # it swings through the bottom, 10 mm below the axis
    expected = mass * 9.81 * drop  # work of gravity = m g Δh, from the body positions alone
    # Mid-step speeds against positions advanced with v_(k+1): the ledger is first order in dt
    # (2.4e-4 of m g d at dt = 1e-4 s); a sign error would be off by 2 m g Δh.
    tol = 1e-3 * mass * 9.81 * offset
    assert_allclose(res.energy["work_gravity"], expected, rtol=0, atol=tol)
    # Energy conservation: nothing else does work, so the kinetic energy is m g Δh too.
    assert_allclose(res.energy["kinetic"], expected, rtol=0, atol=tol)
    change, supplied = _balance(res)
    assert_allclose(change, supplied, rtol=0, atol=1e-9 * mass * 9.81 * offset)


def test_recorded_speeds_satisfy_the_mesh_row_recomputed_from_the_recorded_angles():
    # res.constraint_residual is read after the velocity projection, so it is small by
    # construction. Recompute J(q) v from the recorded angles and speeds alone, with the rows of
    # pinwind.dynamics.mesh, on the swing arm of test_mesh_rows: gear B's centre moves, so J(q)
    # turns in joint space and J v drifts every step unless the speeds are projected (with the
    # projection off, |J v| reaches 0.015 m/s here).
    import pinocchio as pin

    from pinwind.dynamics.mesh import MeshSet
    from tests.dynamics.test_mesh_rows import SWING_ARM

    gb = loads(SWING_ARM, path="swing_arm.urdf")
    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(
            gb, duration=1.0, dt=1e-3, initial_speeds={"arm": 2.0}, torques={"a": 0.05}
        )
    assert np.ptp(res.joint("arm").angle) > 1.0  # the arm swings: the row changes a lot
    meshes = MeshSet(gb)
    data = gb.model.createData()
    # v_k is projected before the solve of step k, onto the row of the flank loaded until then
    # (the step loop starts on flank +1); the solve may switch the flank, and sample k records
    # the new one. With a moving centre the other flank's row is not just −row, so check v_k
    # against the flank of sample k − 1.
    flank_before = np.vstack([np.ones((1, 1)), res.mesh_flank[:-1]])
    assert np.any(flank_before != res.mesh_flank)  # the swing arm does switch flanks
    residual = []
    for k in range(len(res)):
        q, v = res.angle[k], res.speed[k]
        pin.computeJointJacobiansTimeVariation(gb.model, data, q, v)
        meshes.set_velocity(v)
        jac, _ = meshes.combine(meshes.evaluate(gb.model, data), flank_before[k])
        residual.append(np.abs(jac @ v).max())
    # Pitch-line speeds are ~0.6 m/s; rounding leaves ~1e-16 m/s.
    assert_allclose(residual, 0.0, rtol=0, atol=1e-12)
