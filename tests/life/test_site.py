"""Wind bins and time factors: Jørgensen 2014 Tables 1-3 derived from the paper's inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pinwind.errors import InputError, InvalidWindSite
from pinwind.life.site import (
    ToothExposure,
    ntm_turbulence,
    planetary_exposures,
    site_from_hours,
    time_factor,
    weibull_cdf,
    weibull_site,
)

#: Jørgensen 2014 Table 1: operating hours over 20 years per 2 m/s bin centred on 6 ... 20 m/s.
TABLE_1_SPEEDS = [6, 8, 10, 12, 14, 16, 18, 20]
TABLE_1_HOURS = [45418, 31900, 16320, 6189, 1751, 370, 58, 7]
#: Jørgensen 2014 Table 2: time factors of a 30 s simulation.
TABLE_2 = [5450160, 3828000, 1958400, 742680, 210120, 44400, 6960, 840]
#: Jørgensen 2014 Table 3: tooth time factors of the sun, planet and ring.
TABLE_3 = {
    "sun": [272508, 191400, 97920, 37134, 10506, 2220, 348, 42],
    "planet": [155719, 109371, 55954, 21219, 6003, 1269, 199, 24],
    "ring": [59892, 42066, 21521, 8161, 2309, 488, 76, 9],
}


def jorgensen_site():
    """Jørgensen 2014 §1.1: A = 6.62 m/s, k = 2.19, 20 years of 365 days, 2 m/s bins 5-21."""
    return weibull_site(scale=6.62, shape=2.19, edges=np.arange(5.0, 22.0, 2.0))


def test_weibull_hours_per_bin_match_table_1():
    """Table 1 prints whole hours, so each bin may differ by up to 0.5 h from rounding; the
    10 m/s bin comes out 16319.47 h against 16320 printed (0.53 h, 3·10⁻⁵). A and k are printed
    to three digits, and a change of 0.005 in A alone moves that bin by 38 h, so 0.6 h is the
    closest check the printed inputs allow. Availability is 1 and the operating range is the
    outer edges 5-21 m/s: the "approximately 60 % of the time" of §1.1 is F(21) − F(5)."""
    site = jorgensen_site()
    np.testing.assert_allclose(site.speeds, TABLE_1_SPEEDS, rtol=0, atol=0)
    np.testing.assert_allclose(site.hours, TABLE_1_HOURS, rtol=0, atol=0.6)


def test_weibull_total_operation_is_the_table_1_total():
    """Table 1's caption: 102013 h in total, the sum of its eight rounded values (8 × 0.5 h)."""
    np.testing.assert_allclose(jorgensen_site().total_hours, 102013, rtol=0, atol=4.0)


def test_weibull_cdf_at_the_scale_is_one_minus_one_over_e():
    np.testing.assert_allclose(
        weibull_cdf(6.62, scale=6.62, shape=2.19), 1.0 - math.exp(-1.0), rtol=1e-12
    )


def test_availability_and_cut_out_remove_hours():
    """Half availability halves every bin; a cut-out at 19 m/s keeps half the width of the
    18 m/s bin, F(19) − F(17), and nothing of the 20 m/s bin."""
    full = jorgensen_site()
    half = weibull_site(
        scale=6.62, shape=2.19, edges=np.arange(5.0, 22.0, 2.0), availability=0.5, cut_out=19.0
    )
    np.testing.assert_allclose(half.hours[:6], 0.5 * full.hours[:6], rtol=1e-12)
    f = lambda v: 1.0 - math.exp(-((v / 6.62) ** 2.19))  # noqa: E731
    np.testing.assert_allclose(half.hours[6], 0.5 * 175200 * (f(19) - f(17)), rtol=1e-12)
    assert half.hours[7] == 0.0


def test_given_hours_keep_their_bins_and_edges():
    site = site_from_hours(speeds=TABLE_1_SPEEDS, hours=TABLE_1_HOURS, turbulence=0.1)
    np.testing.assert_allclose(site.hours, TABLE_1_HOURS, rtol=0, atol=0)
    assert [(b.low, b.high) for b in site.bins[:2]] == [(5.0, 7.0), (7.0, 9.0)]
    assert site.bins[-1].high == 21.0
    assert all(b.turbulence == 0.1 for b in site.bins)


def test_time_factor_is_table_2():
    """Table 2: hours · 3600 s / 30 s; Table 1's hours are integers, so it is exact."""
    np.testing.assert_allclose(
        time_factor(hours=TABLE_1_HOURS, simulated_seconds=30.0), TABLE_2, rtol=0, atol=1e-6
    )


