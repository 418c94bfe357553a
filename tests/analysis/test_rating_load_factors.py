"""The ISO rating with the run's K_Hβ and the loaded contact's K_Hα (issue 40 item 4).

The run is ``tests/dynamics/test_sliced_mesh``'s: the 20/40 pair of module 2 mm, face 20 mm,
held at rest with a brake on B so that the mesh carries F = T_B / r_b,B, its constant mesh
stiffness K cut into N = 8 slices behind a helix slope deviation f_Hβ = 2 µm (a parallel
misalignment). The whole face carries (F_β c b/(2F) = 0.47 ≤ 1), so ISO 6336-1's closed form
K_Hβ = 1 + F_β c b/(2F) holds for the spring bed, and the sampled bed of N slices peaks half a
slice in: K_Hβ,N = K_Hβ − (K_Hβ − 1)/N. ISO 6336-2 then gives σ_H = Z_B σ_H0 √(K_v K_Hβ) (K_A,
K_γ, K_Hα 1) and ISO 6336-1 K_Fβ = K_Hβ^N_F, N_F = (b/h)²/(1 + b/h + (b/h)²), h = 2.25 m_n.
"""

from __future__ import annotations

import io
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from numpy.testing import assert_allclose
from rich.console import Console

from pinwind.analysis.load_factors import loaded_contact_transverse_factor
from pinwind.analysis.rating import rate
from pinwind.analysis.rating_table import rating_tables
from pinwind.errors import ConflictingInputs, FactorNotInRun, RatingAtZeroSpeed
from pinwind.gears.flank_modification import FlankModification
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.rating_iso import IsoFactors
from tests.conftest import two_gear_urdf
from tests.dynamics.test_sliced_mesh import B, F, K, held, pair

F_HB = 2e-6  # helix slope deviation [m]
SLICES = 8
#: The spring bed's K_Hβ and the N-slice bed's (module docstring).
CLOSED = 1 + F_HB * (K / B) * B / (2 * F)
K_HB = CLOSED - (CLOSED - 1) / SLICES


@pytest.fixture(scope="module")
def sliced():
    gearbox = pair(helix_slope_deviation=F_HB * 1e6)
    return gearbox, held(gearbox, SLICES)


def rated(gearbox, res, **options):
    # The run stands still (a brake against a speed driver at 0): its K_v is 1, and it says so.
    with pytest.warns(RatingAtZeroSpeed):
        return rate(gearbox, res, **options)


def test_the_rating_takes_the_runs_face_load_factor_into_the_contact_stress(sliced):
    assert CLOSED < 2.0  # the whole face carries: the closed form holds
    rating = rated(*sliced, face_load="run-max").meshes[0]
    iso = rating.iso
    f = iso.factors
    assert_allclose(f.K_Hbeta, K_HB, rtol=1e-9)
    # σ_H0, Z_B, Z_D and K_v do not depend on K_Hβ; K_A = K_γ = K_Hα = 1.
    for i, z in enumerate((f.Z_B, f.Z_D)):
        assert_allclose(iso.sigma_H[i], z * iso.sigma_H0 * math.sqrt(f.K_v * K_HB), rtol=1e-9)
    b_h = B / (2.25 * 0.002)
    n_f = b_h**2 / (1 + b_h + b_h**2)
    assert_allclose(f.K_Fbeta, K_HB**n_f, rtol=1e-9)
    assert rating.factor_sources["K_Hbeta"] == "run: mesh_face_load_factor max"


def test_iso_and_run_face_load_factors_scale_the_contact_stress_by_their_square_root(sliced):
    """σ_H ∝ √K_Hβ with the rest fixed: ISO's closed form at F_βy = 10 µm against the run's."""
    iso = rated(*sliced).meshes[0]
    run = rated(*sliced, face_load="run-at").meshes[0]
    ratio = math.sqrt(K_HB / iso.iso.factors.K_Hbeta)
    assert_allclose(np.divide(run.iso.sigma_H, iso.iso.sigma_H), ratio, rtol=1e-9)
    assert iso.factor_sources["K_Hbeta"] == "ISO 6336-1 method C (F_βy = 10 µm)"
    assert run.factor_sources["K_Hbeta"].startswith("run: mesh_face_load_factor at t = ")


def test_the_rating_table_names_each_factors_source(sliced):
    rating = rated(*sliced, face_load="run-max", transverse_load="loaded-contact")
    console = Console(width=80, record=True, file=io.StringIO())
    for table in rating_tables(rating, plain=True):
        console.print(table)
    text = console.export_text()
    assert "run: mesh_face_load_factor max" in text
    assert "loaded contact" in text
    assert f"{K_HB:.4f}" in text
    assert max(len(line) for line in text.splitlines()) <= 80


def test_a_run_without_slices_is_refused_when_asked_for_its_face_load_factor():
    gearbox = pair()
    res = held(gearbox, 1)
    with pytest.raises(FactorNotInRun, match=r'mesh "m".*one contact line.*slices'):
        rate(gearbox, res, face_load="run-max")


def test_a_face_load_factor_given_and_asked_from_the_run_is_refused(sliced):
    with pytest.raises(ConflictingInputs, match="K_Hbeta=1.2"):
        rate(*sliced, iso=IsoFactors(K_Hbeta=1.2), face_load="run-max")


def test_the_rate_command_refuses_a_rigid_run_asked_for_its_face_load_factor(tmp_path):
    model = tmp_path / "pair.urdf"
    model.write_text(two_gear_urdf())
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", str(model), "--torque", "a=4",
         "--torque", "b=-8", "--duration", "0.002", "--dt", "1e-4",
         "--face-load-factor", "run-max"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 2, out.stderr
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len([line for line in lines if "K_Hβ from the run" in line]) == 1
    assert "rigid" in out.stderr and "slices" in out.stderr


def test_the_rate_command_rates_a_logged_sliced_run_with_its_face_load_factor(tmp_path):
    gearbox = pair(helix_slope_deviation=F_HB * 1e6)
    log = tmp_path / "held.mcap"
    held(gearbox, SLICES, log=log)
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "rate", "--from-log", str(log),
         "--face-load-factor", "run-max", "--json"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    mesh = json.loads(out.stdout)["meshes"][0]
    assert_allclose(mesh["iso"]["factors"]["K_Hbeta"], K_HB, rtol=1e-9)
    assert mesh["factor_sources"]["K_Hbeta"] == "run: mesh_face_load_factor max"


def test_tip_relief_leaves_a_spur_pairs_transverse_load_factor_at_one():
    """ε_α < 2: in the single-pair zone one pair carries the whole force, relieved or not."""
    spur = GearPair(teeth_1=20, teeth_2=40, module=0.002, pressure_angle=math.radians(20),
                    face_width=0.02)  # fmt: skip
    assert spur.path.contact_ratio < 2
    relief = FlankModification(tip_relief=10e-6, tip_relief_length=0.8 * spur.path.length / 2)
    for force in (200.0, 2000.0):
        k = loaded_contact_transverse_factor(spur, force, gear_1=relief, gear_2=relief)
        assert_allclose(k, 1.0, rtol=1e-12)
