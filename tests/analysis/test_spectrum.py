"""Welch spectra: a sum of sines gives its frequencies and amplitudes; mesh frequencies by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.analysis.spectrum import (
    gearbox_frequencies,
    nearest_harmonic,
    parse_series,
    power_spectral_density,
    spectral_peaks,
)
from pinwind.errors import InputError
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, two_gear_urdf

RPM = 2.0 * math.pi / 60.0


@pytest.mark.parametrize("frequencies", [(12.3, 47.7, 150.2), (12.25, 47.75, 150.0)])
def test_sum_of_sines_gives_peaks_at_its_frequencies_with_its_amplitudes(frequencies):
    # On bins and halfway between bins of Δf = 0.5 Hz: the amplitude (that of the sinusoid of
    # the peak's power) does not depend on where the frequency falls.
    rate, amplitudes = 1000.0, (3.0, 1.0, 0.5)
    time = np.arange(0.0, 20.0, 1.0 / rate)
    values = 7.0 + sum(
        a * np.sin(2.0 * math.pi * f * time + k)
        for k, (a, f) in enumerate(zip(amplitudes, frequencies, strict=True))
    )
    freq, density = power_spectral_density(values, sample_rate=rate, segment_samples=2000)
    np.testing.assert_allclose(freq[1] - freq[0], 0.5, rtol=1e-12)
    peaks = spectral_peaks(freq, density, count=10)
    assert len(peaks) == 3  # nothing else: the mean is removed, the leakage is below the floor
    np.testing.assert_allclose([p.frequency for p in peaks], frequencies, atol=0.01)
    np.testing.assert_allclose([p.amplitude for p in peaks], amplitudes, rtol=1e-3)


def test_power_of_white_noise_is_its_variance():
    # Parseval: ∫ PSD df over 0..fs/2 is the variance σ² of the signal.
    rng = np.random.default_rng(7)
    values = rng.normal(0.0, 2.0, 200_000)
    freq, density = power_spectral_density(values, sample_rate=100.0, segment_samples=1000)
    np.testing.assert_allclose(np.sum(density) * (freq[1] - freq[0]), 4.0, rtol=0.02)


def test_planetary_mesh_frequency_is_ring_teeth_times_carrier_speed():
    # Sun 24, planet 48, ring 120 (fixed): the sun turns at 6 ω_c, each planet at −2.5 ω_c
    # relative to the carrier (48 ω_p = −120 ω_c), so −1.5 ω_c absolute. Every mesh passes
    # 120 ω_c / 2π teeth per second: 24 (6 − 1) ω_c at the sun, 48 · 2.5 ω_c at the ring.
    gearbox = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    carrier = 14.2 * RPM
    by_joint = {"carrier": carrier, "sun": 6.0 * carrier, "ring": 0.0}
    by_joint |= {f"planet{i}": -2.5 * carrier for i in (1, 2, 3)}
    speeds = np.array([[by_joint[name] for name in gearbox.joint_names]])
    markers = gearbox_frequencies(gearbox, speeds)
    meshes = [m for m in markers if m.kind == "mesh"]
    assert len(meshes) == 1 and len(meshes[0].names) == 6
    np.testing.assert_allclose(meshes[0].frequency, 120 * 14.2 / 60.0, rtol=1e-9)
    shafts = {m.names[0]: m.frequency for m in markers if m.kind == "shaft"}
    assert "ring" not in shafts  # a locked mount has no order
    hz = carrier / (2.0 * math.pi)
    np.testing.assert_allclose(
        [shafts["carrier"], shafts["sun"], shafts["planet2"]], [hz, 6 * hz, 1.5 * hz], rtol=1e-9
    )


def test_parallel_pair_mesh_frequency_is_teeth_times_shaft_speed():
    gearbox = loads(two_gear_urdf(), path="pair.urdf")  # 20/40 on fixed axes
    speed = 300.0 * RPM
    markers = gearbox_frequencies(gearbox, np.array([[speed, -0.5 * speed]]))
    mesh = next(m for m in markers if m.kind == "mesh")
    np.testing.assert_allclose(mesh.frequency, 20 * 300.0 / 60.0, rtol=1e-9)
    assert nearest_harmonic(2 * 100.0 + 0.3, markers, tolerance=1.0) == "2× mesh m"
    assert nearest_harmonic(5.0, markers, tolerance=0.1) == "1× shaft a"
    assert nearest_harmonic(333.0, markers, tolerance=1.0) == ""


def test_unknown_or_pose_series_is_refused_naming_the_series():
    with pytest.raises(InputError, match='unknown series "mesh_force" .*series are: .*mesh_normal'):
        parse_series("mesh_force:sun_planet1")
    with pytest.raises(InputError, match="pose rate"):
        parse_series("body_position")
    found, element = parse_series("bearing_force:carrier")
    assert found.name == "bearing_force" and element == "carrier"
