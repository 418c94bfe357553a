// Time integration of a gearbox: assemble, solve, record, step (pinwind/dynamics/simulate.py
// documents the scheme; this is its compiled inner loop).
//
// Each step k, at state (q_k, v_k) and time t_k = k·dt:
//
// 1. assemble M (CRBA), b (RNEA at a = 0), τ (applied torques and the elements' explicit
//    forces), the elements' implicit parts (compliant meshes, elements.hpp) and the constraint
//    rows J, γ: one row per rigid mesh (mesh_rows.hpp), per speed driver and per locked bearing;
// 2. solve the equality QP with proxsuite (constrained_qp.hpp): a_k and λ_k, the rigid mesh
//    forces [N] and driver torques [N·m], read from the duals through the name → row map (rows
//    0..r−1 are the rigid meshes in file order, then the drivers); elements with contact
//    conditions settle their active set, solving again when it changes;
// 3. bearing reactions by RNEA with the tooth forces at the pitch points;
// 4. semi-implicit Euler: v_{k+1} = v_k + a_k dt, q_{k+1} = q_k ⊕ v_{k+1} dt.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include "compliant_mesh.hpp"
#include "constrained_qp.hpp"
#include "elements.hpp"
#include "generator.hpp"
#include "mesh_path.hpp"
#include "mesh_rows.hpp"
#include "rotor.hpp"
#include "torsional_spring.hpp"

namespace pinwind {

// What stopped a run: the Python side raises the matching PinwindError.
struct RunStatus {
  enum Code { kCompleted = 0, kDiverged, kSolverFailed, kConflictingConstraints };
  int code = kCompleted;
  long sample = 0;  // samples [0, sample) are final
  long step = 0;    // the step and time the error names
  double time = 0.0;
  std::string what;        // Diverged: what became non-finite; SolverFailed: proxsuite's status
  double residual = 0.0;   // ConflictingConstraints: the mismatch left after projection
  double primal = 0.0;     // SolverFailed: residuals and iterations
  double dual = 0.0;
  long iterations = 0;
};

struct StepperSetup {
  pinocchio::Model model;
  MeshConstants meshes;
  std::vector<MeshPathSpec> paths;       // every mesh's path of contact
  std::vector<long> rigid_meshes;        // meshes that are constraint rows, in row order
  std::vector<CompliantMeshSpec> compliant_meshes;
  std::vector<TorsionalSpringSpec> springs;
  std::vector<GeneratorSpec> generators;  // generator.hpp
  std::vector<RotorSpec> rotors;          // rotor.hpp
  long input_columns = 0;                 // per-sample inputs the elements read (wind speeds)
  Eigen::VectorXd bearing_damping;
  std::vector<long> driver_index;  // velocity index of each speed driver and lock
  std::vector<long> frame_parent;  // body frames: parent joint and placement in it
  std::vector<pinocchio::SE3> frame_placement;
  double dt = 1e-3;
  double projection_tol = 1e-14;
  double implicit_theta = 0.5;     // compliant_mesh.hpp
  SolverSettings solver;
};

class Stepper : private BodyForces {
 public:
  // samples: how many samples the whole run has (the last one is recorded, not stepped from).
  Stepper(StepperSetup setup, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, long samples)
      : s_(std::move(setup)),
        data_(s_.model),
        samples_(samples),
        nv_(s_.model.nv),
        nm_(s_.meshes.count()),
        nr_(static_cast<Eigen::Index>(s_.rigid_meshes.size())),
        nd_(static_cast<Eigen::Index>(s_.driver_index.size())),
        rows_(nr_ + nd_),
        qp_(nv_, rows_, s_.solver),
        q_(q0),
        q_next_(q0),
        v_(v0) {
    driver_jac_.setZero(nd_, nv_);
    for (Eigen::Index i = 0; i < nd_; ++i) driver_jac_(i, s_.driver_index[i]) = 1.0;
    flank_.setOnes(nr_);
    te_.setZero(nr_);
    rows_data_.resize(nm_, nv_);
    origin_.resize(s_.meshes.joint_ids.size());
    rot_.resize(s_.meshes.joint_ids.size());
    fext_.assign(s_.model.njoints, pinocchio::Force::Zero());
    if (!s_.springs.empty()) {
      elements_.push_back(std::make_unique<TorsionalSprings>(s_.springs));
    }
    if (s_.bearing_damping.size() && s_.bearing_damping.cwiseAbs().maxCoeff() > 0.0) {
      elements_.push_back(std::make_unique<BearingDamping>(s_.bearing_damping));
    }
    if (!s_.compliant_meshes.empty()) {
      elements_.push_back(std::make_unique<CompliantMeshes>(s_.compliant_meshes, s_.paths,
                                                            s_.implicit_theta, nv_));
    }
    for (size_t i = 0; i < s_.generators.size(); ++i) {
      const auto& g = s_.generators[i];
      const long slot = static_cast<long>(i);
      if (g.law == GeneratorSpec::kInductionDq) {
        elements_.push_back(std::make_unique<InductionMachineDq>(g, slot));
      } else {
        elements_.push_back(std::make_unique<GeneratorLaw>(g, slot));
      }
    }
    for (size_t i = 0; i < s_.rotors.size(); ++i) {
      elements_.push_back(std::make_unique<RotorAerodynamics>(s_.rotors[i], static_cast<long>(i)));
    }
    jac_.setZero(rows_, nv_);
    bias_.setZero(rows_);
    jv_.setZero(rows_);
    mv_.setZero(nv_);
  }

