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

This is a single point. A rotor of radius R sees the average of the wind over its disc, whose
fluctuations above ≈ V / (2R) are smaller. With ``rotor_radius`` the series is that disc average
(rotor-effective wind): each Fourier amplitude of the point series is multiplied by √χ²(f), the
rotor-averaging admittance of the IEC coherence model (IEC 61400-1 ed. 3, annex B, the Kaimal
model's coherence of the longitudinal component: Coh(r, f) = exp(−12 √((f r / V)² + (0.12 r /
L_c)²)), L_c = 8.1 Λ₁, taken as the real normalised cross-spectrum, as TurbSim does). The
spectrum of the mean of u over a disc of area A is S_u(f) · (1/A²) ∬
Coh(|x − y|, f) dA_x dA_y, a double integral that depends on the distance only, so

    χ²(f) = ∫₀^{2R} p(r) Coh(r, f) dr,
    p(r) = (4 r / (π R²)) [acos(r / 2R) − (r / 2R) √(1 − (r / 2R)²)]

with p the density of the distance between two points uniformly distributed on the disc ("disk
line picking", E. W. Weisstein, MathWorld). The integral is taken by Gauss–Legendre quadrature
in φ, r = 2R sin φ, where it is smooth (p ends in (2R − r)^(3/2), which a rule in r converges to
slowly), split at the angle where Coh has fallen to e^(−50), so that a coherence confined near
r = 0 at high f R / V is resolved too; tests check it against Monte Carlo pairs of points and
against its large-f closed form 2/β² − 8/(πβ³) + 4/(πβ⁵), β = 12 R √((f/V)² + (0.12/L_c)²).
The phases stay those of the seed, so the rotor series is the point series filtered by the disc;
its variance is below σ² (the IEC σ is a point's). Rotational sampling (the 3P content a blade
sees) is not part of it: the rotor torque is an integral over the disc.

We chose a short documented synthesis over pyconturb, hipersim or mannrs, which generate full
3-D boxes (with coherence) that a single rotor-torque input does not use; a rotor-effective
series from one of them, or a hub-height channel of an OpenFAST or TurbSim run, can be given as a
table (``csv(...)``, ``openfast(..., channel="Wind1VelX")``) instead.
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


#: Gauss–Legendre nodes on each of the admittance integral's two parts in φ (r = 2R sin φ),
#: split where the coherence is e^(−_ADMITTANCE_SPLIT); see rotor_admittance for its accuracy.
#: 96 nodes in r were off by 3 % at f R / V = 210 (a 63 m rotor in 3 m/s at the default
#: series' Nyquist frequency, 10 Hz).
_ADMITTANCE_NODES = 64
_ADMITTANCE_SPLIT = 50.0


def disc_distance_density(r: np.ndarray, radius: float) -> np.ndarray:
    """p(r): density of the distance between two uniform points on a disc of ``radius`` [1/m]."""
    x = np.clip(np.asarray(r, dtype=float) / (2.0 * radius), 0.0, 1.0)
    return 4.0 * np.asarray(r) / (math.pi * radius**2) * (np.arccos(x) - x * np.sqrt(1.0 - x * x))


def iec_coherence(r: np.ndarray, f: np.ndarray, mean: float, coherence_scale: float) -> np.ndarray:
    """Coh(r, f) = exp(−12 √((f r / V)² + (0.12 r / L_c)²)) (IEC 61400-1 ed. 3, annex B)."""
    r, f = np.asarray(r, dtype=float), np.asarray(f, dtype=float)
    return np.exp(-12.0 * np.sqrt((f * r / mean) ** 2 + (0.12 * r / coherence_scale) ** 2))


def rotor_admittance(
    f: np.ndarray, *, radius: float, mean: float, coherence_scale: float
) -> np.ndarray:
    """χ²(f): spectrum of the disc-averaged wind over the point spectrum (module docstring).

    Gauss–Legendre in φ (r = 2R sin φ) on two parts split where Coh = e^(−50): within 4e-14 of
    an adaptive quadrature and within 1e-14 of the closed form 2/β² − 8/(πβ³) + 4/(πβ⁵) at
    large f R / V, up to f R / V = 1e6 (benchmarks/independent_wind.py).

    Args:
        f: frequencies [Hz].
        radius: rotor radius R [m].
        mean: mean wind speed V [m/s].
        coherence_scale: L_c [m] (IEC: 8.1 Λ₁, ``kaimal_length_scale``).
    """
    nodes, weights = np.polynomial.legendre.leggauss(_ADMITTANCE_NODES)
    f = np.asarray(f, dtype=float)
    out = np.empty(f.shape)
    flat, dest = f.reshape(-1), out.reshape(-1)
    for i in range(0, flat.size, 4096):  # bounded memory: 4096 × 2 × nodes at a time
        part = flat[i : i + 4096, None]
        # r = 2R sin φ (smooth in φ, and accurate near r = 0): Coh = exp(−big sin φ), split at
        # big sin φ_s = _ADMITTANCE_SPLIT (φ_s = π/2 when the coherence stays above e^(−50)).
        big = 24.0 * radius * np.sqrt((part / mean) ** 2 + (0.12 / coherence_scale) ** 2)
        split = np.arcsin(np.minimum(1.0, _ADMITTANCE_SPLIT / big))
        total = np.zeros(part.shape[0])
        for lo, hi in ((np.zeros_like(split), split), (split, np.full_like(split, math.pi / 2))):
            half = (hi - lo) / 2.0
            phi = lo + half * (nodes[None, :] + 1.0)
            r = 2.0 * radius * np.sin(phi)
            # p(r) dr = p(2R sin φ) 2R cos φ dφ
            w = half * weights[None, :] * disc_distance_density(r, radius) * 2.0 * radius
            w = w * np.cos(phi)
            total += np.sum(iec_coherence(r, part, mean, coherence_scale) * w, axis=1)
        dest[i : i + 4096] = total
    return out


#: The most samples of a synthesised wind series: its frequencies, amplitudes and phases are
#: arrays of this length (8 GB each at 1e9).
MAX_SAMPLES = 1e9


def kaimal_series(
    *,
    mean: float,
    turbulence_intensity: float,
    duration: float = 600.0,
    sample_time: float = 0.05,
    seed: int = 0,
    length_scale: float | None = None,
    hub_height: float = 80.0,
    rotor_radius: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(t, u): a turbulent wind-speed series [s], [m/s] (module docstring).

    Args:
        mean: V, the mean wind speed [m/s] (> 0).
        turbulence_intensity: I = σ / V (≥ 0).
        duration: T [s], rounded up to an even number of samples.
        sample_time: Δt of the series [s] (its Nyquist frequency 1 / (2 Δt)).
        seed: seed of the random phases.
        length_scale: L_u [m] of the spectrum; default from the hub height.
        hub_height: z_hub [m], for the default length scale and, always, the coherence's
            scale L_c (8.1 Λ₁ of the hub height).
        rotor_radius: R [m]: the rotor-effective (disc-averaged) series of the same seed;
            None: the point series.
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
    if duration / sample_time > MAX_SAMPLES:
        raise InputError(
            f"kaimal: duration = {duration:g} s at sample_time = {sample_time:g} s is "
            f"{duration / sample_time:.3g} samples, more than the {MAX_SAMPLES:.0e} a series "
            "holds in memory; give a shorter duration or a longer sample_time"
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
    if rotor_radius is not None:
        if not (math.isfinite(rotor_radius) and rotor_radius > 0.0):
            raise InputError(f"kaimal: rotor_radius = {rotor_radius!r} m must be positive")
        coherence_scale = kaimal_length_scale(hub_height)  # L_c = 8.1 Λ₁ (annex B)
        amplitude *= np.sqrt(
            rotor_admittance(f, radius=rotor_radius, mean=mean, coherence_scale=coherence_scale)
        )
    phase = np.random.default_rng(seed).uniform(0.0, 2.0 * math.pi, f.size)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[1:-1] = 0.5 * n * amplitude * np.exp(1j * phase)
    u = mean + np.fft.irfft(spectrum, n)
    t = np.arange(n + 1) * sample_time
    return t, np.append(u, u[0])  # periodic: the last sample closes the period


class KaimalWind(Signal):
    """A seeded Kaimal series as a signal (``kaimal(mean=10, turbulence_intensity=0.1, seed=1)``).

    With ``rotor_radius`` [m], the rotor-effective (disc-averaged) series of the same seed
    (``kaimal(..., rotor_radius=42.85)``; module docstring).

    The series is synthesised once, over ``duration`` (default 600 s; a run longer than it is
    refused, like a table's), and linearly interpolated at the run's samples.
    """

    def __init__(
        self,
        *,
        mean: float,
        turbulence_intensity: float,
        seed: int | float = 0,
        duration: float = 600.0,
        sample_time: float = 0.05,
        length_scale: float | None = None,
        hub_height: float = 80.0,
        rotor_radius: float | None = None,
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
        if rotor_radius is not None:
            self.params["rotor_radius"] = float(rotor_radius)
        t, u = kaimal_series(**self.params)
        self.table = Table(t, u, source=f"kaimal wind (seed {seed}, {duration:g} s)")
        self.end = self.table.end

    def values(self, t: np.ndarray) -> np.ndarray:
        """Wind speed [m/s] at times t [s]."""
        return self.table.values(t)

    def spec(self) -> dict[str, Any]:
        """``{"type": "kaimal", ...}``."""
        return {"type": "kaimal", **self.params}
