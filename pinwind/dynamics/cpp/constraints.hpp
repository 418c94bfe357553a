// The constraint interface of the step loop: rows the step's accelerations satisfy exactly,
// beside the elements' forces (elements.hpp). Rigid gear meshes (rigid_meshes.hpp) and speed
// drivers and locked bearings (speed_drivers.hpp) are Constraints; the stepper stacks their rows in the order of its list and
// iterates them as it iterates elements, knowing none by name (after Pinocchio's
// constraint-model-base.hpp and Chrono's ChLink).
//
// A constraint owns k rows of the step's equality QP (constrained_qp.hpp):
//
//     J a = −γ + (w(t_{k+1}) − w(t_k)) / h,     J = J(q) of shape (k, nv),
//
// with γ = J̇ v its bias (ċ at q̈ = 0) and w its velocity target: J v = w (0 for a mesh). Its
// multipliers λ (k) are the forces along its rows, Jᵀ λ their generalised force on the joints;
// each constraint says what they mean and in which unit. Each constraint also writes its
// outputs, puts its forces on the bodies for the bearing reactions and books their work in the
// energy ledger. A virtual call per constraint and step, never per row; no allocation per step.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "elements.hpp"
#include "mesh_path.hpp"
#include "mesh_rows.hpp"
#include "series.hpp"

namespace pinwind {

// One constraint's rows inside the stacked J, γ, w and λ.
using RowsBlock = Eigen::Ref<Eigen::MatrixXd>;
using ConstRows = Eigen::Ref<const Eigen::MatrixXd>;
using ValuesBlock = Eigen::Ref<Eigen::VectorXd>;
using ConstValues = Eigen::Ref<const Eigen::VectorXd>;

// What a change of rows after a solve asks for.
enum class RowSwitch {
  none,   // the rows hold
  free,   // switched, and the solution carries over: λ was fixed up in place
  solve,  // switched: solve again
};

class Constraint {
 public:
  virtual ~Constraint() = default;

  // k, the number of rows.
  virtual Eigen::Index size() const = 0;
  // J (k × nv) and γ (k) at the state of the view (its mesh rows evaluated).
  virtual void rows(const StepView&, RowsBlock jac, ValuesBlock bias) const = 0;
  // γ alone, J kept from the last rows() at the same angles (the step asks for J at its
  // positions, then for γ once the speeds are projected).
  virtual void biases(const StepView&, ValuesBlock bias) const = 0;
  // Whether J and γ are the same at every state (and for every λ): the stepper then asks for
  // them once.
  virtual bool constant_rows() const { return false; }
  // Whether γ reads the gears' twists and accelerations at q̈ = 0 (MeshRows::twist, accel),
  // which the stepper then computes each step.
  virtual bool reads_gear_motion() const { return false; }
  // The velocity targets w(t_k) and w(t_{k+1}); left 0 by default.
  virtual void targets(const StepView&, ValuesBlock now, ValuesBlock next) const {
    (void)now;
    (void)next;
  }
  // After a solve with multipliers λ: switches the rows that λ shows wrong (module comment).
  virtual RowSwitch switch_rows(const StepView&, ValuesBlock lambda) {
    (void)lambda;
    return RowSwitch::none;
  }
  // Its forces on the bodies, for the bearing reactions.
  virtual void add_body_forces(const StepView&, ConstValues lambda, BodyForces&) const {
    (void)lambda;
  }
  // Writes its outputs of sample k.
  virtual void record(const StepView&, long k, ConstValues lambda, const Outputs&) const {
    (void)k;
    (void)lambda;
  }
  // Adds the work of Jᵀ λ over the step, Δq = (v_k + v_{k+1}) h / 2, to its ledger term.
  virtual void work(const StepView&, ConstRows jac, ConstValues lambda,
                    const Eigen::VectorXd& dq, EnergyLedger& ledger) const = 0;
  // Moves its own states (the transmission error) from t_k to t_{k+1}, given the step's
  // displacement Δq = q_{k+1} ⊖ q_k (time_step.hpp).
  virtual void advance(const StepView&, ConstRows jac, const Eigen::VectorXd& dq) {
    (void)jac;
    (void)dq;
  }
  // A copy, states and all (its rows' flanks, the transmission error), for a saved state of
  // the run; null if the kind keeps none (Element::copy).
  virtual std::unique_ptr<Constraint> copy() const { return nullptr; }
  // Takes the states of saved, a copy() of this constraint (Stepper::restore).
  virtual void restore(const Constraint& saved) { (void)saved; }
};

}  // namespace pinwind
