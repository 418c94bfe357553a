// A torque law τ(ω, t) on one joint (generator and rotor laws), taken linearly implicit in the
// step so that steep laws (an induction machine near synchronous speed: tens of kN·m per rad/s
// on a shaft of a few kg·m²) stay stable at the step the mechanics use. The torque over the
// step is the law's at the time step's weighted speed ω_n + κ_v ā (time_step.hpp), linearised
// about a prediction from the last step's acceleration ā_p:
//
//     τ over the step = τ(ω_n + κ_v ā_p) − w (ā − ā_p),     w ≥ 0
//
// which adds w to the QP's Hessian on the joint's diagonal and τ(ω_n + κ_v ā_p) + w ā_p to its
// force (the same device as the compliant meshes' w JᵀJ, compliant_mesh.hpp). The law's slope
// τ' gives w = −τ' κ_v, the exact linearisation, or w = 0 for a rising law (τ' > 0, e.g. an
// induction machine below its pull-out speed). The weight is lagged (a modified-Newton
// Jacobian): it follows twice the steepest falling slope met so far, −2 τ' κ_v, raised only when
// the law gets more than twice as steep, so that the Hessian, and proxsuite's factorisation of
// it, stays the same from step to step (a rotor in turbulence crosses the peak of C_p/λ, where
// the slope changes sign, many times a second). The error of a weight that is not the exact one
// is (w + τ' κ_v)(ā − ā_p) = O(h²): the step stays second order. For J ω̇ = τ' ω (τ' = −λ) the
// two-step map is stable when J + 2w > 2 λ κ_v, which w ≥ λ κ_v (the lagged weight) keeps for
// every h; at steady state (ā = ā_p = 0) the torque is the law's exactly. Elements whose torque
// has dynamics of its own (the dq machine's fluxes) take the exact slope of every step instead
// (``lagged() == false``): there a weight too large distorts the coupled electromechanical mode.
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
  // Whether the implicit weight may lag the slope (module comment).
  virtual bool lagged() const { return true; }

  void prepare(const StepView& s) override {
    const TorqueSlope ts = evaluate(s, predicted_);
    const double exact = ts.slope < 0.0 ? -ts.slope : 0.0;
    if (!lagged()) {
      weight_ = exact;
    } else if (exact > weight_) {
      weight_ = 2.0 * exact;
    }
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
