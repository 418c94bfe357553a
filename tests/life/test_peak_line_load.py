"""The tooth stresses at the run's peak line load (issue 40 item 4, part 2).

The run is ``tests/dynamics/test_sliced_mesh``'s held pair (20/40 teeth, module 2 mm, face
b = 20 mm, constant mesh stiffness K in N = 8 slices, a brake so that the mesh carries
F = T_B/r_b,B) with a helix slope deviation f_Hβ = 2 µm. The whole face carries, so by hand the
approach is δ = F/(c b) + f_Hβ/2 (c = K/b) and the most loaded slice, at z = b/(2N) behind the
gap f_Hβ/(2N), has the line load w_max = c (δ − f_Hβ/(2N)). Its Hertz line contact (Jørgensen
2014 eqs. 20-22, flank radii ρ1 = s and ρ2 = a sin α_w − s at the roll distance s) and ISO
6336-1's K_Fβ = K_Hβ^N_F on the root stress, N_F from b/h with h = 2.25 m_n, by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.life.contact_stress import contact_stress
from pinwind.life.peak_line_load import force_factor
from pinwind.life.root_stress import ISO_ROOT_STRESS
from tests.dynamics.test_sliced_mesh import B, F, K, held, pair

F_HB, SLICES = 2e-6, 8


@pytest.fixture(scope="module")
def run():
    gearbox = pair(helix_slope_deviation=F_HB * 1e6)
    mesh = gearbox.meshes[0]
    return GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec), held(gearbox, SLICES)


def test_the_contact_stress_at_the_runs_peak_line_load_is_the_peak_slices_hertz(run):
    gears, res = run
    c = K / B
    delta = F / (c * B) + F_HB / 2
    w_max = c * (delta - F_HB / (2 * SLICES))
    s = float(res.mesh_contact_position[0, 0])
    rho_1, rho_2 = s, 0.060 * math.sin(math.radians(20.0)) - s
    assert rho_1 > 0 and rho_2 > 0
    m = sum((1 - mat.poisson_ratio**2) / mat.youngs_modulus for mat in gears.materials)
    curvature = 0.5 * (1 / rho_1 + 1 / rho_2)
    a = math.sqrt(2 / math.pi * m / curvature * w_max)
    p_hand = 2 * w_max / (math.pi * a)
    k = res.mesh_face_load_factor[:, 0]
    force = np.abs(res.mesh_normal[:, 0])
    p = contact_stress(
        gears, force=force * force_factor(gears, k, stress="contact"), position=s
    ).p_max
    assert_allclose(p, p_hand, rtol=1e-9)
    # Spread evenly (ISO's K_Hβ = 1, the life code's default) the flank sees √(w_m/w_max) of it.
    even = contact_stress(gears, force=force, position=s).p_max
    assert_allclose(even, p_hand * math.sqrt(F / B / w_max), rtol=1e-9)


def test_the_root_stress_at_the_runs_peak_line_load_takes_iso_k_fbeta(run):
    gears, res = run
    closed = 1 + F_HB * (K / B) * B / (2 * F)
    k_hb = closed - (closed - 1) / SLICES  # the N-slice bed's peak over its mean
    b_h = B / (2.25 * 0.002)
    n_f = b_h**2 / (1 + b_h + b_h**2)
    k = res.mesh_face_load_factor[:, 0]
    s = float(res.mesh_contact_position[0, 0])
    sigma = ISO_ROOT_STRESS.stress(
        gears, 1, force=F * force_factor(gears, k, stress="root"), position=s
    )
    assert_allclose(sigma, ISO_ROOT_STRESS.factor(gears, 1) * F * k_hb**n_f, rtol=1e-9)


def test_an_unloaded_sample_keeps_its_force_and_a_factor_below_one_is_refused(run):
    gears, _ = run
    assert_allclose(force_factor(gears, [0.0, 1.5], stress="contact"), [1.0, 1.5], rtol=0)
    with pytest.raises(InputError, match=r"K_Hβ 0\.5 .*≥ 1"):
        force_factor(gears, [1.2, 0.5], stress="root")
    with pytest.raises(InputError, match='stress = "bending"'):
        force_factor(gears, [1.2], stress="bending")
