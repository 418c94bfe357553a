// A Stepper's start, with the registry of the kinds of constraints it builds (its elements come
// from element_kinds.cpp), and the assembly the tests check against Pinocchio (stepper.hpp).
#include <memory>
#include <utility>

#include "joint_algorithms.hpp"
#include "stepper.hpp"

namespace pinwind {

using Constraints = std::vector<std::unique_ptr<Constraint>>;

// The registry of constraint kinds, in the order of their rows: the rigid meshes in file order,
// then the speed drivers and locks (the name → row map of the multipliers).
struct ConstraintKind {
  const char* name;
  void (*add)(const StepperSetup&, Constraints&);
};

const ConstraintKind kConstraintKinds[] = {
    {"rigid_meshes",
     [](const StepperSetup& s, Constraints& out) {
       if (s.rigid_meshes.empty()) return;
       out.push_back(std::make_unique<RigidMeshes>(s.rigid_meshes, s.paths));
     }},
    {"speed_drivers",
     [](const StepperSetup& s, Constraints& out) {
       if (s.driver_index.empty()) return;
       out.push_back(std::make_unique<SpeedDrivers>(s.driver_index, s.model.nv));
     }},
};

Stepper::Stepper(StepperSetup setup, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                 long samples)
    : s_(std::move(setup)),
      data_(s_.model),
      samples_(samples),
      nv_(s_.model.nv),
      nm_(s_.meshes.count()),
      rows_(static_cast<Eigen::Index>(s_.rigid_meshes.size() + s_.driver_index.size())),
      qp_(nv_, rows_, s_.solver),
      method_(s_.rho_infinity),
      q_(q0),
      q_next_(q0),
      v_(v0) {
  rows_data_.resize(nm_, nv_);
  origin_.resize(s_.meshes.joint_ids.size());
  rot_.resize(s_.meshes.joint_ids.size());
  fext_.of_joint.assign(s_.model.njoints, pinocchio::Force::Zero());
  slide_axes_ = slide_axes(s_.model);
  for (const auto& inertia : s_.model.inertias) {
    massless_.push_back(inertia.mass() == 0.0 && inertia.inertia().data().isZero(0.0));
  }
  elements_ = build_elements(s_);
  for (const auto& kind : kConstraintKinds) kind.add(s_, constraints_);
  Eigen::Index offset = 0;
  for (const auto& c : constraints_) {
    offset_.push_back(offset);
    size_.push_back(c->size());
    offset += c->size();
  }
  jac_.setZero(rows_, nv_);
  bias_.setZero(rows_);
  const StepView sv = view();
  for (size_t c = 0; c < constraints_.size(); ++c) {
    if (constraints_[c]->constant_rows()) {
      constraints_[c]->rows(sv, rows_of(jac_, c), rows_of(bias_, c));
    } else {
      varying_.push_back(c);
    }
  }
  jv_.setZero(rows_);
  mv_.setZero(nv_);
  dq_free_.setZero(nv_);
  accel_memory_.setZero(nv_);
}

Assembly Stepper::assemble(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const Eigen::VectorXd q_run = q_, v_run = v_;
  q_ = q;
  v_ = v;
  assemble_positions();
  assemble_velocities();
  Assembly out{mass_, nle_, jac_, bias_};
  q_ = q_run;
  v_ = v_run;
  return out;
}

ElementTerms Stepper::element_terms(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                    double position_gain, double speed_gain) {
  const Eigen::VectorXd q_run = q_, v_run = v_, dq_run = dq_free_;
  const StepWeights weights_run = weights_;
  q_ = q;
  v_ = v;
  assemble_positions();
  assemble_velocities();
  weights_ = StepWeights();
  weights_.inertia = 0.0;
  weights_.position_gain = position_gain;
  weights_.speed_gain = speed_gain;
  dq_free_.setZero(nv_);
  ElementTerms out{Eigen::MatrixXd::Zero(nv_, nv_), Eigen::VectorXd::Zero(nv_)};
  const StepView sv = view();
  for (auto& e : elements_) {
    e->prepare(sv);
    e->add_force(sv, out.force);
    e->add_implicit(sv, out.weight, out.force);
  }
  out.weight.triangularView<Eigen::StrictlyUpper>() = out.weight.transpose();
  q_ = q_run;
  v_ = v_run;
  dq_free_ = dq_run;
  weights_ = weights_run;
  return out;
}

}  // namespace pinwind
