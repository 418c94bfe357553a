"""The turbulent wind and the rotor-averaged inflow recoded from the docs and IEC 61400-1, and
compared with ``pinwind.loads.wind``.

Written from docs/loads.md ("Wind"), docs/fatigue.md, docs/validation.md, the scenario files and
the module's and functions' docstrings (what ``help(pinwind.loads.wind)`` prints), with public
sources; pinwind's wind code was read only after the numbers below existed.

Recoded (SI units; frequencies f in Hz, one-sided spectra in (m/s)²/Hz):

- Integral length scale (IEC 61400-1 ed. 3 §6.3 and annex B): L_u = 8.1 Λ₁, Λ₁ = 0.7 min(z, 60 m).
- Normal turbulence model (IEC 61400-1 ed. 3 §6.3.1.3 eq. 11): σ₁ = I_ref (0.75 V + 5.6 m/s),
  I_ref = 0.16, 0.14, 0.12 for classes A, B, C (ed. 3 Table 1), 0.18 for A+ (ed. 4 Table 1).
- Kaimal spectrum (IEC 61400-1 ed. 3 annex B eq. B.14, Table B.1): S_u(f) = 4 σ² (L_u/V) /
  (1 + 6 f L_u/V)^(5/3); ∫₀^∞ S_u df = σ², and ∫₀^{f₀} S_u df = σ² (1 − (1 + 6 f₀ L_u/V)^(−2/3)).
- IEC coherence (ed. 3 annex B eq. B.16): Coh(r, f) = exp(−12 √((f r/V)² + (0.12 r/L_c)²)),
  L_c = 8.1 Λ₁, the normalised cross-spectrum |S₁₂| / √(S₁₁ S₂₂) (Burton et al. 2011 eq. 2.33).
  It is exp(−b r) with b = 12 √((f/V)² + (0.12/L_c)²).
- Rotor-averaged (disc) spectrum: the mean of u over a disc of area A = πR² has the spectrum
  S_u(f) χ²(f), χ²(f) = A⁻² ∬ Coh(|x − y|, f) dA_x dA_y (the cross-spectra averaged, Veers 1988
  takes them as real; Burton et al. 2011 §5.7.4 "rotor-averaged wind"). Two routes, each by
  adaptive quadrature (SciPy ``quad``, relative tolerance 1e-13):

  1. By the separation r: the density of |x − y| is p(r) = 2π r a(r)/A², a(r) the area of the
     lens where the disc and its copy shifted by r overlap, a(r) = 2R² acos(r/2R) − (r/2)
     √(4R² − r²) (the disc's autocorrelation). With r = 2R cos θ the integral is over θ in
     [0, π/2] of (16/π) sin θ cos θ (θ − sin θ cos θ) e^(−2 b R cos θ), smooth (p itself ends
     in (2R − r)^(3/2)).
  2. By the wavenumber (Parseval): the 2-D Fourier transform of e^(−b r) is 2π b/(b² + k²)^(3/2),
     the disc's is A · 2 J₁(kR)/(kR), so χ² = ∫₀^∞ β x (2 J₁(x)/x)² / (β² + x²)^(3/2) dx with
     β = b R; taken between the zeros of J₁ up to x = 4000 (the tail is below β / (π 4000⁴)).

- The series (module docstring): N samples of Δt (N even, the series periodic: pinwind returns
  N + 1 samples, the last equal to the first), lines f_k = k/(N Δt), k = 1 … N/2 − 1, amplitudes
  A_k = c √(2 S_u(f_k) Δf) with c² = σ² / Σ_k S_u(f_k) Δf (the variance of the finite series is
  Σ A_k²/2 = σ² exactly, since the lines are orthogonal over the N samples), phases uniform.
  So the mean is V and the standard deviation σ exactly, every seed; the periodogram
  2 |DFT_k|² / (f_s N) at f_k is A_k² / (2 Δf) = c² S_u(f_k) exactly; the disc series' is
  c² S_u(f_k) χ²(f_k) and its standard deviation σ_disc = √(Σ A_k² χ²(f_k) / 2).
- Welch over seeds (scipy.signal.welch, Hann of 1024 samples, half overlap, no detrending,
  averaged over seeds): its expectation for the random-phase line spectrum is exactly
  E P(f_m) = 2 / (f_s Σw²) Σ_k (A_k²/4) (|W(ω_m − ω_k)|² + |W(ω_m + ω_k)|²), W the Hann window's
  DTFT (a sum of three Dirichlet kernels): the cross terms of independent uniform phases vanish.
  Tolerance: the seeds' own standard error per frequency (the seeds are independent); the
  deviations divided by it, z, are compared with a standard normal: their maximum over the 511
  frequencies below 5 (a normal exceeds it with probability 3e-4 there; 4.5 would be 3.5e-3,
  and the seeds 1-200 give 4.77 at 2.29 Hz, where seeds 201-400 give 0.8 and 1.3 per hundred and
  seeds 401-1000 0.86: a chance excess, not a line), their root mean square within 1 ± 0.15.

Compared: ``kaimal_length_scale``, ``kaimal_spectrum``, ``iec_coherence``,
``disc_distance_density``, ``rotor_admittance`` (public functions of ``pinwind.loads.wind``),
``kaimal_series`` and ``KaimalWind`` (the signal the rotor reads), and
``pinwind.life.site.ntm_turbulence``.

Run:  python benchmarks/independent_wind.py [--seeds 200]    (about 40 s; 15 s with --seeds 50)
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.integrate
import scipy.signal
import scipy.special

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

#: IEC 61400-1 reference turbulence intensity I_ref per class (ed. 3 Table 1; A+ ed. 4 Table 1).
I_REF = {"A+": 0.18, "A": 0.16, "B": 0.14, "C": 0.12}


# ---------------------------------------------------------------------------------------------
# IEC 61400-1 formulas
# ---------------------------------------------------------------------------------------------


def length_scale(hub_height: float) -> float:
    """L_u = 8.1 Λ₁ [m], Λ₁ = 0.7 min(z, 60 m) (IEC 61400-1 ed. 3 §6.3, eq. B.14's L_k)."""
    return 8.1 * 0.7 * min(hub_height, 60.0)


def ntm_sigma(speed: float, turbulence_class: str) -> float:
    """σ₁ = I_ref (0.75 V + 5.6 m/s) [m/s] (IEC 61400-1 ed. 3 §6.3.1.3 eq. 11)."""
    return I_REF[turbulence_class] * (0.75 * speed + 5.6)


def kaimal(f: np.ndarray, mean: float, sigma: float, length: float) -> np.ndarray:
    """One-sided Kaimal spectrum [(m/s)²/Hz] (IEC 61400-1 ed. 3 eq. B.14)."""
    x = length / mean
    return 4.0 * sigma**2 * x / (1.0 + 6.0 * np.asarray(f, dtype=float) * x) ** (5.0 / 3.0)


def kaimal_band_fraction(f0: float, mean: float, length: float) -> float:
    """∫₀^{f0} S_u df / σ² = 1 − (1 + 6 f0 L/V)^(−2/3) (the spectrum integrated by hand)."""
    return 1.0 - (1.0 + 6.0 * f0 * length / mean) ** (-2.0 / 3.0)


def coherence(r: np.ndarray, f: float, mean: float, lc: float) -> np.ndarray:
    """IEC coherence exp(−12 √((f r/V)² + (0.12 r/L_c)²)) (ed. 3 eq. B.16)."""
    r = np.asarray(r, dtype=float)
    return np.exp(-12.0 * np.sqrt((f * r / mean) ** 2 + (0.12 * r / lc) ** 2))


def decay(f: float, mean: float, lc: float) -> float:
    """b [1/m] of Coh = exp(−b r)."""
    return 12.0 * math.sqrt((f / mean) ** 2 + (0.12 / lc) ** 2)


def distance_density(r: np.ndarray, radius: float) -> np.ndarray:
    """p(r) = 2π r a(r) / A² [1/m], a(r) the overlap (lens) area of two discs r apart."""
    r = np.asarray(r, dtype=float)
    rr = np.clip(r, 0.0, 2.0 * radius)
    lens = 2 * radius**2 * np.arccos(rr / (2 * radius)) - rr / 2 * np.sqrt(4 * radius**2 - rr**2)
    return np.where(r <= 2 * radius, 2 * np.pi * rr * lens / (np.pi * radius**2) ** 2, 0.0)


def admittance_by_separation(f: float, radius: float, mean: float, lc: float) -> float:
    """χ²(f) by route 1 (the separation's density, r = 2R cos θ)."""
    two_b_r = 2.0 * decay(f, mean, lc) * radius

    def integrand(th: float) -> float:
        s, c = math.sin(th), math.cos(th)
        return 16.0 / math.pi * s * c * (th - s * c) * math.exp(-two_b_r * c)

    # The weight sits at θ → π/2 (r → 0) when b R is large: split there.
    edge = max(0.0, math.pi / 2 - 40.0 / max(two_b_r, 1e-300))
    points = [p for p in (edge, math.pi / 2 - 1.0 / max(two_b_r, 1e-300)) if 0 < p < math.pi / 2]
    with warnings.catch_warnings():  # at f R / V ≫ 1e3 quad reports its roundoff (2e-12 there)
        warnings.simplefilter("ignore", scipy.integrate.IntegrationWarning)
        val, _ = scipy.integrate.quad(
            integrand, 0.0, math.pi / 2, epsabs=0.0, epsrel=2e-14, limit=500, points=points or None
        )
    return float(val)


def admittance_by_wavenumber(f: float, radius: float, mean: float, lc: float) -> float:
    """χ²(f) by route 2 (Parseval over the wavenumber, x = kR): Gauss–Legendre of 24 nodes on
    each interval between the zeros of J₁ up to X = 20 000 (analytic there), the intervals
    below 10 β split geometrically (the weight β x/(β² + x²)^(3/2) peaks at x = β/√2), and the
    tail beyond X from J₁(x)² ≈ (1 − sin 2x)/(π x): β/(π X⁴)."""
    beta = decay(f, mean, lc) * radius
    top = 20000.0
    zeros = scipy.special.jn_zeros(1, int(top / math.pi) + 2)
    zeros = zeros[zeros < top]
    fine = np.geomspace(beta * 1e-4, 10 * beta, 200)
    edges = np.unique(np.concatenate([[0.0], zeros, fine[fine < top], [top]]))
    x, w = np.polynomial.legendre.leggauss(24)
    lo, hi = edges[:-1, None], edges[1:, None]
    xs = (hi - lo) / 2 * x + (hi + lo) / 2
    jinc = 2 * scipy.special.j1(xs) / xs
    g = beta * xs * jinc**2 / (beta**2 + xs**2) ** 1.5
    total = float(np.sum((hi - lo)[:, 0] / 2 * (g @ w)))
    return total + beta / (math.pi * top**4)


# ---------------------------------------------------------------------------------------------
# The series, recoded from the module docstring
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Lines:
    """The spectral lines of a series: f_k [Hz], A_k [m/s], the scale c, Δf [Hz]."""

    f: np.ndarray
    amplitude: np.ndarray
    c: float
    df: float
    n: int
    sample_time: float


def lines(
    *, mean: float, sigma: float, length: float, n: int, sample_time: float, chi2=None
) -> Lines:
    """A_k = c √(2 S_u(f_k) Δf), k = 1 … N/2 − 1, c² = σ² / Σ S_u(f_k) Δf; with ``chi2``
    (values at f_k) the disc series' A_k √χ²(f_k)."""
    df = 1.0 / (n * sample_time)
    f = np.arange(1, n // 2) * df
    s = kaimal(f, mean, sigma, length)
    c = math.sqrt(sigma**2 / float(np.sum(s) * df))
    a = c * np.sqrt(2.0 * s * df)
    if chi2 is not None:
        a = a * np.sqrt(chi2)
    return Lines(f, a, c, df, n, sample_time)


def periodogram(u: np.ndarray, n: int, sample_time: float) -> np.ndarray:
    """One-sided periodogram 2 |DFT_k|² Δt / N at k = 1 … N/2 − 1 [(m/s)²/Hz]."""
    x = np.fft.rfft(u[:n] - np.mean(u[:n]))
    return (2.0 * np.abs(x[1 : n // 2]) ** 2 * sample_time / n).astype(float)


def hann_dtft_sq(omega: np.ndarray, m: int) -> np.ndarray:
    """|W(ω)|² of the periodic Hann window of m samples, w = ½ − ½ cos(2π n/m)."""

    def dirichlet(w: np.ndarray) -> np.ndarray:
        # Σ_{n<m} e^{−i w n} = e^{−i w (m−1)/2} sin(m w/2)/sin(w/2)
        half = np.sin(w / 2)
        small = np.abs(half) < 1e-12
        ratio = np.sin(m * w / 2) / np.where(small, 1.0, half)
        # at w = 2π j the ratio's limit is m (−1)^(j (m − 1))
        j = np.round(w / (2 * np.pi))
        limit = m * np.where((j * (m - 1)) % 2 == 0, 1.0, -1.0)
        ratio = np.where(small, limit, ratio)
        return ratio * np.exp(-1j * w * (m - 1) / 2)

    step = 2 * np.pi / m
    w = 0.5 * dirichlet(omega) - 0.25 * dirichlet(omega - step) - 0.25 * dirichlet(omega + step)
    return np.abs(w) ** 2


def expected_welch(ln: Lines, nperseg: int) -> tuple[np.ndarray, np.ndarray]:
    """(f_m, E P(f_m)) of scipy's Welch estimate (Hann, no detrend, one-sided) of the line
    process with uniform independent phases, m = 1 … nperseg/2 − 1."""
    fs = 1.0 / ln.sample_time
    m = np.arange(1, nperseg // 2)
    wm = 2 * np.pi * m / nperseg
    wk = 2 * np.pi * ln.f * ln.sample_time
    win = scipy.signal.get_window("hann", nperseg)
    s2 = float(np.sum(win**2))
    out = np.empty(len(m))
    quarter = ln.amplitude**2 / 4
    for i, w in enumerate(wm):
        out[i] = np.sum(quarter * (hann_dtft_sq(w - wk, nperseg) + hann_dtft_sq(w + wk, nperseg)))
    return m * fs / nperseg, 2.0 / (fs * s2) * out


# ---------------------------------------------------------------------------------------------
# Comparisons
# ---------------------------------------------------------------------------------------------


@dataclass
class Row:
    quantity: str
    pinwind: float
    recoded: float
    difference: float
    tolerance: float
    why: str

    @property
    def ok(self) -> bool:
        return abs(self.difference) <= self.tolerance


def rel(a: np.ndarray, b: np.ndarray) -> float:
    """max |a − b| / max |b|."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


#: Cases of the admittance: (R [m], V [m/s], hub height [m]): the shipped scenarios' rotors.
ADMITTANCE_CASES = (
    (42.85, 10.0, 80.0),  # saleh2017 rotor, docs/loads.md's example
    (63.0, 13.0, 90.0),  # scenarios/nrel5mw_turbulent.toml
    (20.5, 6.0, 36.0),  # scenarios/dtu500_fatigue.toml, lowest bin
    (20.5, 20.0, 36.0),  # and highest
)
ADMITTANCE_F = np.concatenate([[0.0], np.geomspace(1e-3, 10.0, 25)])


def admittance_rows(cases=ADMITTANCE_CASES, freqs=ADMITTANCE_F) -> tuple[list[Row], dict]:
    from pinwind.loads import wind

    rows: list[Row] = []
    worst_routes = 0.0
    worst = {"abs": 0.0, "rel": 0.0, "at": None}
    for radius, mean, z in cases:
        lc = length_scale(z)
        one = np.array([admittance_by_separation(f, radius, mean, lc) for f in freqs])
        two = np.array([admittance_by_wavenumber(f, radius, mean, lc) for f in freqs])
        worst_routes = max(worst_routes, float(np.max(np.abs(one - two) / one)))
        pw = np.asarray(
            wind.rotor_admittance(freqs, radius=radius, mean=mean, coherence_scale=lc), float
        )
        d = np.abs(pw - one)
        i = int(np.argmax(d / one))
        if d[i] / one[i] > worst["rel"]:
            worst = {
                "abs": float(np.max(d)),
                "rel": float(d[i] / one[i]),
                "at": (radius, mean, freqs[i]),
            }
        rows.append(
            Row(
                f"χ²(f), R {radius:g} m, V {mean:g} m/s, z {z:g} m (max |Δ|, f 0-10 Hz)",
                float(pw[i]),
                float(one[i]),
                float(np.max(d)),
                1e-12,
                "route 1's own accuracy",
            )
        )
    return rows, {"routes": worst_routes, "worst": worst}


def deterministic_rows() -> list[Row]:
    from pinwind.life.site import ntm_turbulence
    from pinwind.loads import wind

    rows: list[Row] = []
    zs = [10.0, 36.0, 59.9, 60.0, 80.0, 90.0, 150.0]
    mine = np.array([length_scale(z) for z in zs])
    theirs = np.array([wind.kaimal_length_scale(z) for z in zs])
    rows.append(
        Row(
            "L_u = 8.1·0.7·min(z, 60) [m], z 10-150 m",
            theirs[-1],
            mine[-1],
            rel(theirs, mine),
            1e-15,
            "rounding",
        )
    )
    speeds = np.array([3.0, 6.0, 10.0, 13.0, 15.0, 25.0])
    for cls in ("A+", "A", "B", "C"):
        ti = np.asarray(ntm_turbulence(speeds, turbulence_class=cls), float)
        mine_ti = np.array([ntm_sigma(v, cls) / v for v in speeds])
        rows.append(
            Row(
                f"NTM I = σ₁/V, class {cls}, 3-25 m/s",
                float(ti[3]),
                float(mine_ti[3]),
                rel(ti, mine_ti),
                1e-15,
                "rounding",
            )
        )
    f = np.concatenate([[0.0], np.geomspace(1e-4, 20.0, 60)])
    for mean, sigma, length in ((10.0, 1.0, 340.2), (13.0, 2.149, 340.2), (6.0, 0.48, 204.12)):
        s_p = np.asarray(wind.kaimal_spectrum(f, mean, sigma, length), float)
        s_m = kaimal(f, mean, sigma, length)
        rows.append(
            Row(
                f"S_u(f) V {mean:g}, σ {sigma:g}, L {length:g}, f 0-20 Hz (rel.)",
                float(s_p[0]),
                float(s_m[0]),
                rel(s_p, s_m),
                1e-14,
                "rounding",
            )
        )
    r = np.linspace(0.0, 130.0, 200)
    for fq in (0.0, 0.05, 1.0):
        c_p = np.asarray(wind.iec_coherence(r, np.full_like(r, fq), 13.0, 340.2), float)
        c_m = coherence(r, fq, 13.0, 340.2)
        rows.append(
            Row(
                f"Coh(r, {fq:g} Hz), r 0-130 m (rel.)",
                float(c_p[50]),
                float(c_m[50]),
                rel(c_p, c_m),
                1e-14,
                "rounding",
            )
        )
    for radius in (20.5, 63.0):
        rr = np.linspace(0.0, 2 * radius, 301)
        p_p = np.asarray(wind.disc_distance_density(rr, radius), float)
        p_m = distance_density(rr, radius)
        rows.append(
            Row(
                f"p(r), R {radius:g} m (rel. to max)",
                float(p_p[100]),
                float(p_m[100]),
                rel(p_p, p_m),
                1e-14,
                "lens area vs MathWorld form",
            )
        )
    return rows


@dataclass
class SeriesCase:
    name: str
    mean: float
    ti: float
    duration: float
    sample_time: float
    hub_height: float
    radius: float | None


SERIES_CASES = (
    SeriesCase("point, 10 m/s, I 0.1, 600 s", 10.0, 0.1, 600.0, 0.05, 80.0, None),
    SeriesCase("disc R 42.85, 10 m/s, 600 s", 10.0, 0.1, 600.0, 0.05, 80.0, 42.85),
    SeriesCase("nrel5mw_turbulent (disc R 63)", 13.0, 0.1653077, 600.0, 0.05, 90.0, 63.0),
    SeriesCase("a 30 s series, 10 m/s, disc R 20.5, z 36", 10.0, 0.10, 30.0, 0.05, 36.0, 20.5),
)


def series(case: SeriesCase, seed: int) -> tuple[np.ndarray, np.ndarray]:
    from pinwind.loads.wind import kaimal_series

    return kaimal_series(
        mean=case.mean,
        turbulence_intensity=case.ti,
        duration=case.duration,
        sample_time=case.sample_time,
        seed=seed,
        hub_height=case.hub_height,
        rotor_radius=case.radius,
    )


def case_lines(case: SeriesCase, n: int) -> tuple[Lines, np.ndarray]:
    """The recoded lines of ``case`` (N samples) and χ² at its f_k (ones for a point)."""
    sigma = case.ti * case.mean
    length = length_scale(case.hub_height)
    df = 1.0 / (n * case.sample_time)
    fk = np.arange(1, n // 2) * df
    if case.radius is None:
        chi2 = np.ones_like(fk)
    else:
        chi2 = admittance_on(fk, case.radius, case.mean, length)
    return lines(
        mean=case.mean, sigma=sigma, length=length, n=n, sample_time=case.sample_time, chi2=chi2
    ), chi2


def admittance_on(f: np.ndarray, radius: float, mean: float, lc: float) -> np.ndarray:
    """χ² at many frequencies: route 1 by Gauss–Legendre in θ (smooth integrand), 400 nodes
    split at the weight's edge; checked against ``admittance_by_separation`` at a few points."""
    x, w = np.polynomial.legendre.leggauss(400)
    out = np.empty(len(f))
    for i, fq in enumerate(f):
        two_b_r = 2 * decay(fq, mean, lc) * radius
        edge = max(0.0, math.pi / 2 - 60.0 / two_b_r)
        total = 0.0
        for a, b in ((0.0, edge), (edge, math.pi / 2)):
            if b <= a:
                continue
            th = (b - a) / 2 * x + (a + b) / 2
            s, c = np.sin(th), np.cos(th)
            g = 16 / math.pi * s * c * (th - s * c) * np.exp(-two_b_r * c)
            total += (b - a) / 2 * float(np.dot(w, g))
        out[i] = total
    return out


def recoded_series(ln: Lines, mean: float, seed: int, t: np.ndarray) -> np.ndarray:
    """u(t_j) = V + Σ_k A_k cos(2π k j / N + φ_k) at t_j = j Δt, summed directly (no FFT; the
    argument reduced exactly, k j mod N in integers), φ_k the first N/2 − 1 draws of NumPy's
    ``default_rng(seed).uniform(0, 2π)`` (the docstring's "φ_k ~ U(0, 2π) seeded ... NumPy's
    PCG64", read as the plain call)."""
    phase = np.random.default_rng(seed).uniform(0.0, 2 * np.pi, len(ln.f))
    j = np.rint(np.asarray(t) / ln.sample_time).astype(np.int64)
    k = np.arange(1, len(ln.f) + 1, dtype=np.int64)
    u = np.full(len(j), float(mean))
    for lo in range(0, len(k), 500):
        sl = slice(lo, lo + 500)
        arg = 2 * np.pi * (np.outer(j, k[sl]) % ln.n) / ln.n + phase[sl]
        u += np.cos(arg) @ ln.amplitude[sl]
    return u


def series_rows(case: SeriesCase, seeds: int) -> tuple[list[Row], dict]:
    rows: list[Row] = []
    t, u = series(case, 1)
    n = len(t) - 1
    ln, chi2 = case_lines(case, n)
    sigma = case.ti * case.mean
    check = (
        [
            admittance_by_separation(ff, case.radius, case.mean, length_scale(case.hub_height))
            for ff in ln.f[[0, 10, 100]]
        ]
        if case.radius
        else None
    )
    if check is not None:
        assert np.allclose(check, chi2[[0, 10, 100]], rtol=1e-12, atol=1e-15), (
            check,
            chi2[[0, 10, 100]],
        )
    target_sd = float(np.sqrt(np.sum(ln.amplitude**2) / 2))
    # The disc series carry pinwind's χ², within 2e-13 of the recoded one (the χ² rows): their
    # amplitudes, standard deviation and periodogram agree to that, a point's to rounding.
    tol = 1e-12
    rec = recoded_series(ln, case.mean, 1, t)
    if case.radius is not None:
        # The same lines with pinwind's χ²: what is left is rounding.
        from pinwind.loads.wind import rotor_admittance

        theirs = rotor_admittance(
            ln.f, radius=case.radius, mean=case.mean, coherence_scale=length_scale(case.hub_height)
        )
        with_theirs = Lines(
            ln.f, ln.amplitude * np.sqrt(theirs / chi2), ln.c, ln.df, n, ln.sample_time
        )
        dev = float(np.max(np.abs(u - recoded_series(with_theirs, case.mean, 1, t))) / sigma)
        rows.append(
            Row(
                f"{case.name}: u(t) recoded with pinwind's χ², max |Δu| / σ",
                dev,
                0.0,
                dev,
                1e-12,
                "rounding",
            )
        )
    rows.append(
        Row(
            f"{case.name}: u(t) recoded, seed 1, max |Δu| / σ",
            float(u[n // 3]),
            float(rec[n // 3]),
            float(np.max(np.abs(u - rec)) / sigma),
            tol,
            "direct sum vs inverse FFT",
        )
    )
    rows.append(
        Row(
            f"{case.name}: periodic (u[N] = u[0])",
            float(u[-1]),
            float(u[0]),
            float(u[-1] - u[0]),
            1e-12,
            "rounding",
        )
    )
    rows.append(
        Row(
            f"{case.name}: mean [m/s]",
            float(np.mean(u[:n])),
            case.mean,
            float(np.mean(u[:n]) - case.mean),
            1e-12,
            "no f = 0 line; rounding",
        )
    )
    rows.append(
        Row(
            f"{case.name}: std [m/s] (target √ΣA²/2)",
            float(np.std(u[:n])),
            target_sd,
            float(np.std(u[:n]) - target_sd),
            tol * sigma,
            "deterministic amplitudes",
        )
    )
    if case.radius is not None:
        rows.append(
            Row(
                f"{case.name}: std / σ",
                float(np.std(u[:n]) / sigma),
                target_sd / sigma,
                float(np.std(u[:n]) - target_sd) / sigma,
                tol,
                "the disc's variance ratio",
            )
        )
    per = periodogram(u, n, case.sample_time)
    target = ln.amplitude**2 / (2 * ln.df)
    rows.append(
        Row(
            f"{case.name}: periodogram / c²S_uχ² − 1, every f_k",
            float(per[0]),
            float(target[0]),
            float(np.max(np.abs(per / target - 1))),
            1e-9,
            "FFT rounding on lines 1e-9 of the peak",
        )
    )
    # Seeds: the same seed twice, and another seed differs.
    t2, u2 = series(case, 1)
    _, u3 = series(case, 2)
    rows.append(
        Row(
            f"{case.name}: seed 1 twice, max |Δu|",
            float(np.max(np.abs(u2 - u))),
            0.0,
            float(np.max(np.abs(u2 - u))),
            0.0,
            "bit for bit",
        )
    )
    rows.append(
        Row(
            f"{case.name}: seed 2 vs 1, rms Δu / (√2 σ_series)",
            float(np.std(u3 - u) / (math.sqrt(2) * target_sd)),
            1.0,
            float(np.std(u3 - u) / (math.sqrt(2) * target_sd)) - 1.0,
            0.5,
            "independent phases",
        )
    )
    info: dict = {"n": n, "c2": ln.c**2, "sd": target_sd}
    if n >= 4096 and seeds > 1:
        info.update(welch_check(case, ln, n, seeds))
        rows.append(
            Row(
                f"{case.name}: Welch {seeds} seeds, max |z| over {info['bins']} f",
                info["max_z"],
                0.0,
                info["max_z"],
                5.0,
                "P(max|z|>5 of 511 N(0,1)) 3e-4",
            )
        )
        rows.append(
            Row(
                f"{case.name}: Welch {seeds} seeds, rms z",
                info["rms_z"],
                1.0,
                info["rms_z"] - 1.0,
                0.15,
                "z ~ N(0, 1)",
            )
        )
    return rows, info


def welch_check(case: SeriesCase, ln: Lines, n: int, seeds: int, nperseg: int = 1024) -> dict:
    fs = 1.0 / case.sample_time
    est = []
    for s in range(1, seeds + 1):
        _, u = series(case, s)
        f, p = scipy.signal.welch(
            u[:n] - case.mean,
            fs=fs,
            window="hann",
            nperseg=nperseg,
            noverlap=nperseg // 2,
            detrend=False,
        )
        est.append(p[1 : nperseg // 2])
    e = np.array(est)
    fm, expected = expected_welch(ln, nperseg)
    mean_est = e.mean(axis=0)
    se = e.std(axis=0, ddof=1) / math.sqrt(seeds)
    z = (mean_est - expected) / se
    # How far the window's expectation is from the line spectrum's own density (bias of Welch).
    kaimal_at = ln.c**2 * kaimal(fm, case.mean, case.ti * case.mean, length_scale(case.hub_height))
    if case.radius is not None:
        kaimal_at = kaimal_at * admittance_on(
            fm, case.radius, case.mean, length_scale(case.hub_height)
        )
    band = fm >= 4 * fs / nperseg
    bias = np.abs(expected / kaimal_at - 1)
    segments = (n - nperseg) // (nperseg // 2) + 1
    return {
        "bins": len(z),
        "max_z": float(np.max(np.abs(z))),
        "rms_z": float(np.sqrt(np.mean(z**2))),
        "rel_se_median": float(np.median(se / expected)),
        "gaussian_rel_se": math.sqrt(1.056 / (segments * seeds)),
        "bias_above_4_bins": float(np.max(bias[band])),
        "bias_at_hz": float(fm[band][np.argmax(bias[band])]),
        "bias_below_5hz": float(np.max(bias[band & (fm <= 5.0)])),
        "mean_rel_dev_median": float(np.median(np.abs(mean_est / expected - 1))),
    }


def signal_rows() -> list[Row]:
    """KaimalWind (the signal a run reads) against kaimal_series: at the samples and between."""
    from pinwind.loads.wind import KaimalWind, kaimal_series

    w = KaimalWind(
        mean=13.0,
        turbulence_intensity=0.1653077,
        seed=1,
        duration=600.0,
        hub_height=90.0,
        rotor_radius=63.0,
    )
    t, u = kaimal_series(
        mean=13.0,
        turbulence_intensity=0.1653077,
        seed=1,
        duration=600.0,
        hub_height=90.0,
        rotor_radius=63.0,
    )
    at = np.asarray(w.values(t), float)
    mid = np.asarray(w.values(t[:-1] + 0.3 * np.diff(t)), float)
    lin = u[:-1] + 0.3 * np.diff(u)
    return [
        Row(
            "KaimalWind at the samples vs kaimal_series",
            float(at[7]),
            float(u[7]),
            float(np.max(np.abs(at - u))),
            1e-12,
            "same series",
        ),
        Row(
            "KaimalWind between samples vs linear interp.",
            float(mid[7]),
            float(lin[7]),
            float(np.max(np.abs(mid - lin))),
            1e-12,
            "docstring: linear",
        ),
    ]


def convention_rows() -> list[Row]:
    """Which L_c a disc series takes when ``length_scale`` is given: the periodogram ratio of
    the disc series to the point series of the same seed is χ²(f_k); compared with χ² at
    L_c = 8.1 Λ₁ of the hub height and at L_c = the given L_u."""
    from pinwind.loads.wind import kaimal_series

    kw = dict(
        mean=10.0,
        turbulence_intensity=0.1,
        duration=600.0,
        seed=3,
        hub_height=80.0,
        length_scale=500.0,
    )
    t, point = kaimal_series(**kw)
    _, disc = kaimal_series(**kw, rotor_radius=42.85)
    n = len(t) - 1
    ratio = periodogram(disc, n, 0.05) / periodogram(point, n, 0.05)
    f = np.arange(1, n // 2)[:40] / 600.0
    hub = admittance_on(f, 42.85, 10.0, length_scale(80.0))
    given = admittance_on(f, 42.85, 10.0, 500.0)
    return [
        Row(
            "length_scale 500 m given: disc/point = χ²(L_c = 8.1 Λ₁(z))",
            float(ratio[0]),
            float(hub[0]),
            float(np.max(np.abs(ratio[:40] / hub - 1))),
            1e-11,
            "L_c from hub_height",
        ),
        Row(
            "  ... against χ²(L_c = 500 m), the other reading",
            float(ratio[0]),
            float(given[0]),
            float(np.max(np.abs(ratio[:40] / given - 1))),
            math.inf,
            "not taken",
        ),
    ]


#: High f R / V, where pinwind's former 96-node rule in r was off (3.4 %, 6.9 %, −97.5 %):
#: (R, V, z, f, why).
HIGH_F_CASES = (
    (63.0, 3.0, 90.0, 10.0, "5 MW rotor at 3 m/s, default Δt's Nyquist"),
    (63.0, 13.0, 90.0, 50.0, "nrel5mw_turbulent with Δt 0.01 s, Nyquist"),
    (63.0, 13.0, 90.0, 500.0, "nrel5mw_turbulent with Δt 1 ms, Nyquist"),
)


def high_frequency_rows() -> list[Row]:
    """χ² at high f R / V against route 1 and against its large-β closed form 2/β² − 8/(πβ³) +
    4/(πβ⁵) (p(x) = (4x/π)(π/2 − x + x³/24 + ...) near x = r/R = 0, Laplace-transformed; the
    rest is O(β⁻⁶)), and the 3 m/s disc series against the recoded one."""
    from pinwind.loads import wind

    rows: list[Row] = []
    for radius, mean, z, f, why in HIGH_F_CASES:
        lc = length_scale(z)
        mine = admittance_by_separation(f, radius, mean, lc)
        beta = decay(f, mean, lc) * radius
        closed = 2 / beta**2 - 8 / (math.pi * beta**3) + 4 / (math.pi * beta**5)
        theirs = float(
            wind.rotor_admittance(np.array([f]), radius=radius, mean=mean, coherence_scale=lc)[0]
        )
        label = f"χ²({f:g} Hz) R {radius:g}, V {mean:g}: f R/V {f * radius / mean:.0f} (rel.)"
        rows.append(Row(label, theirs, mine, theirs / mine - 1, 1e-11, why))
        rows.append(
            Row("  ... against the closed form", theirs, closed, theirs / closed - 1, 1e-12, "β⁻⁶")
        )
    case = SeriesCase("x", 3.0, 0.2, 600.0, 0.05, 90.0, 63.0)
    t, u = series(case, 1)
    n = len(t) - 1
    ln, chi2 = case_lines(case, n)
    sd = math.sqrt(float(np.sum(ln.amplitude**2)) / 2)
    dev = float(np.max(np.abs(u - recoded_series(ln, 3.0, 1, t))) / sd)
    rows.append(
        Row("V 3 m/s, R 63, 600 s: series max |Δu| / σ_disc", dev, 0.0, dev, 1e-12, "rounding")
    )
    return rows


def variance_claims() -> list[Row]:
    """The docs' numbers: χ² 0.85/0.43/0.06, std ratio 0.71, 18 % of σ² below 1/T."""
    rows: list[Row] = []
    lc = length_scale(80.0)
    for fq, doc in ((0.0, 0.85), (0.02, 0.43), (0.1, 0.06)):
        v = admittance_by_separation(fq, 42.85, 10.0, lc)
        rows.append(
            Row(
                f"docs/loads.md χ²({fq:g} Hz), R 42.85, 10 m/s",
                doc,
                v,
                doc - v,
                0.005,
                "docs print 2 digits",
            )
        )
    frac = kaimal_band_fraction(1 / 600, 10.0, lc)
    rows.append(
        Row(
            "module doc: σ² below 1/T, L/V 34 s, T 600 s",
            0.18,
            frac,
            0.18 - frac,
            0.005,
            "docs print 2 digits",
        )
    )
    return rows


def fmt(x: float) -> str:
    return f"{x:.6g}" if x == x else "nan"


def print_table(rows: list[Row]) -> None:
    w = max(len(r.quantity) for r in rows)
    head = ("quantity", "pinwind", "recoded", "difference", "tolerance")
    print(f"{head[0]:<{w}}  {head[1]:>13} {head[2]:>13} {head[3]:>11} {head[4]:>9}  ok  why")
    for r in rows:
        ok = "yes" if r.ok else "NO "
        values = f"{fmt(r.pinwind):>13} {fmt(r.recoded):>13}"
        print(
            f"{r.quantity:<{w}}  {values} {r.difference:>11.2e} {r.tolerance:>9.1e}  {ok} {r.why}"
        )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=200, help="seeds of the Welch check (200)")
    args = ap.parse_args(argv)
    rows = deterministic_rows()
    adm, info = admittance_rows()
    rows += adm
    rows.append(
        Row(
            "χ² route 1 vs route 2 (max rel., all cases)",
            math.nan,
            math.nan,
            info["routes"],
            1e-11,
            "two quadratures",
        )
    )
    rows += variance_claims()
    rows += convention_rows()
    rows += signal_rows()
    extra = {}
    for case in SERIES_CASES:
        r, i = series_rows(case, args.seeds)
        rows += r
        extra[case.name] = i
    high = high_frequency_rows()
    print_table(rows)
    print()
    print("High f R / V (where pinwind's former 96-node rule in r was off):")
    print_table(high)
    rows += high
    print()
    w = info["worst"]
    print(
        f"χ²: pinwind against route 1 at worst {w['rel']:.2e} relative ({w['abs']:.2e} absolute)"
        f" at R {w['at'][0]:g} m, V {w['at'][1]:g} m/s, f {w['at'][2]:g} Hz; routes 1 and 2"
        f" agree to {info['routes']:.2e}"
    )
    for name, i in extra.items():
        if "max_z" not in i:
            continue
        print(
            f"Welch, {name}: relative standard error of the {args.seeds}-seed mean (median over f)"
            f" {i['rel_se_median']:.3%}, a Gaussian process's would be {i['gaussian_rel_se']:.3%}"
            f" (√(1.056/(K M))); median |mean/expectation − 1| {i['mean_rel_dev_median']:.3%};"
            f" Welch's own bias against c²S_uχ² at f ≥ 4 bins {i['bias_above_4_bins']:.1%} (at"
            f" {i['bias_at_hz']:.3g} Hz: Hann's main lobe on the curved spectrum), which comparing"
            " with the exact expectation leaves out"
        )
    return 0 if all(r.ok for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
