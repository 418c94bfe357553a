// The constraint interface of the step loop: rows the step's accelerations satisfy exactly,
// beside the elements' forces (elements.hpp). Rigid gear meshes and speed drivers (and locked
// bearings) are Constraints; the stepper stacks their rows in the order of its list and
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
  // Whether J and γ are the same at every state (and for every λ): the stepper then asks for
  // them once.
  virtual bool constant_rows() const { return false; }
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
};

// Rigid gear meshes (mesh_rows.hpp; pinwind/dynamics/mesh.py): one row per mesh, the loaded
// flank's J = s cos α_w J_t + ε sin α_w J_r with its bias. λ is the tooth normal force F_n on
// gear B [N] along the line of action n of the loaded flank; −F_n n acts on gear A. A negative
// λ means the other flank carries the load: the row switches to it. Writes the mesh forces,
// transmission error (∫ J v dt along the loaded flank [m]), contact position, pairs and
// single-tooth force; its work joins work_constraints (zero but for the rows' drift).
class RigidMeshes final : public Constraint {
 public:
  // meshes: the indices of the rigid meshes in the model's mesh list, in row order.
  RigidMeshes(std::vector<long> meshes, const std::vector<MeshPathSpec>& paths)
      : meshes_(std::move(meshes)), paths_(paths) {
    const auto n = static_cast<Eigen::Index>(meshes_.size());
    flank_.setOnes(n);
    te_.setZero(n);
    jv_.setZero(n);
  }

  Eigen::Index size() const override { return flank_.size(); }

  void rows(const StepView& s, RowsBlock jac, ValuesBlock bias) const override {
    for (Eigen::Index r = 0; r < size(); ++r) {
      flank_row(s.meshes, s.rows, meshes_[r], flank_[r], jac.row(r), bias[r]);
    }
  }

  // With fixed axes the other flank's row is the opposite row and λ just flips sign;
  // otherwise solve again (a switch can move load between meshes).
  RowSwitch switch_rows(const StepView& s, ValuesBlock lambda) override {
    bool any = false, all_free = true;
    for (Eigen::Index r = 0; r < size(); ++r) {
      if (lambda[r] < 0.0) {
        any = true;
        all_free = all_free && flank_flip_is_free(s.rows, meshes_[r]);
      }
    }
    if (!any) return RowSwitch::none;
    for (Eigen::Index r = 0; r < size(); ++r) {
      if (lambda[r] < 0.0) flank_[r] = -flank_[r];
    }
    if (!all_free) return RowSwitch::solve;
    for (Eigen::Index r = 0; r < size(); ++r) {
      if (lambda[r] < 0.0) lambda[r] = -lambda[r];
    }
    return RowSwitch::free;
  }

  // The tooth forces at the pitch points: the reduced-coordinate form of
  // 000_3b7c4a8fe52a6eee.txt eqs. 16, 18, 23 and 26.
  void add_body_forces(const StepView& s, ConstValues lambda, BodyForces& out) const override {
    const auto& mc = s.meshes;
    for (Eigen::Index r = 0; r < size(); ++r) {
      const Eigen::Index m = meshes_[r];
      const Vec3 f = tooth_force_on_b(mc, s.rows, m, flank_[r], lambda[r]);
      const Vec3 p = s.rows.pitch_point.row(m).transpose();
      out.add(mc.joint_b[m], p, f);
      out.add(mc.joint_a[m], p, -f);
    }
  }

