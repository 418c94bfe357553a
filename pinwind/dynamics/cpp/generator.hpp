// Generator laws on one joint (the output shaft): the torque the generator puts on the shaft,
// τ = −T_gen, with T_gen > 0 when generating (pinwind/loads/generator.py documents each law):
//
//   kConstant        T_gen = T₀
//   kLinearSlip      T_gen = k (ω − ω_sync)
//   kVariableSpeed   T_gen = K ω|ω| below rated speed, P_rated/|ω| (sign of ω) above
//   kInduction       steady-state induction machine from its equivalent circuit (per phase:
//                    R_s + jX_ls in series with jX_m ∥ (R_r'/s + jX_lr')), motor convention
//                    τ = 3 |I_r'|² R_r' / (s ω_s),  s = (ω_s − ω)/ω_s,  ω_s = 2π f / p
//   kInductionDq     Krause's dq model in the synchronous frame (001_2d0e0f624d8db633.txt),
//                    flux linkages λ = (λ_qs, λ_ds, λ'_qr, λ'_dr) integrated with the trapezoidal
//                    rule at the mechanical step, the rotor speed taken at mid-step:
//                      dλ/dt = u − R L⁻¹ λ − W(ω_r) λ,  u = (√2 V_ph, 0, 0, 0)
//                      τ = (3/2) p (λ_ds i_qs − λ_qs i_ds),  i = L⁻¹ λ,  ω_r = p ω
//                    The trapezoidal rule keeps the 60 Hz stator transient undamped by the
//                    integrator (A-stable, no numerical damping) and its fixed point is the
//                    exact steady state, so the torque settles on the equivalent circuit's.
// The torque of the first four is a law of the shaft speed, taken linearly implicit
// (joint_torque.hpp); the dq machine's is that of its end-of-step fluxes, linear in the step's
// acceleration through the speed at mid-step, taken implicitly the same way.
#pragma once

#include <cmath>
#include <complex>

#include <Eigen/Dense>

#include "joint_torque.hpp"

namespace pinwind {

struct GeneratorSpec {
  enum Law { kConstant = 0, kLinearSlip, kVariableSpeed, kInduction, kInductionDq };
  long index = 0;             // velocity index of the generator joint
  long law = kConstant;
  double torque = 0.0;        // kConstant: T₀ [N·m]
  double slope = 0.0;         // kLinearSlip: k [N·m·s/rad]
  double sync_speed = 0.0;    // kLinearSlip: ω_sync [rad/s]
  double gain = 0.0;          // kVariableSpeed: K [N·m·s²/rad²]
  double rated_power = 0.0;   // kVariableSpeed: P_rated [W] (0: no limit)
  // Induction machine, per phase, referred to the stator.
  double stator_resistance = 0.0;  // R_s [Ω]
  double rotor_resistance = 0.0;   // R_r' [Ω]
  double stator_leakage = 0.0;     // L_ls [H]
  double rotor_leakage = 0.0;      // L_lr' [H]
  double magnetizing = 0.0;        // L_M [H]
  double voltage = 0.0;            // line-to-line RMS [V] (star connection)
  double frequency = 0.0;          // grid frequency f [Hz]
  long pole_pairs = 2;             // p
  double phases = 3.0;
  bool steady_start = false;       // kInductionDq: start at the steady-state fluxes of ω(0)
};

// Steady-state torque of the induction machine on the shaft at speed ω [N·m], motor
// convention (positive below synchronous speed). Computed on the full circuit with the rotor
// branch multiplied by s, so that s = 0 gives exactly 0.
inline double induction_torque(const GeneratorSpec& g, double omega) {
  using C = std::complex<double>;
  const double we = 2.0 * M_PI * g.frequency;
  const double ws = we / static_cast<double>(g.pole_pairs);
  const double s = (ws - omega) / ws;
  const C zs(g.stator_resistance, we * g.stator_leakage);
  const C zm(0.0, we * g.magnetizing);
  const C zr_s(g.rotor_resistance, s * we * g.rotor_leakage);  // s · (R_r'/s + jX_lr')
  const C denominator = s * zm + zr_s;                           // s (Z_m + Z_r)
  const C parallel = zm * zr_s / denominator;                    // Z_m ∥ Z_r
  const double v_phase = g.voltage / std::sqrt(3.0);
  const C is = v_phase / (zs + parallel);
  // |I_r|² R_r'/s = |I_s|² |Z_m|² s R_r' / |s Z_m + s Z_r|²
  const double airgap = g.phases * std::norm(is) * std::norm(zm) * s * g.rotor_resistance /
                        std::norm(denominator);
  return airgap / ws;
}

// The laws of the shaft speed alone.
class GeneratorLaw : public JointTorqueElement {
 public:
  explicit GeneratorLaw(const GeneratorSpec& g) : JointTorqueElement(g.index), g_(g) {}

