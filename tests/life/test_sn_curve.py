"""S-N curve and Palmgren-Miner damage (Jørgensen 2014 eqs. 2, 3, 23; Tables 4-5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InputError, InvalidSNCurve
from pinwind.life.cycles import rainflow_cycles
from pinwind.life.sn_curve import (
    IsoLifeCurve,
    SNCurve,
    iso6336_contact_curve,
    iso6336_root_curve,
    jorgensen_2014_curve,
    miner_damage,
)

#: A curve with round numbers: N(s) = (1000 MPa / s)^3, so 100 MPa fails in 10³ cycles.
ROUND = SNCurve(reference_stress=1000e6, slope_exponent=3.0, reference_cycles=1.0)


def pulsating(peak: float, cycles: int) -> np.ndarray:
    """0 → peak → 0 repeated ``cycles`` times: a tooth loaded once per mesh pass."""
    return np.array([0.0, *([peak, 0.0] * cycles)])


def test_constant_amplitude_damage_is_cycles_over_cycles_to_failure():
    """50 pulsating cycles of range 100 MPa on N = (1000/100)³ = 1000: D = 50 / 1000."""
    cycles = rainflow_cycles(pulsating(100e6, 50))
    np.testing.assert_allclose(miner_damage(cycles, ROUND), 50 / 1000, rtol=1e-12)


def test_damage_read_at_the_amplitude_uses_half_the_range():
    """Amplitude 50 MPa: N = (1000/50)³ = 8000, D = 50 / 8000."""
    cycles = rainflow_cycles(pulsating(100e6, 50))
    np.testing.assert_allclose(
        miner_damage(cycles, ROUND, stress="amplitude"), 50 / 8000, rtol=1e-12
    )


def test_damage_scales_with_the_time_factor():
    """The same 50 cycles standing for 40 times as long: D = 40 · 50 / 1000 = 2."""
    cycles = rainflow_cycles(pulsating(100e6, 50)).scaled(40.0)
    np.testing.assert_allclose(miner_damage(cycles, ROUND), 2.0, rtol=1e-12)


def test_stresses_below_the_endurance_limit_do_no_damage():
    curve = SNCurve(reference_stress=1000e6, slope_exponent=3.0, endurance_limit=150e6)
    cycles = rainflow_cycles(pulsating(100e6, 50))
    assert miner_damage(cycles, curve) == 0.0


def test_ignoring_the_endurance_limit_counts_cycles_on_the_sloped_line():
    curve = SNCurve(reference_stress=1000e6, slope_exponent=3.0, endurance_limit=150e6)
    cycles = rainflow_cycles(pulsating(100e6, 50))
    np.testing.assert_allclose(
        miner_damage(cycles, curve, use_endurance_limit=False), 50 / 1000, rtol=1e-12
    )


def test_two_level_history_adds_the_damage_of_each_level():
    """10 cycles at 200 MPa (N = 125) then 100 at 100 MPa (N = 1000): D = 10/125 + 100/1000."""
    history = np.concatenate([pulsating(200e6, 10), pulsating(100e6, 100)[1:]])
    np.testing.assert_allclose(
        miner_damage(rainflow_cycles(history), ROUND), 10 / 125 + 100 / 1000, rtol=1e-12
    )


def test_table_4_points_give_the_curve_of_eq_23():
    """Jørgensen 2014 Table 4: 3·10⁴ cycles at 1400 MPa and 10⁶ at 500 MPa; eq. 23 prints
    s0 = 28.9 GPa and m = 3.4, both rounded, so they must agree to the printed digits."""
    curve = SNCurve.through_points(cycles_1=3e4, stress_1=1400e6, cycles_2=1e6, stress_2=500e6)
    np.testing.assert_allclose(curve.slope_exponent, 3.4, rtol=0, atol=0.01)
    np.testing.assert_allclose(curve.reference_stress, 28.9e9, rtol=0, atol=0.05e9)
    np.testing.assert_allclose(curve.stress([3e4, 1e6]), [1400e6, 500e6], rtol=1e-12)


def test_003_presets_pass_through_table_4_and_carry_table_5_limits():
    """eq. 23 with its rounded s0 and m passes within 1 % of both Table 4 points."""
    limits = {"sun": 800e6, "planet": 800e6, "ring": 550e6}
    for gear, limit in limits.items():
        for location in ("contact", "root"):
            curve = jorgensen_2014_curve(gear, location=location)
            np.testing.assert_allclose(curve.endurance_limit, limit, rtol=0, atol=0)
            np.testing.assert_allclose(curve.stress([3e4, 1e6]), [1400e6, 500e6], rtol=0.01)


def test_cycles_to_failure_follow_eq_3():
    """N = N0 (s0/s)^m with N0 = 10⁶ at s0 = 300 MPa and m = 5: 600 MPa fails in 10⁶/32."""
    curve = SNCurve(reference_stress=300e6, slope_exponent=5.0, reference_cycles=1e6)
    np.testing.assert_allclose(curve.cycles_to_failure(600e6), 1e6 / 32, rtol=1e-12)
    assert math.isinf(float(curve.cycles_to_failure(0.0)))


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("slope_exponent", 0.0, "slope exponent m"),
        ("slope_exponent", -3.4, "slope exponent m"),
        ("slope_exponent", math.nan, "slope exponent m"),
        ("reference_stress", math.inf, "reference stress s0"),
        ("reference_cycles", 0.0, "reference cycles N0"),
        ("endurance_limit", -1.0, "endurance limit"),
        ("endurance_limit", math.nan, "endurance limit"),
    ],
)
def test_bad_sn_curve_raises_and_keeps_the_value(field, value, message):
    arguments = {"reference_stress": 28.9e9, "slope_exponent": 3.4, "endurance_limit": 800e6}
    arguments[field] = value
    with pytest.raises(InvalidSNCurve, match=message) as caught:
        SNCurve(**arguments)
    assert caught.value.parameter.startswith(message)
    assert caught.value.value == value or math.isnan(value)


def test_points_of_a_rising_curve_raise():
    with pytest.raises(InvalidSNCurve, match="falling curve"):
        SNCurve.through_points(cycles_1=1e6, stress_1=1400e6, cycles_2=3e4, stress_2=1200e6)


def test_unknown_preset_gear_names_the_known_ones():
    with pytest.raises(InputError, match="sun, planet, ring"):
        jorgensen_2014_curve("carrier")


def test_unknown_cycle_stress_raises():
    with pytest.raises(InputError, match="range"):
        miner_damage(rainflow_cycles(pulsating(1.0, 2)), ROUND, stress="peak")  # type: ignore[arg-type]


# --- ISO 6336's own curves --------------------------------------------------------------------
# ISO 6336-2:2006 Table 2, case-hardened steel (Eh), no pitting: Z_NT = 1.6 up to 10⁵ cycles,
# (5·10⁷/N)^0.0756 to 5·10⁷, then 1 (optimum conditions) or falling to 0.85 at 10¹⁰.
# ISO 6336-3:2006 Table 3, Eh root: Y_NT = 2.5 up to 10³, (3·10⁶/N)^0.115 to 3·10⁶, 0.85 at 10¹⁰.
# 18CrNiMo7-6 (materials.py): σ_Hlim = 1500 MPa, σ_Flim = 500 MPa; σ_FE = 2 σ_Flim.


def test_iso_contact_curve_passes_through_the_knee_points_of_iso_6336_2():
    curve = iso6336_contact_curve("18CrNiMo7-6")
    knees = np.array([1e5, 5e7, 1e10])
    np.testing.assert_allclose(curve.stress(knees), 1500e6 * np.array([1.6, 1.0, 0.85]), rtol=1e-12)
    np.testing.assert_allclose(
        curve.cycles_to_failure(1500e6 * np.array([1.6, 1.0, 0.85]), use_endurance_limit=False),
        knees,
        rtol=1e-9,
    )
    # Static plateau below 10⁵ cycles; the standard's rounded exponent 0.0756 between the knees.
    np.testing.assert_allclose(curve.stress([1.0, 1e3]), 2400e6, rtol=1e-12)
    np.testing.assert_allclose(curve.stress(1e6), 1500e6 * 50**0.0756, rtol=1e-3)


def test_iso_root_curve_passes_through_the_knee_points_of_iso_6336_3():
    curve = iso6336_root_curve("18CrNiMo7-6")
    np.testing.assert_allclose(
        curve.stress([1e3, 3e6, 1e10]), 1000e6 * np.array([2.5, 1.0, 0.85]), rtol=1e-12
    )
    np.testing.assert_allclose(curve.stress(1e5), 1000e6 * 30**0.115, rtol=3e-3)
    idler = iso6336_root_curve("18CrNiMo7-6", reversed_bending=True)
    np.testing.assert_allclose(idler.stress(3e6), 0.7 * 1000e6, rtol=1e-12)


def test_miner_on_the_iso_contact_curve_for_a_constant_history_by_hand():
    """1000 cycles at Z_NT = 1.3: N = 5·10⁷ · 1.3^(−ln 500 / ln 1.6) on the sloped line."""
    curve = iso6336_contact_curve("18CrNiMo7-6")
    cycles = rainflow_cycles(pulsating(1.3 * 1500e6, 1000))
    life = 5e7 * 1.3 ** (-math.log(500.0) / math.log(1.6))
    np.testing.assert_allclose(miner_damage(cycles, curve), 1000 / life, rtol=1e-9)


def test_iso_curve_below_its_strength_does_no_damage_with_the_limit_and_falls_without_it():
    """0.9 σ_Hlim: none on the optimum line; on the line to 0.85 at 10¹⁰, N = 5·10⁷ · 0.9^(−k)."""
    curve = iso6336_contact_curve("18CrNiMo7-6")
    cycles = rainflow_cycles(pulsating(0.9 * 1500e6, 1000))
    assert miner_damage(cycles, curve) == 0.0
    k = math.log(1e10 / 5e7) / math.log(1 / 0.85)
    np.testing.assert_allclose(
        miner_damage(cycles, curve, use_endurance_limit=False),
        1000 / (5e7 * 0.9 ** (-k)),
        rtol=1e-9,
    )


def test_iso_curve_beyond_10_to_the_10_cycles_continues_the_falling_line():
    """Past the last knee the line from (5·10⁷, 1) to (10¹⁰, 0.85) goes on: at 10¹² cycles
    Z_NT = 0.85^(ln(10¹²/5·10⁷) / ln(10¹⁰/5·10⁷)), below 0.85, not above it."""
    curve = iso6336_contact_curve("18CrNiMo7-6")
    factor = 0.85 ** (math.log(1e12 / 5e7) / math.log(1e10 / 5e7))
    np.testing.assert_allclose(curve.stress(1e12), factor * 1500e6, rtol=1e-12)


def test_curve_scaled_to_von_mises_fails_at_the_same_cycles():
    curve = iso6336_contact_curve("18CrNiMo7-6")
    stresses = np.array([2000e6, 1600e6, 1400e6])
    np.testing.assert_allclose(
        curve.scaled(0.65).cycles_to_failure(0.65 * stresses, use_endurance_limit=False),
        curve.cycles_to_failure(stresses, use_endurance_limit=False),
        rtol=1e-12,
    )


def test_pitting_permitted_row_and_nitrided_rows():
    permitted = iso6336_contact_curve("18CrNiMo7-6", pitting_permitted=True)
    np.testing.assert_allclose(
        permitted.stress([6e5, 1e7, 1e9]), 1500e6 * np.array([1.6, 1.3, 1.0]), rtol=1e-12
    )
    nitrided = iso6336_contact_curve("34CrNiMo6")
    np.testing.assert_allclose(nitrided.stress([1e5, 2e6]), [1300e6, 1000e6], rtol=1e-12)
    with pytest.raises(InputError, match='no "some pitting permitted" row'):
        iso6336_contact_curve("34CrNiMo6", pitting_permitted=True)


def test_life_factor_knees_that_do_not_fall_are_refused():
    with pytest.raises(InvalidSNCurve, match="falling through 1"):
        IsoLifeCurve(1e9, ((1e5, 1.6), (5e7, 1.7)))
