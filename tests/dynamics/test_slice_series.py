"""The line load of each slice of a sliced mesh (``slice_line_load``), against the spring bed.

The pair of ``tests/dynamics/test_sliced_mesh.py`` (20/40 teeth, b = 20 mm, constant mesh
stiffness K, N slices of K/N at z_s), held still with a brake on B, its gear g1 carrying a helix
slope deviation f_Hβ: a lead gap e(z) = f_Hβ z/b growing linearly from side I, as a parallel
misalignment of the axes in the plane of action leaves (ISO 6336-1's F_β). The slices are then
the spring bed of ``spring_bed``: slice s carries F_s = (K/N) max(0, δ − e_s) with Σ F_s = F, and
its line load is w_s = F_s/(b/N). Where the whole face carries, δ = F/K + f_Hβ/2 (the mean gap
at the slice centres) and w_s = c (δ − f_Hβ z_s/b), c = K/b: ISO 6336-1's linear distribution
sampled at the slice centres.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import pinwind
from pinwind.errors import InputError
from pinwind.io.export import export_log
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf
from tests.dynamics.test_sliced_mesh import TORQUE_B, B, F, K, held, pair, spring_bed


def slice_centres(n: int) -> np.ndarray:
    """z of each slice's centre from side I [m] (equal slices b/N)."""
    return (np.arange(n) + 0.5) * B / n


def test_each_slice_carries_the_linear_distribution_at_its_centre():
    """f_Hβ = 2 µm, F_β c b/(2F) = 0.47 < 1: every slice carries, w_s = c (F/(cb) + f_Hβ/2 −
    f_Hβ z_s/b); the slice columns are named by mesh and index, with their face positions."""
    f_hb, n = 2e-6, 8
    res = held(pair(helix_slope_deviation=f_hb * 1e6), n)
    z = slice_centres(n)
    c = K / B
    w = c * (F / (c * B) + f_hb / 2 - f_hb * z / B)
    assert 0 < w.min() < 0.5 * w.max()  # the whole face carries, unevenly
    assert res.slice_names == [f"m.{j}" for j in range(n)]
    positions, line_load = res.slice_line_loads("m")
    assert_allclose(positions, z - B / 2, rtol=0, atol=1e-15)
    assert line_load.shape == (len(res), n)
    assert_allclose(line_load, np.broadcast_to(w, line_load.shape), rtol=1e-9)
    # side I (z = 0, where the gap is closed) carries most
    assert np.all(np.argmax(line_load, axis=1) == 0)


def test_slices_that_lift_off_read_zero_and_the_others_the_spring_bed():
    """f_Hβ = 20 µm, F_β c b/(2F) = 4.7 > 1: the slices beyond the loaded length carry nothing
    and read exactly 0; the loaded ones N F_s / b of the spring bed by hand."""
    f_hb, n = 20e-6, 40
    res = held(pair(helix_slope_deviation=f_hb * 1e6), n)
    _, slice_force = spring_bed(f_hb * slice_centres(n) / B, F)
    lifted = slice_force == 0.0
    assert 0 < np.count_nonzero(~lifted) < n // 2
    _, line_load = res.slice_line_loads("m")
    assert np.all(line_load[:, lifted] == 0.0)
    expected = slice_force[~lifted] * n / B
    assert_allclose(line_load[:, ~lifted], np.broadcast_to(expected, (len(res), expected.size)),
                    rtol=1e-9)  # fmt: skip


def turning(n: int, f_hb_um: float = 6.0, **kwargs) -> pinwind.Result:
    """The pair turning under balanced torques from the undeflected pose: the mesh rings, its
    slices lift and land (a helix slope deviation of 6 µm), 400 steps."""
    return pinwind.simulate(
        pair(helix_slope_deviation=f_hb_um),
        duration=4e-3,
        dt=1e-5,
        initial_speeds={"a": 20.0},
        torques={"b": TORQUE_B, "a": TORQUE_B / 2},
        gravity=np.zeros(3),
        initial_deflection="none",
        meshes={
            "m": MeshCompliance(
                mean_stiffness=K, variation="constant", damping_ratio=0.02, slices=n, backlash=5e-5
            )
        },
        **kwargs,
    )


def test_peak_and_mean_line_loads_are_the_max_and_mean_of_the_slices_and_sum_to_the_force():
    """On a run whose slices lift and land: mesh_peak_line_load is the largest slice column,
    mesh_mean_line_load their width-weighted mean Σ w_s (b/N) / b, and Σ w_s (b/N) is the mesh
    normal force (1e-12)."""
    n = 6
    res = turning(n)
    mesh = res.mesh("m")
    _, w = res.slice_line_loads("m")
    lifted = (w == 0.0) & (mesh.normal > 0.0)[:, None]
    assert lifted.any() and (~lifted & (w > 0)).any()  # some slices lift while others carry
    scale = np.max(mesh.normal) / B
    width = np.full(n, B / n)
    assert_allclose(mesh.peak_line_load, w.max(axis=1), rtol=1e-12, atol=0)
    assert_allclose(mesh.mean_line_load, (w @ width) / B, rtol=0, atol=1e-12 * scale)
    assert_allclose(w @ width, mesh.normal, rtol=0, atol=1e-12 * scale * B)
    loaded = mesh.normal > 0
    ratio = mesh.peak_line_load[loaded] / mesh.mean_line_load[loaded]
    assert_allclose(mesh.face_load_factor[loaded], ratio, rtol=1e-12)


