"""Kaimal wind statistics and spectrum; rotor torque from C_p; λ_opt tracking."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import minimize_scalar

import pinwind
from pinwind.dynamics.elements import rotor_power_coefficient, rotor_torque
from pinwind.errors import InputError
from pinwind.loads.generator import VariableSpeed
from pinwind.loads.rotor import CpTable, HeierCp, Rotor
from pinwind.loads.signal_text import parse_signal
from pinwind.loads.wind import KaimalWind, kaimal_series

RPM = 2 * math.pi / 60


def heier(tsr, beta_deg=0.0):
    """Heier's C_p(λ, β), β in degrees, written out here."""
    inv = 1 / (tsr + 0.08 * beta_deg) - 0.035 / (beta_deg**3 + 1)
    return 0.5176 * (116 * inv - 0.4 * beta_deg - 5) * np.exp(-21 * inv) + 0.0068 * tsr


# --- wind ---------------------------------------------------------------------------------------


def test_ten_minutes_of_kaimal_wind_have_the_requested_mean_and_deviation():
    t, u = kaimal_series(mean=10.0, turbulence_intensity=0.16, duration=600.0, seed=7)
    assert_allclose(t[-1], 600.0, rtol=1e-12)
    assert abs(u.mean() / 10.0 - 1) < 0.01
    assert abs(u[:-1].std() / 1.6 - 1) < 0.05


def test_kaimal_wind_is_reproducible_for_a_seed_and_differs_between_seeds():
    a = KaimalWind(mean=10.0, turbulence_intensity=0.1, seed=3).values(np.arange(0, 600, 0.01))
    b = parse_signal("kaimal(mean=10, turbulence_intensity=0.1, seed=3)").values(
        np.arange(0, 600, 0.01)
    )
    c = KaimalWind(mean=10.0, turbulence_intensity=0.1, seed=4).values(np.arange(0, 600, 0.01))
    assert np.array_equal(a, b)
    assert np.abs(a - c).max() > 0.1


def test_kaimal_wind_spectrum_is_the_iec_kaimal_spectrum_at_every_resolved_frequency():
    mean, ti, dt, duration, hub = 10.0, 0.12, 0.05, 600.0, 80.0
    _, u = kaimal_series(mean=mean, turbulence_intensity=ti, duration=duration,
                         sample_time=dt, seed=11, hub_height=hub)  # fmt: skip
    u = u[:-1]
    n = u.size
    f = np.fft.rfftfreq(n, dt)[1:-1]  # from 1/T to below Nyquist
    periodogram = 2 * np.abs(np.fft.rfft(u - mean)[1:-1]) ** 2 / (n / dt)  # one-sided
    # IEC 61400-1 ed. 3: L_u = 8.1 · 42 m above 60 m hub height; S = 4σ²(L/V)/(1 + 6fL/V)^(5/3).
    sigma, lu = ti * mean, 8.1 * 42.0
    kaimal = 4 * sigma**2 * (lu / mean) / (1 + 6 * f * lu / mean) ** (5 / 3)
    # The variance below 1/T is the 10-minute mean's, not turbulence: the resolved band is scaled
    # to carry all of σ², a constant factor on the whole spectrum.
    level = sigma**2 / np.sum(kaimal / duration)
    assert 1.1 < level < 1.3
    assert_allclose(periodogram, level * kaimal, rtol=1e-8)


def test_wind_series_shorter_than_the_run_is_refused(pair_urdf):
    from pinwind.model.gearbox import loads

    gb = loads(pair_urdf(), path="pair.urdf")
    wind = KaimalWind(mean=10, turbulence_intensity=0.1, duration=0.5, sample_time=0.01)
    with pytest.raises(InputError, match=r"wind: kaimal wind .* ends at .* but the run lasts 1 s"):
        pinwind.simulate(gb, duration=1.0, dt=1e-3, rotors={"a": Rotor(radius=1.0)}, wind=wind)


# --- rotor --------------------------------------------------------------------------------------


def test_rotor_torque_is_power_over_speed_from_cp():
    rotor = Rotor(radius=40.0, air_density=1.2, cp=HeierCp(scale=1.03))
    for speed, wind in ((1.5, 10.0), (2.0, 8.0), (0.8, 12.0)):
        tsr = speed * 40.0 / wind
        power = 0.5 * 1.2 * math.pi * 40.0**2 * wind**3 * 1.03 * heier(tsr)
        assert_allclose(rotor_torque(rotor, speed, wind), power / speed, rtol=1e-12)
    pitched = Rotor(radius=40.0, pitch=math.radians(5.0))
    tsr = 1.5 * 40 / 10
    expected = 0.5 * 1.225 * math.pi * 40**2 * 1000 * heier(tsr, 5.0) / 1.5
    assert_allclose(rotor_torque(pitched, 1.5, 10.0), expected, rtol=1e-12)