  // The forces from the loaded flanks' multipliers, with where the teeth are along the path of
  // contact.
  void record(const StepView& s, long k, ConstValues lambda, const Outputs& out) const override {
    const auto& mc = s.meshes;
    for (Eigen::Index r = 0; r < size(); ++r) {
      const Eigen::Index m = meshes_[r];
      const auto& path = paths_[static_cast<size_t>(m)];
      const double angle =
          gear_a_angle(mc, s.rows, path, s.data.oMi[mc.joint_a[m]].rotation(), m);
      const PathState p = path_state(path, angle, flank_[r]);
      record_mesh_force(out, mc, s.rows, k, m, lambda[r], flank_[r]);
      const long e = out.entry(Family::mesh, k, m);
      out.at(Series::transmission_error, e) = te_[r];
      out.at(Series::mesh_deflection, e) = 0.0;
      out.at(Series::mesh_contact_position, e) = path.roll_start + p.entering;
      out.at(Series::mesh_pairs, e) = p.pairs;
      out.at(Series::mesh_single_tooth_force, e) = lambda[r] * p.share;
    }
  }

  void work(const StepView&, ConstRows jac, ConstValues lambda, const Eigen::VectorXd& dq,
            EnergyLedger& ledger) const override {
    if (!size()) return;
    jv_.noalias() = jac * dq;
    ledger.constraints += lambda.dot(jv_);
  }

  void advance(const StepView&, ConstRows jac, const Eigen::VectorXd& dq) override {
    for (Eigen::Index r = 0; r < size(); ++r) te_[r] += jac.row(r).dot(dq);
  }

 private:
  // Whether mesh m's other flank has the opposite row (fixed axes): λ just changes sign. When
  // the radial part of the row vanishes in joint space it vanishes at every state (the axes
  // cannot move apart), so its bias, the time derivative, vanishes too.
  static bool flank_flip_is_free(const MeshRows& rows, Eigen::Index m) {
    const double scale = rows.jac_t.row(m).cwiseAbs().maxCoeff() + 1e-300;
    return rows.jac_r.row(m).cwiseAbs().maxCoeff() <= 1e-12 * scale;
  }

  std::vector<long> meshes_;
  const std::vector<MeshPathSpec>& paths_;
  Eigen::VectorXd flank_, te_;  // loaded flank s (±1) and transmission error [m] of each row
  mutable Eigen::VectorXd jv_;
};

// Speed drivers and locked bearings: row e_i on velocity i, J v = w(t), w the driver's speed
// [rad/s] (0 for a lock), bias 0. λ is the torque the driver puts on its joint [N·m]; it joins
// the joint's recorded torque, and its work joins work_drivers.
class SpeedDrivers final : public Constraint {
 public:
  // index: velocity index of each driver and lock, in row order.
  SpeedDrivers(std::vector<long> index, Eigen::Index nv) : index_(std::move(index)) {
    torque_.setZero(nv);
  }

  Eigen::Index size() const override { return static_cast<Eigen::Index>(index_.size()); }

  void rows(const StepView&, RowsBlock jac, ValuesBlock bias) const override {
    jac.setZero();
    for (Eigen::Index i = 0; i < size(); ++i) jac(i, index_[i]) = 1.0;
    bias.setZero();
  }

  bool constant_rows() const override { return true; }

  void targets(const StepView& s, ValuesBlock now, ValuesBlock next) const override {
    if (!size()) return;
    now = Eigen::Map<const Eigen::VectorXd>(s.target_now, size());
    next = Eigen::Map<const Eigen::VectorXd>(s.target_next, size());
  }

  void record(const StepView&, long k, ConstValues lambda, const Outputs& out) const override {
    for (Eigen::Index i = 0; i < size(); ++i) {
      out.at(Series::torque, out.entry(Family::joint, k, index_[i])) += lambda[i];
    }
  }

  void work(const StepView&, ConstRows, ConstValues lambda, const Eigen::VectorXd& dq,
            EnergyLedger& ledger) const override {
    torque_.setZero();
    for (Eigen::Index i = 0; i < size(); ++i) torque_[index_[i]] += lambda[i];
    ledger.drivers += torque_.dot(dq);
  }

 private:
  std::vector<long> index_;
  mutable Eigen::VectorXd torque_;  // Σ λ_i e_i [N·m]
};

}  // namespace pinwind
