"""K_Hα > 1 from the loaded contact, against a closed form (ISO 6336-1 §8's definition).

A helical 20/40 pair, normal module 2 mm, α_n = 20°, β = 20°, its face b = π m_n/sin β so that
the overlap ratio ε_β = b sin β/(π m_n) is exactly 1: a pair's contact line crosses the face
while the pairs roll one base pitch. In face-width units ζ = z/b from side I, the pair whose
front-section roll is v base pitches from A touches the sections ζ ∈ [v − ε_α, v] ∩ [0, 1], and
every unit of its line carries the same stiffness, so with the pairs at v = u, u + 1, u + 2 the
total line is ε_α whatever u. Ideal flanks share F by length: the pair spanning the whole face
carries the most, F/ε_α.

A helix slope deviation f_Hβ on gear 1 opens the gap f_Hβ ζ towards side II. With the whole face
carrying (δ > f_Hβ), each pair carries k (δ L − f_Hβ M) over its segment (L its length, M = ∫ζ),
k = c̄/ε_α per unit ζ (c̄ the mean mesh stiffness), and Σ = F fixes δ = (F/k + f_Hβ ΣM)/ε_α. The
most loaded pair over the cycle is the whole-face pair at u → 0, when the third pair sits at
side II on [2 − ε_α, 1] (ΣM = ½ + ½ (1 − (2 − ε_α)²), largest there; the pair on [0, u] at
u → 1 carries the same): k (δ − f_Hβ/2). Over the ideal's F/ε_α,

    K_Hα = 1 + c̄ f_Hβ (ε_α − 1)(2 − ε_α) / (2 ε_α F).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.analysis.load_factors import loaded_contact_transverse_factor
from pinwind.analysis.rating import rate
from pinwind.errors import RatingAtZeroSpeed
from pinwind.gears.flank_modification import FlankModification
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import mesh_stiffness
from pinwind.gears.transmission_error import static_transmission_error
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

BETA = math.radians(20.0)
M_N = 0.002
B = math.pi * M_N / math.sin(BETA)  # ε_β = 1 [m]
PAIR = GearPair(
    teeth_1=20, teeth_2=40, module=M_N, pressure_angle=math.radians(20.0), face_width=B,
    helix_angle=BETA,
)  # fmt: skip


def closed_form(force: float, f_hb: float) -> float:
    """K_Hα of the module docstring."""
    eps = PAIR.path.contact_ratio
    return 1 + mesh_stiffness(PAIR) * f_hb * (eps - 1) * (2 - eps) / (2 * eps * force)


@pytest.mark.parametrize(("force", "f_hb"), [(2000.0, 5e-6), (2000.0, 2e-6), (5000.0, 5e-6)])
def test_a_helix_slope_deviation_raises_k_h_alpha_as_the_closed_form(force, f_hb):
    """Measured: within 6.4e-5 of K_Hα − 1 (40 slices, 256 roll positions)."""
    assert_allclose(PAIR.path.overlap_ratio, 1.0, rtol=1e-12)
    assert 1.0 < PAIR.path.contact_ratio < 2.0
    modification = FlankModification(helix_slope_deviation=f_hb)
    te = static_transmission_error(PAIR, force, gear_1=modification, positions=256)
    assert np.min(te.approach) > f_hb  # the whole face carries: the closed form holds
    got = loaded_contact_transverse_factor(PAIR, force, gear_1=modification)
    want = closed_form(force, f_hb)
    assert want > 1.02
    assert_allclose(got - 1, want - 1, rtol=1e-3)


def test_the_rating_of_a_run_takes_k_h_alpha_of_its_force_from_the_loaded_contact():
    """The pair held still, B braked by T_B: the rating's force is the run's, F = T_B/r_b,B
    (r_b,B = z₂ m_n cos α_t/(2 cos β), tan α_t = tan α_n/cos β), its K_Hα and K_Fα the closed
    form's at that force, with g1's f_Hβ read from the model file."""
    f_hb, torque = 5e-6, 80.0
    alpha_t = math.atan(math.tan(math.radians(20.0)) / math.cos(BETA))
    force = torque / (40 * M_N * math.cos(alpha_t) / (2 * math.cos(BETA)))
    text = (
        two_gear_urdf(centre_distance=M_N / math.cos(BETA) * 30)
        .replace('face_width_mm="20"', f'face_width_mm="{B * 1e3!r}"')
        .replace(
            '<gear name="g1" ',
            f'<gear name="g1" helix_angle_deg="20" helix_slope_deviation_um="{f_hb * 1e6!r}" ',
        )
        .replace('<gear name="g2" ', '<gear name="g2" helix_angle_deg="-20" ')
    )
    gearbox = loads(text, "helical.urdf")
    res = pinwind.simulate(
        gearbox,
        duration=2e-3,
        dt=1e-4,
        speeds={"a": 0.0},
        torques={"b": torque},
        gravity=np.zeros(3),
    )
    assert_allclose(res.mesh("m").normal[-1], force, rtol=1e-9)
    with pytest.warns(RatingAtZeroSpeed):
        rating = rate(gearbox, res, transverse_load="loaded-contact")
    factors = rating.meshes[0].iso.factors
    want = closed_form(force, f_hb)
    assert_allclose(factors.K_Halpha - 1, want - 1, rtol=1e-3)
    assert factors.K_Falpha == factors.K_Halpha
    assert rating.meshes[0].factor_sources["K_Halpha"].startswith("loaded contact")
