"""Tooth-root stress along the path of contact: ISO 6336-3 method B and a user table, against
the standard's nominal root stress and linear interpolation computed here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.rating_iso import form_factors, iso_rating
from pinwind.life.root_stress import ISO_ROOT_STRESS, TableRootStress, table_root_stress

ALPHA = math.radians(20.0)
MODULE = 10e-3
WIDTH = 0.21


def sun_planet() -> GearPair:
    """Jørgensen 2014's sun/planet pair without profile shift: 20/35 teeth, 10 mm, 210 mm."""
    return GearPair(20, 35, module=MODULE, pressure_angle=ALPHA, face_width=WIDTH)


def iso_nominal_root_stress(normal_force: float, pair: GearPair, gear: int) -> float:
    """ISO 6336-3: σ_F0 = F_t/(b m_n) Y_F Y_S Y_β, F_t = F_n cos α at the reference circle of a
    spur pair (Y_β = 1), with Y_F, Y_S of method B (outer point of single contact)."""
    y_f, y_s = form_factors(pair, gear)
    return normal_force * math.cos(ALPHA) / (WIDTH * MODULE) * y_f * y_s


def test_iso_root_stress_at_a_static_load_is_iso_6336_3_nominal_root_stress():
    """100 kN at the pitch point (single contact): the standard's σ_F0 for each gear, also as
    the ISO rating gives it with every load factor 1."""
    pair = sun_planet()
    force = 100e3
    rating = iso_rating(
        pair,
        MeshLoad(tangential_force=force * math.cos(ALPHA)),
        None,
    )
    for gear in (1, 2):
        stress = ISO_ROOT_STRESS.stress(pair, gear, force=force, position=pair.path.pitch_roll_1)
        expected = iso_nominal_root_stress(force, pair, gear)
        np.testing.assert_allclose(stress, expected, rtol=1e-12)
        np.testing.assert_allclose(stress, rating.sigma_F0[gear - 1], rtol=1e-12)


def test_root_stress_follows_the_force_and_is_nan_off_the_involutes():
    pair = sun_planet()
    inside = pair.path.start_roll_1 + 0.5 * pair.path.length
    stress = ISO_ROOT_STRESS.stress(
        pair, 1, force=[-50e3, 100e3, 100e3], position=[inside, inside, -1e-3]
    )
    np.testing.assert_allclose(stress[0] * 2.0, stress[1], rtol=1e-12)
    assert np.isnan(stress[2])


def test_table_interpolates_a_two_point_table_exactly():
    """Stress per force 2 MPa/kN at 30 mm of the pinion's roll, 4 MPa/kN at 50 mm: at 40 mm,
    10 kN gives (2 + 4)/2 · 10 = 30 MPa. The same table on the planet: its roll is |T1T2| − x,
    so at x = |T1T2| − 35 mm it reads 2.5 MPa/kN."""
    pair = sun_planet()
    table = table_root_stress(position_mm=[30.0, 50.0], mpa_per_kn=[2.0, 4.0])
    np.testing.assert_allclose(
        table.stress(pair, 1, force=10e3, position=[0.030, 0.040, 0.050]),
        [20e6, 30e6, 40e6],
        rtol=1e-12,
    )
    np.testing.assert_allclose(
        table.stress(pair, 2, force=10e3, position=pair.tangency_distance - np.array([0.035])),
        [25e6],
        rtol=1e-12,
    )


def test_table_fraction_runs_from_the_lowest_contact_to_the_tip():
    """0 → 1 MPa/kN over the active flank: the start of contact is the pinion's lowest point
    (0) and the end its tip (1), and the other way round for the wheel."""
    pair = sun_planet()
    table = table_root_stress(fraction=[0.0, 1.0], mpa_per_kn=[0.0, 1.0])
    ends = [pair.path.start_roll_1, pair.path.start_roll_1 + pair.path.length]
    np.testing.assert_allclose(table.stress(pair, 1, force=1e3, position=ends), [0, 1e6], atol=1)
    np.testing.assert_allclose(table.stress(pair, 2, force=1e3, position=ends), [1e6, 0], atol=1)


def test_table_fraction_of_an_internal_gear_is_zero_at_its_root_side():
    """A ring's active flank starts near its root, at the larger |ρ|: the end of contact."""
    pair = GearPair(35, 91, module=MODULE, pressure_angle=ALPHA, face_width=WIDTH, internal_2=True)
    table = table_root_stress(fraction=[0.0, 1.0], mpa_per_kn=[0.0, 1.0])
    ends = np.array([pair.path.start_roll_1, pair.path.start_roll_1 + pair.path.length])
    rho = np.abs(np.array(pair.flank_radii(ends)[1]))
    expected = np.where(rho == rho.max(), 0.0, 1e6)
    np.testing.assert_allclose(table.stress(pair, 2, force=1e3, position=ends), expected, atol=1)


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"position": (1.0,), "stress_per_force": (1.0,)}, "two or more positions"),
        ({"position": (2.0, 1.0), "stress_per_force": (1.0, 1.0)}, "rising positions"),
    ],
)
def test_bad_table_raises(arguments, message):
    with pytest.raises(InputError, match=message):
        TableRootStress(**arguments)


def test_table_needs_exactly_one_kind_of_position():
    with pytest.raises(InputError, match="position_mm or fraction"):
        table_root_stress(mpa_per_kn=[1.0, 2.0])
