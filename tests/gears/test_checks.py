"""Geometry checks: virtual teeth, undercut, tip thickness, internal-pair interference."""

import math

import pytest

from pinwind.errors import InvalidGearTrain
from pinwind.gears.checks import (
    check_gear,
    check_pair,
    check_planetary,
    errors,
    min_profile_shift,
    raise_for,
    tip_thickness,
    trochoid_clearance,
)
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.involute import virtual_teeth

ALPHA = math.radians(20.0)
#: Face width [m]: no geometry check reads it.
WIDTH = 0.05


def test_virtual_teeth_of_a_helical_gear_by_hand():
    beta = math.radians(15.0)
    alpha_t = math.atan(math.tan(ALPHA) / math.cos(beta))  # 20.647°
    beta_b = math.asin(math.sin(beta) * math.cos(ALPHA))  # sin β_b = sin β cos α_n
    expected = 30 / (math.cos(beta_b) ** 2 * math.cos(beta))
    assert virtual_teeth(30, beta, ALPHA) == pytest.approx(expected, rel=1e-12)
    assert alpha_t > ALPHA
    assert virtual_teeth(30) == 30


def test_undercut_starts_below_17_teeth_at_20_degrees():
    # Straight flank of the ISO 53 A tool ends 1.0 m above the datum: z_min = 2/sin² 20° = 17.1.
    assert min_profile_shift(17, pressure_angle=ALPHA) == pytest.approx(
        1.25 - 0.38 * (1 - math.sin(ALPHA)) - 17 * math.sin(ALPHA) ** 2 / 2, rel=1e-12
    )
    assert not check_gear(18, module=0.01, pressure_angle=ALPHA)
    found = check_gear(14, module=0.01, pressure_angle=ALPHA, name="pinion")
    assert [f.check for f in found] == ["undercut"]
    assert "pinion (14 teeth" in found[0].message and "18 teeth" in found[0].message
    assert not errors(check_gear(14, module=0.01, pressure_angle=ALPHA, profile_shift=0.19))


def test_tip_thickness_of_a_standard_20_tooth_gear_by_hand():
    d, d_a, d_b = 20.0, 22.0, 20.0 * math.cos(ALPHA)  # module 1 mm
    alpha_a = math.acos(d_b / d_a)
    inv = lambda a: math.tan(a) - a  # noqa: E731
    expected = d_a * (math.pi / 2 / d + inv(ALPHA) - inv(alpha_a))  # 0.6921 mm
    assert tip_thickness(20, module=1e-3, pressure_angle=ALPHA) * 1e3 == pytest.approx(
        expected, rel=1e-12
    )


def test_large_profile_shift_on_few_teeth_gives_pointed_teeth():
    found = check_gear(10, module=0.01, pressure_angle=ALPHA, profile_shift=1.0)
    pointed = [f for f in found if f.check == "tip_thickness"]
    assert pointed and pointed[0].severity == "error" and "pointed" in pointed[0].message


def test_internal_tooth_thickens_towards_its_root():
    tip = tip_thickness(120, module=0.01, pressure_angle=ALPHA, internal=True)
    at_reference = math.pi / 2 * 0.01
    assert 0 < tip < at_reference  # thinnest at the tip, the inner circle


def test_trochoid_interference_by_the_khk_formula_for_a_small_tooth_difference():
    # KHK Gear Technical Reference: internal gears with few more teeth than the pinion foul
    # at the tips. Hand evaluation of the formula for 48/120 and 60/66 (module 1, α = 20°).
    def margin(z1, z2):
        a = (z2 - z1) / 2
        ra1, ra2 = z1 / 2 + 1, z2 / 2 - 1
        rb1, rb2 = z1 / 2 * math.cos(ALPHA), z2 / 2 * math.cos(ALPHA)
        inv = lambda t: math.tan(t) - t  # noqa: E731
        aa1, aa2 = math.acos(rb1 / ra1), math.acos(rb2 / ra2)
        t1 = math.acos((ra2**2 - ra1**2 - a**2) / (2 * a * ra1)) + inv(aa1) - inv(ALPHA)
        t2 = math.acos((a**2 + ra2**2 - ra1**2) / (2 * a * ra2))
        return t1 * z1 / z2 + inv(ALPHA) - inv(aa2) - t2

    def ring_pair(z1, z2):
        return GearPair(z1, z2, module=1e-3, pressure_angle=ALPHA, face_width=WIDTH,
                        internal_2=True)  # fmt: skip

    assert trochoid_clearance(ring_pair(48, 120)) == pytest.approx(margin(48, 120), rel=1e-9)
    assert margin(48, 120) > 0
    assert trochoid_clearance(ring_pair(60, 66)) < 0
    found = check_pair(ring_pair(60, 66))
    assert "trochoid_interference" in [f.check for f in found]


def test_saleh_preliminary_stage_passes_every_check():
    assert not errors(
        check_planetary(sun=24, planet=48, ring=120, planets=3, module=0.015,
                        pressure_angle=math.radians(24.5), face_width=0.38)
    )  # fmt: skip


def test_unequal_spacing_and_colliding_planets_are_errors_with_reasons():
    found = check_planetary(sun=25, planet=48, ring=121, planets=3, module=0.015,
                            pressure_angle=ALPHA, face_width=WIDTH)  # fmt: skip
    assert [f.check for f in errors(found)] == ["assembly"]
    assert "(25 + 121)/3" in found[0].message
    crowded = check_planetary(sun=12, planet=48, ring=108, planets=4, module=0.01,
                              pressure_angle=ALPHA, face_width=WIDTH)  # fmt: skip
    assert "planet_clearance" in [f.check for f in crowded]
    with pytest.raises(InvalidGearTrain, match="undercut"):
        raise_for(crowded)
