// Torsional spring-dampers between two coaxial joints (Kelso 2011 "RSDA",
// k = GJ/L): torque −k(θ₁ − θ₂ − θ₀) − c(ω₁ − ω₂) on joint 1 and the opposite on joint 2 (viscous
// bearing damping is bearing_damping.hpp). A spring without joint 2 (index_2 = −1) acts across joint 1 alone,
// between its body and the body it turns in: −k(θ₁ − θ₀) − cω₁ (a ring held in torsion, a torque
// arm to the ground, a bearing's torsional stiffness). It is taken at the time step's weighted
// state (time_step.hpp), linear in the step's acceleration ā like a compliant mesh
// (compliant_mesh.hpp): with Δθ = θ₁ − θ₂ − θ₀ and the same differences of dq₀, ω and ā,
//
//     τ₁ = −k (Δθ_n + Δdq₀ + κ_q Δā) − c (Δω_n + κ_v Δā),   W = (k κ_q + c κ_v) (e₁ − e₂)(e₁ − e₂)ᵀ,
//
// (e₂ = 0 without joint 2) so that the step stays second order and, with ρ∞ = 1, keeps the
// spring's energy.
#pragma once

#include <memory>
#include <stdexcept>
#include <vector>

#include <nanobind/nanobind.h>

#include "element_kind.hpp"
#include "elements.hpp"

namespace pinwind {

struct TorsionalSpringSpec {
  long index_1 = 0, index_2 = 0;  // velocity indices of the two joints; index_2 −1: joint 1 alone
  double stiffness = 0.0;         // k [N·m/rad]
  double damping = 0.0;           // c [N·m·s/rad]
  double preload_angle = 0.0;     // θ₀ [rad]
};

class TorsionalSprings : public Element {
 public:
  explicit TorsionalSprings(std::vector<TorsionalSpringSpec> springs)
      : springs_(std::move(springs)) {}

  void add_implicit(const StepView& s, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    for (const auto& sp : springs_) {
      const long i = sp.index_1, j = sp.index_2;
      const double w = sp.stiffness * s.weights.position_gain + sp.damping * s.weights.speed_gain;
      hessian(i, i) += w;
      const double torque = -sp.stiffness * (twist(sp, s.q) + difference(sp, s.dq_free)) -
                            sp.damping * difference(sp, s.v);
      force[i] += torque;
      if (j < 0) continue;
      hessian(j, j) += w;
      hessian(i, j) -= w;
      hessian(j, i) -= w;
      force[j] -= torque;
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool) override {
    elastic_.setZero(s.q.size());
    damping_.setZero(s.q.size());
    for (const auto& sp : springs_) {
      const long i = sp.index_1, j = sp.index_2;
      const double da = difference(sp, a);
      const double torque = -sp.stiffness * (twist(sp, s.q) + difference(sp, s.dq_free) +
                                             s.weights.position_gain * da);
      const double friction = -sp.damping * (difference(sp, s.v) + s.weights.speed_gain * da);
      elastic_[i] += torque;
      damping_[i] += friction;
      if (j < 0) continue;
      elastic_[j] -= torque;
      damping_[j] -= friction;
    }
    return false;
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

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override {
    return copy_of<TorsionalSprings, Element>(*this);
  }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  // x₁ − x₂ of a joint vector (angles, speeds, accelerations), x₁ alone without joint 2.
  static double difference(const TorsionalSpringSpec& sp, const Eigen::VectorXd& x) {
    return sp.index_2 < 0 ? x[sp.index_1] : x[sp.index_1] - x[sp.index_2];
  }

  static double twist(const TorsionalSpringSpec& sp, const Eigen::VectorXd& q) {
    return difference(sp, q) - sp.preload_angle;
  }

  std::vector<TorsionalSpringSpec> springs_;
  Eigen::VectorXd elastic_, damping_;
};

// The kind (element_kind.hpp): StepperSpec.springs, one element for all of them.
struct TorsionalSpringsKind : KindBase {
  using Specs = std::vector<TorsionalSpringSpec>;
  using Built = Elements;
  static constexpr const char* field = "springs";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& sp : specs) {
      if (sp.index_1 < 0 || sp.index_2 < -1 || sp.index_1 >= c.nv || sp.index_2 >= c.nv ||
          sp.index_1 == sp.index_2) {
        throw std::invalid_argument("bad spring joint index");
      }
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    if (!specs.empty()) out.push_back(std::make_unique<TorsionalSprings>(specs));
  }

  static void bind(nanobind::module_& m) {
    nanobind::class_<TorsionalSpringSpec>(m, "TorsionalSpringSpec")
        .def(nanobind::init<>())
        .def_rw("index_1", &TorsionalSpringSpec::index_1)
        .def_rw("index_2", &TorsionalSpringSpec::index_2)
        .def_rw("stiffness", &TorsionalSpringSpec::stiffness)
        .def_rw("damping", &TorsionalSpringSpec::damping)
        .def_rw("preload_angle", &TorsionalSpringSpec::preload_angle);
  }
};

}  // namespace pinwind