def test_cp_table_is_bilinear_between_its_points():
    table = CpTable(tsr=(2.0, 6.0, 10.0), pitch=(0.0, 0.2), cp=((0.1, 0.0), (0.4, 0.2), (0.3, 0.1)))
    rotor = Rotor(radius=10.0, pitch=0.1, cp=table)
    # λ = 4: halfway between rows 0 and 1; β halfway between the columns.
    cp = 0.5 * (0.5 * (0.1 + 0.0) + 0.5 * (0.4 + 0.2))
    assert_allclose(rotor_power_coefficient(rotor, 4.0), cp, rtol=1e-12)
    assert_allclose(rotor_torque(rotor, 4.0 * 8.0 / 10.0, 8.0),
                    0.5 * 1.225 * math.pi * 100 * 512 * cp / 3.2, rtol=1e-12)  # fmt: skip


def test_saleh2017_rotor_gives_1_mnm_at_14_2_rpm_in_10_m_s():
    assert_allclose(rotor_torque(Rotor.saleh2017(), 14.2 * RPM, 10.0), 1e6, rtol=1e-6)
    assert_allclose(Rotor.saleh2017().radius, 41 + 3.7 / 2, rtol=1e-15)


def test_k_omega_squared_law_settles_the_rotor_at_the_optimal_tip_speed_ratio():
    gb = pinwind.load("models/saleh2017_planetary.urdf")
    radius, rho, wind = 42.85, 1.225, 8.0
    best = minimize_scalar(lambda x: -heier(x), bounds=(2, 15), method="bounded",
                           options={"xatol": 1e-12})  # fmt: skip
    tsr_opt, cp_max = best.x, -best.fun
    # Generator on the sun (6 × the carrier): K = ½ρπR⁵ C_p,max / λ_opt³ / 6³.
    gain = 0.5 * rho * math.pi * radius**5 * cp_max / tsr_opt**3 / 6**3
    rotor = Rotor(radius=radius, inertia=2e5, air_density=rho)
    start = 0.8 * tsr_opt * wind / radius
    res = pinwind.simulate(gb, duration=60.0, dt=5e-3, rotors={"carrier": rotor}, wind=wind,
                           generators={"sun": VariableSpeed(gain)},
                           initial_speeds={"carrier": start}, keep="last")  # fmt: skip
    speed = res.joint("carrier").speed[-1]
    assert_allclose(speed * radius / wind, tsr_opt, rtol=1e-4)
    # There the rotor delivers P = ½ρπR²v³ C_p,max: its torque is P/ω.
    power = 0.5 * rho * math.pi * radius**2 * wind**3 * cp_max
    assert_allclose(res.joint("carrier").torque[-1], power / speed, rtol=1e-4)


def test_wind_from_a_csv_file_drives_the_rotor_sample_by_sample(tmp_path):
    path = tmp_path / "wind.csv"
    path.write_text("time,wind\n0,8\n0.2,12\n0.4,9\n")
    gb = pinwind.load("models/saleh2017_planetary.urdf")
    rotor = Rotor.saleh2017()
    sun = 6 * 14.2 * RPM
    res = pinwind.simulate(gb, duration=0.4, dt=1e-3, rotors={"carrier": rotor},
                           wind=parse_signal(f'csv(file="{path}", column="wind")'),
                           speeds={"sun": sun})  # fmt: skip
    wind = np.interp(res.time, [0, 0.2, 0.4], [8, 12, 9])
    # The sun is held: the carrier turns at 14.2 rpm and carries the rotor's torque alone.
    expected = [rotor_torque(rotor, sun / 6, v) for v in wind]
    assert_allclose(res.joint("carrier").torque, expected, rtol=1e-9)


def test_rotor_and_generator_work_balance_the_kinetic_energy_with_the_rotor_inertia():
    from pinwind.loads.generator import InductionMachine

    gb = pinwind.load("models/saleh2017_planetary.urdf")
    res = pinwind.simulate(gb, duration=2.0, dt=1e-3, rotors={"carrier": Rotor.saleh2017()},
                           wind=KaimalWind(mean=11, turbulence_intensity=0.2, seed=5, duration=5),
                           generators={"sun": InductionMachine.cart600(poles=84, dynamic=True)},
                           initial_speeds={"carrier": 13 * RPM})  # fmt: skip
    e = res.energy
    work = e["work_applied"] + e["work_drivers"] + e["work_gravity"] + e["work_constraints"]
    change = e["kinetic"] - e["kinetic"][0]
    assert_allclose(change, work - e["dissipated"], rtol=0, atol=1e-9 * np.abs(work).max())
    # The rotor's inertia is in the kinetic energy: ½ (J_train + J_rotor) ω_c² at the start.
    assert e["kinetic"][0] > 0.5 * 5.0e6 * (13 * RPM) ** 2


# --- rotor-effective wind -----------------------------------------------------------------------


