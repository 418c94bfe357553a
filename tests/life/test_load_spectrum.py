"""LDD and LRD of the shafts (IEC 61400-4): time and revolutions per torque level."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.errors import InputError, NonFiniteInput, TorquesUnbalanced
from pinwind.life.load_spectrum import load_spectrum, shaft_spectra, shaft_torque
from tests.conftest import MODELS

RPM = 2.0 * math.pi / 60.0


@pytest.fixture(scope="module")
def planetary():
    return pinwind.load(MODELS / "saleh2017_planetary.urdf")


@pytest.fixture(scope="module")
def rippled_run(planetary):
    """The Saleh stage spun up by a rippling rotor torque against a smaller sun torque."""

    def rotor(t: float) -> float:
        return 1.0e6 * (1.0 + 0.3 * math.sin(2.0 * math.pi * 5.0 * t))

    with pytest.warns(TorquesUnbalanced):  # it spins up: the sun's torque does not hold it
        return pinwind.simulate(
            planetary, duration=0.4, dt=1e-3, torques={"carrier": rotor, "sun": -1.0e5},
            initial_speeds={"carrier": 10.0 * RPM},
        )  # fmt: skip


def _trapezoid(values: np.ndarray, time: np.ndarray) -> float:
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(time)))


def test_ldd_time_sums_to_the_duration(rippled_run, planetary):
    for spectrum in shaft_spectra(rippled_run, planetary, bins=20):
        np.testing.assert_allclose(spectrum.time.sum(), 0.4, rtol=1e-12)
        assert len(spectrum.time) == 20


def test_lrd_revolutions_sum_to_the_integral_of_the_speed(rippled_run, planetary):
    spectra = {s.joint: s for s in shaft_spectra(rippled_run, planetary)}
    assert "ring" not in spectra  # a locked mount does not turn
    for joint, spectrum in spectra.items():
        speed = np.abs(rippled_run.joint(joint).speed)
        revolutions = _trapezoid(speed, rippled_run.time) / (2.0 * math.pi)
        assert revolutions > 0.3  # the stage turns: the sum is not trivially zero
        np.testing.assert_allclose(spectrum.revolutions.sum(), revolutions, rtol=1e-12)


def test_two_level_history_puts_its_time_and_turns_in_two_bins():
    # 2 s at 10 kN·m and 60 rpm, then 1 s at 30 kN·m and 120 rpm: 2 and 2 revolutions.
    time = np.linspace(0.0, 3.0, 30001)
    first = time < 2.0
    torque = np.where(first, 10e3, 30e3)
    speed = np.where(first, 60.0, 120.0) * RPM
    spectrum = load_spectrum(torque, speed, time, bins=[0.0, 20e3, 40e3])
    np.testing.assert_allclose(spectrum.time, [2.0, 1.0], atol=2e-4)
    np.testing.assert_allclose(spectrum.revolutions, [2.0, 2.0], atol=4e-4)
    np.testing.assert_allclose(spectrum.levels, [10e3, 30e3], rtol=1e-12)


def test_geared_shafts_carry_the_torque_of_their_teeth_at_constant_speed(planetary):
    # At a constant carrier speed the sun's teeth balance its applied torque, the ring's its
    # lock: T_ring = −(T_carrier + T_sun) with T_carrier = −6 T_sun, and a simple planet's two
    # meshes balance.
    res = pinwind.simulate(planetary, duration=0.05, dt=1e-3, speeds={"carrier": 14.2 * RPM},
                           torques={"sun": -1.0e6 / 6.0})  # fmt: skip
    sun, source = shaft_torque(res, planetary, "sun")
    assert source == "gear sun"
    np.testing.assert_allclose(sun, 1.0e6 / 6.0, rtol=1e-9)
    ring, _ = shaft_torque(res, planetary, "ring")
    np.testing.assert_allclose(ring, 1.0e6 - 1.0e6 / 6.0, rtol=1e-9)
    planet, _ = shaft_torque(res, planetary, "planet1")
    np.testing.assert_allclose(planet, 0.0, atol=1e-6 * 1.0e6)
    carrier, source = shaft_torque(res, planetary, "carrier")
    assert source == "external torque"
    np.testing.assert_allclose(carrier[1:], 1.0e6, rtol=1e-9)


def test_bins_that_miss_samples_or_do_not_increase_are_refused():
    time = np.linspace(0.0, 1.0, 11)
    torque = np.linspace(-5.0, 5.0, 11)
    with pytest.raises(InputError, match="beyond the bins"):
        load_spectrum(torque, np.ones(11), time, bins=[0.0, 10.0], joint="sun")
    with pytest.raises(InputError, match="must increase"):
        load_spectrum(torque, np.ones(11), time, bins=[10.0, -10.0])


def test_non_finite_torque_is_refused():
    time = np.linspace(0.0, 1.0, 11)
    torque = np.full(11, np.nan)
    with pytest.raises(NonFiniteInput, match='shaft "sun"'):
        load_spectrum(torque, np.ones(11), time, joint="sun")


def test_a_torque_constant_to_rounding_makes_a_spectrum_not_a_numpy_error():
    # A steady run's sun torque spans two ulps of 1e6/6 N·m: numpy's bin edges raised
    # "Too many bins for data range" (docs/spectra_and_modes.md's shaft_spectra).
    time = np.linspace(0.0, 2.0, 2001)
    torque = 1e6 / 6 + np.spacing(1e6 / 6) * (np.arange(len(time)) % 3)  # 0, 1, 2 ulps
    speed = np.full_like(time, 2 * math.pi)  # one turn a second
    spectrum = load_spectrum(torque, speed, time, bins=10)
    assert len(spectrum.edges) == 11
    assert spectrum.edges[0] <= torque.min() and torque.max() <= spectrum.edges[-1]
    # every sample counted: the whole 2 s and its 2 turns, whatever the bins
    np.testing.assert_allclose(spectrum.time.sum(), 2.0, rtol=1e-12)
    np.testing.assert_allclose(spectrum.revolutions.sum(), 2.0, rtol=1e-12)


def test_shaft_spectra_of_a_steady_run_cover_every_turning_shaft(planetary):
    res = pinwind.simulate(planetary, duration=0.05, dt=1e-3,
                           torques={"carrier": 1e6, "sun": -1e6 / 6},
                           initial_speeds={"carrier": 14.2 * 2 * math.pi / 60})  # fmt: skip
    spectra = shaft_spectra(res, planetary, bins=10)
    assert [s.joint for s in spectra] == ["carrier", "planet1", "planet2", "planet3", "sun"]
    for s in spectra:
        np.testing.assert_allclose(s.time.sum(), 0.05, rtol=1e-12)
