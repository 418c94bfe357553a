"""The time step of a run: the generalized-α method with its numerical dissipation as a setting.

Each step solves for the step's mean acceleration ā (v_{k+1} = v_k + h ā) and moves the angles by
Δq = h v_k + h² (β/γ) ā + h² (½ − β/γ) a_k, with every stiff element (compliant meshes, torsional
springs, bearing damping, generator and rotor laws) taken at the method's weighted state, linear
in ā (Chung & Hulbert, J. Appl. Mech. 60 (1993) 371-375; Arnold & Brüls, Multibody Syst. Dyn. 18
(2007) 185-202; the derivation is in ``cpp/time_step.hpp``). The method is second order for every
spectral radius ρ∞ ∈ [0, 1]; ρ∞ is how much of a mode the step cannot resolve survives one step:

- ρ∞ = 1: the trapezoidal rule (implicit midpoint on linear elements): Δq = h (v_k + v_{k+1})/2
  and every element force at mid-step. No numerical dissipation: an undamped compliant mesh keeps
  its amplitude to rounding; the period of a mode of ω lengthens by (ωh)²/12 (0.8 % at 20 steps
  per period, 0.2 % at 40).
- ρ∞ < 1: the unresolved modes (tooth-pass transients above the step's Nyquist rate) are damped,
  the resolved ones keep second order; ρ∞ = 0 annihilates the highest modes in one step.

The former step (semi-implicit Euler with the meshes at θ = ½) acted as an extra dashpot k·dt/2,
a numerical damping ratio ω·dt/4: 39 % of the amplitude lost per period at 20 steps per period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pinwind.dynamics import _native
from pinwind.errors import InputError

#: The time-stepping schemes ``Integrator.scheme`` names.
SCHEMES = ("generalized-alpha",)

#: Default spectral radius ρ∞ (``Integrator``).
DEFAULT_RHO_INFINITY = 1.0


@dataclass(frozen=True)
class Integrator:
    """The time step of a run (module docstring).

    Attributes:
        rho_infinity: spectral radius ρ∞ ∈ [0, 1] at ωh → ∞. 1 keeps energy (the trapezoidal
            rule); smaller damps the modes the step does not resolve. Default 1, from
            measurements (``tests/dynamics/test_time_stepping.py``): it keeps the rigid rows'
            multipliers the instantaneous ones (with ρ∞ < 1 the inertia memory −c₂ M a_n
            shifts them by c₂ M (ā − a_n), O(dt) under a varying acceleration: a sinusoidal
            speed driver's torque is 1e-4 off J_eq α at ρ∞ = 0.8) and the force over a step of
            a mesh k times its mean overlap; at 20 steps per period ρ∞ = 0.8 would lose only
            0.013 % of the amplitude per period and damp a mode at one step per period by 4.4 %
            a step.
        scheme: ``"generalized-alpha"`` (the only one).
    """

    rho_infinity: float = DEFAULT_RHO_INFINITY
    scheme: str = "generalized-alpha"

    def __post_init__(self) -> None:
        if self.scheme not in SCHEMES:
            raise InputError(
                f'integrator scheme "{self.scheme}" is unknown; use one of: {", ".join(SCHEMES)}'
            )
        rho = self.rho_infinity
        if isinstance(rho, bool) or not isinstance(rho, (int, float)) or not 0.0 <= rho <= 1.0:
            raise InputError(
                f"rho_infinity={rho!r}: give the spectral radius as a number in [0, 1] "
                "(1 keeps energy, smaller damps the unresolved modes)"
            )

    @property
    def constants(self) -> _native.GeneralizedAlpha:
        """αm, αf, γ and β as the compiled step computes them (``cpp/time_step.hpp``).

        Read from the compiled implementation, not computed again here: the step and the
        metadata, the dt advice and the numerical damping of the modes share one source.
        """
        return _native.generalized_alpha(self.rho_infinity)

    @property
    def alpha_m(self) -> float:
        """αm = (2ρ∞ − 1)/(ρ∞ + 1) (Chung & Hulbert 1993 eq. 25; the compiled step's)."""
        return self.constants.alpha_m

    @property
    def alpha_f(self) -> float:
        """αf = ρ∞/(ρ∞ + 1) (Chung & Hulbert 1993 eq. 25; the compiled step's)."""
        return self.constants.alpha_f

    @property
    def gamma(self) -> float:
        """γ = ½ − αm + αf: second order (Chung & Hulbert 1993 eq. 17; the compiled step's)."""
        return self.constants.gamma

    @property
    def beta(self) -> float:
        """β = ¼ (1 − αm + αf)² (Chung & Hulbert 1993 eq. 20; the compiled step's)."""
        return self.constants.beta

    def as_dict(self) -> dict:
        """The scheme and its constants, for ``result.metadata["integrator"]``."""
        trapezoidal = math.isclose(self.rho_infinity, 1.0)
        return {
            "integrator": (
                "generalized-alpha (Chung & Hulbert 1993), second order, "
                + ("the trapezoidal rule, " if trapezoidal else "")
                + "with velocity projection"
            ),
            "scheme": self.scheme,
            "rho_infinity": self.rho_infinity,
            "alpha_m": self.alpha_m,
            "alpha_f": self.alpha_f,
            "gamma": self.gamma,
            "beta": self.beta,
        }