  // Torque on the shaft τ(ω) [N·m].
  double operator()(double omega) const {
    switch (g_.law) {
      case GeneratorSpec::kConstant:
        return -g_.torque;
      case GeneratorSpec::kLinearSlip:
        return -g_.slope * (omega - g_.sync_speed);
      case GeneratorSpec::kVariableSpeed: {
        const double w = std::abs(omega);
        double t = g_.gain * w * w;
        if (g_.rated_power > 0.0 && t * w > g_.rated_power) t = g_.rated_power / w;
        return omega >= 0.0 ? -t : t;
      }
      case GeneratorSpec::kInduction:
        return induction_torque(g_, omega);
      default:
        return 0.0;
    }
  }

  TorqueSlope evaluate(const StepView& s) const override {
    const double scale = std::abs(g_.sync_speed) + 2.0 * M_PI * g_.frequency + 1.0;
    return torque_and_slope(*this, s.v[index_], scale);
  }

 private:
  GeneratorSpec g_;
};

// Krause's dq induction machine with its flux linkages as states.
class InductionMachineDq : public JointTorqueElement {
 public:
  using Mat4 = Eigen::Matrix4d;
  using Vec4 = Eigen::Vector4d;

  explicit InductionMachineDq(const GeneratorSpec& g) : JointTorqueElement(g.index), g_(g) {
    const double ls = g.stator_leakage + g.magnetizing, lr = g.rotor_leakage + g.magnetizing;
    Mat4 inductance;
    inductance << ls, 0, g.magnetizing, 0,  //
        0, ls, 0, g.magnetizing,            //
        g.magnetizing, 0, lr, 0,            //
        0, g.magnetizing, 0, lr;
    inverse_ = inductance.inverse();
    resistance_ = Vec4(g.stator_resistance, g.stator_resistance, g.rotor_resistance,
                       g.rotor_resistance)
                      .asDiagonal();
    we_ = 2.0 * M_PI * g.frequency;
    u_ = Vec4(std::sqrt(2.0) * g.voltage / std::sqrt(3.0), 0.0, 0.0, 0.0);
    flux_.setZero();
  }

  // dλ/dt = A(ω_r) λ + u.
  Mat4 system(double omega_mech) const {
    const double slip_speed = we_ - static_cast<double>(g_.pole_pairs) * omega_mech;
    Mat4 w = Mat4::Zero();
    w(0, 1) = we_;
    w(1, 0) = -we_;
    w(2, 3) = slip_speed;
    w(3, 2) = -slip_speed;
    return -resistance_ * inverse_ - w;
  }

  double torque(const Vec4& flux) const {
    const Vec4 i = inverse_ * flux;
    return 1.5 * static_cast<double>(g_.pole_pairs) * (flux[1] * i[0] - flux[0] * i[1]);
  }

  void prepare(const StepView& s) override {
    if (first_ && g_.steady_start) flux_ = system(s.v[index_]).partialPivLu().solve(-u_);
    first_ = false;
    JointTorqueElement::prepare(s);
  }

  // The torque over the step is the one of the end-of-step fluxes, λ_{k+1}(ω_mid), with
  // ω_mid = ω_k + (h/2) a: linear in a through dτ/dω_mid (h/2), taken implicitly like the laws
  // of the shaft speed. Explicit in the fluxes, a machine whose slip stiffness is large next to
  // its shaft's inertia (many poles, a light shaft) would be unstable at the mechanical step.
  TorqueSlope evaluate(const StepView& s) const override {
    const double w = s.v[index_];
    const double d = 1e-6 * (std::abs(w) + we_ / static_cast<double>(g_.pole_pairs));
    const double t0 = torque(step(w, s.dt));
    const double t1 = torque(step(w + d, s.dt));
    // dτ/da = dτ/dω_mid · h/2; JointTorqueElement multiplies the slope it gets by h.
    return {t0, 0.5 * (t1 - t0) / d};
  }

  bool lagged() const override { return false; }

  void advance(const StepView& s, const Eigen::VectorXd& v_next) override {
    flux_ = step(0.5 * (s.v[index_] + v_next[index_]), s.dt);
  }

  // Trapezoidal step of the fluxes from λ_k at rotor speed ω_mid over h.
  Vec4 step(double omega_mid, double h) const {
    const Mat4 half = 0.5 * h * system(omega_mid);
    const Vec4 rhs = flux_ + half * flux_ + h * u_;
    return (Mat4::Identity() - half).partialPivLu().solve(rhs);
  }

 private:
  GeneratorSpec g_;
  Mat4 inverse_, resistance_;
  Vec4 u_;
  double we_ = 0.0;
  Vec4 flux_;
  bool first_ = true;
};

}  // namespace pinwind
