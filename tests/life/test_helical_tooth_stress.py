"""Tooth stresses of helical pairs from the mesh force (ISO 6336-2/-3), one cycle per tooth pass,
against the standard's formulas worked here, its static rating, the spur limit and Miner by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.materials import MATERIALS
from pinwind.gears.rating_iso import IsoFactors, form_factors, iso_rating
from pinwind.life.contact_stress import contact_stress, helical_contact_stress
from pinwind.life.root_stress import ISO_ROOT_STRESS, table_root_stress
from pinwind.life.sn_curve import SNCurve
from pinwind.life.tooth_damage import (
    HelicalContacts,
    ToothContacts,
    entering_teeth,
    gear_tooth_damage,
    histories_damage,
    mesh_teeth,
    tooth_histories,
)
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

STEEL = MATERIALS["18CrNiMo7-6"]
ALPHA_N = math.radians(20.0)
#: Every load factor of the rating 1: the nominal stresses of the standard.
UNIT_K = IsoFactors(K_v=1.0, K_Hbeta=1.0, K_Fbeta=1.0)


def helical(z1: int, z2: int, beta_deg: float, width: float, module: float = 8e-3, **kw):
    """An unshifted steel helical pair (unless ``kw`` says otherwise), α_n = 20°."""
    return GearPair(
        z1, z2, module=module, pressure_angle=ALPHA_N, face_width=width,
        helix_angle=math.radians(beta_deg), material_1=STEEL, material_2=STEEL, **kw,
    )  # fmt: skip


def nrel5mw_stage3(*, wheel_first: bool) -> GearPair:
    """Nejad et al. 2016's stage 3 (models/nrel5mw_gearbox.urdf): pinion 24, wheel 95, m_n 14 mm,
    β 10°, b 360 mm, x 0.48 / 0.669, tip alteration −0.938 mm on both."""
    pair = GearPair(
        24, 95, module=14e-3, pressure_angle=ALPHA_N, face_width=0.36,
        profile_shift_1=0.48, profile_shift_2=0.669, helix_angle=math.radians(10.0),
        tip_alteration_1=-0.938e-3, tip_alteration_2=-0.938e-3,
        names=("stage3_pinion", "stage3_wheel"),
    )  # fmt: skip
    return pair.reversed() if wheel_first else pair


def hand_contact_stress(z1: int, z2: int, beta_deg: float, width: float, module: float, f_n):
    """ISO 6336-2 σ_H = Z_H Z_E Z_ε Z_β √(F_t/(d1 b)(u + 1)/u) of an unshifted external pair at
    its reference centre distance, every factor from the standard's definition:
    α_t = atan(tan α_n/cos β), β_b = atan(tan β cos α_t), α_wt = α_t;
    Z_H = √(2 cos β_b/(cos α_t sin α_t)); Z_E = √(1/(π 2(1 − ν²)/E));
    ε_α = (√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a sin α_t)/(π m_t cos α_t), r_a = r + m_n,
    r_b = r cos α_t, r = z m_t/2; ε_β = b sin β/(π m_n) ≥ 1 so Z_ε = √(1/ε_α);
    Z_β = 1/√cos β (ISO 6336-2:2006); F_t = F_n cos β_b cos α_t."""
    beta = math.radians(beta_deg)
    alpha_t = math.atan(math.tan(ALPHA_N) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    m_t = module / math.cos(beta)
    r1, r2 = z1 * m_t / 2, z2 * m_t / 2
    tip = math.sqrt((r1 + module) ** 2 - (r1 * math.cos(alpha_t)) ** 2) + math.sqrt(
        (r2 + module) ** 2 - (r2 * math.cos(alpha_t)) ** 2
    )
    eps_alpha = (tip - (r1 + r2) * math.sin(alpha_t)) / (math.pi * m_t * math.cos(alpha_t))
    assert width * math.sin(beta) / (math.pi * module) >= 1.0
    z_h = math.sqrt(2 * math.cos(beta_b) / (math.cos(alpha_t) * math.sin(alpha_t)))
    z_e = math.sqrt(STEEL.youngs_modulus / (2 * math.pi * (1 - STEEL.poisson_ratio**2)))
    u = z2 / z1
    f_t = np.asarray(f_n) * math.cos(beta_b) * math.cos(alpha_t)
    return (
        z_h * z_e * math.sqrt(1 / eps_alpha) / math.sqrt(math.cos(beta))
        * np.sqrt(f_t / (2 * r1 * width) * (u + 1) / u)
    )  # fmt: skip


def test_contact_stress_is_iso_6336_2_worked_by_hand():
    """21/52, m_n 8 mm, β 15°, b 120 mm (ε_β = 1.236) at 50, 100 and 200 kN normal to the
    flanks, in either order of the gears."""
    f_n = np.array([50e3, 100e3, 200e3])
    expected = hand_contact_stress(21, 52, 15.0, 0.12, 8e-3, f_n)
    pair = helical(21, 52, 15.0, 0.12)
    np.testing.assert_allclose(helical_contact_stress(pair, force=f_n), expected, rtol=1e-9)
    np.testing.assert_allclose(
        helical_contact_stress(pair.reversed(), force=-f_n), expected, rtol=1e-9
    )


def test_stage3_stresses_are_the_iso_rating_at_unit_load_factors():
    """The 5 MW stage 3 (shifted, tips altered, ε_β = 1.42) at F_t = 400 kN: σ_H of both gears
    (Z_B = Z_D = 1 at ε_β ≥ 1) and σ_F0 of each, from the rating of the pinion-first pair; the
    stresses take the mesh's own order, wheel first, and F_n = F_t/(cos β_b cos α_t)."""
    f_t = 400e3
    pinion_first = nrel5mw_stage3(wheel_first=False)
    rating = iso_rating(pinion_first, MeshLoad(tangential_force=f_t), UNIT_K)
    assert rating.factors.Z_B == rating.factors.Z_D == 1.0
    mesh_order = nrel5mw_stage3(wheel_first=True)
    alpha_t = math.atan(math.tan(ALPHA_N) / math.cos(math.radians(10.0)))
    beta_b = math.atan(math.tan(math.radians(10.0)) * math.cos(alpha_t))
    f_n = f_t / (math.cos(beta_b) * math.cos(alpha_t))
    sigma_h = helical_contact_stress(mesh_order, force=f_n)
    np.testing.assert_allclose(sigma_h, rating.sigma_H[0], rtol=1e-9)
    np.testing.assert_allclose(sigma_h, rating.sigma_H[1], rtol=1e-9)
    for gear, rated in ((2, 0), (1, 1)):  # mesh order: 1 the wheel, 2 the pinion
        root = ISO_ROOT_STRESS.mesh_stress(mesh_order, gear, force=f_n)
        np.testing.assert_allclose(root, rating.sigma_F0[rated], rtol=1e-9)
        np.testing.assert_allclose(root, rating.sigma_F[rated], rtol=1e-9)


