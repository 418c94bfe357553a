"""The time step's numerical damping of a mesh mode, and the dt that keeps it small.

A step too coarse for a mode does not go unstable here (the compliant meshes are implicit,
``dynamics/compliant.py``); it damps the mode numerically, which lowers the dynamic forces as a
physical dashpot would. What a run needs is that numerical damping ratio ζ_num small beside the
mode's physical one: ``dt_advice`` names both at the chosen dt and the dt that keeps
ζ_num ≤ ζ_phys / 10 (``ACCURATE_FRACTION``). ``numerical_damping_ratio`` holds the scheme's
formula, in this one place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pinwind.errors import InputError

#: ζ_num ≤ this fraction of the physical ζ: the accurate step that the advice names.
ACCURATE_FRACTION = 0.1

#: Steps per period that resolve a mode's period (not its amplitude: see ``DtAdvice``).
RESOLVING_STEPS = 10

#: Schemes ``numerical_damping_ratio`` has a formula for.
SCHEMES = ("implicit-mesh",)


@dataclass(frozen=True)
class TimeStepScheme:
    """How the step integrates the compliant meshes: the scheme and its settings.

    Attributes:
        kind: ``"implicit-mesh"``: semi-implicit Euler (v⁺ = v + h a, q⁺ = q + h v⁺) with the
            mesh force taken θ of the way through the step in deflection
            (``cpp/compliant_mesh.hpp``).
        implicit_theta: θ of the implicit mesh force; ½ damps the mesh modes least.

    A new scheme (e.g. generalized-α or HHT with a spectral radius ρ∞) adds its kind to
    ``SCHEMES``, its settings here, and its own formula to ``numerical_damping_ratio``.
    """

    kind: str = "implicit-mesh"
    implicit_theta: float = 0.5

    def __post_init__(self) -> None:
        if self.kind not in SCHEMES:
            raise InputError(
                f'time-step scheme "{self.kind}" is unknown; use one of: {", ".join(SCHEMES)}'
            )


#: The scheme every run uses.
DEFAULT_SCHEME = TimeStepScheme()


def numerical_damping_ratio(omega: float, dt: float, scheme: TimeStepScheme) -> float:
    """Damping ratio the step adds to an undamped mode of angular frequency ω [-].

    ``"implicit-mesh"``: ζ_num = θ ω dt / 2, i.e. ω dt / 4 at θ = ½. Derivation, for a mode
    m ẍ = −k x (ω² = k/m): the step is

        m (v⁺ − v) / h = −k (x + θ h v⁺),    x⁺ = x + h v⁺,

    whose force is that of semi-implicit Euler, −k x (which keeps the amplitude: its
    amplification matrix has determinant 1 for ω h < 2), plus −θ h k v⁺: a dashpot
    c = θ k h (c = k h / 2 at θ = ½). Its damping ratio is c / (2 m ω) = θ ω h / 2. Exactly,
    the determinant becomes 1 / (1 + θ ω² h²), an amplitude kept per step of
    (1 + θ ω² h²)^(−½) = exp(−θ ω² h² / 2 + …) = exp(−ζ_num ω h), the same to leading order.

    Args:
        omega: angular frequency of the mode [rad/s].
        dt: time step [s].
        scheme: the step's scheme and settings.
    """
    if scheme.kind == "implicit-mesh":
        return 0.5 * scheme.implicit_theta * omega * dt
    raise InputError(f'no numerical damping formula for the scheme "{scheme.kind}"')


def dt_for_damping_ratio(omega: float, ratio: float, scheme: TimeStepScheme) -> float:
    """The largest dt whose numerical damping ratio of a mode is ``ratio`` [s].

    Found by bisection on ``numerical_damping_ratio`` (which grows with dt in every scheme),
    so that a new scheme needs no inverse formula. 0 when ``ratio`` ≤ 0.
    """
    if ratio <= 0.0 or omega <= 0.0:
        return 0.0
    low, high = 0.0, 1.0 / omega
    while numerical_damping_ratio(omega, high, scheme) < ratio and high < 1e6 / omega:
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
        accurate_dt: the dt that keeps ζ_num ≤ ``ACCURATE_FRACTION`` ζ_phys [s]; 0 when the
            mode has no physical damping.
        scheme: the step's scheme.
    """

    frequency: float
    dt: float
    physical_ratio: float
    numerical_ratio: float
    accurate_dt: float
    scheme: TimeStepScheme = DEFAULT_SCHEME

    @property
    def steps_per_period(self) -> float:
        """Steps per period of the mode at dt."""
        return 1.0 / (self.frequency * self.dt)

    @property
    def accurate(self) -> bool:
        """ζ_num ≤ ``ACCURATE_FRACTION`` ζ_phys."""
        return self.numerical_ratio <= ACCURATE_FRACTION * self.physical_ratio

    def text(self) -> str:
        """One line: the mode, both damping ratios, and the dt that keeps the numerical small."""
        line = (
            f"highest mesh mode {self.frequency:.4g} Hz: at dt = {self.dt:.3g} s "
            f"({self.steps_per_period:.3g} steps per period) the step damps it with "
            f"ζ_num = {self.numerical_ratio:.3g} beside its physical ζ = {self.physical_ratio:.3g}"
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
    scheme: TimeStepScheme = DEFAULT_SCHEME,
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
    )
