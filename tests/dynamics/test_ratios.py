"""Kinematic speed ratios from the constraint rows agree with tooth counts."""

from __future__ import annotations

import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.ratios import speed_ratio
from pinwind.errors import UnknownJoint
from tests.conftest import MODELS


def test_saleh_drivetrain_overall_ratio_is_the_product_of_the_stages():
    gb = pinwind.load(MODELS / "saleh2017_drivetrain.urdf")
    # Planetary 1 + 120/24 = 6; each parallel stage reverses the direction.
    expected = 6 * (83 / 23) * (103 / 26)
    assert_allclose(speed_ratio(gb, "stage2_pinion", "carrier"), expected, rtol=1e-12)
    assert_allclose(speed_ratio(gb, "stage1_pinion", "carrier"), -6 * 83 / 23, rtol=1e-12)


def test_cart600_compound_planet_ratio():
    gb = pinwind.load(MODELS / "cart600_gearbox.urdf")
    # Compound planetary, ring fixed: ω_sun/ω_c = 1 + (z_ring z_planetB)/(z_planetA z_sun).
    assert_allclose(speed_ratio(gb, "sun", "carrier"), 1 + (93 * 103) / (22 * 29), rtol=1e-12)


def test_unknown_joint_is_named():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with pytest.raises(UnknownJoint, match='"rotor"'):
        speed_ratio(gb, "rotor", "carrier")