def test_root_stress_is_f_t_over_b_m_n_times_form_and_helix_factors_by_hand():
    """σ_F = F_t/(b m_n) Y_F Y_S Y_β with Y_β = 1 − ε_β β/120° and ε_β taken as 1 above 1:
    Y_β = 1 − 15/120 = 0.875 for the 21/52 pair at β 15°."""
    pair = helical(21, 52, 15.0, 0.12)
    beta = math.radians(15.0)
    alpha_t = math.atan(math.tan(ALPHA_N) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    f_n = 120e3
    f_t = f_n * math.cos(beta_b) * math.cos(alpha_t)
    for gear in (1, 2):
        y_f, y_s = form_factors(pair, gear)
        np.testing.assert_allclose(
            ISO_ROOT_STRESS.mesh_stress(pair, gear, force=[f_n, -f_n]),
            f_t / (0.12 * 8e-3) * y_f * y_s * 0.875,
            rtol=1e-12,
        )


def test_small_helix_angle_gives_the_spur_pitch_point_stresses():
    """β → 0 with b = 1.01 π m_n/sin β (ε_β = 1.01 stays above 1): Z_β → 1, Z_H → the spur one,
    so σ_H √ε_α (the share Z_ε = √(1/ε_α) undone) is the spur pair's Hertz p_max at the pitch
    point with the whole force on one pair; Y_β = 1 − β/120° → 1, so σ_F/Y_β is the spur ISO
    root stress of that force. At β = 1e-4 rad the differences are O(β²)."""
    beta_deg = math.degrees(1e-4)
    width = 1.01 * math.pi * 8e-3 / math.sin(1e-4)
    nearly_spur = helical(21, 52, beta_deg, width)
    spur = helical(21, 52, 0.0, width)
    f_n = 80e3
    pitch = spur.path.pitch_roll_1
    eps_alpha = spur.path.contact_ratio
    np.testing.assert_allclose(
        helical_contact_stress(nearly_spur, force=f_n) * math.sqrt(eps_alpha),
        contact_stress(spur, force=f_n, position=pitch).p_max,
        rtol=1e-7,
    )
    y_beta = 1.0 - beta_deg / 120.0
    for gear in (1, 2):
        np.testing.assert_allclose(
            ISO_ROOT_STRESS.mesh_stress(nearly_spur, gear, force=f_n) / y_beta,
            ISO_ROOT_STRESS.stress(spur, gear, force=f_n, position=pitch),
            rtol=1e-7,
        )


@pytest.mark.parametrize(
    ("pair", "message"),
    [
        (helical(21, 52, 0.0, 0.12), "a spur pair"),
        (helical(21, 52, 5.0, 0.12), "ε_β = 0.4161"),
    ],
)
def test_spur_pair_or_overlap_below_one_raises(pair, message):
    """ε_β = 0.12 sin 5°/(π 0.008) = 0.4161: the load per tooth still jumps."""
    with pytest.raises(InputError, match=message):
        helical_contact_stress(pair, force=1e5)
    with pytest.raises(InputError, match="ε_β"):
        ISO_ROOT_STRESS.mesh_stress(pair, 1, force=1e5)


def test_root_stress_table_on_a_helical_pair_raises():
    table = table_root_stress(position_mm=[30.0, 50.0], mpa_per_kn=[2.0, 4.0])
    with pytest.raises(InputError, match="helical pair"):
        table.mesh_stress(helical(21, 52, 15.0, 0.12), 1, force=1e5)


#: N(s) = (1000 MPa / s)³: 100 MPa fails in 10³ cycles.
ROUND = SNCurve(reference_stress=1000e6, slope_exponent=3.0)


def swept_roll(*, teeth: int, revolutions: int) -> np.ndarray:
    """Roll X of a gear through a helical mesh, in base pitches, 40 samples per pitch: from
    X = 2.6 to X = revolutions · z + 0.5 (`swept_mesh`)."""
    return np.arange(2.6, revolutions * teeth + 0.5, 1.0 / 40.0)


def swept_mesh(*, teeth: int, revolutions: int, stress: np.ndarray | float) -> HelicalContacts:
    """A gear rolling forward through a helical mesh of total contact ratio 2.5 (base pitch 1):
    tooth k enters at X = k, its pair at x = X − k, in contact for x ∈ [0, 2.5]; the entering
    pair has x ∈ [0, 1), so 3 pairs for x ≤ 0.5 and 2 beyond. From X = 2.6 (teeth 1 and 2 in
    contact) to X = revolutions · z + 0.5 (tooth 0 back in) every tooth passes ``revolutions``
    times, the first passes of teeth 1 and 2 and the last of tooth 0 cut."""
    x = swept_roll(teeth=teeth, revolutions=revolutions) % 1.0
    tooth = entering_teeth(x, base_pitch=1.0, teeth=teeth, first_tooth=2)
    return HelicalContacts(
        tooth=tooth,
        leading_tooth=(tooth - 1) % teeth,
        stress=np.broadcast_to(stress, x.shape).astype(float),
        pairs=np.where(x <= 0.5, 3, 2),
        teeth=teeth,
    )


def test_constant_stress_is_one_cycle_per_pass_and_miner_by_hand():
    """A helical gear of 15 teeth for 4 revolutions at 200 MPa: each tooth passes 4 times (a
    cut pass still counts from 0: each history starts and ends unloaded), one cycle each;
    N(200 MPa) = 5³ = 125, so D = 4/125 per tooth."""
    contacts = swept_mesh(teeth=15, revolutions=4, stress=200e6)
    damage = histories_damage(
        tooth_histories([contacts], teeth=15), gear="g", curve=ROUND, time_factor=1.0
    )
    np.testing.assert_allclose(damage.cycle_counts, 4, rtol=0, atol=0)
    np.testing.assert_allclose(damage.damage, 4 / 125, rtol=1e-12)
    np.testing.assert_allclose(damage.peak_stress, 200e6, rtol=0, atol=0)


def test_a_pass_counts_once_at_its_largest_stress():
    """The stress rises and falls within each pass (a ripple at the mesh frequency, 150 to
    250 MPa): still one cycle per pass, of 250 MPa (N = 64), not the ripple's small cycles."""
    x = swept_roll(teeth=15, revolutions=4) % 1.0
    ripple = 200e6 + 50e6 * np.sin(2 * math.pi * x)
    contacts = swept_mesh(teeth=15, revolutions=4, stress=ripple)
    histories = tooth_histories([contacts], teeth=15)
    np.testing.assert_allclose([h.size for h in histories], 1 + 2 * 4, rtol=0, atol=0)
    damage = histories_damage(histories, gear="g", curve=ROUND, time_factor=1.0)
    np.testing.assert_allclose(damage.cycle_counts, 4, rtol=0, atol=0)
    np.testing.assert_allclose(damage.damage, 4 / 64, rtol=1e-9)


def helical_pair_urdf() -> str:
    """The 20/40 test pair made helical: β = ±30°, m_n 2 mm, b 20 mm, so ε_β = 0.02 sin 30°/
    (π 0.002) = 1.59, at the reference centre distance m_n (z1 + z2)/(2 cos β)."""
    text = two_gear_urdf(centre_distance=0.002 * 60 / (2 * math.cos(math.radians(30.0))))
    text = text.replace('face_width_mm="20" internal="false"/>\n    <gear name="g2"',
                        'face_width_mm="20" internal="false" helix_angle_deg="30"/>\n'
                        '    <gear name="g2"')  # fmt: skip
    return text.replace(
        'face_width_mm="20" internal="false"/>\n    <mesh',
        'face_width_mm="20" internal="false" helix_angle_deg="-30"/>\n    <mesh',
    )


def test_compliant_helical_pair_counts_one_cycle_per_tooth_pass_at_the_mesh_force():
    """The helical 20/40 pair at a 200 Hz mesh frequency against 10 N·m for 0.15 s: about 30
    pairs enter (the entering position jumps back a base pitch), each one pinion and one wheel
    tooth, and the pairs in contact at the start were in already: each of those is one tooth
    pass of each gear, one cycle each (a pinion tooth passes once or twice, a wheel tooth at
    most once); the largest contact stress is 0.65 σ_H of the largest mesh force (the
    equivalent the set's curves read) and the largest root stress each gear's
    F_t/(b m_n) Y_F Y_S Y_β of it, Y_β = 1 − 30/120, F_n = F_bt / cos β_b."""
    gearbox = loads(helical_pair_urdf(), "pair.urdf")
    assert gearbox.meshes[0].path.overlap_ratio > 1.5
    result = pinwind.simulate(
        gearbox,
        duration=0.15,
        dt=2e-5,
        speeds={"a": 2 * math.pi * 200 / 20},
        torques={"b": 10.0},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e9, damping_ratio=0.1)},
    )
    assert np.max(result.mesh_pairs[:, 0]) >= 3
    base_pitch = gearbox.meshes[0].path.base_pitch
    entered = np.sum(np.diff(result.mesh_contact_position[:, 0]) < -0.5 * base_pitch)
    assert 29 <= entered <= 31
    passes_expected = entered + int(result.mesh_pairs[0, 0])
    beta = math.radians(30.0)
    alpha_t = math.atan(math.tan(ALPHA_N) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    largest = float(np.max(np.abs(result.mesh_normal[:, 0]))) / math.cos(beta_b)
    pair = helical(20, 40, 30.0, 0.02, module=2e-3)
    for gear, index in (("g1", 1), ("g2", 2)):
        (contact,) = gear_tooth_damage(result, gearbox, gear, curve=ROUND, time_factor=1.0)
        (root,) = gear_tooth_damage(
            result, gearbox, gear, curve=ROUND, time_factor=1.0, root_stress=ISO_ROOT_STRESS
        )
        for rated in (contact, root):
            passes = rated.cycle_counts
            assert passes.sum() == passes_expected, passes
            assert passes.max() == (2 if gear == "g1" else 1), passes
        np.testing.assert_allclose(
            contact.peak_stress.max(),
            0.65 * hand_contact_stress(20, 40, 30.0, 0.02, 2e-3, largest),
            rtol=1e-9,
        )
        y_f, y_s = form_factors(pair, index)
        f_t = largest * math.cos(beta_b) * math.cos(alpha_t)
        np.testing.assert_allclose(
            root.peak_stress.max(), f_t / (0.02 * 2e-3) * y_f * y_s * 0.75, rtol=1e-9
        )


def test_spur_histories_keep_every_sample_of_a_pass_and_a_helical_pass_its_largest():
    """Three teeth, six samples. Spur: tooth 0 enters at samples 0-1 (1, 2) and leads at 2 (30):
    one pass 1, 2, 30; tooth 2 leads at 0 (10) and enters at 4-5 (5, 6): two passes. Helical
    with the same teeth in contact and stresses 1, 2, 30, 4, 5, 6: each pass keeps its largest
    (tooth 0: 30; tooth 1: 30; tooth 2: 1, then 6)."""
    tooth = np.array([0, 0, 1, 1, 2, 2])
    pairs = np.array([2, 1, 2, 1, 2, 1])
    spur = ToothContacts(
        tooth=tooth,
        leading_tooth=(tooth - 1) % 3,
        entering=np.array([1.0, 2, 3, 4, 5, 6]),
        leading=np.array([10.0, 20, 30, 40, 50, 60]),
        pairs=pairs,
    )
    expected = [[0, 1, 2, 30, 0], [0, 3, 4, 50, 0], [0, 10, 0, 5, 6, 0]]
    for got, want in zip(tooth_histories([spur], teeth=3), expected, strict=True):
        np.testing.assert_array_equal(got, want)
    swept = HelicalContacts(
        tooth=tooth,
        leading_tooth=(tooth - 1) % 3,
        stress=np.array([1.0, 2, 30, 4, 5, 6]),
        pairs=pairs,
        teeth=3,
    )
    expected = [[0, 30, 0], [0, 30, 0], [0, 1, 0, 6, 0]]
    for got, want in zip(tooth_histories([swept], teeth=3), expected, strict=True):
        np.testing.assert_array_equal(got, want)


def test_helical_teeth_and_flank_found_at_any_sample_agree_with_those_tracked():
    """The helical 20/40 pair, a driving positively against a brake on b: a's teeth push with
    the flank facing a's positive turn (+1); b turns the other way and is pushed on the flank
    that faces the pusher, behind it in its motion, so facing b's positive turn (+1), as for
    the spur pair. Numbered anew from any later sample (a case counted from ``skip_start``),
    the teeth are the ones tracked from the first sample, one tooth per base pitch, and the
    flank the same: the mid-face position (Δ/2 = 0.8 p_bt behind the front face) would put
    the contact beyond b's tooth tips at some phases and misjudge the flank there."""
    gearbox = loads(helical_pair_urdf(), "pair.urdf")
    result = pinwind.simulate(
        gearbox,
        duration=0.02,
        dt=2e-5,
        speeds={"a": 2 * math.pi * 10},
        torques={"b": 10.0},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e9, damping_ratio=0.1)},
    )
    for gear in ("g1", "g2"):
        tracked = mesh_teeth(result, gearbox, "m", gear)
        np.testing.assert_array_equal(tracked.flank, 1)
        for start in range(7, len(result), 37):
            later = mesh_teeth(result.rows(start, len(result)), gearbox, "m", gear)
            np.testing.assert_array_equal(later.tooth, tracked.tooth[start:])
            np.testing.assert_array_equal(later.flank, 1)