  // Steps samples [k0, k1), writing sample k into row k − k0 of out. torque: (k1 − k0, nv)
  // applied torques [N·m] at t_k; target: (k1 − k0 + 1, drivers) driver speeds [rad/s] at t_k
  // and t_{k1} (locks 0); inputs: (k1 − k0, input_columns) the elements' inputs at t_k.
  RunStatus run(long k0, long k1, const RowMat& torque, const RowMat& target, const Outputs& out,
                const RowMat& inputs) {
    RunStatus st;
    out_ = out;
    for (long k = k0; k < k1; ++k) {
      const double t = k * s_.dt;
      st.sample = k;
      time_ = t;
      inputs_ = s_.input_columns ? inputs.row(k - k0).data() : nullptr;
      tau_applied_ = torque.row(k - k0).transpose();
      target_now_.setZero(rows_);
      target_next_.setZero(rows_);
      if (nd_) {
        target_now_.tail(nd_) = target.row(k - k0).transpose();
        target_next_.tail(nd_) = target.row(k - k0 + 1).transpose();
      }
      if (!solve(k, t, st)) return st;
      if (!std::isfinite(a_.squaredNorm() + lam_.squaredNorm())) {
        return fail(st, k, t, "the accelerations or constraint forces are not finite");
      }
      bearing_reactions();
      record(k - k0, t);
      if (k + 1 == samples_) {
        st.sample = k + 1;
        return st;
      }
      advance();
      if (!std::isfinite(q_.squaredNorm() + v_.squaredNorm())) {
        return fail(st, k + 1, t + s_.dt, "the joint angles or speeds are not finite");
      }
    }
    st.sample = k1;
    return st;
  }

  // Joint-space inertia at q (for checks against Pinocchio's own).
  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) {
    pinocchio::computeJointJacobians(s_.model, data_, q);
    mass_from_jacobian();
    return mass_;
  }

 private:
  static RunStatus& fail(RunStatus& st, long step, double time, const std::string& what) {
    st.code = RunStatus::kDiverged;
    st.step = step;
    st.time = time;
    st.what = what;
    return st;
  }

  StepView view() const { return {q_, v_, s_.dt, data_, s_.meshes, rows_data_, time_, inputs_}; }

  // Joint placements, world Jacobian J and the meshes' geometry and rows: what depends on the
  // angles only.
  void kinematics() {
    pinocchio::computeJointJacobians(s_.model, data_, q_);
    for (size_t i = 0; i < s_.meshes.joint_ids.size(); ++i) {
      origin_[i] = data_.oMi[s_.meshes.joint_ids[i]].translation();
      rot_[i] = data_.oMi[s_.meshes.joint_ids[i]].rotation();
    }
    if (nm_) evaluate_mesh_geometry(s_.meshes, data_.J, origin_, rot_, rows_data_);
  }

