// Viscous bearing damping: a torque −c ω on each joint [N·m] (the URDF's <dynamics damping>),
// taken at the time step's weighted speed v_n + κ_v ā (time_step.hpp) like the torsional
// springs' damping (torsional_spring.hpp): W = κ_v diag(c).
#pragma once

#include <memory>
#include <utility>

#include <Eigen/Core>
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>

#include "element_kind.hpp"
#include "elements.hpp"
#include "spec_checks.hpp"

namespace pinwind {

// Viscous bearing damping −c ω on each joint [N·m], at the weighted speed v_n + κ_v ā.
class BearingDamping : public Element {
 public:
  explicit BearingDamping(Eigen::VectorXd damping) : damping_(std::move(damping)) {}

  void add_implicit(const StepView& s, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    hessian.diagonal() += s.weights.speed_gain * damping_;
    force -= damping_.cwiseProduct(s.v);
  }
  bool settle(const StepView& s, const Eigen::VectorXd& a, bool) override {
    torque_ = -damping_.cwiseProduct(s.v + s.weights.speed_gain * a);
    return false;
  }
  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    return {0.0, -torque_.dot(v_mid) * s.dt};
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<BearingDamping, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  Eigen::VectorXd damping_, torque_;
};

// The kind (element_kind.hpp): StepperSpec.bearing_damping, c of every velocity [N·m·s/rad or
// N·s/m]; one element when any is non-zero. Its spec is a vector of the module's Eigen type, so
// it binds nothing of its own.
struct BearingDampingKind : KindBase {
  using Specs = Eigen::VectorXd;
  using Built = Elements;
  static constexpr const char* field = "bearing_damping";

  static void check(const Specs& damping, const KindContext& c) {
    check_size("bearing_damping", damping, static_cast<size_t>(c.nv));
  }

  static void add(const Specs& damping, const KindContext&, Elements& out) {
    if (damping.size() && damping.cwiseAbs().maxCoeff() > 0.0) {
      out.push_back(std::make_unique<BearingDamping>(damping));
    }
  }

  static void bind(nanobind::module_&) {}
};

}  // namespace pinwind
