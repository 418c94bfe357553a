"""Turbulent hub-height wind speed with the IEC 61400-1 Kaimal spectrum, seeded.

Longitudinal spectrum (IEC 61400-1 ed. 3, annex B, table B.1: Kaimal):

    S_u(f) = 4 σ² (L_u / V) / (1 + 6 f L_u / V)^(5/3),   L_u = 8.1 Λ₁,
    Λ₁ = 0.7 z_hub for z_hub ≤ 60 m, else 42 m,          σ = I · V

Synthesis (Shinozuka's spectral representation with deterministic amplitudes): on the frequencies
f_k = k / T, k = 1 … N/2 − 1, of a series of N samples of ``sample_time`` over T = ``duration``,

    u(t) = V + Σ_k A_k cos(2π f_k t + φ_k),   A_k = c √(2 S_u(f_k) Δf),  φ_k ~ U(0, 2π) seeded,

summed by one inverse FFT. c scales the variance of the finite series to σ² exactly: the variance
below 1/T (the 10-minute mean's own fluctuations, about 18 % of σ² for L_u/V = 34 s) is, by the
IEC definition of σ over 10 minutes, not part of the turbulence, and TurbSim does the same. The
mean of the series is V exactly (no term at f = 0), and the same seed gives the same series on
any machine (NumPy's PCG64).

This is a single point: a rotor of 86 m sees the rotor average, whose fluctuations above
≈ V / (2R) are smaller. We chose a short documented synthesis over pyconturb, hipersim or mannrs,
which generate full 3-D boxes (with coherence) that a single rotor-torque input does not use; a
rotor-effective series from one of them, or a hub-height channel of an OpenFAST or TurbSim run,
can be given as a table (``csv(...)``, ``openfast(..., channel="Wind1VelX")``) instead.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pinwind.errors import InputError
from pinwind.loads.signals import Signal, Table


def kaimal_length_scale(hub_height: float) -> float:
    """L_u = 8.1 Λ₁ [m] (IEC 61400-1 ed. 3 §6.3: Λ₁ = 0.7 z for z ≤ 60 m, else 42 m)."""
    return 8.1 * (0.7 * hub_height if hub_height <= 60.0 else 42.0)


def kaimal_spectrum(f: np.ndarray, mean: float, sigma: float, length_scale: float) -> np.ndarray:
    """One-sided Kaimal spectrum S_u(f) [(m/s)²/Hz] at frequencies f [Hz]."""
    ratio = length_scale / mean
    return 4.0 * sigma**2 * ratio / (1.0 + 6.0 * np.asarray(f) * ratio) ** (5.0 / 3.0)


def kaimal_series(
    *,
    mean: float,
    turbulence_intensity: float,
    duration: float = 600.0,
    sample_time: float = 0.05,
    seed: int = 0,
    length_scale: float | None = None,
    hub_height: float = 80.0,
) -> tuple[np.ndarray, np.ndarray]:
    """(t, u): a turbulent wind-speed series [s], [m/s] (module docstring).

    Args:
        mean: V, the mean wind speed [m/s] (> 0).
        turbulence_intensity: I = σ / V (≥ 0).
        duration: T [s].
        sample_time: Δt of the series [s] (its Nyquist frequency 1 / (2 Δt)).
        seed: seed of the random phases.
        length_scale: L_u [m]; default from the hub height.
        hub_height: z_hub [m], for the default length scale.
    """
    if not mean > 0.0 or not turbulence_intensity >= 0.0:
        raise InputError(
            f"kaimal: mean = {mean:g} m/s must be > 0 and turbulence_intensity = "
            f"{turbulence_intensity:g} ≥ 0"
        )
    if not duration > 0.0 or not 0.0 < sample_time <= duration / 4:
        raise InputError(
            f"kaimal: duration = {duration:g} s and sample_time = {sample_time:g} s must be "
            "positive, with at least four samples"
        )
    n = 2 * math.ceil(duration / sample_time / 2)  # even
    big_t = n * sample_time
    lu = kaimal_length_scale(hub_height) if length_scale is None else float(length_scale)
    sigma = turbulence_intensity * mean
    f = np.arange(1, n // 2) / big_t  # no term at 0 (the mean) nor at Nyquist
    amplitude = np.sqrt(2.0 * kaimal_spectrum(f, mean, sigma, lu) / big_t)
    variance = 0.5 * np.sum(amplitude**2)
    if variance > 0:
        amplitude *= sigma / math.sqrt(variance)
    phase = np.random.default_rng(seed).uniform(0.0, 2.0 * math.pi, f.size)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[1:-1] = 0.5 * n * amplitude * np.exp(1j * phase)
    u = mean + np.fft.irfft(spectrum, n)
    t = np.arange(n + 1) * sample_time
    return t, np.append(u, u[0])  # periodic: the last sample closes the period


class KaimalWind(Signal):
    """A seeded Kaimal series as a signal (``kaimal(mean=10, turbulence_intensity=0.1, seed=1)``).

    The series is synthesised once, over ``duration`` (default 600 s; a run longer than it is
    refused, like a table's), and linearly interpolated at the run's samples.
    """

    def __init__(
        self,
        *,
        mean: float,
        turbulence_intensity: float,
        seed: int = 0,
        duration: float = 600.0,
        sample_time: float = 0.05,
        length_scale: float | None = None,
        hub_height: float = 80.0,
    ):
        if isinstance(seed, float) and seed.is_integer():
            seed = int(seed)
        if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
            raise InputError(f"kaimal: seed must be a whole number ≥ 0; got {seed!r}")
        self.params: dict[str, Any] = {
            "mean": float(mean),
            "turbulence_intensity": float(turbulence_intensity),
            "seed": seed,
            "duration": float(duration),
            "sample_time": float(sample_time),
            "hub_height": float(hub_height),
        }
        if length_scale is not None:
            self.params["length_scale"] = float(length_scale)
        t, u = kaimal_series(**self.params)
        self.table = Table(t, u, source=f"kaimal wind (seed {seed}, {duration:g} s)")
        self.end = self.table.end

    def values(self, t: np.ndarray) -> np.ndarray:
        """Wind speed [m/s] at times t [s]."""
        return self.table.values(t)

    def spec(self) -> dict[str, Any]:
        """``{"type": "kaimal", ...}``."""
        return {"type": "kaimal", **self.params}