def test_tooth_time_factors_are_table_3():
    """Table 3 from the DTU stage (sun 20, planet 35, ring 91 teeth, 3 planets) and 30 s runs;
    Table 3 rounds to whole numbers, so within 0.5."""
    exposures = planetary_exposures(sun_teeth=20, planet_teeth=35, ring_teeth=91, planets=3)
    for gear, expected in TABLE_3.items():
        factor = exposures[gear].time_factor(hours=TABLE_1_HOURS, simulated_seconds=30.0)
        np.testing.assert_allclose(factor, expected, rtol=0, atol=0.5, err_msg=gear)


def test_joined_histories_are_the_table_3_lengths():
    """Table 3's headers: the sun's and the ring's histories joined are 90 s, the planet's
    60 s (§3.1: three planets meet each sun and ring tooth, a sun and a ring each planet)."""
    exposures = planetary_exposures(sun_teeth=20, planet_teeth=35, ring_teeth=91, planets=3)
    lengths = {gear: e.history_seconds(30.0) for gear, e in exposures.items()}
    assert lengths == {"sun": 90.0, "planet": 60.0, "ring": 90.0}


def test_single_mesh_time_factor_counts_every_mesh_a_tooth_passes():
    """A sun tooth of 20 passing 3 planets: 1 h over a 1 s history of one mesh is 3600 · 3 / 20
    cycles per counted cycle."""
    exposure = ToothExposure(teeth=20, meshes=3)
    np.testing.assert_allclose(
        exposure.single_mesh_time_factor(hours=1.0, simulated_seconds=1.0), 540.0, rtol=1e-12
    )


def test_ntm_turbulence_at_15_m_s_follows_iec_61400_1():
    """σ1 = I_ref (0.75 · 15 + 5.6) = 0.16 · 16.85 for class A, over 15 m/s."""
    np.testing.assert_allclose(
        ntm_turbulence(15.0, turbulence_class="A"), 0.16 * 16.85 / 15.0, rtol=1e-12
    )
    site = site_from_hours(speeds=[10.0, 20.0], hours=[1.0, 2.0], turbulence="B")
    np.testing.assert_allclose(
        [b.turbulence for b in site.bins],
        [0.14 * (7.5 + 5.6) / 10.0, 0.14 * (15.0 + 5.6) / 20.0],
        rtol=1e-12,
    )


@pytest.mark.parametrize(
    ("scale", "shape", "message"),
    [(0.0, 2.19, "Weibull scale A"), (-6.62, 2.19, "Weibull scale A"),
     (6.62, 0.0, "Weibull shape k"), (6.62, -1.0, "Weibull shape k"),
     (math.nan, 2.19, "Weibull scale A")],
)  # fmt: skip
def test_bad_weibull_parameters_raise(scale, shape, message):
    with pytest.raises(InvalidWindSite, match=message):
        weibull_site(scale=scale, shape=shape, edges=[5.0, 7.0])


@pytest.mark.parametrize("hours", [[45418, None, 16320], [45418, math.nan, 16320]])
def test_bin_without_hours_raises_and_names_the_bin(hours):
    with pytest.raises(InvalidWindSite, match="8 m/s bin") as caught:
        site_from_hours(speeds=[6, 8, 10], hours=hours)
    assert caught.value.value is None or math.isnan(caught.value.value)


def test_missing_bin_hours_raise():
    with pytest.raises(InvalidWindSite, match="one value per bin"):
        site_from_hours(speeds=[6, 8, 10], hours=[1.0, 2.0])


@pytest.mark.parametrize("turbulence", [0.0, -0.1, [0.1, 0.0, 0.1], math.inf])
def test_non_positive_turbulence_raises(turbulence):
    with pytest.raises(InvalidWindSite, match="turbulence intensity"):
        site_from_hours(speeds=[6, 8, 10], hours=[1.0, 2.0, 3.0], turbulence=turbulence)


def test_turbulence_list_of_the_wrong_length_raises():
    with pytest.raises(InvalidWindSite, match="one per bin"):
        site_from_hours(speeds=[6, 8, 10], hours=[1.0, 2.0, 3.0], turbulence=[0.1, 0.2])


def test_unknown_turbulence_class_raises():
    with pytest.raises(InvalidWindSite, match="turbulence class"):
        site_from_hours(speeds=[6, 8], hours=[1.0, 2.0], turbulence="D")


def test_non_positive_simulated_length_raises():
    with pytest.raises(InputError, match="simulated length"):
        time_factor(hours=[1.0], simulated_seconds=0.0)
