// The time step: the generalized-α method (Chung & Hulbert, J. Appl. Mech. 60 (1993) 371-375,
// eqs. 2-3, 17, 25; for constrained multibody systems Arnold & Brüls, Multibody Syst. Dyn. 18
// (2007) 185-202, eqs. 8-9), written for the step loop's one unknown per step: the step's mean
// acceleration ā, with v_{n+1} = v_n + h ā.
//
// Generalized-α, with a_n the accelerations the method carries from step to step:
//
//     M a_{n+1−αm} = f(q_{n+1−αf}, v_{n+1−αf}),         x_{n+1−α} = (1 − α) x_{n+1} + α x_n
//     q_{n+1} = q_n + h v_n + h² ((½ − β) a_n + β a_{n+1})
//     v_{n+1} = v_n + h ((1 − γ) a_n + γ a_{n+1})
//
//     αm = (2ρ∞ − 1)/(ρ∞ + 1),  αf = ρ∞/(ρ∞ + 1),  γ = ½ − αm + αf,  β = ¼ (1 − αm + αf)²
//
// is second order for every ρ∞ ∈ [0, 1] (γ = ½ − αm + αf), unconditionally stable on linear
// systems (αm ≤ αf ≤ ½, β ≥ ¼ + ½ (αf − αm)), and ρ∞ is the spectral radius of its
// amplification matrix as ωh → ∞: how much of an unresolved mode survives a step. With
// ā = (1 − γ) a_n + γ a_{n+1} (so a_{n+1} = (ā − (1 − γ) a_n)/γ):
//
//     a_{n+1−αm} = c₁ ā + c₂ a_n,              c₁ = (1 − αm)/γ,  c₂ = 1 − c₁
//     Δq = q_{n+1} ⊖ q_n = h v_n + h² (β/γ) ā + h² (½ − β/γ) a_n
//     q_{n+1−αf} = q_n ⊕ (dq₀ + κ_q ā),  v_{n+1−αf} = v_n + κ_v ā,
//     dq₀ = (1 − αf) h (v_n + h (½ − β/γ) a_n),  κ_q = (1 − αf) h² β/γ,  κ_v = (1 − αf) h,
//
// so the step solves, with the constraints' rows J ā = r (constraints.hpp),
//
//     (c₁ M + Σ W_e) ā = τ − b − c₂ M a_n + Σ f_e + Jᵀ λ
//
// where each element's force is taken at (q_{n+1−αf}, v_{n+1−αf}), linear in ā (exact for
// the linear spring-dampers; elements.hpp): a compliant mesh F = k (δ_n − J (dq₀ + κ_q ā)) −
// c J (v_n + κ_v ā) adds W = (k κ_q + c κ_v) JᵀJ. The applied torques and b are taken at the
// step's start (t_n, q_n, v_n), as the rigid rows' multipliers are recorded: a load that varies
// in time or with the speeds enters at first order in h (its change over the step times h).
//
// ρ∞ = 1 gives αm = αf = γ = ½, β = ¼: c₁ = 1, c₂ = 0, Δq = h (v_n + v_{n+1})/2 and every
// element force at mid-step, the trapezoidal rule (implicit midpoint on linear elements): no
// numerical dissipation, a compliant mesh's weight W = h (h k/4 + c/2) JᵀJ, and the period of a
// mode of ω lengthened by (ωh)²/12. ρ∞ < 1 damps the modes the step does not resolve and keeps
// second order in those it does. The method starts from consistent accelerations a_0, the
// dynamics at the first sample (forces at (q_0, v_0), no weights: StepWeights()), and carries
// a_n, the accelerations at the samples: for ρ∞ = 1 and linear forces a_{n+1} = 2 ā − a_n is
// M⁻¹ f(q_{n+1}, v_{n+1}) exactly, since M ā is the mean of the forces at both ends.
#pragma once

#include <algorithm>

namespace pinwind {

// The method's constants for a spectral radius ρ∞ ∈ [0, 1] (module comment).
struct GeneralizedAlpha {
  double rho_infinity = 1.0;
  double alpha_m = 0.5, alpha_f = 0.5, gamma = 0.5, beta = 0.25;

  explicit GeneralizedAlpha(double rho = 1.0) : rho_infinity(std::clamp(rho, 0.0, 1.0)) {
    alpha_m = (2.0 * rho_infinity - 1.0) / (rho_infinity + 1.0);
    alpha_f = rho_infinity / (rho_infinity + 1.0);
    gamma = 0.5 - alpha_m + alpha_f;
    const double s = 1.0 - alpha_m + alpha_f;
    beta = 0.25 * s * s;
  }
};

// One step's weights (module comment), for step size h; the default ones give the dynamics at
// the sample itself (forces at (q_n, v_n), M a = f): the consistent start a_0.
struct StepWeights {
  double inertia = 1.0;        // c₁
  double memory = 0.0;         // c₂ (of M a_n)
  double force_new = 0.0;      // 1 − αf: the weight of the end-of-step state in the forces
  double position_gain = 0.0;  // κ_q [s²]
  double speed_gain = 0.0;     // κ_v [s]
  double step_gain = 0.0;      // h² β/γ [s²]: ā in Δq
  double memory_gain = 0.0;    // h² (½ − β/γ) [s²]: a_n in Δq
  bool statics = false;        // the weights of a static solve (statics() below)

  StepWeights() = default;

  // The weights of a static solve (Stepper::equilibrium): the unknown is a displacement Δq
  // instead of an acceleration, each element's force is taken at q ⊕ Δq with the speeds held,
  // so its implicit weight W_e is its stiffness −∂f_e/∂q and its force at Δq = 0 the force at q.
  // Elements with contact keep a flank in contact (they switch flanks, never open).
  static StepWeights static_solve() {
    StepWeights w;
    w.inertia = 0.0;
    w.position_gain = 1.0;
    w.statics = true;
    return w;
  }

  StepWeights(const GeneralizedAlpha& g, double h) {
    const double ratio = g.beta / g.gamma;
    inertia = (1.0 - g.alpha_m) / g.gamma;
    memory = 1.0 - inertia;
    force_new = 1.0 - g.alpha_f;
    step_gain = h * h * ratio;
    memory_gain = h * h * (0.5 - ratio);
    position_gain = force_new * step_gain;
    speed_gain = force_new * h;
  }
};

}  // namespace pinwind