  // What depends on the speeds too, at the final (projected) v: the world spatial velocity of
  // joint i is that of its parent plus J_i v_i, so the time variation dJ_i = v_i ×(motion) J_i
  // (what computeJointJacobiansTimeVariation computes) follows from J without another pass over
  // the joint placements; then the meshes' bias.
  void velocity_kinematics() {
    const auto& model = s_.model;
    const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
    drift_.resize(nj);
    data_.ov[0].setZero();
    drift_[0].setZero();
    for (pinocchio::JointIndex i = 1; i < nj; ++i) {
      const int idx = model.idx_vs[i], n = model.nvs[i];
      const auto parent = model.parents[i];
      const pinocchio::Motion::Vector6 twist = data_.J.middleCols(idx, n) * v_.segment(idx, n);
      data_.ov[i] = data_.ov[parent] + pinocchio::Motion(twist);
      for (int c = idx; c < idx + n; ++c) {
        data_.dJ.col(c) = data_.ov[i].cross(pinocchio::Motion(data_.J.col(c))).toVector();
      }
      const pinocchio::Motion::Vector6 dj = data_.dJ.middleCols(idx, n) * v_.segment(idx, n);
      drift_[i] = drift_[parent] + pinocchio::Motion(dj);
    }
    if (nm_) {
      // The twist and the acceleration at q̈ = 0 of each gear's body are those of its joint.
      const auto& ids = s_.meshes.joint_ids;
      rows_data_.twist.resize(ids.size());
      rows_data_.accel.resize(ids.size());
      for (size_t i = 0; i < ids.size(); ++i) {
        rows_data_.twist[i] = data_.ov[ids[i]].toVector();
        rows_data_.accel[i] = drift_[ids[i]].toVector();
      }
      evaluate_mesh_bias_from(s_.meshes, rows_data_);
    }
  }

