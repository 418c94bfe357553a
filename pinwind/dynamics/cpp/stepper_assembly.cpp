// A Stepper's start, with its elements and constraints from their kinds' factories
// (element_kinds.hpp), and the assembly the tests check against Pinocchio (stepper.hpp).
#include <algorithm>
#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>

#include "joint_algorithms.hpp"
#include "stepper.hpp"

namespace pinwind {

Elements Stepper::build_elements() const {
  Elements out;
  const KindContext c = context();
  for (const auto& add : s_.elements) add(c, out);
  return out;
}

Constraints Stepper::build_constraints() const {
  Constraints out;
  const KindContext c = context();
  for (const auto& add : s_.constraints) add(c, out);
  return out;
}

namespace {

Eigen::Index total_rows(const Constraints& constraints) {
  Eigen::Index rows = 0;
  for (const auto& c : constraints) rows += c->size();
  return rows;
}

bool reads_gear_motion(const Constraints& constraints) {
  return std::any_of(constraints.begin(), constraints.end(),
                     [](const auto& c) { return c->reads_gear_motion(); });
}

// A number for each stepper of the process, never reused (StepperState::run).
unsigned long long next_stepper_id() {
  static std::atomic<unsigned long long> next{1};
  return next++;
}

// The copy of each of items (Element::copy), checked to be whole: a kind that keeps no copy, or
// a class that inherits its base's copy (which would slice it), makes the state unsaveable.
template <class List>
List copies(const List& items) {
  List out;
  out.reserve(items.size());
  for (const auto& item : items) {
    auto copy = item->copy();
    if (!copy || typeid(*copy) != typeid(*item)) {
      throw std::logic_error(std::string("the run's state cannot be saved: its element ") +
                             typeid(*item).name() + " keeps no copy of its state (copy())");
    }
    out.push_back(std::move(copy));
  }
  return out;
}

template <class List>
bool all_copy(const List& items) {
  return std::all_of(items.begin(), items.end(), [](const auto& item) {
    const auto copy = item->copy();
    return copy && typeid(*copy) == typeid(*item);
  });
}

}  // namespace

bool Stepper::saves_state() const { return all_copy(elements_) && all_copy(constraints_); }

std::unique_ptr<StepperState> Stepper::save() const {
  auto st = std::make_unique<StepperState>();
  st->run = id_;
  st->q = q_;
  st->v = v_;
  st->accel_memory = accel_memory_;
  st->nle_last = nle_last_;
  st->gravity_last = gravity_last_;
  st->a = a_;
  st->lam = lam_;
  st->bias = bias_;
  st->mass = mass_;
  st->jac = jac_;
  st->first_step = first_step_;
  st->ledger = ledger_;
  st->elements = copies(elements_);
  st->constraints = copies(constraints_);
  st->qp = std::make_unique<ConstrainedQp>(qp_);
  return st;
}

void Stepper::restore(const StepperState& st) {
  if (st.run != id_) {
    throw std::invalid_argument(
        "the state was saved from another run (another model or session); a run takes back "
        "only the states its own save() gave");
  }
  q_ = st.q;
  v_ = st.v;
  accel_memory_ = st.accel_memory;
  nle_last_ = st.nle_last;
  gravity_last_ = st.gravity_last;
  a_ = st.a;
  lam_ = st.lam;
  bias_ = st.bias;
  mass_ = st.mass;
  jac_ = st.jac;
  first_step_ = st.first_step;
  ledger_ = st.ledger;
  for (size_t i = 0; i < elements_.size(); ++i) elements_[i]->restore(*st.elements[i]);
  for (size_t c = 0; c < constraints_.size(); ++c) constraints_[c]->restore(*st.constraints[c]);
  qp_ = *st.qp;
}

Stepper::Stepper(StepperSetup setup, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                 long samples)
    : s_(std::move(setup)),
      id_(next_stepper_id()),
      data_(s_.model),
      samples_(samples),
      nv_(s_.model.nv),
      nm_(s_.meshes.count()),
      elements_(build_elements()),
      constraints_(build_constraints()),
      rows_(total_rows(constraints_)),
      gear_motion_(reads_gear_motion(constraints_)),
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
  rows_data_.translation.assign(static_cast<size_t>(nv_), 0);
  for (size_t i = 1; i < slide_axes_.size(); ++i) {
    if (slide_axes_[i] >= 0) rows_data_.translation[s_.model.idx_vs[i]] = 1;
  }
  constant_mass_ = mass_is_constant(s_.model, slide_axes_);
  vector_space_ = is_vector_space(s_.model);
  for (const auto& placement : s_.frame_placement) {
    frame_at_joint_.push_back(placement.rotation().isIdentity(0.0) &&
                              placement.translation().isZero(0.0));
  }
  for (const auto& inertia : s_.model.inertias) {
    massless_.push_back(inertia.mass() == 0.0 && inertia.inertia().data().isZero(0.0));
  }
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

ElementForces Stepper::element_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const Eigen::VectorXd q_run = q_, v_run = v_;
  q_ = q;
  v_ = v;
  assemble_positions();
  assemble_velocities();
  const Eigen::VectorXd held = Eigen::VectorXd::Zero(nv_);  // dq₀ = 0: the force at q itself
  ElementForces out{Eigen::VectorXd::Zero(nv_), Eigen::MatrixXd::Zero(nv_, nv_),
                    Eigen::MatrixXd::Zero(nv_, nv_), 0.0};
  // With κ_q = κ_v = 0 an implicit element's force b − W ā is its force at (q, v); with one gain
  // at 1, W is its derivative along q or v.
  StepWeights at_state, along_q, along_v;
  along_q.position_gain = 1.0;
  along_v.speed_gain = 1.0;
  Eigen::VectorXd unused = Eigen::VectorXd::Zero(nv_);
  for (const StepWeights* w : {&at_state, &along_q, &along_v}) {
    const StepView view{q_,  v_,      s_.dt,   data_,   s_.meshes, rows_data_, *w,
                        held, time_, nullptr, nullptr, nullptr,   &mass_};
    Eigen::MatrixXd& tangent = w == &along_v ? out.damping : out.stiffness;
    Eigen::MatrixXd scratch = Eigen::MatrixXd::Zero(nv_, nv_);
    for (auto& element : build_elements()) {
      element->prepare(view);
      if (w == &at_state) {
        element->add_force(view, out.force);
        element->add_implicit(view, scratch, out.force);
        out.potential += element->potential(view);
      } else {
        element->add_implicit(view, tangent, unused);
      }
    }
  }
  // The elements fill the lower triangle only (Element::add_implicit).
  out.stiffness.triangularView<Eigen::StrictlyUpper>() = out.stiffness.transpose();
  out.damping.triangularView<Eigen::StrictlyUpper>() = out.damping.transpose();
  q_ = q_run;
  v_ = v_run;
  assemble_positions();
  assemble_velocities();
  return out;
}

}  // namespace pinwind
