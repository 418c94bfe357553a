"""The generalized-α constants (``dynamics/integrator.py``): the compiled step's, and Chung &
Hulbert's closed forms (J. Appl. Mech. 60 (1993) 371-375).

The method on ü + ω² u = 0 (Ω = ωh, the state x = (u, h v, h² a)):

    (1 − αm) a₊ + αm a + ω² [(1 − αf) u₊ + αf u] = 0
    u₊ = u + h v + h² [(½ − β) a + β a₊],    v₊ = v + h [(1 − γ) a + γ a₊]

that is L x₊ = R x with the matrices of ``amplification``. Second order needs γ = ½ − αm + αf
(eq. 17). As Ω → ∞ the spurious root tends to αf/(αf − 1) and the principal pair to a double root
when β = ¼ (1 − αm + αf)² (eq. 20); asking all three to be −ρ∞ gives αf = ρ∞/(ρ∞ + 1) and
αm = (2ρ∞ − 1)/(ρ∞ + 1) (eq. 25). The tests derive these from ρ∞ and compare, and check the
roots at Ω → ∞ of the compiled constants.
"""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.dynamics import Integrator, _native

#: Spectral radii across [0, 1], with the default 1 and the documented 0.8.
RHOS = (0.0, 0.1, 0.25, 0.5, 0.8, 0.9, 1.0)


def closed_forms(rho: float) -> tuple[float, float, float, float]:
    """αm, αf, γ, β from ρ∞ (Chung & Hulbert 1993 eqs. 17, 20, 25; module docstring)."""
    alpha_f = rho / (rho + 1.0)  # the spurious root αf/(αf − 1) = −ρ∞
    alpha_m = (2.0 * rho - 1.0) / (rho + 1.0)  # the principal double root −ρ∞
    gamma = 0.5 - alpha_m + alpha_f  # second order
    beta = 0.25 * (1.0 - alpha_m + alpha_f) ** 2  # the principal roots meet at Ω → ∞
    return alpha_m, alpha_f, gamma, beta


def amplification(integrator: Integrator, omega_h: float) -> np.ndarray:
    """The step's matrix A, x₊ = A x on ü + ω² u = 0 with Ω = ωh (module docstring)."""
    am, af, g, b = integrator.alpha_m, integrator.alpha_f, integrator.gamma, integrator.beta
    w2 = omega_h**2
    left = np.array([[1.0, 0.0, -b], [0.0, 1.0, -g], [w2 * (1.0 - af), 0.0, 1.0 - am]])
    right = np.array([[1.0, 1.0, 0.5 - b], [0.0, 1.0, 1.0 - g], [-w2 * af, 0.0, -am]])
    return np.linalg.solve(left, right)


@pytest.mark.parametrize("rho", RHOS)
def test_the_constants_are_chung_and_hulberts_closed_forms(rho):
    integrator = Integrator(rho_infinity=rho)
    got = (integrator.alpha_m, integrator.alpha_f, integrator.gamma, integrator.beta)
    np.testing.assert_allclose(got, closed_forms(rho), rtol=0, atol=1e-15)


@pytest.mark.parametrize("rho", RHOS)
def test_the_integrator_reads_the_compiled_step_s_constants(rho):
    # One source: the values the step uses (cpp/time_step.hpp), bit for bit, in the metadata too.
    compiled = _native.generalized_alpha(rho)
    integrator = Integrator(rho_infinity=rho)
    assert compiled.rho_infinity == rho
    meta = integrator.as_dict()
    for name in ("alpha_m", "alpha_f", "gamma", "beta"):
        assert getattr(integrator, name) == getattr(compiled, name), name
        assert meta[name] == getattr(compiled, name), name


@pytest.mark.parametrize("rho", RHOS)
def test_a_mode_the_step_cannot_resolve_keeps_rho_infinity_of_its_amplitude(rho):
    # The three roots at Ω → ∞ all have modulus ρ∞; a triple root moves by O(Ω^(-2/3)).
    roots = np.linalg.eigvals(amplification(Integrator(rho_infinity=rho), 1e6))
    np.testing.assert_allclose(np.abs(roots), rho, rtol=0, atol=1e-3)


@pytest.mark.parametrize("rho", RHOS)
def test_a_resolved_mode_loses_amplitude_only_at_fourth_order_in_the_step(rho):
    # The principal roots e^{(−ξ̄ ± i)Ω̄} with an algorithmic damping ξ̄ = O(Ω³): |λ| = 1 − O(Ω⁴)
    # for ρ∞ < 1 (half of Ω⁴ at ρ∞ = 0), exactly 1 at ρ∞ = 1.
    for omega_h in (1e-2, 2e-2):
        roots = np.linalg.eigvals(amplification(Integrator(rho_infinity=rho), omega_h))
        principal = roots[np.argsort(-np.abs(roots))[:2]]
        np.testing.assert_allclose(np.abs(principal), 1.0, rtol=0, atol=omega_h**4)
