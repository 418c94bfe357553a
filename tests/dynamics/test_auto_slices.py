"""``slices="auto"``: the run cuts a compliant mesh into the rule's N slices, N = ⌈10 F_β/δ_m⌉.

The pair is ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm) with a constant mean
mesh stiffness K = 1e8 N/m given in the file, g1 with a helix slope deviation f_Hβ. By hand:
F_β = |f_Hβ| + 10 µm (the rating's default F_βy for what the file does not give), δ_m =
w b/K at the line load w = 100 N/mm, N = ⌈10 F_β/δ_m⌉. Held still with a brake on B, the run's
K_Hβ then is ISO 6336-1's closed form 1 + f_Hβ K/(2F) less (K_Hβ − 1)/N (the spur law of
N slices, test_sliced_mesh.py), which only the N slices built give.
"""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import InputError
from pinwind.gears.face_load import expected_misalignment
from pinwind.gears.flank_modification import FlankModification
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import held_still, two_gear_urdf

K = 1e8  # mean mesh stiffness [N/m]
TORQUE_B = 8.0  # brake on B [N·m]
F = TORQUE_B / (40 * 0.002 * math.cos(math.radians(20.0)) / 2)  # the mesh force [N], 212.8
F_HB = 2e-6  # g1's helix slope deviation [m]


def auto_text(face_width_mm: float, slices: str = "auto") -> str:
    """The pair's model file: both gears face_width_mm wide, a compliant mesh cut by ``slices``."""
    return (
        two_gear_urdf()
        .replace('face_width_mm="20"', f'face_width_mm="{face_width_mm!r}"')
        .replace('<gear name="g1" ', f'<gear name="g1" helix_slope_deviation_um="{F_HB * 1e6!r}" ')
        .replace(
            '<mesh name="m" ',
            f'<mesh name="m" type="compliant" mean_stiffness="{K!r}" '
            f'stiffness_variation="constant" damping_ratio="0.5" slices="{slices}" ',
        )
    )


def held(gearbox: pinwind.Gearbox):
    """A held by a speed driver at rest, B braked, from the static deflection: 20 steps."""
    return held_still(gearbox, TORQUE_B)


@pytest.mark.parametrize("face_width_mm, slices", [(20.0, 6), (50.0, 3)])
def test_auto_slices_are_the_rule_by_hand_and_load_the_face_as_n_slices(face_width_mm, slices):
    b = face_width_mm * 1e-3
    misalignment = F_HB + 10e-6
    deflection = 100e3 * b / K
    assert slices == math.ceil(10 * misalignment / deflection)  # 6 (12/2), 3 (12/5)
    res = held(loads(auto_text(face_width_mm), "auto.urdf"))
    meta = res.metadata["meshes"]["m"]
    assert meta["slices"] == slices
    assert_allclose(meta["slice_rule"]["misalignment"], misalignment, rtol=1e-12)
    assert_allclose(meta["slice_rule"]["deflection"], deflection, rtol=1e-12)
    mesh = res.mesh("m")
    closed = 1 + F_HB * K / (2 * F)  # c b = K whatever b: the same closed form at both widths
    assert closed < 2.0
    assert_allclose(mesh.normal, F, rtol=1e-9)
    assert_allclose(mesh.face_load_factor, closed - (closed - 1) / slices, rtol=1e-6)


def test_the_expected_misalignment_takes_crowning_at_its_steepest():
    """Crowning C_β (2z/b − 1)² has slope 4 C_β/b at the ends, where f_Hβ's adds; the steepest
    chord of 2000 across the face is 4 C_β (1 − 1/2000) + f_Hβ, plus 10 µm."""
    crown, f_hb, b = 3e-6, 2e-6, 0.03
    got = expected_misalignment(
        FlankModification(helix_slope_deviation=f_hb), FlankModification(crowning=crown), b
    )
    assert_allclose(got, 4 * crown * (1 - 1 / 2000) + f_hb + 10e-6, rtol=1e-9)
    with pytest.raises(InputError, match="face width 0.0 m"):
        expected_misalignment(FlankModification(), FlankModification(), 0.0)


def test_pinwind_info_names_the_slices_the_rule_gives(tmp_path):
    path = tmp_path / "auto.urdf"
    path.write_text(auto_text(20.0))
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "info", str(path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert 'compliant, 6 slices (slices="auto"' in out.stdout
    assert "F_β = 12 µm, δ_m = 20 µm at 100 N/mm" in out.stdout


@pytest.mark.parametrize("slices", ["0", "several"])
def test_a_bad_slice_count_exits_2_with_one_line(tmp_path, slices):
    path = tmp_path / "bad.urdf"
    path.write_text(auto_text(20.0, slices))
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "info", str(path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    assert "whole number ≥ 1" in out.stderr and '"auto"' in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_the_python_api_takes_auto_slices_per_run():
    """MeshCompliance(slices="auto") in ``meshes=`` resolves as the model file's attribute."""
    text = two_gear_urdf().replace(
        '<gear name="g1" ', f'<gear name="g1" helix_slope_deviation_um="{F_HB * 1e6!r}" '
    )
    res = held_still(
        loads(text, "pair.urdf"),
        TORQUE_B,
        meshes={
            "m": MeshCompliance(
                mean_stiffness=K, variation="constant", damping_ratio=0.5, slices="auto"
            )
        },
    )
    assert res.metadata["meshes"]["m"]["slices"] == 6  # b = 20 mm: ⌈10 · 12/20⌉
