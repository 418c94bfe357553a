"""A rolling bearing's frictional moment by hand from ISO/TR 14179-2's Palmgren formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.errors import InvalidBearingFriction, InvalidLossInput
from pinwind.losses.bearing_friction import (
    PALMGREN_FACTORS,
    friction_load,
    load_moment,
    no_load_moment,
    no_load_moment_coefficients,
)
from pinwind.model.bearing_friction_data import friction_data

RPM = 2.0 * math.pi / 60.0


def test_spherical_roller_moment_at_speed_is_palmgrens_viscous_branch_by_hand():
    # ISO/TR 14179-2: M0 = 1e-7 f0 (ν n)^(2/3) d_m³ [N·mm] for ν n ≥ 2000 (ν mm²/s, n rpm,
    # d_m mm); M1 = f1 P1 d_m. Spherical roller, oil bath: f0 = 5, f1 = 0.0004 (Palmgren 1959).
    # d_m = 300 mm, ν = 100 mm²/s, n = 1000 rpm: ν n = 1e5, (1e5)^(2/3) = 2154.43.
    m0_nmm = 1e-7 * 5.0 * 2154.4347 * 300.0**3  # 29 084.9 N·mm
    m1_nmm = 0.0004 * 1.0e5 * 300.0  # P1 = 100 kN: 12 000 N·mm
    f = PALMGREN_FACTORS["spherical_roller"]
    assert (f.f0, f.f1) == (5.0, 0.0004)
    m0 = no_load_moment(f.f0, 100e-6, 1000.0 * RPM, 0.300)
    assert_allclose(m0, m0_nmm * 1e-3, rtol=1e-6)
    assert_allclose(load_moment(f.f1, 1.0e5, 0.300), m1_nmm * 1e-3, rtol=1e-12)
    # either direction of turning: the same magnitude
    assert_allclose(no_load_moment(f.f0, 100e-6, -1000.0 * RPM, 0.300), m0, rtol=1e-12)


def test_cylindrical_roller_moment_at_low_speed_is_the_constant_branch_by_hand():
    # ν n = 60 mm²/s × 10 rpm = 600 < 2000: M0 = 160e-7 f0 d_m³ [N·mm], f0 = 2.5 (2-3 with cage)
    # d_m = 240 mm: 160e-7 × 2.5 × 240³ = 552.96 N·mm; M1 = 0.000275 × 50 kN × 240 = 3300 N·mm.
    f = PALMGREN_FACTORS["cylindrical_roller"]
    m0 = no_load_moment(f.f0, 60e-6, 10.0 * RPM, 0.240)
    assert_allclose(m0, 552.96e-3, rtol=1e-12)
    assert_allclose(load_moment(f.f1, 5.0e4, 0.240), 3.3, rtol=1e-12)
    # at rest too (M0 does not vanish: Palmgren's constant branch)
    assert_allclose(no_load_moment(f.f0, 60e-6, 0.0, 0.240), 552.96e-3, rtol=1e-12)


def test_the_compiled_steps_coefficients_give_the_same_moment():
    c0, floor = no_load_moment_coefficients(5.0, 100e-6, 0.3)
    for rpm in (1.0, 30.0, 1000.0):
        omega = rpm * RPM
        assert_allclose(
            max(c0 * omega ** (2 / 3), floor), no_load_moment(5.0, 100e-6, omega, 0.3), rtol=1e-12
        )


def test_the_moment_is_continuous_where_the_branches_meet():
    # (ν n)^(2/3) = 160 at ν n = 160^1.5 = 2023.9: the larger branch on either side
    nu = 100e-6
    n = 160.0**1.5 / 100.0
    below = no_load_moment(3.0, nu, (n - 1e-6) * RPM, 0.1)
    above = no_load_moment(3.0, nu, (n + 1e-6) * RPM, 0.1)
    assert_allclose(below, above, rtol=1e-6)  # a jump would be 0.8 %


def test_friction_load_takes_the_axial_load_by_the_types_rule():
    # spherical: max(0.8 F_a cot α, F_r), α = 10°; cylindrical: F_r; deep groove:
    # max(3 F_a - 0.1 F_r, F_r)
    assert_allclose(
        friction_load("spherical_roller", 10e3, 5e3), 0.8 * 5e3 / math.tan(math.radians(10.0))
    )
    assert_allclose(friction_load("spherical_roller", 50e3, 5e3), 50e3)
    assert_allclose(friction_load("cylindrical_roller", 10e3, 50e3), 10e3)
    assert_allclose(friction_load("deep_groove_ball", 1e3, 2e3), 3 * 2e3 - 0.1 * 1e3)


def test_a_negative_viscosity_or_load_is_refused():
    with pytest.raises(InvalidLossInput, match="viscosity"):
        no_load_moment(2.0, -1e-6, 1.0, 0.1)
    with pytest.raises(InvalidLossInput, match="load"):
        load_moment(0.0004, np.array([1.0, -1.0]), 0.1)


def test_an_unknown_friction_model_is_refused_with_the_known_ones():
    with pytest.raises(InvalidBearingFriction, match="iso_tr_14179_2") as err:
        friction_data({"friction_model": "skf_2018"}, where="<bearing joint='a'>", path="m.urdf")
    assert "skf_2018" in str(err.value)
    with pytest.raises(InvalidBearingFriction, match="friction_f0"):
        friction_data({"friction_f0": "-1"}, where="<bearing joint='a'>", path="m.urdf")
