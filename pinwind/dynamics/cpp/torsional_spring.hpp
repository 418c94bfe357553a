// Torsional spring-dampers between two coaxial joints (002_bb0c67d52fe8a188.txt "RSDA",
// k = GJ/L): torque −k(θ₁ − θ₂ − θ₀) − c(ω₁ − ω₂) on joint 1 and the opposite on joint 2.
// Explicit: shaft modes are slow next to mesh modes.
#pragma once

#include <vector>

#include "elements.hpp"

namespace pinwind {

struct TorsionalSpringSpec {
  long index_1 = 0, index_2 = 0;  // velocity indices of the two joints
  double stiffness = 0.0;         // k [N·m/rad]
  double damping = 0.0;           // c [N·m·s/rad]
  double preload_angle = 0.0;     // θ₀ [rad]
};

class TorsionalSprings : public Element {
 public:
  explicit TorsionalSprings(std::vector<TorsionalSpringSpec> springs)
      : springs_(std::move(springs)) {}

  void prepare(const StepView& s) override {
    elastic_.setZero(s.q.size());
    damping_.setZero(s.q.size());
    for (const auto& sp : springs_) {
      const double torque = -sp.stiffness * twist(sp, s.q);
      elastic_[sp.index_1] += torque;
      elastic_[sp.index_2] -= torque;
      const double friction = -sp.damping * (s.v[sp.index_1] - s.v[sp.index_2]);
      damping_[sp.index_1] += friction;
      damping_[sp.index_2] -= friction;
    }
  }

  void add_force(const StepView&, Eigen::VectorXd& force) override {
    force += elastic_ + damping_;
  }

  double potential(const StepView& s) const override {
    double energy = 0.0;
    for (const auto& sp : springs_) {
      const double t = twist(sp, s.q);
      energy += 0.5 * sp.stiffness * t * t;
    }
    return energy;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    return {elastic_.dot(v_mid) * s.dt, -damping_.dot(v_mid) * s.dt};
  }

 private:
  static double twist(const TorsionalSpringSpec& sp, const Eigen::VectorXd& q) {
    return q[sp.index_1] - q[sp.index_2] - sp.preload_angle;
  }

  std::vector<TorsionalSpringSpec> springs_;
  Eigen::VectorXd elastic_, damping_;
};

// Viscous bearing damping −c ω on each joint [N·m].
class BearingDamping : public Element {
 public:
  explicit BearingDamping(Eigen::VectorXd damping) : damping_(std::move(damping)) {}

  void prepare(const StepView& s) override { torque_ = -damping_.cwiseProduct(s.v); }
  void add_force(const StepView&, Eigen::VectorXd& force) override { force += torque_; }
  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    return {0.0, -torque_.dot(v_mid) * s.dt};
  }

 private:
  Eigen::VectorXd damping_, torque_;
};

}  // namespace pinwind
