// A torque law τ(ω, t) on one joint (generator and rotor laws), taken linearly implicit in the
// step so that steep laws (an induction machine near synchronous speed: tens of kN·m per rad/s
// on a shaft of a few kg·m²) stay stable at the step the mechanics use. The torque over the
// step is the law's at the time step's weighted speed ω_n + κ_v ā (time_step.hpp), linearised
// about a prediction from the last step's acceleration ā_p:
//
//     τ over the step = τ(ω_n + κ_v ā_p) − w (ā − ā_p),     w ≥ 0
//
// which adds w to the QP's Hessian on the joint's diagonal and τ(ω_n + κ_v ā_p) + w ā_p to its
// force (the same device as the compliant meshes' w JᵀJ, compliant_mesh.hpp). The weight
// follows the law's local slope τ' at the predicted speed, every step:
//
//     w = φ λ κ_v,   λ = max(−τ', 0),   φ = 1 + x/(1 + x),   x = λ κ_v / M_jj
//
// with M_jj the joint's inertia. Where the step resolves the law's relaxation (x ≪ 1) φ → 1,
// the exact linearisation; the error left, (w + τ' κ_v)(ā − ā_p) = O(x h) (ā − ā_p), is of
// second order and so is the step on a speed ramp (a rising law, τ' > 0, takes w = 0 and leaves
// τ' κ_v (ā − ā_p) = O(h²)). Where it does not (x ≫ 1: a stiff slip law on a light shaft, time
// constant M_jj/λ below the step) φ → 2: with the exact weight the trapezoidal rule would carry
// the relaxation as ω_{n+1} = −ω_n, an alternation that never decays, while φ = 2 makes the
// two-step map ω_{n+1} = (ω_n − ω_{n−1})/2, whose roots have modulus 1/√2: the unresolved
// relaxation dies out in a few steps whatever ρ∞. At steady state (ā = ā_p = 0) the torque is
// the law's exactly. Elements whose torque has dynamics of its own (the dq machine's fluxes)
// take φ = 1 (``damps_unresolved() == false``): there a weight too large distorts the coupled
// electromechanical mode. A weight that changes from step to step changes one diagonal entry of
// the Hessian, which the direct solve absorbs without refactorising (constrained_qp.hpp).
#pragma once

#include <cmath>

#include "elements.hpp"

namespace pinwind {

// Value and slope of a law at one speed.
struct TorqueSlope {
  double torque = 0.0;  // τ [N·m]
  double slope = 0.0;   // dτ/dω [N·m·s/rad]
};

// Central difference of a law τ(ω) with a step relative to the speed scale [rad/s].
template <class Law>
TorqueSlope torque_and_slope(const Law& law, double omega, double scale) {
  const double d = 1e-6 * (std::abs(omega) + scale);
  return {law(omega), (law(omega + d) - law(omega - d)) / (2.0 * d)};
}

class JointTorqueElement : public Element {
 public:
  explicit JointTorqueElement(long index) : index_(index) {}

  // The torque over the step if the step's acceleration were ā = accel, and its slope dτ/dā
  // [N·m·s²/rad] (the law's at ω_n + κ_v ā: τ(ω) and τ'(ω) κ_v).
  virtual TorqueSlope evaluate(const StepView& s, double accel) const = 0;
  // Whether the weight grows to damp a relaxation the step does not resolve (module comment).
  virtual bool damps_unresolved() const { return true; }

  void prepare(const StepView& s) override {
    const TorqueSlope ts = evaluate(s, predicted_);
    const double exact = ts.slope < 0.0 ? -ts.slope : 0.0;
    double factor = 1.0;
    if (damps_unresolved() && s.mass != nullptr && (*s.mass)(index_, index_) > 0.0) {
      const double x = exact / (*s.mass)(index_, index_);
      factor = 1.0 + x / (1.0 + x);
    }
    weight_ = factor * exact;
    torque_ = ts.torque + weight_ * predicted_;
    applied_ = torque_;
  }

  void add_implicit(const StepView&, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    hessian(index_, index_) += weight_;
    force[index_] += torque_;
  }

  bool settle(const StepView&, const Eigen::VectorXd& a, bool) override {
    applied_ = torque_ - weight_ * a[index_];
    return false;
  }

  // The step's ā, the next step's prediction.
  void advance(const StepView& s, const Eigen::VectorXd& v_next) override {
    predicted_ = (v_next[index_] - s.v[index_]) / s.dt;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    StepWork w;
    w.applied = applied_ * v_mid[index_] * s.dt;
    return w;
  }

  // The torque joins the joint's recorded torque (applied + drivers + elements).
  void record(const StepView&, long k, const Outputs& out) const override {
    out.at(Series::torque, out.entry(Family::joint, k, index_)) += applied_;
  }

  double applied() const { return applied_; }

 protected:
  long index_;

 private:
  double torque_ = 0.0, weight_ = 0.0, applied_ = 0.0;
  double predicted_ = 0.0;  // ā_p, the last step's acceleration [rad/s²]
};

}  // namespace pinwind
