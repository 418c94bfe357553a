"""The line load across the face width against the spring bed's closed forms.

A contact line of stiffness c per unit width behind a gap e(z), pressed by F:
w(z) = c max(0, δ − e(z)), ∫w dz = F. A linear gap F_β z/b: where the whole face carries,
δ = F/(cb) + F_β/2 and w is linear, K_Hβ = 1 + F_β c b/(2F); where it lifts off, the loaded
length ℓ = √(2Fb/(c F_β)) and K_Hβ = √(2 F_β c b/F) (ISO 6336-1's closed form). Crowning C_β:
e = C_β (2z/b − 1)², the parabola; where the whole face carries, δ = F/(cb) + C_β/3; where its
ends lift, the loaded half-width x b/2 with x³ = 3F/(2 c C_β b), w = c C_β (x² − (2z/b − 1)²).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.errors import InputError
from pinwind.gears.face_load import face_load, slice_count
from pinwind.gears.flank_modification import FlankModification
from pinwind.gears.rating_iso import face_load_factor

B = 0.21  # DTU face width [m]
C = 2.0e10  # c_γ [N/m²], 20 N/(mm·µm)
F = 4.0e5  # [N]


def test_no_misalignment_loads_every_slice_alike():
    load = face_load(F, face_width=B, stiffness_per_width=C, slices=17)
    assert_allclose(load.line_load, F / B, rtol=1e-13)
    assert_allclose(load.approach, F / (C * B), rtol=1e-13)
    assert_allclose(load.face_load_factor, 1.0, rtol=1e-13)
    assert_allclose(load.load_centre, B / 2, rtol=1e-13)


def test_a_small_misalignment_loads_the_face_linearly_as_the_closed_form():
    misalignment = 100e-6  # F_β c b / (2F) = 0.525 ≤ 1: the whole face carries
    load = face_load(F, face_width=B, stiffness_per_width=C, misalignment=misalignment, slices=40)
    delta = F / (C * B) + misalignment / 2
    assert_allclose(load.approach, delta, rtol=1e-12)
    assert_allclose(load.line_load, C * (delta - misalignment * load.z / B), rtol=1e-12)
    # The peak at the slice next to side I, half a slice in: K_Hβ of 40 slices.
    closed = 1 + misalignment * C * B / (2 * F)
    assert_allclose(load.face_load_factor, closed - (closed - 1) / 40, rtol=1e-12)
    # ISO's own form, as the rating computes it with c_γβ = 0.85 c_γα.
    assert_allclose(face_load_factor(C / 0.85, misalignment, F / B), closed, rtol=1e-12)
    # Load centre of a trapezoid towards side I.
    w0, w1 = C * delta, C * (delta - misalignment)
    assert_allclose(load.load_centre, B * (w0 + 2 * w1) / (3 * (w0 + w1)), rtol=1e-3)


def test_a_large_misalignment_lifts_part_of_the_face_as_the_closed_form():
    misalignment = 400e-6  # F_β c b/(2F) = 2.1 > 1
    slices = 4000
    load = face_load(F, face_width=B, stiffness_per_width=C, misalignment=misalignment,
                     slices=slices)  # fmt: skip
    loaded = math.sqrt(2 * F * B / (C * misalignment))
    assert loaded < B
    assert_allclose(load.loaded_width, loaded, atol=B / slices)
    analytic = C * np.maximum(0.0, misalignment * (loaded - load.z) / B)
    assert_allclose(load.line_load, analytic, atol=1e-6 * analytic.max())
    assert_allclose(load.face_load_factor, math.sqrt(2 * misalignment * C * B / F), rtol=1e-3)
    assert_allclose(load.force, F, rtol=1e-12)


def test_a_negative_misalignment_loads_side_ii():
    load = face_load(F, face_width=B, stiffness_per_width=C, misalignment=-10e-6, slices=40)
    mirrored = face_load(F, face_width=B, stiffness_per_width=C, misalignment=10e-6, slices=40)
    assert_allclose(load.line_load, mirrored.line_load[::-1], rtol=1e-12)
    assert load.load_centre > B / 2


@pytest.mark.parametrize("crowning", [5e-6, 300e-6])
def test_lead_crowning_leaves_the_parabola(crowning):
    crowned = FlankModification(crowning=crowning)
    slices = 4000
    load = face_load(F, face_width=B, stiffness_per_width=C, slices=slices, gear_1=crowned)
    u = 2 * load.z / B - 1
    if F / (C * B) >= crowning * (1 - 1 / 3):  # the ends still touch (5 µm, not 300 µm)
        delta = F / (C * B) + crowning / 3
        analytic = C * (delta - crowning * u**2)
        assert_allclose(load.line_load, analytic, rtol=1e-6)
    else:
        x = (3 * F / (2 * C * crowning * B)) ** (1 / 3)
        analytic = C * crowning * np.maximum(0.0, x**2 - u**2)
        assert_allclose(load.line_load, analytic, atol=1e-5 * analytic.max())
        assert_allclose(load.face_load_factor, C * crowning * x**2 * B / F, rtol=1e-5)
    assert_allclose(load.load_centre, B / 2, rtol=1e-9)


def test_bad_input_is_refused():
    with pytest.raises(InputError, match="face width"):
        face_load(F, face_width=0.0, stiffness_per_width=C)
    with pytest.raises(InputError, match="slices"):
        face_load(F, face_width=B, stiffness_per_width=C, slices=0)
    with pytest.raises(InputError, match="finite and ≥ 0"):
        face_load(float("nan"), face_width=B, stiffness_per_width=C)


def test_slice_count_resolves_a_tenth_of_the_mean_deflection_and_iso_within_a_tenth():
    """N = ⌈10 F_β/δ_m⌉: the slice width b/N is at most the length b δ_m/(10 F_β) over which
    the gap grows by δ_m/10, one slice fewer is not; K_Hβ of those slices is within a tenth of
    ISO's K_Hβ − 1 where the whole face carries (the peak half a slice in: (K − 1)/N)."""
    delta_m = F / (C * B)  # 95.2 µm
    misalignment = 100e-6  # F_β c b/(2F) = 0.525
    n = slice_count(misalignment, delta_m)
    assert n == 11  # 10 × 100/95.24 = 10.5 → 11
    assert slice_count(misalignment, delta_m, most=8) == 8
    assert B / n <= B * delta_m / (10 * misalignment) < B / (n - 1)
    closed = face_load_factor(C, misalignment, F / B)
    load = face_load(F, face_width=B, stiffness_per_width=C, misalignment=misalignment, slices=n)
    assert abs(load.face_load_factor - closed) <= (closed - 1) / 10
    assert slice_count(0.0, delta_m) == 1  # no misalignment: one contact line
    for bad in ((misalignment, 0.0), (-1e-6, delta_m), (math.nan, delta_m)):
        with pytest.raises(InputError, match="slice_count"):
            slice_count(*bad)
