"""The loaded static transmission error against hand solutions of the tooth-pair springs.

On the DTU sun–planet pair (Jørgensen 2014: ε_α 1.47): ISO 6336-1's pair stiffness is c′ b in
the single-pair zone and 0.875 c′ b per pair in the double-pair zones (`pair_stiffness_along_
path`), so an unmodified pair's TE is F/(c′b) there and F/(1.75 c′b) here. With linear "long"
tip relief on both gears (each over the double-pair zone, L = g_α − p_bt) the two pairs in a
double zone sit at complementary points of the two reliefs, their gaps adding to C_a, so with
both in contact 1.75 k δ = F + 0.875 k C_a: the TE's peak-to-peak is |F/k − F/(1.75k) − C_a/2|
= |3F/(7k) − C_a/2|, zero at the design load F* = 7 k C_a / 6 and growing linearly on either
side (the V of the Harris map).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.errors import InputError
from pinwind.gears.flank_modification import FlankModification, lead_gap, profile_gap
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import contact_line_pair_stiffness, mesh_stiffness
from pinwind.gears.transmission_error import static_transmission_error, transmission_error_map
from tests.conftest import dtu_pairs

SUN_PLANET = dtu_pairs()[0]
#: A round c′ b [N/m], so the hand numbers below are simple.
K = 1.0e10
FORCE = 2.0e5


def long_relief(amount: float, pair: GearPair = SUN_PLANET) -> FlankModification:
    return FlankModification(
        tip_relief=amount, tip_relief_length=pair.path.length - pair.path.base_pitch
    )


def test_an_unmodified_spur_pair_lags_by_the_force_over_the_stiffness_of_the_pairs_in_contact():
    te = static_transmission_error(SUN_PLANET, FORCE, single_pair=K, positions=200)
    path = SUN_PLANET.path
    single = (te.roll >= path.single_start) & (te.roll <= path.single_end)
    assert single.any() and (~single).any()
    expected = np.where(single, FORCE / K, FORCE / (1.75 * K))
    assert_allclose(te.approach, expected, rtol=1e-13)
    assert_allclose(te.pair_forces.sum(axis=1), FORCE, rtol=1e-13)
    assert_allclose(te.peak_to_peak, FORCE / K * (1 - 1 / 1.75), rtol=1e-13)


@pytest.mark.parametrize("load_ratio", [0.8, 1.0, 1.3])
def test_long_linear_tip_relief_flattens_the_te_at_its_design_load_and_opens_a_v_around_it(
    load_ratio,
):
    relief = 40e-6
    design = 7.0 * K * relief / 6.0
    force = load_ratio * design
    mod = long_relief(relief)
    te = static_transmission_error(SUN_PLANET, force, gear_1=mod, gear_2=mod, single_pair=K)
    # Every pair stays in contact at these loads: 1.75 k δ ≥ ... (δ in the double zones ≥ C_a).
    assert (force / (1.75 * K) + relief / 2) >= relief
    assert_allclose(te.peak_to_peak, abs(3 * force / (7 * K) - relief / 2), atol=1e-12)
    unmodified = static_transmission_error(SUN_PLANET, force, single_pair=K)
    if load_ratio == 1.0:
        assert te.peak_to_peak < 1e-6 * unmodified.peak_to_peak


def test_the_harris_map_is_a_v_with_its_minimum_at_the_design_load():
    relief = 30e-6
    design = 7.0 * K * relief / 6.0
    forces = design * np.array([0.9, 0.95, 1.0, 1.05, 1.1])
    mod = long_relief(relief)
    maps = transmission_error_map(SUN_PLANET, forces, gear_1=mod, gear_2=mod, single_pair=K)
    ptp = np.array([m.peak_to_peak for m in maps])
    assert_allclose(ptp, np.abs(3 * forces / (7 * K) - relief / 2), atol=1e-12)
    assert np.argmin(ptp) == 2


def test_a_relieved_pair_entering_contact_carries_what_its_gap_leaves_it():
    # One roll position in the double zone [0, B): the entering pair (gear 2's tip relief)
    # and the leaving pair (gear 1's tip relief), each k (δ − gap) by hand.
    relief = 25e-6
    mod = long_relief(relief)
    te = static_transmission_error(
        SUN_PLANET, FORCE, gear_1=mod, gear_2=mod, single_pair=K, positions=64
    )
    path = SUN_PLANET.path
    length = path.length - path.base_pitch
    m = np.flatnonzero(te.roll < path.single_start)[3]
    y = te.roll[m]
    entering = relief * (length - y) / length  # gear 2's tip: C_a at A, 0 at B
    leaving = relief * (y + path.base_pitch - path.single_end) / length  # gear 1's tip from D
    assert_allclose(entering + leaving, relief, rtol=1e-12)
    delta = (FORCE + 0.875 * K * relief) / (1.75 * K)
    assert_allclose(te.approach[m], delta, rtol=1e-12)
    loaded = te.pair_forces[m][te.pair_forces[m] > 0]
    assert_allclose(
        np.sort(loaded), np.sort(0.875 * K * (delta - np.array([entering, leaving]))), rtol=1e-10
    )


def test_a_light_load_leaves_the_deep_relief_without_contact():
    relief = 40e-6
    mod = long_relief(relief)
    force = 0.1 * K * relief
    te = static_transmission_error(SUN_PLANET, force, gear_1=mod, gear_2=mod, single_pair=K)
    # Where only the pair in its unmodified middle carries: δ = F/k (single zone); near A the
    # entering pair, gap C_a(1 − y/L), does not touch while δ stays below it.
    path = SUN_PLANET.path
    single = (te.roll > path.single_start) & (te.roll < path.single_end)
    assert_allclose(te.approach[single], force / K, rtol=1e-13)
    assert np.all(np.count_nonzero(te.pair_forces[~single] > 0, axis=1) >= 1)
    assert te.approach.max() <= relief


def test_profile_relief_gaps_by_hand():
    g = SUN_PLANET.path.length
    linear = FlankModification(tip_relief=20e-6, tip_relief_length=4e-3)
    parabolic = FlankModification(
        tip_relief=20e-6, tip_relief_length=4e-3, root_relief=5e-6, root_relief_length=2e-3,
        relief_shape="parabolic",
    )  # fmt: skip
    none = FlankModification()
    y = np.array([0.0, 1e-3, g - 4e-3, g - 1e-3, g])
    assert_allclose(profile_gap(linear, none, g, y), [0, 0, 0, 15e-6, 20e-6], atol=1e-18)
    assert_allclose(profile_gap(none, linear, g, y), [20e-6, 15e-6, 0, 0, 0], atol=1e-18)
    # Gear 1 parabolic: tip 20 µm (u/L)² near E, root 5 µm (u/L)² near A.
    assert_allclose(
        profile_gap(parabolic, none, g, y),
        [5e-6, 5e-6 * 0.25, 0, 20e-6 * (3 / 4) ** 2, 20e-6],
        atol=1e-18,
    )


def test_lead_crowning_end_relief_and_slope_by_hand():
    b = 0.2
    crowned = FlankModification(crowning=10e-6)
    ends = FlankModification(end_relief=8e-6, end_relief_length=0.02, helix_slope_deviation=6e-6)
    z = np.array([0.0, 0.01, 0.05, 0.1, 0.19, 0.2])
    assert_allclose(lead_gap(crowned, FlankModification(), b, z),
                    10e-6 * (2 * z / b - 1) ** 2, atol=1e-18)  # fmt: skip
    assert_allclose(
        lead_gap(FlankModification(), ends, b, z),
        [8e-6, 4e-6 + 0.3e-6, 1.5e-6, 3e-6, 4e-6 + 5.7e-6, 8e-6 + 6e-6],
        atol=1e-15,
    )


def test_helical_slices_sum_to_the_contact_line_stiffness_and_carry_the_force():
    helical = GearPair(
        23, 91, module=8e-3, pressure_angle=math.radians(20), face_width=0.2,
        helix_angle=math.radians(10),
    )  # fmt: skip
    te = static_transmission_error(helical, FORCE, slices=400, positions=50)
    y, k = contact_line_pair_stiffness(helical.path, mesh_stiffness(helical))
    # No modification: δ = F / Σ_j k(y + j p_bt) with the trapezoid of the contact line.
    total = sum(np.interp(te.roll + o, y, k, left=0, right=0) for o in te.offsets)
    assert_allclose(te.approach, FORCE / total, rtol=2e-3)  # slices resolve the trapezoid's ends
    assert_allclose(te.pair_forces.sum(axis=1), FORCE, rtol=1e-12)


def test_a_helical_pair_with_a_whole_overlap_ratio_has_a_flat_te():
    # ε_β = b sin β/(π m_n) = 1: the total contact-line length is the same at every roll
    # position, so is the mesh stiffness and the TE (to the slices' resolution of the lines).
    beta = math.radians(10)
    helical = GearPair(
        23, 91, module=8e-3, pressure_angle=math.radians(20),
        face_width=math.pi * 8e-3 / math.sin(beta), helix_angle=beta,
    )  # fmt: skip
    assert_allclose(helical.path.overlap_ratio, 1.0, rtol=1e-12)
    te = static_transmission_error(helical, FORCE, slices=2000, positions=40)
    assert te.peak_to_peak < 2e-3 * te.mean
    # The stiffness the mean holds: ISO's c_γα b, the mean mesh stiffness.
    assert_allclose(te.mean, FORCE / mesh_stiffness(helical), rtol=2e-3)


def test_harmonics_of_a_square_wave_te():
    te = static_transmission_error(SUN_PLANET, FORCE, single_pair=K, positions=1000)
    path = SUN_PLANET.path
    duty = (path.single_end - path.single_start) / path.base_pitch  # share of the single zone
    step = FORCE / K - FORCE / (1.75 * K)
    # A pulse of height h over a share d of the period: the h-th harmonic 2h|sin(πnd)|/(πn).
    n = np.arange(1, 4)
    assert_allclose(te.harmonics(3), 2 * step * np.abs(np.sin(np.pi * n * duty)) / (np.pi * n),
                    rtol=1e-2)  # fmt: skip


def test_bad_input_is_refused():
    with pytest.raises(InputError, match="finite and ≥ 0"):
        static_transmission_error(SUN_PLANET, -1.0)
    with pytest.raises(InputError, match="at least 4"):
        static_transmission_error(SUN_PLANET, 1.0, positions=2)
    with pytest.raises(InputError, match="tip_relief_length"):
        FlankModification(tip_relief=1e-5)
    with pytest.raises(InputError, match="≥ 0"):
        FlankModification(crowning=-1e-6)
    with pytest.raises(InputError, match="relief_shape"):
        FlankModification(relief_shape="circular")
