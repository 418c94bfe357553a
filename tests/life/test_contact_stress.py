"""Hertz contact stress of a tooth pair from its force and contact position (Jørgensen 2014
eqs. 20-22), against closed forms computed here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.materials import MATERIALS
from pinwind.life.contact_stress import contact_stress

STEEL = MATERIALS["18CrNiMo7-6"]
ALPHA = math.radians(20.0)
MODULE = 10e-3
WIDTH = 0.21


def compliance_sum() -> float:
    """m1 + m2 = 2 (1 − ν²)/E of two steel flanks [1/Pa] (Jørgensen 2014 eq. 21)."""
    return 2.0 * (1.0 - STEEL.poisson_ratio**2) / STEEL.youngs_modulus


def line_contact_pressure(force: float, rho_1: float, rho_2: float) -> float:
    """p_max = √(F (1/ρ1 + 1/ρ2) / (π L (m1 + m2))), eqs. 20-22 combined by hand."""
    return math.sqrt(force * (1.0 / rho_1 + 1.0 / rho_2) / (math.pi * WIDTH * compliance_sum()))


def spur(z1: int, z2: int, **kwargs) -> GearPair:
    """An unshifted steel spur pair of module 10 mm, 20°, face width 210 mm."""
    return GearPair(
        z1, z2, module=MODULE, pressure_angle=ALPHA, face_width=WIDTH,
        material_1=STEEL, material_2=STEEL, **kwargs,
    )  # fmt: skip


def iso_nominal_contact_stress(tangential_force: float, z1: int, z2: int, internal: bool) -> float:
    """ISO 6336-2 σ_H0 = Z_H Z_E √(F_t/(d1 b) (u ± 1)/u) of an unshifted spur pair, the
    textbook pitch-point Hertz stress (Z_H = √(2/(cos α sin α)), Z_E = √(1/(π (m1 + m2))))."""
    z_h = math.sqrt(2.0 / (math.cos(ALPHA) * math.sin(ALPHA)))
    z_e = math.sqrt(1.0 / (math.pi * compliance_sum()))
    ratio = z2 / z1
    d1 = MODULE * z1
    return (
        z_h
        * z_e
        * math.sqrt(
            tangential_force / (d1 * WIDTH) * ((ratio - 1.0) if internal else (ratio + 1.0)) / ratio
        )
    )


def test_external_pair_follows_the_line_contact_closed_form_along_the_line_of_action():
    """20/40 unshifted: |T1T2| = a sin α with a = m (z1 + z2)/2; ρ1 = u, ρ2 = |T1T2| − u."""
    pair = spur(20, 40)
    line = MODULE * 60 / 2 * math.sin(ALPHA)
    position = np.array([0.03, 0.04, 0.05, 0.06])
    force = np.array([1e5, 2e5, 3e5, 4e5])
    stress = contact_stress(pair, force=force, position=position)
    expected = [line_contact_pressure(f, u, line - u) for f, u in zip(force, position, strict=True)]
    np.testing.assert_allclose(stress.p_max, expected, rtol=1e-12)
    np.testing.assert_allclose(stress.rho_1 + stress.rho_2, line, rtol=1e-12)
    np.testing.assert_allclose(stress.von_mises, 0.65 * stress.p_max, rtol=1e-12)


def test_external_pitch_point_stress_is_the_textbook_hertz_stress():
    """At the pitch point (u = r1 sin α) with F_n = F_t / cos α, eqs. 20-22 are ISO 6336-2's
    nominal σ_H0 of the pair."""
    tangential = 2.5e5
    stress = contact_stress(
        spur(20, 40), force=tangential / math.cos(ALPHA), position=MODULE * 10 * math.sin(ALPHA)
    )
    np.testing.assert_allclose(
        stress.p_max, iso_nominal_contact_stress(tangential, 20, 40, internal=False), rtol=1e-12
    )


def test_internal_pitch_point_stress_is_the_textbook_hertz_stress_with_u_minus_one():
    """Planet 35 in ring 91: σ_H0 with (u − 1)/u, the concave ring flank."""
    tangential = 2.5e5
    stress = contact_stress(
        spur(35, 91, internal_2=True),
        force=tangential / math.cos(ALPHA),
        position=MODULE * 17.5 * math.sin(ALPHA),
    )
    np.testing.assert_allclose(
        stress.p_max, iso_nominal_contact_stress(tangential, 35, 91, internal=True), rtol=1e-12
    )
    assert float(stress.rho_2) < 0.0


def test_ring_named_first_gives_the_stress_at_the_same_physical_point():
    """With the ring as gear A the position counts from the ring's tangency point, which lies
    |T1T2| = a sin α = m (91 − 35)/2 sin α behind the planet's."""
    line = MODULE * 56 / 2 * math.sin(ALPHA)
    from_planet = np.array([0.05, 0.06, 0.07])
    planet_first = contact_stress(spur(35, 91, internal_2=True), force=3e5, position=from_planet)
    ring_first = contact_stress(
        spur(91, 35, internal_1=True), force=3e5, position=from_planet + line
    )
    np.testing.assert_allclose(ring_first.p_max, planet_first.p_max, rtol=1e-12)
    np.testing.assert_allclose(ring_first.rho_1, planet_first.rho_2, rtol=1e-12)


def test_no_position_or_a_position_beyond_the_tangency_points_gives_nan():
    """A rigid mesh without a path logs NaN positions; past T2 there is no involute."""
    line = MODULE * 60 / 2 * math.sin(ALPHA)
    stress = contact_stress(spur(20, 40), force=1e5, position=[math.nan, line + 0.001, -0.001])
    assert np.all(np.isnan(stress.p_max))


def test_zero_force_gives_zero_stress():
    np.testing.assert_allclose(
        contact_stress(spur(20, 40), force=0.0, position=0.04).p_max, 0.0, rtol=0, atol=0
    )


def test_helical_pair_raises():
    with pytest.raises(InputError, match="spur"):
        contact_stress(spur(20, 40, helix_angle=math.radians(10)), force=1e5, position=0.04)


def test_force_and_position_of_different_lengths_raise():
    with pytest.raises(InputError, match="same number of samples"):
        contact_stress(spur(20, 40), force=[1.0, 2.0], position=[0.03, 0.04, 0.05])
