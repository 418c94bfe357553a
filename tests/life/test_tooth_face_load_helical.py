"""Helical tooth histories of `pinwind fatigue` at the run's peak line load (face_load="run").

The run is ``tests/conftest.two_gear_urdf``'s pair made helical (20/40 teeth, normal module
2 mm, β = ±20° (ε_β = b sin β/(π m_n) = 1.09, the helical stresses' range), face b = 20 mm)
held still with a brake on B, its mesh cut into N = 40 slices of
the constant mean stiffness K (``variation="constant"``: every slice K/N whatever its pairs), g1
with a helix slope deviation f_Hβ = 2 µm. By hand: the mesh carries F = T_B/r_b,B with
r_b,B = z₂ m_n cos α_t/(2 cos β), tan α_t = tan α_n/cos β (ISO 21771); the whole face carries,
so ISO 6336-1's spring bed gives K_Hβ = 1 + f_Hβ K/(2F) (c b = K) and the N slices peak half a
slice in, K_Hβ,N = K_Hβ − (K_Hβ − 1)/N. A helical pair's ISO 6336-2 contact stress goes as
√F_t and its ISO 6336-3 root stress as F_t, so at the peak line load each counted stress is the
even one times √K_Hβ,N (contact) or K_Hβ,N^N_F (root, N_F = (b/h)²/(1 + b/h + (b/h)²),
h = 2.25 m_n), and the Palmgren-Miner damage of N = N0 (s0/s)^m by that ratio to the m-th power.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.life.root_stress import ISO_ROOT_STRESS
from pinwind.life.sn_curve import SNCurve
from pinwind.life.tooth_damage import gear_tooth_damage
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import held_still, two_gear_urdf

K = 1e8  # mean mesh stiffness [N/m]
B = 0.020  # face width [m]
F_HB, SLICES = 2e-6, 40
BETA = math.radians(20.0)
TORQUE_B = 8.0  # brake on B [N·m]
ALPHA_T = math.atan(math.tan(math.radians(20.0)) / math.cos(BETA))
R_BB = 40 * 0.002 * math.cos(ALPHA_T) / (2 * math.cos(BETA))  # base radius of B [m]
F = TORQUE_B / R_BB  # the mesh force along the transverse line of action [N]
CLOSED = 1 + F_HB * K / (2 * F)
K_HB = CLOSED - (CLOSED - 1) / SLICES
B_H = B / (2.25 * 0.002)
N_F = B_H**2 / (1 + B_H + B_H**2)
#: No endurance limit, so that every cycle counts: damage ∝ stress^m.
CURVE = SNCurve(reference_stress=2e9, slope_exponent=8.7, reference_cycles=1e6)


def helical_pair() -> pinwind.Gearbox:
    """β = ±20° at the reference centre distance m_t (z1 + z2)/2, g1 with f_Hβ."""
    text = (
        two_gear_urdf(centre_distance=0.002 / math.cos(BETA) * 30)
        .replace(
            '<gear name="g1" ',
            f'<gear name="g1" helix_angle_deg="20" helix_slope_deviation_um="{F_HB * 1e6!r}" ',
        )
        .replace('<gear name="g2" ', '<gear name="g2" helix_angle_deg="-20" ')
    )
    return loads(text, "helical.urdf")


@pytest.fixture(scope="module")
def sliced():
    gearbox = helical_pair()
    res = held_still(
        gearbox,
        TORQUE_B,
        meshes={
            "m": MeshCompliance(
                mean_stiffness=K, variation="constant", damping_ratio=0.5, slices=SLICES
            )
        },
    )
    return gearbox, res


def test_the_held_helical_run_carries_the_hand_force_at_the_hand_face_load_factor(sliced):
    gearbox, res = sliced
    assert gearbox.meshes[0].path.overlap_ratio >= 1.0
    assert CLOSED < 2.0  # the whole face carries: the closed form holds
    mesh = res.mesh("m")
    assert_allclose(mesh.normal, F, rtol=1e-9)
    assert_allclose(mesh.face_load_factor, K_HB, rtol=1e-6)


@pytest.mark.parametrize("gear", ["g1", "g2"])
@pytest.mark.parametrize(
    ("root", "ratio"),
    [(None, math.sqrt(K_HB)), (ISO_ROOT_STRESS, K_HB**N_F)],
    ids=["contact", "root"],
)
def test_helical_stresses_and_damage_scale_by_the_peak_line_loads_factor(sliced, gear, root, ratio):
    gearbox, res = sliced

    def damage(**options):
        return gear_tooth_damage(
            res, gearbox, gear, curve=CURVE, time_factor=1.0, root_stress=root, **options
        )

    even, peak = damage(), damage(face_load="run")
    assert [d.flank for d in peak] == [d.flank for d in even]
    for e, p in zip(even, peak, strict=True):
        assert np.max(e.peak_stress) > 0.0
        # K_Hβ,N from the run is within 1e-6 of the hand value (the test above).
        assert_allclose(p.peak_stress, e.peak_stress * ratio, rtol=1e-6)
        assert np.max(e.damage) > 0.0
        assert_allclose(p.damage, e.damage * ratio**CURVE.slope_exponent, rtol=1e-5)
