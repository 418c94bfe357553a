// A torque law τ(ω, t) on one joint (generator and rotor laws), taken linearly implicit in the
// step so that steep laws (an induction machine near synchronous speed: tens of kN·m per rad/s
// on a shaft of a few kg·m²) stay stable at the step the mechanics use:
//
//     τ over the step = τ(ω_k) + min(τ'(ω_k), 0) h a,     τ' = dτ/dω at ω_k
//
// which adds w = −min(τ', 0) h to the QP's Hessian on the joint's diagonal and τ(ω_k) to its
// force (the same device as the compliant meshes' w JᵀJ, compliant_mesh.hpp). A rising law
// (τ' > 0, e.g. an induction machine below its pull-out speed) stays explicit. The weight is
// lagged (a modified-Newton Jacobian): it follows the steepest falling slope met so far, raised
// only when the law gets more than twice as steep, so that the Hessian, and proxsuite's
// factorisation of it, stays the same from step to step (a rotor in turbulence crosses the
// peak of C_p/λ, where the slope changes sign, many times a second). Any w ≥ 0 is consistent to
// first order (the error is (w + τ' h) a), stable for a falling law as long as w ≥ |τ'| h / 2
// (the amplification of J ω̇ = τ' ω is 1 + τ' h / (J + w)), and at steady state (a = 0) the
// torque is the law's exactly. Elements whose torque has dynamics of its own (the dq machine's
// fluxes) take the slope of every step instead (``lagged() == false``): there a weight too
// large distorts the coupled electromechanical mode.
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

  // The law at the step's state: τ(ω_k) and its slope.
  virtual TorqueSlope evaluate(const StepView& s) const = 0;
  // Whether the implicit weight may lag the slope (module comment).
  virtual bool lagged() const { return true; }

  void prepare(const StepView& s) override {
    const TorqueSlope ts = evaluate(s);
    torque_ = ts.torque;
    const double target = ts.slope < 0.0 ? -ts.slope * s.dt : 0.0;
    if (!lagged() || target > 2.0 * weight_) weight_ = target;
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
};

}  // namespace pinwind