  // Recursive Newton-Euler in world axes about the world origin (Featherstone, Rigid Body
  // Dynamics Algorithms, 2008, §5.3; Pinocchio's world-convention passes), from the
  // J, J̇, joint velocities and world inertias the step has already computed: the bias forces
  // C(q, v) v + g(q), their gravity part g(q) on its own (for the energy ledger), and per body
  // the force at q̈ = 0 for the bearing reactions after the QP. Each pass over the joints is a
  // few spatial products; Pinocchio's computeGeneralizedGravity, nonLinearEffects and rnea
  // would each recompute the joint placements (two sines and cosines per joint).
  void bias_forces() {
    const auto& model = s_.model;
    const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
    body_force_.resize(nj);
    subtree_.resize(nj);
    weight_.resize(nj);
    for (pinocchio::JointIndex i = 1; i < nj; ++i) {
      // gravity as an upward acceleration of the base, plus the drift J̇ v of velocity_kinematics
      weight_[i] = body_[i] * (-model.gravity);
      body_force_[i] = body_[i] * drift_[i] + weight_[i] + body_[i].vxiv(data_.ov[i]);
      subtree_[i] = body_force_[i];
    }
    nle_.resize(nv_);
    gravity_.resize(nv_);
    for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
      const int idx = model.idx_vs[i], n = model.nvs[i];
      const auto cols = data_.J.middleCols(idx, n);
      nle_.segment(idx, n).noalias() = cols.transpose() * subtree_[i].toVector();
      gravity_.segment(idx, n).noalias() = cols.transpose() * weight_[i].toVector();
      const auto parent = model.parents[i];
      if (parent > 0) {
        subtree_[parent] += subtree_[i];
        weight_[parent] += weight_[i];
      }
    }
  }

  // The force each joint transmits to its subtree at accelerations a_ under the external body
  // forces fext_ (world, about the origin), in the joint frame about the joint origin as
  // Pinocchio's rnea leaves it in data.f: the bearing reactions.
  void joint_forces() {
    const auto& model = s_.model;
    const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
    accel_.resize(nj);
    accel_[0].setZero();
    for (pinocchio::JointIndex i = 1; i < nj; ++i) {
      const int idx = model.idx_vs[i], n = model.nvs[i];
      const pinocchio::Motion::Vector6 ja = data_.J.middleCols(idx, n) * a_.segment(idx, n);
      accel_[i] = accel_[model.parents[i]] + pinocchio::Motion(ja);
      subtree_[i] = body_force_[i] + body_[i] * accel_[i] - fext_[i];
    }
    for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
      if (model.parents[i] > 0) subtree_[model.parents[i]] += subtree_[i];
      data_.f[i] = data_.oMi[i].actInv(subtree_[i]);
    }
  }

  // Joint-space inertia M(q) from the placements and J of kinematics(), as Pinocchio's CRBA in
  // world convention computes it (composite inertias Y_i of each subtree in world,
  // M(i, j) = J_iᵀ Y_j J_j for j in the subtree of i, plus the armature), without CRBA's own
  // pass over the joint placements.
  void mass_from_jacobian() {
    const auto& model = s_.model;
    const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
    composite_.resize(nj);
    body_.resize(nj);
    for (pinocchio::JointIndex i = 1; i < nj; ++i) {
      body_[i] = composite_[i] = data_.oMi[i].act(model.inertias[i]);
    }
    mass_.setZero(nv_, nv_);
    momenta_.resize(6, nv_);
    for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
      const int idx = model.idx_vs[i], n = model.nvs[i], sub = data_.nvSubtree[i];
      for (int c = idx; c < idx + n; ++c) {
        momenta_.col(c) = (composite_[i] * pinocchio::Motion(data_.J.col(c))).toVector();
      }
      mass_.block(idx, idx, n, sub).noalias() =
          data_.J.middleCols(idx, n).transpose() * momenta_.middleCols(idx, sub);
      if (model.parents[i] > 0) composite_[model.parents[i]] += composite_[i];
    }
    mass_.diagonal() += model.armature;
    mass_.triangularView<Eigen::StrictlyLower>() = mass_.transpose().triangularView<Eigen::StrictlyLower>();
  }

  // J and γ of the rigid meshes' loaded flanks, then the driver rows.
  void constraint_matrix() {
    for (Eigen::Index r = 0; r < nr_; ++r) {
      flank_row(s_.meshes, rows_data_, s_.rigid_meshes[r], flank_[r], jac_.row(r), bias_[r]);
    }
    if (nd_) jac_.bottomRows(nd_) = driver_jac_;
  }

  double residual() {
    if (!rows_) return 0.0;
    jv_.noalias() = jac_ * v_;
    return (jv_ - target_now_).cwiseAbs().maxCoeff();
  }

  // M-orthogonal projection of v onto J v = target (pseudo-inverse: redundant rows).
  bool project(long k, double t, RunStatus& st) {
    const Eigen::MatrixXd minv_jt = mass_.ldlt().solve(jac_.transpose());
    const Eigen::MatrixXd delassus = jac_ * minv_jt;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(delassus, Eigen::ComputeThinU | Eigen::ComputeThinV);
    Eigen::VectorXd sv = svd.singularValues();
    const double cutoff = sv.size() ? 1e-12 * sv[0] : 0.0;
    for (Eigen::Index i = 0; i < sv.size(); ++i) sv[i] = sv[i] > cutoff ? 1.0 / sv[i] : 0.0;
    const Eigen::VectorXd mismatch = jac_ * v_ - target_now_;
    const Eigen::VectorXd correction =
        svd.matrixV() * sv.asDiagonal() * (svd.matrixU().transpose() * mismatch);
    const Eigen::VectorXd projected = v_ - minv_jt * correction;
    const double left = (jac_ * projected - target_now_).cwiseAbs().maxCoeff();
    const double scale = 1.0 + target_now_.cwiseAbs().maxCoeff() +
                         jac_.cwiseAbs().maxCoeff() * v_.cwiseAbs().maxCoeff();
    if (left > 1e-9 * scale) {
      st.code = RunStatus::kConflictingConstraints;
      st.step = k;
      st.time = t;
      st.residual = left;
      return false;
    }
    v_ = projected;
    return true;
  }

  bool check(long k, double t, const QpSolution& sol, RunStatus& st) {
    if (!(std::isfinite(sol.primal_residual) && std::isfinite(sol.dual_residual))) {
      fail(st, k, t, "the constrained-dynamics QP returned non-finite values");
      return false;
    }
    if (!sol.solved) {
      st.code = RunStatus::kSolverFailed;
      st.step = k;
      st.time = t;
      st.what = sol.status;
      st.primal = sol.primal_residual;
      st.dual = sol.dual_residual;
      st.iterations = sol.iterations;
      return false;
    }
    return true;
  }

  // The QP's Hessian and force for the elements' current active sets, then the solve.
  const QpSolution* solve_qp(long k, double t, RunStatus& st) {
    hessian_ = mass_;
    force_ = force_explicit_;
    const StepView sv = view();
    for (auto& e : elements_) e->add_implicit(sv, hessian_, force_);
    rhs_ = -bias_ + (target_next_ - target_now_) / s_.dt;
    if (!std::isfinite(force_.squaredNorm() + rhs_.squaredNorm())) {
      fail(st, k, t, "the joint forces or constraint terms are not finite");
      return nullptr;
    }
    const QpSolution* sol = &qp_.solve(hessian_, force_, jac_, rhs_);
    return check(k, t, *sol, st) ? sol : nullptr;
  }

  // Dynamics at (q, v, t): a, λ and the forces the recorder and the integrator need.
  bool solve(long k, double t, RunStatus& st) {
    kinematics();
    mass_from_jacobian();
    constraint_matrix();
    residual_ = residual();
    if (residual_ > s_.projection_tol * (1.0 + v_.cwiseAbs().maxCoeff())) {
      // Post-stabilisation: J changed over the last step, or the run starts off the
      // constraint manifold.
      if (!project(k, t, st)) return false;
      residual_ = residual();
    }
    velocity_kinematics();
    constraint_matrix();
    bias_forces();
    const Eigen::VectorXd& nle = nle_;
    const StepView sv = view();
    elements_force_.setZero(nv_);
    for (auto& e : elements_) {
      e->prepare(sv);
      e->add_force(sv, elements_force_);
    }
    force_explicit_ = tau_applied_ + elements_force_ - nle;
    const QpSolution* sol = solve_qp(k, t, st);
    if (!sol) return false;
    lam_ = sol->multipliers;
    // A negative rigid tooth force means the other flank carries the load: switch those rows to
    // it. With fixed axes the other flank's row is the opposite row and λ just flips sign;
    // otherwise solve again (a switch can move load between meshes, so repeat, a few times).
    // Elements with contact (compliant meshes) settle their active sets in the same loop.
    constexpr int kPasses = 8;
    for (int pass = 0; pass < kPasses; ++pass) {
      bool any = false, all_free = true;
      for (Eigen::Index r = 0; r < nr_; ++r) {
        if (lam_[r] < 0.0) {
          any = true;
          all_free = all_free && flank_flip_is_free(s_.rigid_meshes[r]);
        }
      }
      bool settled = true;
      const bool last = pass + 1 == kPasses;
      for (auto& e : elements_) settled = !e->settle(sv, sol->acceleration, last) && settled;
      if (!any && settled) break;
      for (Eigen::Index r = 0; r < nr_; ++r) {
        if (lam_[r] < 0.0) flank_[r] = -flank_[r];
      }
      constraint_matrix();
      if (all_free && settled) {
        for (Eigen::Index r = 0; r < nr_; ++r) {
          if (lam_[r] < 0.0) lam_[r] = -lam_[r];
        }
        break;
      }
      sol = solve_qp(k, t, st);
      if (!sol) return false;
      lam_ = sol->multipliers;
      if (pass + 2 == kPasses) {
        for (auto& e : elements_) e->settle(sv, sol->acceleration, true);
        break;
      }
    }
    a_ = sol->acceleration;
    return true;
  }

  // Whether mesh m's other flank has the opposite row (fixed axes): λ just changes sign. When
  // the radial part of the row vanishes in joint space it vanishes at every state (the axes
  // cannot move apart), so its bias, the time derivative, vanishes too.
  bool flank_flip_is_free(Eigen::Index m) const {
    const double scale = rows_data_.jac_t.row(m).cwiseAbs().maxCoeff() + 1e-300;
    return rows_data_.jac_r.row(m).cwiseAbs().maxCoeff() <= 1e-12 * scale;
  }

  // Adds a force f applied at world point p to joint j's external force (world axes, about the
  // world origin, as joint_forces() takes it).
  void add(long j, const Vec3& p, const Vec3& f) override {
    fext_[j].linear() += f;
    fext_[j].angular() += p.cross(f);
  }

  // Tooth forces on the gears, and the bearing reactions by RNEA with them applied at the
  // pitch points: data.f[j] is the spatial force joint j transmits from its parent to its
  // child, in the joint frame about the joint origin (the reduced-coordinate form of
  // 000_3b7c4a8fe52a6eee.txt eqs. 16, 18, 23 and 26).
  void bearing_reactions() {
    const auto& mc = s_.meshes;
    for (auto& f : fext_) f.setZero();
    for (Eigen::Index r = 0; r < nr_; ++r) {
      const Eigen::Index m = s_.rigid_meshes[r];
      const Vec3 f = tooth_force_on_b(mc, rows_data_, m, flank_[r], lam_[r]);
      const Vec3 p = rows_data_.pitch_point.row(m).transpose();
      add(mc.joint_b[m], p, f);
      add(mc.joint_a[m], p, -f);
    }
    const StepView sv = view();
    for (const auto& e : elements_) e->add_body_forces(sv, *this);
    joint_forces();
  }

  // Forces of the rigid meshes from the loaded flanks' multipliers, with where the teeth are
  // along the path of contact (the compliant meshes' element records its own).
  void record_rigid_meshes(long k) {
    const auto& mc = s_.meshes;
    for (Eigen::Index r = 0; r < nr_; ++r) {
      const Eigen::Index m = s_.rigid_meshes[r];
      const auto& path = s_.paths[static_cast<size_t>(m)];
      const double angle = gear_a_angle(mc, rows_data_, path, data_.oMi[mc.joint_a[m]].rotation(), m);
      const PathState p = path_state(path, angle, flank_[r]);
      record_mesh_force(out_, mc, rows_data_, k, m, lam_[r], flank_[r]);
      const long i = k * nm_ + m;
      out_.transmission_error[i] = te_[r];
      out_.mesh_deflection[i] = 0.0;
      out_.mesh_contact_position[i] = path.roll_start + p.entering;
      out_.mesh_pairs[i] = p.pairs;
      out_.mesh_single_tooth_force[i] = lam_[r] * p.share;
    }
  }

  // Writes the state of the step into row k of the block's outputs.
  void record(long k, double t) {
    const Eigen::Index nj = s_.model.njoints - 1;
    out_.time[k] = t;
    Eigen::Map<Eigen::VectorXd>(out_.angle + k * nv_, nv_) = q_;
    Eigen::Map<Eigen::VectorXd>(out_.speed + k * nv_, nv_) = v_;
    Eigen::Map<Eigen::VectorXd>(out_.acceleration + k * nv_, nv_) = a_;
    driver_torque_.setZero(nv_);
    for (Eigen::Index i = 0; i < nd_; ++i) driver_torque_[s_.driver_index[i]] += lam_[nr_ + i];
    Eigen::Map<Eigen::VectorXd>(out_.torque + k * nv_, nv_) = tau_applied_ + driver_torque_;
    record_rigid_meshes(k);
    const StepView sv = view();
    for (const auto& e : elements_) e->record(sv, k, out_);
    for (Eigen::Index j = 1; j <= nj; ++j) {
      const long i = 3 * (k * nj + j - 1);
      const auto& f = data_.f[j];
      const auto& rot = data_.oMi[j].rotation();
      Eigen::Map<Vec3>(out_.bearing_force_local + i) = f.linear();
      Eigen::Map<Vec3>(out_.bearing_moment_local + i) = f.angular();
      // World axes; the moment stays about the bearing centre.
      Eigen::Map<Vec3>(out_.bearing_force + i) = rot * f.linear();
      Eigen::Map<Vec3>(out_.bearing_moment + i) = rot * f.angular();
    }
    const Eigen::Index nb = static_cast<Eigen::Index>(s_.frame_parent.size());
    for (Eigen::Index b = 0; b < nb; ++b) {
      // Each link is rigid on a joint: its pose is the joint's placement times a constant one.
      const pinocchio::SE3 pose = data_.oMi[s_.frame_parent[b]] * s_.frame_placement[b];
      Eigen::Map<Vec3>(out_.body_position + 3 * (k * nb + b)) = pose.translation();
      const Eigen::Quaterniond quat(pose.rotation());
      Eigen::Map<Eigen::Vector4d>(out_.body_quaternion + 4 * (k * nb + b)) = quat.coeffs();
    }
    out_.constraint_residual[k] = residual_;
    mv_.noalias() = mass_ * v_;
    out_.kinetic[k] = 0.5 * v_.dot(mv_);
    double potential = 0.0;
    for (const auto& e : elements_) potential += e->potential(sv);
    out_.potential_spring[k] = potential;
    for (int i = 0; i < 6; ++i) out_.work[i][k] = work_[i];
  }

  // Semi-implicit Euler, with the work of each force over the step at the mid-step speed (with
  // which the kinetic-energy change of a step equals the work of its forces when M is constant)
  // and the transmission error along the rigid rows.
  void advance() {
    v_next_ = v_ + a_ * s_.dt;
    mid_ = (0.5 * s_.dt) * (v_ + v_next_);
    if (nr_) jv_.head(nr_).noalias() = jac_.topRows(nr_) * mid_;
    StepWork elements;
    const StepView sv = view();
    const Eigen::VectorXd v_mid = mid_ / s_.dt;
    for (const auto& e : elements_) {
      const StepWork w = e->work(sv, v_next_, v_mid);
      elements.elastic += w.elastic;
      elements.dissipated += w.dissipated;
      elements.applied += w.applied;
    }
    const double work[6] = {
        tau_applied_.dot(mid_) + elements.applied,
        driver_torque_.dot(mid_),
        elements.elastic,
        -gravity_.dot(mid_),
        nr_ ? lam_.head(nr_).dot(jv_.head(nr_)) : 0.0,
        elements.dissipated,
    };
    for (int i = 0; i < 6; ++i) work_[i] += work[i];
    for (Eigen::Index r = 0; r < nr_; ++r) te_[r] += jac_.row(r).dot(v_next_ * s_.dt);
    for (auto& e : elements_) e->advance(sv, v_next_);
    pinocchio::integrate(s_.model, q_, v_next_ * s_.dt, q_next_);
    q_ = q_next_;
    v_ = v_next_;
  }

  StepperSetup s_;
  pinocchio::Data data_;
  long samples_;
  Outputs out_{};
  double work_[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // cumulative work of each ledger term [J]
  Eigen::Index nv_, nm_, nr_, nd_, rows_;
  ConstrainedQp qp_;
  std::vector<std::unique_ptr<Element>> elements_;
  Eigen::VectorXd q_, q_next_, v_, v_next_, mid_;
  Eigen::VectorXd flank_, te_;
  MeshRows rows_data_;
  std::vector<Vec3> origin_;
  std::vector<Eigen::Matrix3d> rot_;
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Force) fext_;
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Inertia) composite_, body_;  // world inertias
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Motion) accel_, drift_;
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Force) body_force_, subtree_, weight_;
  Eigen::VectorXd nle_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> momenta_;
  Eigen::MatrixXd driver_jac_, jac_, mass_, hessian_;
  Eigen::VectorXd bias_, target_now_, target_next_, jv_, mv_;
  Eigen::VectorXd tau_applied_, elements_force_, gravity_, force_explicit_, force_, rhs_;
  Eigen::VectorXd a_, lam_, driver_torque_;
  double residual_ = 0.0;
  double time_ = 0.0;
  const double* inputs_ = nullptr;
};

}  // namespace pinwind