def three_shafts() -> pinwind.Gearbox:
    """The pair and a third shaft c at 120 mm with a 20-tooth gear g3 meshing g2 (mesh m2);
    g1 and g3 carry helix slope deviations of 2 and 3 µm."""
    text = two_gear_urdf().replace(
        '  <joint name="a" ',
        """  <link name="c">
    <inertial><mass value="1.0"/>
      <inertia ixx="0.001" iyy="0.001" izz="0.0015" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="c" type="continuous">
    <parent link="housing"/><child link="c"/>
    <origin xyz="0.12 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="a" """,
    )
    text = text.replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        '<gear name="g3" link="c" teeth="20" module_mm="2" face_width_mm="20" '
        'helix_slope_deviation_um="3"/>\n    <mesh name="m" gear1="g1" gear2="g2"/>\n'
        '    <mesh name="m2" gear1="g2" gear2="g3"/>',
    )
    text = text.replace('<gear name="g1" ', '<gear name="g1" helix_slope_deviation_um="2" ')
    return loads(text, "three.urdf")


def test_two_sliced_meshes_each_have_their_own_columns_in_mesh_order():
    """m in 3 slices, m2 in 5, a held, a brake T_c = 2 N·m on c, b free: both meshes carry
    F = T_c / r_b,c (b's two gears have one base radius). The slice family is m's 3 columns,
    then m2's 5, each mesh's the spring bed of its own gaps: f_Hβ z/b on the front flank,
    f_Hβ (1 − z/b) on the back (``compliant.slice_tables``), on the flank it loads (both ≥ 0:
    without backlash the other flank opens)."""
    r_bc = 20 * 0.002 * math.cos(math.radians(20.0)) / 2
    force = 2.0 / r_bc
    common = dict(duration=2e-4, dt=1e-5, speeds={"a": 0.0}, torques={"c": 2.0},
                  gravity=np.zeros(3), initial_deflection="static")  # fmt: skip

    def compliance(n: int) -> MeshCompliance:
        return MeshCompliance(mean_stiffness=K, variation="constant", damping_ratio=0.5, slices=n)

    res = pinwind.simulate(three_shafts(), meshes={"m": compliance(3), "m2": compliance(5)},
                           **common)  # fmt: skip
    assert res.slice_names == [*(f"m.{j}" for j in range(3)), *(f"m2.{j}" for j in range(5))]
    assert res.slice_line_load.shape == (len(res), 8)
    for mesh, n, f_hb in (("m", 3, 2e-6), ("m2", 5, 3e-6)):
        positions, w = res.slice_line_loads(mesh)
        assert_allclose(positions, slice_centres(n) - B / 2, rtol=0, atol=1e-15)
        assert_allclose(res.mesh(mesh).normal, force, rtol=1e-9)
        z = slice_centres(n)
        gap = f_hb * z / B if res.mesh(mesh).flank[-1] > 0 else f_hb * (1 - z / B)
        _, slice_force = spring_bed(gap, force)
        assert_allclose(w, np.broadcast_to(slice_force * n / B, w.shape), rtol=1e-9)
    one = pinwind.simulate(three_shafts(), meshes={"m": compliance(1), "m2": compliance(4)},
                           **common)  # fmt: skip
    assert one.slice_names == [f"m2.{j}" for j in range(4)]
    with pytest.raises(InputError, match='mesh "m" has no slices'):
        one.slice_line_loads("m")


def test_an_unsliced_run_has_no_slice_columns():
    res = turning(1)
    assert res.slice_names == [] and res.slice_line_load.shape == (len(res), 0)
    assert "slice_positions" not in res.metadata["meshes"]["m"]


def test_the_slice_series_survives_the_log_round_trip_bit_for_bit(tmp_path):
    path = tmp_path / "sliced.mcap"
    res = turning(5, log=path)
    back = pinwind.read_log(path)
    assert back.slice_names == res.slice_names == [f"m.{j}" for j in range(5)]
    assert_array_equal(back.slice_line_load.view(np.uint64), res.slice_line_load.view(np.uint64))
    positions, w = back.slice_line_loads("m")
    assert_array_equal(positions, res.slice_line_loads("m")[0])
    assert_array_equal(w, res.slice_line_load)
    # exported: a column per slice, named by mesh and index, to the bit
    rows, _ = export_log(path, tmp_path / "sliced.parquet")
    table = pq.read_table(tmp_path / "sliced.parquet")
    assert rows == len(res)
    for j in range(5):
        column = table.column(f"slice/m.{j}/line_load_N_m").to_numpy()
        assert_array_equal(column.view(np.uint64), res.slice_line_load[:, j].view(np.uint64))


def test_a_log_written_before_the_slice_family_reads_with_no_slice_columns():
    """A format-2 log (no slice names in its model record): the family has no element, so the
    series is (samples, 0), as a run without sliced meshes; its absent mesh series read NaN."""
    old = Path(__file__).parents[1] / "io" / "data" / "planetary_format2.mcap"
    back = pinwind.read_log(old)
    assert back.slice_names == [] and back.slice_line_load.shape == (len(back), 0)
    assert np.isnan(back.mesh_peak_line_load).all()
