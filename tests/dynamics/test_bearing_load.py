"""Bearing loads about the bearing axis: radial, axial, tilting; the transmitted torque apart."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import pinwind
from pinwind.dynamics import bearing_load
from tests.conftest import MODELS

#: Saleh 2017's planetary stage held at rest by balanced torques: carrier 1 MN·m, sun −1/6 of it.
CARRIER_TORQUE = 1e6
SUN_TORQUE = -CARRIER_TORQUE / 6.0


def _block(force: list[float], moment: list[float], axis: list[float]):
    """One sample of one bearing ``b`` whose axis in its joint frame is ``axis``."""
    block = SimpleNamespace(
        bearing_names=["b"],
        bearing_force_local=np.array([[force]], dtype=float),
        bearing_moment_local=np.array([[moment]], dtype=float),
    )
    gearbox = SimpleNamespace(joint_axis=lambda name: np.array(axis, dtype=float))
    return block, gearbox


def test_force_splits_into_radial_normal_to_the_axis_and_axial_along_it():
    # F = (3, 4, 12) N: about z, |(3, 4)| = 5 N radial and 12 N axial; about x, the other way.
    block, gb = _block([3.0, 4.0, 12.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(bearing_load.radial_force(block, gb), [[5.0]], rtol=1e-15)
    np.testing.assert_allclose(bearing_load.axial_force(block, gb), [[12.0]], rtol=1e-15)
    block, gb = _block([3.0, 4.0, 12.0], [0.0, 0.0, 0.0], [-1.0, 0.0, 0.0])
    np.testing.assert_allclose(
        bearing_load.radial_force(block, gb), [[np.hypot(4.0, 12.0)]], rtol=1e-15
    )
    np.testing.assert_allclose(bearing_load.axial_force(block, gb), [[-3.0]], rtol=1e-15)


def test_each_bearing_of_each_sample_splits_about_its_own_axis():
    # Two samples of two bearings, about z and about a tilted axis (3, 0, 4)/5: the same force
    # splits differently on each, and the second sample is the first doubled.
    k = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
    force = np.array([[[3.0, 4.0, 12.0], [3.0, 4.0, 12.0]]])
    force = np.concatenate([force, 2.0 * force])
    along = np.array([[12.0, 0.6 * 3.0 + 0.8 * 12.0]])  # F·k per bearing
    across = np.sqrt(13.0**2 - along**2)  # |F| = 13 N
    np.testing.assert_allclose(bearing_load.along_axis(force, k), [along[0], 2.0 * along[0]])
    np.testing.assert_allclose(
        bearing_load.across_axis(force, k), [across[0], 2.0 * across[0]], rtol=1e-14
    )


def test_moment_splits_into_tilting_normal_to_the_axis_and_torque_along_it():
    # M = (6, -8, 500) N·m about y: 500 and 6 tilt it (|(6, 500)|), −8 N·m turns the shaft.
    block, gb = _block([0.0, 0.0, 0.0], [6.0, -8.0, 500.0], [0.0, 1.0, 0.0])
    np.testing.assert_allclose(
        bearing_load.tilting_moment(block, gb), [[np.hypot(6.0, 500.0)]], rtol=1e-15
    )
    np.testing.assert_allclose(bearing_load.transmitted_torque(block, gb), [[-8.0]], rtol=1e-15)


@pytest.fixture(scope="module")
def at_rest():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    res = pinwind.simulate(
        gb, duration=0.01, dt=1e-3, torques={"carrier": CARRIER_TORQUE, "sun": SUN_TORQUE}
    )
    return res


def test_ring_mount_transmits_the_reaction_torque_of_the_stage(at_rest):
    # Moment balance of the stage about its axis: T_ring + T_carrier + T_sun = 0.
    np.testing.assert_allclose(
        at_rest.bearing("ring").torque, -(CARRIER_TORQUE + SUN_TORQUE), rtol=1e-9
    )
    np.testing.assert_allclose(at_rest.bearing("carrier").torque, CARRIER_TORQUE, rtol=1e-9)
    np.testing.assert_allclose(at_rest.bearing("sun").torque, SUN_TORQUE, rtol=1e-9)
    for planet in ("planet1", "planet2", "planet3"):
        np.testing.assert_allclose(at_rest.bearing(planet).torque, 0.0, atol=1e-6)


def test_spur_stage_bearings_carry_no_axial_force_and_no_tilting_moment(at_rest):
    # Spur teeth push in the plane of the gears: nothing along the axes, nothing tilts them.
    np.testing.assert_allclose(at_rest.bearing_axial, 0.0, atol=1e-6)
    np.testing.assert_allclose(at_rest.bearing_tilting, 0.0, atol=1e-6)


def test_radial_and_axial_add_up_to_the_force_and_tilting_and_torque_to_the_moment(at_rest):
    b = at_rest
    np.testing.assert_allclose(
        np.hypot(b.bearing_radial, b.bearing_axial),
        np.linalg.norm(b.bearing_force, axis=-1),
        rtol=1e-12,
    )
    np.testing.assert_allclose(
        np.hypot(b.bearing_tilting, b.bearing_torque),
        np.linalg.norm(b.bearing_moment, axis=-1),
        rtol=1e-12,
    )


def test_export_has_radial_axial_tilting_and_torque_columns_of_every_bearing(tmp_path):
    import csv

    from pinwind.io.export import export_log

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    log = tmp_path / "rest.mcap"
    pinwind.simulate(
        gb, duration=0.01, dt=1e-3, torques={"carrier": CARRIER_TORQUE, "sun": SUN_TORQUE}, log=log
    )
    out = tmp_path / "rest.csv"
    export_log(log, out)
    with open(out, newline="", encoding="utf-8") as f:
        table = list(csv.DictReader(f))
    for name in ("carrier", "planet1", "planet2", "planet3", "ring", "sun"):
        for column in ("radial_N", "axial_N", "tilting_N_m", "torque_N_m"):
            assert f"bearing/{name}/{column}" in table[0], (name, column)
    ring = [float(row["bearing/ring/torque_N_m"]) for row in table]
    np.testing.assert_allclose(ring, -(CARRIER_TORQUE + SUN_TORQUE), rtol=1e-9)


def test_a_log_written_before_the_bearing_loads_were_declared_derives_them_on_read(
    tmp_path, monkeypatch
):
    from pinwind.dynamics import series

    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    log = tmp_path / "older.mcap"
    older = series.current()
    for name in ("bearing_radial", "bearing_axial", "bearing_tilting", "bearing_torque"):
        older = older.without(name)
    # The schema of a run before these were declared; monkeypatch puts the current one back
    # as it was, in its order, for the tests after.
    monkeypatch.setattr(series, "_current", older)
    pinwind.simulate(
        gb, duration=0.01, dt=1e-3, torques={"carrier": CARRIER_TORQUE, "sun": SUN_TORQUE},
        log=log,
    )  # fmt: skip
    monkeypatch.undo()
    back = pinwind.read_log(log)
    np.testing.assert_allclose(
        back.bearing("ring").torque, -(CARRIER_TORQUE + SUN_TORQUE), rtol=1e-9
    )
    np.testing.assert_allclose(
        np.hypot(back.bearing_radial, back.bearing_axial),
        np.linalg.norm(back.bearing_force, axis=-1),
        rtol=1e-12,
    )
    # Streamed in blocks too; and NaN where the inputs were not read.
    from pinwind.io import iter_log

    blocks = list(iter_log(log, block=2))
    np.testing.assert_array_equal(
        np.concatenate([b.bearing_torque for b in blocks]), back.bearing_torque
    )
    alone = pinwind.read_log(log, channels="/bearings/torque")
    assert np.isnan(alone.bearing_torque).all()


def _elementwise(vectors: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """v·k and |v − (v·k) k| by numpy, one operation at a time in the formula's order."""
    k = np.broadcast_to(axes, vectors.shape)
    along = vectors[..., 0] * k[..., 0] + vectors[..., 1] * k[..., 1]
    along = along + vectors[..., 2] * k[..., 2]
    normal = vectors - along[..., None] * k
    square = normal[..., 0] * normal[..., 0] + normal[..., 1] * normal[..., 1]
    square = square + normal[..., 2] * normal[..., 2]
    return along, np.sqrt(square)


