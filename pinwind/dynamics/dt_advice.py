"""The time step's numerical damping of a mesh mode, and the dt that keeps it small.

A step too coarse for a mode does not go unstable here (every stiff element is implicit,
``dynamics/integrator.py``); with a spectral radius ρ∞ < 1 it damps the mode numerically,
which lowers the dynamic forces as a physical dashpot would. What a run needs is that numerical
damping ratio ζ_num small beside the mode's physical one: ``dt_advice`` names both at the chosen
dt and the dt that keeps ζ_num ≤ ζ_phys / 10 (``ACCURATE_FRACTION``). ``numerical_damping_ratio``
holds the scheme's formula, in this one place; the scheme and its settings are the run's
``Integrator``.

What no setting removes is the error of the mode's frequency: the trapezoidal rule (ρ∞ = 1)
lowers it to ω̄ = (2/h) atan(ωh/2), −0.81 % at 20 steps per period. By Dahlquist's second
barrier (Dahlquist 1963; Hairer & Wanner, Solving ODEs II, §V.1) an A-stable linear multistep
method is at most second order and the trapezoidal rule has the smallest error constant (1/12)
among them, so no unconditionally stable second-order step of this family does better at a
given dt; the cheapest cure is more steps. ``frequency_error`` gives it at dt and the advice names
the dt that keeps it within ``FREQUENCY_TOLERANCE`` (26 steps per period at ρ∞ = 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pinwind.dynamics.integrator import Integrator
from pinwind.errors import InputError

#: ζ_num ≤ this fraction of the physical ζ: the accurate step that the advice names.
ACCURATE_FRACTION = 0.1

#: Steps per period that resolve a mode's period (not its amplitude: see ``DtAdvice``).
RESOLVING_STEPS = 10

#: |ω̄/ω − 1| ≤ this: the step that keeps a mode's frequency accurate [-] (issue 22's check).
FREQUENCY_TOLERANCE = 0.005

#: The scheme every run uses unless given another: the default ``Integrator``.
DEFAULT_SCHEME = Integrator()


def amplification_matrix(omega_h: float, scheme: Integrator) -> np.ndarray:
    """The step's amplification matrix on an undamped mode ẍ = −ω² x, state (x, h v, h² a).

    Chung & Hulbert 1993 eqs. 2-3: (1 − αm) a_{n+1} + αm a_n = −ω² ((1 − αf) x_{n+1} + αf x_n)
    with the Newmark updates of x and v, written B y_{n+1} = A y_n; returns B⁻¹ A.
    """
    am, af = scheme.alpha_m, scheme.alpha_f
    gamma, beta = scheme.gamma, scheme.beta
    w2 = omega_h * omega_h
    b = np.array([[1.0, 0.0, -beta], [0.0, 1.0, -gamma], [w2 * (1.0 - af), 0.0, 1.0 - am]])
    a = np.array([[1.0, 1.0, 0.5 - beta], [0.0, 1.0, 1.0 - gamma], [-w2 * af, 0.0, -am]])
    return np.linalg.solve(b, a)


def numerical_damping_ratio(omega: float, dt: float, scheme: Integrator = DEFAULT_SCHEME) -> float:
    """Damping ratio the step adds to an undamped mode of angular frequency ω [-].

    ``"generalized-alpha"``: from the principal root λ of the amplification matrix
    (``amplification_matrix``), the one of largest modulus, the spectral radius ρ(ωh). Writing
    λ = exp(ω̄h (−ζ + i √(1 − ζ²))) for the discrete mode (Hilber, Hughes & Taylor 1977):

        ζ_num = −ln |λ| / √(ln² |λ| + arg² λ).

    At ρ∞ = 1 (the trapezoidal rule) |λ| = 1 at every ωh: ζ_num = 0. For ρ∞ < 1 it grows as
    (ωh)³ while ωh is small (the method is second order) and tends to
    −ln ρ∞ / √(ln² ρ∞ + π²) as ωh → ∞.

    Args:
        omega: angular frequency of the mode [rad/s].
        dt: time step [s].
        scheme: the step's scheme and settings.
    """
    if scheme.scheme != "generalized-alpha":
        raise InputError(f'no numerical damping formula for the scheme "{scheme.scheme}"')
    if scheme.rho_infinity == 1.0 or omega * dt == 0.0:
        return 0.0
    roots = np.linalg.eigvals(amplification_matrix(omega * dt, scheme))
    root = roots[np.argmax(np.abs(roots))]
    log_modulus = math.log(abs(root))
    return max(-log_modulus / math.hypot(log_modulus, abs(float(np.angle(root)))), 0.0)


def frequency_error(omega: float, dt: float, scheme: Integrator = DEFAULT_SCHEME) -> float:
    """Relative error ω̄/ω − 1 of the frequency of a mode of angular frequency ω at dt [-].

    ω̄h = |ln λ| of the principal root λ of the amplification matrix (``amplification_matrix``,
    the complex root of largest modulus; ``numerical_damping_ratio``). At ρ∞ = 1 (the
    trapezoidal rule) |λ| = 1 and arg λ = 2 atan(ωh/2): ω̄ = (2/h) atan(ωh/2), the error
    −(ωh)²/12 while ωh is small (module docstring). Negative: the step lengthens the period;
    −1 when the step no longer oscillates the mode at all (no complex root).
    """
    if scheme.scheme != "generalized-alpha":
        raise InputError(f'no frequency error formula for the scheme "{scheme.scheme}"')
    omega_h = omega * dt
    if omega_h == 0.0:
        return 0.0
    roots = np.linalg.eigvals(amplification_matrix(omega_h, scheme))
    oscillating = roots[np.abs(roots.imag) > 1e-12 * np.abs(roots)]
    if oscillating.size == 0:
        return -1.0
    root = oscillating[np.argmax(np.abs(oscillating))]
    return abs(complex(np.log(root))) / omega_h - 1.0


def dt_for_frequency_error(
    omega: float, tolerance: float = FREQUENCY_TOLERANCE, scheme: Integrator = DEFAULT_SCHEME
) -> float:
    """The largest dt that keeps a mode's frequency error |ω̄/ω − 1| within ``tolerance`` [s].

    Found by bisection on ``frequency_error`` (whose size grows with dt), as
    ``dt_for_damping_ratio``. 0 when ``tolerance`` ≤ 0.
    """
    if tolerance <= 0.0 or omega <= 0.0:
        return 0.0
    low, high = 0.0, 1.0 / omega
    while abs(frequency_error(omega, high, scheme)) <= tolerance:
        low, high = high, 2.0 * high
    for _ in range(100):
        middle = 0.5 * (low + high)
        if abs(frequency_error(omega, middle, scheme)) <= tolerance:
            low = middle
        else:
            high = middle
    return low


def dt_for_damping_ratio(omega: float, ratio: float, scheme: Integrator) -> float:
    """The largest dt whose numerical damping ratio of a mode is ``ratio`` [s].

    Found by bisection on ``numerical_damping_ratio`` (which grows with dt in every scheme),
    so that a new scheme needs no inverse formula. Infinite when no dt reaches it (ρ∞ = 1 adds
    no damping at any dt); else 0 when ``ratio`` ≤ 0.
    """
    if scheme.rho_infinity == 1.0:
        return math.inf
    if ratio <= 0.0 or omega <= 0.0:
        return 0.0
    low, high = 0.0, 1.0 / omega
    while numerical_damping_ratio(omega, high, scheme) < ratio:
        if high > 1e6 / omega:
            return math.inf
        low, high = high, 2.0 * high
    for _ in range(100):
        middle = 0.5 * (low + high)
        if numerical_damping_ratio(omega, middle, scheme) <= ratio:
            low = middle
        else:
            high = middle
    return low


@dataclass(frozen=True)
class DtAdvice:
    """The accuracy of a dt for the highest mesh mode.

    Attributes:
        frequency: the highest mesh mode [Hz].
        dt: the run's time step [s].
        physical_ratio: the mode's damping ratio from the mesh dashpots [-].
        numerical_ratio: the damping ratio the step adds at dt [-].
        accurate_dt: the dt that keeps ζ_num ≤ ``ACCURATE_FRACTION`` ζ_phys [s]; infinite when
            the scheme adds no damping; else 0 when the mode has no physical damping.
        scheme: the step's scheme.
        frequency_error: ω̄/ω − 1 of the mode at dt [-] (``frequency_error``).
        frequency_dt: the dt that keeps |ω̄/ω − 1| ≤ ``FREQUENCY_TOLERANCE`` [s].
    """

    frequency: float
    dt: float
    physical_ratio: float
    numerical_ratio: float
    accurate_dt: float
    scheme: Integrator = DEFAULT_SCHEME
    frequency_error: float = 0.0
    frequency_dt: float = math.inf

    @property
    def steps_per_period(self) -> float:
        """Steps per period of the mode at dt."""
        return 1.0 / (self.frequency * self.dt)

    @property
    def accurate(self) -> bool:
        """ζ_num ≤ ``ACCURATE_FRACTION`` ζ_phys."""
        return self.numerical_ratio <= ACCURATE_FRACTION * self.physical_ratio

    def text(self) -> str:
        """One line: the mode, its damping ratios and frequency error, and the dt that bounds them.

        The numerical and the physical damping ratio with the dt that keeps the first below a
        tenth of the second, then the mode's frequency error at dt with the dt that keeps it
        within ``FREQUENCY_TOLERANCE``.
        """
        return self._damping_text() + self._frequency_text()

    def _frequency_text(self) -> str:
        if self.frequency <= 0.0 or self.dt <= 0.0:
            return ""
        steps = 1.0 / (self.frequency * self.frequency_dt)
        return (
            f"; its frequency in the step is {100 * self.frequency_error:.2g} % off, "
            f"dt ≤ {self.frequency_dt:.2g} s ({steps:.3g} steps per period) keeps it within "
            f"{100 * FREQUENCY_TOLERANCE:g} % (the trapezoidal rule, ρ∞ = 1, errs least of "
            "the unconditionally stable second-order steps: docs/limitations.md)"
        )

    def _damping_text(self) -> str:
        start = (
            f"highest mesh mode {self.frequency:.4g} Hz: at dt = {self.dt:.3g} s "
            f"({self.steps_per_period:.3g} steps per period) the step "
        )
        if math.isinf(self.accurate_dt):  # a scheme without numerical damping (ρ∞ = 1)
            return start + (
                f"adds no damping to it (ζ_num = {self.numerical_ratio:.3g}; its physical "
                f"ζ = {self.physical_ratio:.3g}; ρ∞ = {self.scheme.rho_infinity:g} keeps the "
                f"amplitude at any dt; dt ≤ {1.0 / (RESOLVING_STEPS * self.frequency):.2g} s, "
                f"{RESOLVING_STEPS} steps per period, resolves its period)"
            )
        line = start + (
            f"damps it with ζ_num = {self.numerical_ratio:.3g} beside its physical "
            f"ζ = {self.physical_ratio:.3g}"
        )
        if self.physical_ratio > 0.0:
            return line + (
                f"; dt ≤ {self.accurate_dt:.2g} s keeps ζ_num below a tenth of the physical one"
            )
        resolving = 1.0 / (RESOLVING_STEPS * self.frequency)
        omega = 2.0 * math.pi * self.frequency
        at_resolving = numerical_damping_ratio(omega, resolving, self.scheme)
        return line + (
            "; the mode has no physical damping, so all its damping is numerical and shrinks "
            f"with dt (dt ≤ {resolving:.2g} s, {RESOLVING_STEPS} steps per period, still damps "
            f"it with ζ_num ≈ {at_resolving:.2g})"
        )


def dt_advice(
    frequency: float,
    dt: float,
    physical_ratio: float,
    scheme: Integrator = DEFAULT_SCHEME,
) -> DtAdvice:
    """The accuracy of dt for a mode of ``frequency`` [Hz] with damping ratio ``physical_ratio``."""
    omega = 2.0 * math.pi * frequency
    return DtAdvice(
        frequency=frequency,
        dt=dt,
        physical_ratio=physical_ratio,
        numerical_ratio=numerical_damping_ratio(omega, dt, scheme),
        accurate_dt=dt_for_damping_ratio(omega, ACCURATE_FRACTION * physical_ratio, scheme),
        scheme=scheme,
        frequency_error=frequency_error(omega, dt, scheme),
        frequency_dt=dt_for_frequency_error(omega, FREQUENCY_TOLERANCE, scheme),
    )


def coarse_step_notes(duration: float, dt: float, spring_mode: float = 0.0) -> list[str]:
    """What a dt too coarse for the run or the model misses, one line each (empty: nothing).

    A run of fewer than ``RESOLVING_STEPS`` steps cannot show how its loads change (``--dt 1``
    on a 2 s run gives two steps); a dt longer than half the period of the highest
    torsional-spring mode (``torsional_modes.highest_spring_mode``, ``spring_mode`` [Hz]) has
    fewer samples than the Nyquist rate of that oscillation, so the run cannot show it at all.
    The compliant meshes' modes are ``compliant._warn_if_damped_numerically``'s.

    Args:
        duration: simulated time [s]; dt: time step [s].
        spring_mode: frequency of the highest torsional-spring mode [Hz] (0: none).
    """
    notes = []
    steps = round(duration / dt)
    if steps < RESOLVING_STEPS:
        notes.append(
            f"dt = {dt:g} s leaves {steps} step{'s' if steps != 1 else ''} in the {duration:g} s "
            f"run: too few samples to show how the loads change; give dt ≤ "
            f"{duration / RESOLVING_STEPS:.3g} s (at least {RESOLVING_STEPS} steps)"
        )
    if spring_mode > 0.0 and dt > 0.5 / spring_mode:
        period = 1.0 / spring_mode
        notes.append(
            f"dt = {dt:g} s is longer than half the period of the highest torsional-spring mode "
            f"({spring_mode:.4g} Hz, period {period:.3g} s): the samples cannot show that "
            f"oscillation and the step sets its response; dt ≤ {period / RESOLVING_STEPS:.2g} s "
            f"({RESOLVING_STEPS} steps per period) resolves it"
        )
    return notes
