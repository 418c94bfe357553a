"""AGMA 2001 rating against Shigley's Mechanical Engineering Design, 10th ed., Example 14-4.

Example 14-4 (Budynas & Nisbett, Shigley's MED 10th ed., §14-19): a 17-tooth 20° spur pinion at
1800 rev/min transmits 4 hp to a 52-tooth gear; P_d = 10 teeth/in, F = 1.5 in, Q_v = 6; grade 1
through-hardened steel, pinion 240 HB, gear 200 HB; 10⁸ pinion cycles, R = 0.9. The book's
factors and results, transcribed from it (US units), are the expectations here.
"""

import math
from dataclasses import fields

import pytest

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.materials import Material
from pinwind.gears.rating_agma import (
    AgmaFactors,
    ResolvedAgmaFactors,
    agma_rating,
    dynamic_factor,
    load_distribution_factor,
    pitting_geometry_factor,
    reliability_factor,
    shigley_size_factor,
)

PSI = 6894.757293168
LBF = 4.4482216152605
INCH = 0.0254


def _steel(s_t_psi: float, s_c_psi: float, hb: float) -> Material:
    return Material(
        name=f"grade 1 {hb:g} HB",
        treatment="through_hardened",
        youngs_modulus=30e6 * PSI,
        poisson_ratio=0.3,
        density=7850.0,
        brinell_hardness=hb,
        sigma_H_lim=1.0,
        sigma_F_lim=1.0,
        agma_contact_allowable=s_c_psi * PSI,
        agma_bending_allowable=s_t_psi * PSI,
    )


@pytest.fixture
def example_14_4() -> tuple[GearPair, MeshLoad]:
    pair = GearPair(
        17,
        52,
        module=INCH / 10.0,
        pressure_angle=math.radians(20.0),
        face_width=1.5 * INCH,
        material_1=_steel(31350, 106400, 240),
        material_2=_steel(28260, 93500, 200),
    )
    speed = math.pi * 1.7 * INCH * 1800 / 60  # pitch-line speed, 801.1 ft/min
    return pair, MeshLoad(
        tangential_force=33000 * 4 / (speed / 0.00508) * LBF, pitch_line_speed=speed
    )


def test_shigley_example_14_4_stresses_and_safety_factors(example_14_4):
    pair, load = example_14_4
    factors = AgmaFactors(
        K_o=1.0, K_v=1.377, K_s=(1.043, 1.052), K_m=1.22, K_B=1.0, J=(0.30, 0.40), I=0.121,
        C_p=2300 * math.sqrt(PSI), C_f=1.0, Y_N=(0.977, 0.996), Z_N=(0.948, 0.973),
        C_H=(1.0, 1.005), K_T=1.0, K_R=0.85,
    )  # fmt: skip
    r = agma_rating(pair, load, factors)
    # The book rounds W_t to 164.8 lbf; the load here is the unrounded 164.77 lbf (0.02 %).
    assert r.transmitted_load / LBF == pytest.approx(164.8, rel=5e-4)
    bending = [s / PSI for s in r.bending_stress]
    contact = [s / PSI for s in r.contact_stress]
    assert bending == pytest.approx([6417, 4854], rel=1e-3)
    assert contact == pytest.approx([70360, 70660], rel=1e-3)
    assert [s / PSI for s in r.bending_allowable] == pytest.approx([36034, 33114], rel=1e-3)
    assert r.S_F == pytest.approx([5.62, 6.82], abs=0.006)
    assert r.S_H == pytest.approx([1.69, 1.52], abs=0.006)
    assert r.passes


def test_default_dynamic_and_load_distribution_factors_match_example_14_4(example_14_4):
    pair, load = example_14_4
    assert dynamic_factor(load.pitch_line_speed, 6) == pytest.approx(1.377, abs=5e-4)
    k_m = load_distribution_factor(1.5 * INCH, 1.7 * INCH, "commercial_enclosed")
    assert k_m == pytest.approx(1.22, abs=5e-4)
    assert pitting_geometry_factor(pair) == pytest.approx(0.121, abs=5e-4)
    # Shigley's size-factor estimate with Lewis Y = 0.303 (17 teeth), 0.412 (52 teeth).
    assert shigley_size_factor(1.5 * INCH, INCH / 10, 0.303) == pytest.approx(1.043, abs=5e-4)
    assert shigley_size_factor(1.5 * INCH, INCH / 10, 0.412) == pytest.approx(1.052, abs=5e-4)


def test_iso_geometry_factor_option_J_from_form_factors_is_within_12_percent_of_chart(
    example_14_4,
):
    pair, load = example_14_4
    r = agma_rating(pair, load, AgmaFactors(geometry_factor="iso"))
    # Shigley Fig. 14-6: J = 0.30 (17 teeth) and 0.40 (52 teeth) for this pair; the option
    # J = 1/(Y_F Y_S) (ISO 6336-3 method B) is not AGMA 908's layout and differs by up to 12 %.
    assert r.factors.J[0] == pytest.approx(0.30, rel=0.12)
    assert r.factors.J[1] == pytest.approx(0.40, rel=0.12)


def test_internal_pair_contact_geometry_factor_uses_ratio_over_ratio_minus_one():
    pair = GearPair(48, 120, module=0.015, pressure_angle=math.radians(24.5), face_width=0.38,
                    internal_2=True)  # fmt: skip
    phi = math.radians(24.5)
    expected = math.cos(phi) * math.sin(phi) / 2 * 2.5 / 1.5
    assert pitting_geometry_factor(pair) == pytest.approx(expected, rel=1e-12)


def test_safety_factor_is_allowable_over_stress_so_that_one_passes(example_14_4):
    pair, load = example_14_4
    light = agma_rating(pair, load)
    heavy = agma_rating(pair, MeshLoad(load.tangential_force * 20, load.pitch_line_speed))
    assert light.passes and not heavy.passes
    assert heavy.S_F[0] < 1.0 < light.S_F[0]


def test_resolved_factors_have_the_fields_of_the_given_ones_in_order():
    assert [f.name for f in fields(ResolvedAgmaFactors)] == [f.name for f in fields(AgmaFactors)]


def test_rating_again_with_the_resolved_factors_gives_the_same_stresses(example_14_4):
    pair, load = example_14_4
    first = agma_rating(pair, load, AgmaFactors(quality=6, reliability_percent=90.0))
    assert agma_rating(pair, load, first.factors) == first


@pytest.mark.parametrize(
    ("percent", "k_r"), [(50.01, 0.70), (90.0, 0.85), (99.0, 1.00), (99.9, 1.25), (99.99, 1.50)]
)
def test_reliability_factor_takes_percent_and_matches_agma_table_8(percent, k_r):
    # AGMA 2001 Table 8 (Shigley Table 14-10): K_R by reliability 0.5, 0.9, 0.99, 0.999, 0.9999.
    # Shigley eq. 14-38 is a fit of the table: 0.833 at 90 % for its 0.85, 0.711 at 50 %.
    assert reliability_factor(percent) == pytest.approx(k_r, abs=0.02)


@pytest.mark.parametrize("percent", [0.99, 50.0, 100.0, math.nan])
def test_reliability_factor_refuses_a_fraction_or_a_percent_outside_its_range(percent):
    with pytest.raises(InputError, match=r"50 < R ≤ 99\.99") as err:
        reliability_factor(percent)
    assert (f"{percent:g} is {100 * percent:g} %" in str(err.value)) == (percent == 0.99)