def test_the_split_about_the_axis_is_the_elementwise_formula_bit_for_bit():
    # The compiled split of a block's reaction equals numpy's element-wise v·k and
    # |v − (v·k) k| to the last bit (zeros of either sign, 1e-300 and 1e6 scales, axes along
    # the frame of either sign and tilted ones, a strided view of a block), and |v × k|
    # (a cross product, computed apart) to rounding.
    rng = np.random.default_rng(37)
    block = rng.normal(size=(400, 6, 3)) * 10.0 ** rng.uniform(-3.0, 6.0, size=(400, 6, 3))
    block[::7, :, 2] = 0.0
    block[::5, :, 0] = -0.0
    block[::11] *= 1e-300
    vectors = block[:, 1:, :]  # not contiguous
    tilt = np.array([0.6, 0.0, 0.8])
    for j in range(3):
        axes = np.zeros((5, 3))
        axes[:4, j] = [1.0, -1.0, 1.0, -1.0]
        axes[4] = tilt
        along, across = _elementwise(vectors, axes)
        bits = np.uint64
        assert np.array_equal(bearing_load.along_axis(vectors, axes).view(bits), along.view(bits))
        assert np.array_equal(bearing_load.across_axis(vectors, axes).view(bits), across.view(bits))
        cross = np.linalg.norm(np.cross(vectors, axes), axis=-1)
        np.testing.assert_allclose(bearing_load.across_axis(vectors, axes), cross, rtol=1e-15)
        dot = np.einsum("sbi,bi->sb", vectors, axes)  # a product of its own
        off = np.abs(bearing_load.along_axis(vectors, axes) - dot)
        assert np.all(off <= 1e-15 * np.linalg.norm(vectors, axis=-1))


def test_a_non_finite_component_gives_nan_with_axes_along_the_frame_as_in_general():
    # The general formula multiplies every component by the axis: ∞ anywhere gives NaN.
    vectors = np.array([[[3.0, 4.0, np.inf], [np.inf, 4.0, 0.0], [3.0, 4.0, 12.0]]])
    axes = np.array([[0.0, 0.0, 1.0]] * 3)
    with np.errstate(invalid="ignore"):  # ∞ · 0 in the general formula
        across = bearing_load.across_axis(vectors, axes)
    np.testing.assert_array_equal(np.isnan(across), [[True, True, False]])