def _coherence(r, f, mean, lc):
    """IEC 61400-1 ed. 3 annex B coherence, written out here."""
    return np.exp(-12 * np.sqrt((f * r / mean) ** 2 + (0.12 * r / lc) ** 2))


def test_rotor_admittance_is_the_coherence_averaged_over_pairs_of_points_on_the_disc():
    from pinwind.loads.wind import disc_distance_density, rotor_admittance

    radius, mean, lc = 42.85, 10.0, 8.1 * 42
    # The distance density integrates to 1 and has the disc's mean chord-free distance 128R/45π.
    r = np.linspace(0, 2 * radius, 200_001)
    p = disc_distance_density(r, radius)
    assert_allclose(np.trapezoid(p, r), 1.0, rtol=1e-8)
    assert_allclose(np.trapezoid(r * p, r), 128 * radius / (45 * math.pi), rtol=1e-8)
    # Monte Carlo: uniform pairs of points on the disc (seeded), coherence averaged over them.
    rng = np.random.default_rng(2)
    n = 200_000
    rho = radius * np.sqrt(rng.uniform(size=(2, n)))
    phi = rng.uniform(0, 2 * math.pi, size=(2, n))
    x, y = rho * np.cos(phi), rho * np.sin(phi)
    d = np.hypot(x[0] - x[1], y[0] - y[1])
    f = np.array([0.0, 0.01, 0.05, 0.2, 1.0])
    monte_carlo = np.array([_coherence(d, fk, mean, lc).mean() for fk in f])
    chi2 = rotor_admittance(f, radius=radius, mean=mean, coherence_scale=lc)
    assert_allclose(chi2, monte_carlo, atol=3e-3)
    assert np.all(np.diff(chi2) < 0) and chi2[-1] < 0.05


def test_rotor_effective_kaimal_wind_has_the_point_spectrum_times_the_admittance():
    from pinwind.loads.wind import rotor_admittance

    mean, ti, dt, radius = 10.0, 0.12, 0.05, 42.85
    kwargs = dict(mean=mean, turbulence_intensity=ti, duration=600.0, sample_time=dt, seed=5)
    _, point = kaimal_series(**kwargs)
    _, rotor = kaimal_series(**kwargs, rotor_radius=radius)
    assert_allclose(rotor[:-1].mean(), mean, rtol=1e-12)
    n = point.size - 1
    f = np.fft.rfftfreq(n, dt)[1:-1]
    ratio = np.abs(np.fft.rfft(rotor[:-1])[1:-1]) ** 2 / np.abs(np.fft.rfft(point[:-1])[1:-1]) ** 2
    # The admittance integrated here on a fine grid of distances (trapezoid rule, error below
    # 3e-6 up to Nyquist), at every 50th frequency.
    r = np.linspace(0, 2 * radius, 200_001)
    x = r / (2 * radius)
    p = 4 * r / (math.pi * radius**2) * (np.arccos(x) - x * np.sqrt(1 - x * x))
    lc = 8.1 * 42  # hub height 80 m
    some = slice(0, None, 50)
    chi2 = np.array([np.trapezoid(p * _coherence(r, fk, mean, lc), r) for fk in f[some]])
    assert_allclose(ratio[some], chi2, rtol=1e-5)
    # Its variance: σ² weighted by the admittance over the point series' spectrum.
    chi2 = rotor_admittance(f, radius=radius, mean=mean, coherence_scale=lc)
    point_spectrum = np.abs(np.fft.rfft(point[:-1] - mean)[1:-1]) ** 2
    expected = (ti * mean) ** 2 * np.sum(point_spectrum * chi2) / np.sum(point_spectrum)
    assert_allclose(rotor[:-1].var(), expected, rtol=1e-6)
    assert rotor[:-1].std() < 0.9 * point[:-1].std()


def test_rotor_radius_is_a_kaimal_signal_parameter():
    a = parse_signal("kaimal(mean=10, turbulence_intensity=0.1, seed=3, rotor_radius=40)")
    b = KaimalWind(mean=10.0, turbulence_intensity=0.1, seed=3, rotor_radius=40.0)
    t = np.arange(0, 600, 0.1)
    assert np.array_equal(a.values(t), b.values(t))
    assert a.spec()["rotor_radius"] == 40.0
    with pytest.raises(InputError, match="rotor_radius"):
        KaimalWind(mean=10.0, turbulence_intensity=0.1, rotor_radius=-1.0)


def test_a_kaimal_series_too_long_to_hold_is_refused_naming_its_samples():
    from pinwind.loads.wind import kaimal_series

    # 1e12 s at 0.05 s is 2e13 samples (numpy: "Maximum allowed size exceeded").
    with pytest.raises(InputError, match=r"duration = 1e\+12 s at sample_time = 0.05 s is 2e\+13"):
        kaimal_series(mean=10.0, turbulence_intensity=0.1, duration=1e12, sample_time=0.05)
