// Time integration of a gearbox: assemble, solve, record, step (pinwind/dynamics/simulate.py
// documents the scheme; this is its compiled inner loop).
//
// The stepper knows no kind of force or row by name. It holds
//
// - Elements (elements.hpp): forces, explicit or implicit in the step (torsional springs,
//   bearing damping, compliant meshes, generator and rotor laws);
// - Constraints (constraints.hpp): rows J a = r with multipliers λ (rigid meshes, speed
//   drivers and locks), stacked in the order of their list;
//
// both built from the registries kElementKinds and kConstraintKinds below, and iterates them.
// Outputs go into one array per series (series.hpp), the energy ledger's terms are named
// (EnergyLedger, elements.hpp). Each step k, at state (q_k, v_k) and time t_k = k·dt:
//
// 1. assemble (assemble_positions, assemble_velocities; Stepper::assemble for tests): M (CRBA),
//    b (RNEA at a = 0), J and γ of the constraints' rows; then τ (applied torques and the
//    elements' explicit forces) and the elements' implicit parts;
// 2. solve the equality QP with proxsuite (constrained_qp.hpp): a_k and λ_k, read by each
//    constraint from its own rows; constraints switch rows that λ shows wrong (a rigid mesh's
//    loaded flank) and elements with contact conditions settle their active sets, solving
//    again while any asks;
// 3. bearing reactions by RNEA with the constraints' and elements' forces on the bodies;
// 4. the generalized-α step (advance; time_step.hpp derives it): with ā the step's mean
//    acceleration, v_{k+1} = v_k + ā dt and q_{k+1} = q_k ⊕ Δq, Δq = h (v_k + v_{k+1})/2 for
//    ρ∞ = 1, with each force's work booked in the ledger. The recorded acceleration is the
//    method's a_k, the acceleration at the sample. The elements take their forces at the
//    method's weighted state, the QP's Hessian is c₁ M and its force carries −c₂ M a_n.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/QR>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include "bearing_spring.hpp"
#include "compliant_mesh.hpp"
#include "constrained_qp.hpp"
#include "constraints.hpp"
#include "elements.hpp"
#include "generator.hpp"
#include "mesh_path.hpp"
#include "mesh_rows.hpp"
#include "rotor.hpp"
#include "series.hpp"
#include "time_step.hpp"
#include "torsional_spring.hpp"

namespace pinwind {

// What stopped a run: the Python side raises the matching PinwindError.
enum class RunCode { completed, diverged, solver_failed, conflicting_constraints };

struct RunStatus {
  RunCode code = RunCode::completed;
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
  std::vector<BearingSpringSpec> bearing_springs;  // compliant bearings (bearing_spring.hpp)
  std::vector<GeneratorSpec> generators;  // generator.hpp
  std::vector<RotorSpec> rotors;          // rotor.hpp
  long input_columns = 0;                 // per-sample inputs the elements read (wind speeds)
  Eigen::VectorXd bearing_damping;
  std::vector<long> driver_index;  // velocity index of each speed driver and lock
  std::vector<long> frame_parent;  // body frames: parent joint and placement in it
  std::vector<pinocchio::SE3> frame_placement;
  double dt = 1e-3;
  double projection_tol = 1e-14;
  double rho_infinity = 1.0;       // the time step's spectral radius ρ∞ (time_step.hpp)
  SolverSettings solver;
};

using Elements = std::vector<std::unique_ptr<Element>>;
using Constraints = std::vector<std::unique_ptr<Constraint>>;

// The registry of element kinds: each adds the elements of its kind that the setup asks for.
// The stepper builds its elements from this table in its order, the order their forces are
// summed in (which the results' last bits depend on).
struct ElementKind {
  const char* name;
  void (*add)(const StepperSetup&, Elements&);
};

inline const ElementKind kElementKinds[] = {
    {"torsional_springs",
     [](const StepperSetup& s, Elements& out) {
       if (!s.springs.empty()) out.push_back(std::make_unique<TorsionalSprings>(s.springs));
     }},
    {"bearing_damping",
     [](const StepperSetup& s, Elements& out) {
       if (s.bearing_damping.size() && s.bearing_damping.cwiseAbs().maxCoeff() > 0.0) {
         out.push_back(std::make_unique<BearingDamping>(s.bearing_damping));
       }
     }},
    {"bearing_springs",
     [](const StepperSetup& s, Elements& out) {
       if (!s.bearing_springs.empty()) {
         out.push_back(std::make_unique<BearingSprings>(s.bearing_springs));
       }
     }},
    {"compliant_meshes",
     [](const StepperSetup& s, Elements& out) {
       if (s.compliant_meshes.empty()) return;
       out.push_back(std::make_unique<CompliantMeshes>(s.compliant_meshes, s.paths, s.model.nv));
     }},
    {"generators",
     [](const StepperSetup& s, Elements& out) {
       for (size_t i = 0; i < s.generators.size(); ++i) {
         const GeneratorSpec& g = s.generators[i];
         out.push_back(kGeneratorElements[static_cast<size_t>(g.law)](g, static_cast<long>(i)));
       }
     }},
    {"rotors",
     [](const StepperSetup& s, Elements& out) {
       for (size_t i = 0; i < s.rotors.size(); ++i) {
         out.push_back(std::make_unique<RotorAerodynamics>(s.rotors[i], static_cast<long>(i)));
       }
     }},
};

// The registry of constraint kinds, in the order of their rows: the rigid meshes in file order,
// then the speed drivers and locks (the name → row map of the multipliers).
struct ConstraintKind {
  const char* name;
  void (*add)(const StepperSetup&, Constraints&);
};

inline const ConstraintKind kConstraintKinds[] = {
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

// How a static start went (Stepper::equilibrium).
struct EquilibriumStatus {
  long iterations = 0;       // Newton iterations taken
  bool converged = false;    // the last correction fell below the tolerance
  double correction = 0.0;   // max |Δq| of the last iteration [rad or m]
  double displacement = 0.0; // max |q − q₀| over the joints [rad or m]
  double residual = 0.0;     // relative residual of the last linear solve
  long flank_switches = 0;   // compliant meshes that handed their load to the other flank
};

// The terms of the step's equations of motion at one state (solve() documents them).
struct Assembly {
  Eigen::MatrixXd mass;   // M(q) [kg·m²]
  Eigen::VectorXd bias;   // b = C(q, v) v + g(q) [N·m]
  Eigen::MatrixXd jac;    // J (rows × nv): the constraints' rows in the stepper's order
  Eigen::VectorXd gamma;  // γ = J̇ v [m/s² or rad/s²]
};

class Stepper {
 public:
  // samples: how many samples the whole run has (the last one is recorded, not stepped from).
  Stepper(StepperSetup setup, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, long samples)
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
    for (const auto& kind : kElementKinds) kind.add(s_, elements_);
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

  // The samples of [k0, k1) a run keeping every stride-th sample from 0 and the last records.
  long kept_rows(long k0, long k1, long stride) const {
    if (stride <= 1) return k1 - k0;
    const long last = (k1 == samples_ && (samples_ - 1) % stride != 0) ? 1 : 0;
    return (k1 + stride - 1) / stride - (k0 + stride - 1) / stride + last;
  }

  // Steps samples [k0, k1), writing sample k into row k − k0 of out; with stride > 1 only every
  // stride-th sample from 0 and the run's last are recorded (their bearing reactions computed),
  // into consecutive rows of out. torque: (k1 − k0, nv) applied torques [N·m] at t_k; target:
  // (k1 − k0 + 1, drivers) driver speeds [rad/s] at t_k and t_{k1} (locks 0); inputs:
  // (k1 − k0, input_columns) the elements' inputs at t_k.
  RunStatus run(long k0, long k1, const RowMat& torque, const RowMat& target, const Outputs& out,
                const RowMat& inputs, long stride = 1) {
    RunStatus st;
    out_ = out;
    stride = std::max(stride, 1L);
    const long row0 = (k0 + stride - 1) / stride;  // the kept index of out's first row
    for (long k = k0; k < k1; ++k) {
      const double t = k * s_.dt;
      st.sample = k;
      time_ = t;
      inputs_ = s_.input_columns ? inputs.row(k - k0).data() : nullptr;
      tau_applied_ = torque.row(k - k0).transpose();
      target_row_ = target.cols() ? target.row(k - k0).data() : nullptr;
      target_next_row_ = target.cols() ? target.row(k - k0 + 1).data() : nullptr;
      targets();
      if (!solve(k, t, st)) return st;
      if (!std::isfinite(a_.squaredNorm() + lam_.squaredNorm())) {
        return fail(st, k, t, "the accelerations or constraint forces are not finite");
      }
      if (k % stride == 0 || k + 1 == samples_) {
        bearing_reactions();
        record((k + stride - 1) / stride - row0, t);
      }
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

  // Moves the run's start q₀ to static equilibrium under the first sample's loads (torque:
  // (1, nv) applied torques at t = 0, target: (2, drivers) driver speeds at t₀ and t₁, inputs:
  // (1, input_columns)), the speeds held: the compliant meshes and springs deflected so that
  // they carry, at the first sample, the forces the same loads put on rigid meshes and locked
  // springs. With the constraints' rows J (rigid meshes, drivers, locks), the elements' stiffness
  // K = −∂f/∂q (their implicit weights under StepWeights::static_solve) and the force
  // F = τ + Σ f_e − b at q, each Newton iteration solves
  //
  //     M ā + K Δq − Jᵀ λ = F,   J ā = r,   J Δq = 0,   K ā = 0
  //
  // for the acceleration ā the whole train shares (no element's deflection changes: K ā = 0),
  // the displacement Δq and the multipliers, in the least-norm sense (Δq has no part along the
  // train's free motion, which the loads do not determine), then q ← q ⊕ Δq. A compliant mesh
  // whose force would pull hands it to the other flank (closing the backlash). The stiffness
  // follows the pairs in contact at each q, so the iteration ends when Δq stops changing.
  EquilibriumStatus equilibrium(const RowMat& torque, const RowMat& target, const RowMat& inputs,
                                long max_iterations, double tolerance) {
    EquilibriumStatus st;
    time_ = 0.0;
    inputs_ = s_.input_columns ? inputs.row(0).data() : nullptr;
    tau_applied_ = torque.row(0).transpose();
    target_row_ = target.cols() ? target.row(0).data() : nullptr;
    target_next_row_ = target.cols() ? target.row(1).data() : nullptr;
    targets();
    const Eigen::VectorXd q_start = q_;
    weights_ = StepWeights::static_solve();
    dq_free_.setZero(nv_);
    RunStatus unused;
    constexpr int kPasses = 8;
    for (long it = 0; it < max_iterations; ++it) {
      assemble_positions();
      if (residual() > s_.projection_tol * (1.0 + v_.cwiseAbs().maxCoeff()) &&
          !project(0, 0.0, unused)) {
        break;
      }
      assemble_velocities();
      const StepView sv = view();
      elements_force_.setZero(nv_);
      for (auto& e : elements_) {
        e->prepare(sv);
        e->add_force(sv, elements_force_);
      }
      Eigen::VectorXd dq;
      for (int pass = 0; pass < kPasses; ++pass) {
        hessian_.setZero(nv_, nv_);
        force_ = tau_applied_ + elements_force_ - nle_;
        for (auto& e : elements_) e->add_implicit(sv, hessian_, force_);
        dq = static_displacement(st);
        bool settled = true;
        for (auto& e : elements_) settled = !e->settle(sv, dq, pass + 1 == kPasses) && settled;
        if (settled) break;
        ++st.flank_switches;
      }
      pinocchio::integrate(s_.model, q_, dq, q_next_);
      q_ = q_next_;
      st.iterations = it + 1;
      st.correction = dq.cwiseAbs().maxCoeff();
      Eigen::VectorXd moved(nv_);
      pinocchio::difference(s_.model, q_start, q_, moved);
      st.displacement = moved.cwiseAbs().maxCoeff();
      if (st.correction <= tolerance * st.displacement || st.correction == 0.0) {
        st.converged = true;
        break;
      }
    }
    return st;
  }

  // The step's assembly alone at (q, v), with the rows' current flanks (for checks against
  // Pinocchio's own and finite differences); the run's state is kept.
  Assembly assemble(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
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

 private:
  static RunStatus& fail(RunStatus& st, long step, double time, const std::string& what) {
    st.code = RunCode::diverged;
    st.step = step;
    st.time = time;
    st.what = what;
    return st;
  }

  StepView view() const {
    return {q_,       v_,          s_.dt,     data_,   s_.meshes,   rows_data_,
            weights_, dq_free_,    time_,     inputs_, target_row_, target_next_row_,
            &mass_};
  }

  // Constraint c's rows in the stacked J, γ, targets and λ.
  Eigen::MatrixXd::RowsBlockXpr rows_of(Eigen::MatrixXd& m, size_t c) {
    return m.middleRows(offset_[c], size_[c]);
  }
  Eigen::VectorXd::SegmentReturnType rows_of(Eigen::VectorXd& x, size_t c) {
    return x.segment(offset_[c], size_[c]);
  }

  // The velocity targets of this sample's rows at t_k and t_{k+1}.
  void targets() {
    target_now_.setZero(rows_);
    target_next_.setZero(rows_);
    const StepView sv = view();
    for (size_t c = 0; c < constraints_.size(); ++c) {
      constraints_[c]->targets(sv, rows_of(target_now_, c), rows_of(target_next_, c));
    }
  }

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

  // The spatial motion Σ cols_c x_c over joint i's velocities idx … idx + n − 1: a fixed-size
  // product for a one-degree-of-freedom joint (every joint of a gearbox but a free flyer),
  // where Eigen's general product of a dynamic block costs more than the arithmetic.
  template <class Cols>
  static pinocchio::Motion::Vector6 joint_product(const Cols& cols, const Eigen::VectorXd& x,
                                                  int idx, int n) {
    if (n == 1) return cols.col(idx) * x[idx];
    return cols.middleCols(idx, n) * x.segment(idx, n);
  }

  // What depends on the speeds too, at the final (projected) v: the world spatial velocity of
  // joint i is that of its parent plus J_i v_i, so the time variation dJ_i = v_i ×(motion) J_i
  // (what computeJointJacobiansTimeVariation computes) follows from J without another pass over
  // the joint placements; then the rigid meshes' bias.
  void velocity_kinematics() {
    const auto& model = s_.model;
    const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
    drift_.resize(nj);
    data_.ov[0].setZero();
    drift_[0].setZero();
    for (pinocchio::JointIndex i = 1; i < nj; ++i) {
      const int idx = model.idx_vs[i], n = model.nvs[i];
      const auto parent = model.parents[i];
      data_.ov[i] = data_.ov[parent] + pinocchio::Motion(joint_product(data_.J, v_, idx, n));
      for (int c = idx; c < idx + n; ++c) {
        data_.dJ.col(c) = data_.ov[i].cross(pinocchio::Motion(data_.J.col(c))).toVector();
      }
      drift_[i] = drift_[parent] + pinocchio::Motion(joint_product(data_.dJ, v_, idx, n));
    }
    if (!s_.rigid_meshes.empty()) {
      // Only rigid rows have a bias γ (compliant meshes read J alone). The twist and the
      // acceleration at q̈ = 0 of each gear's body are those of its joint.
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
    // gravity as an upward acceleration of the base, plus the drift J̇ v of velocity_kinematics
    const pinocchio::Motion up = -model.gravity;
    for (pinocchio::JointIndex i = 1; i < nj; ++i) {
      weight_[i] = body_[i] * up;
      body_force_[i] = body_[i] * drift_[i] + weight_[i] + body_[i].vxiv(data_.ov[i]);
      subtree_[i] = body_force_[i];
    }
    nle_.resize(nv_);
    gravity_.resize(nv_);
    for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
      const int idx = model.idx_vs[i], n = model.nvs[i];
      if (n == 1) {
        nle_[idx] = data_.J.col(idx).dot(subtree_[i].toVector());
        gravity_[idx] = data_.J.col(idx).dot(weight_[i].toVector());
      } else {
        const auto cols = data_.J.middleCols(idx, n);
        nle_.segment(idx, n).noalias() = cols.transpose() * subtree_[i].toVector();
        gravity_.segment(idx, n).noalias() = cols.transpose() * weight_[i].toVector();
      }
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
      accel_[i] = accel_[model.parents[i]] + pinocchio::Motion(joint_product(data_.J, a_, idx, n));
      subtree_[i] = body_force_[i] + body_[i] * accel_[i] - fext_.of_joint[i];
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
      if (n == 1) {
        for (int c = idx; c < idx + sub; ++c) mass_(idx, c) = data_.J.col(idx).dot(momenta_.col(c));
      } else {
        mass_.block(idx, idx, n, sub).noalias() =
            data_.J.middleCols(idx, n).transpose() * momenta_.middleCols(idx, sub);
      }
      if (model.parents[i] > 0) composite_[model.parents[i]] += composite_[i];
    }
    mass_.diagonal() += model.armature;
    mass_.triangularView<Eigen::StrictlyLower>() = mass_.transpose().triangularView<Eigen::StrictlyLower>();
  }

  // J and γ of every constraint's rows (constant ones are set at construction).
  void constraint_matrix() {
    const StepView sv = view();
    for (const size_t c : varying_) constraints_[c]->rows(sv, rows_of(jac_, c), rows_of(bias_, c));
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
      st.code = RunCode::conflicting_constraints;
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
      st.code = RunCode::solver_failed;
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
    hessian_ = weights_.inertia * mass_;
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

  // What depends on the angles: the kinematics, M and J.
  void assemble_positions() {
    kinematics();
    mass_from_jacobian();
    constraint_matrix();
  }

  // What depends on the speeds too: the bias forces b and the rows' γ.
  void assemble_velocities() {
    velocity_kinematics();
    constraint_matrix();
    bias_forces();
  }

  // Dynamics at (q, v, t): a, λ and the forces the recorder and the integrator need.
  bool solve(long k, double t, RunStatus& st) {
    assemble_positions();
    residual_ = residual();
    if (residual_ > s_.projection_tol * (1.0 + v_.cwiseAbs().maxCoeff())) {
      // Post-stabilisation: J changed over the last step, or the run starts off the
      // constraint manifold.
      if (!project(k, t, st)) return false;
      residual_ = residual();
    }
    assemble_velocities();
    if (first_step_) {
      // The consistent start a_0: the dynamics at the first sample (time_step.hpp).
      weights_ = StepWeights();
      dq_free_.setZero(nv_);
      nle_step_ = nle_;
      gravity_step_ = gravity_;
      if (!dynamics(k, t, st)) return false;
      accel_memory_ = a_;
      first_step_ = false;
    }
    // The time step's weights and the weighted state's displacement at ā = 0 (time_step.hpp).
    weights_ = StepWeights(method_, s_.dt);
    dq_free_ = weights_.force_new * (s_.dt * v_ + weights_.memory_gain * accel_memory_);
    weighted_bias();
    if (!dynamics(k, t, st)) return false;
    nle_last_ = nle_;
    gravity_last_ = gravity_;
    return true;
  }

  // b and g at the step's weighted state t_{n+1−αf}, extrapolated from the last two samples:
  // b_n + (1 − αf)(b_n − b_{n−1}), second order like the step (b at t_n alone is first order:
  // a pendulum's gravity work was 1e-3 m g d off at dt = 1e-4 s), for the cost of two vector
  // sums instead of a second pass over the joints at a predicted state. The first step, with
  // no sample before it, takes b_0.
  void weighted_bias() {
    if (nle_last_.size() != nv_) {
      nle_step_ = nle_;
      gravity_step_ = gravity_;
      return;
    }
    const double w = weights_.force_new;
    nle_step_ = nle_ + w * (nle_ - nle_last_);
    gravity_step_ = gravity_ + w * (gravity_ - gravity_last_);
  }

  // Δq of one Newton iteration of equilibrium() from M, J, γ, the stiffness in hessian_ and
  // the force in force_: the least-norm solution of the stacked system, with Δq scaled by
  // κ = max|K| / max|M| so that both blocks weigh alike in the rank decision.
  Eigen::VectorXd static_displacement(EquilibriumStatus& st) {
    const double mass_scale = mass_.cwiseAbs().maxCoeff();
    const double stiffness_scale = hessian_.cwiseAbs().maxCoeff();
    if (!(stiffness_scale > 0.0)) return Eigen::VectorXd::Zero(nv_);
    const double kappa = stiffness_scale / mass_scale;
    const Eigen::Index n = nv_, r = rows_;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n + 2 * r, 2 * n + r);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * n + 2 * r);
    a.topLeftCorner(n, n) = mass_;
    a.block(0, n, n, n) = hessian_ / kappa;
    a.block(0, 2 * n, n, r) = -jac_.transpose();
    a.block(n, 0, r, n) = jac_;
    a.block(n + r, n, r, n) = jac_;
    a.block(n + 2 * r, 0, n, n) = hessian_ / kappa;
    b.head(n) = force_;
    b.segment(n, r) = (target_next_ - target_now_) / s_.dt - bias_;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    cod.setThreshold(1e-12);
    cod.compute(a);
    const Eigen::VectorXd x = cod.solve(b);
    st.residual = (a * x - b).norm() / std::max(b.norm(), 1e-300);
    return x.segment(n, n) / kappa;
  }

  // The step's ā and λ for the current weights, at the assembled state.
  bool dynamics(long k, double t, RunStatus& st) {
    const Eigen::VectorXd& nle = nle_step_;
    const StepView sv = view();
    elements_force_.setZero(nv_);
    for (auto& e : elements_) {
      e->prepare(sv);
      e->add_force(sv, elements_force_);
    }
    force_explicit_ = tau_applied_ + elements_force_ - nle;
    if (weights_.memory != 0.0) force_explicit_.noalias() -= weights_.memory * (mass_ * accel_memory_);
    const QpSolution* sol = solve_qp(k, t, st);
    if (!sol) return false;
    lam_ = sol->multipliers;
    // Constraints switch rows their multipliers show wrong (a rigid mesh pulling: the other
    // flank carries the load), either carrying the solution over or asking for another solve (a
    // switch can move load between meshes, so repeat, a few times). Elements with contact
    // (compliant meshes) settle their active sets in the same loop.
    constexpr int kPasses = 8;
    for (int pass = 0; pass < kPasses; ++pass) {
      RowSwitch change = RowSwitch::none;
      for (size_t c = 0; c < constraints_.size(); ++c) {
        change = std::max(change, constraints_[c]->switch_rows(sv, rows_of(lam_, c)));
      }
      bool settled = true;
      const bool last = pass + 1 == kPasses;
      for (auto& e : elements_) settled = !e->settle(sv, sol->acceleration, last) && settled;
      if (change == RowSwitch::none && settled) break;
      constraint_matrix();
      if (change != RowSwitch::solve && settled) break;
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

  // The constraints' and elements' forces on the bodies (the tooth forces at the pitch
  // points), and the bearing reactions by RNEA with them: data.f[j] is the spatial force joint
  // j transmits from its parent to its child, in the joint frame about the joint origin.
  void bearing_reactions() {
    for (auto& f : fext_.of_joint) f.setZero();
    const StepView sv = view();
    for (size_t c = 0; c < constraints_.size(); ++c) {
      constraints_[c]->add_body_forces(sv, rows_of(lam_, c), fext_);
    }
    for (const auto& e : elements_) e->add_body_forces(sv, fext_);
    joint_forces();
  }

  // Writes the state of the step into row k of the block's outputs.
  void record(long k, double t) {
    const Eigen::Index nj = s_.model.njoints - 1;
    out_.at(Series::time, k) = t;
    joint_row(Series::angle, k) = q_;
    joint_row(Series::speed, k) = v_;
    // ā, the step's mean acceleration: the one the multipliers and bearing reactions of the
    // sample come from. a_k itself carries, at ρ∞ = 1, an error of alternating sign after a
    // jump in the forces (a torque step, a flank switch) that never decays; ā does not.
    joint_row(Series::acceleration, k) = a_;
    joint_row(Series::torque, k) = tau_applied_;
    const StepView sv = view();
    for (size_t c = 0; c < constraints_.size(); ++c) {
      constraints_[c]->record(sv, k, rows_of(lam_, c), out_);
    }
    for (const auto& e : elements_) e->record(sv, k, out_);
    for (Eigen::Index j = 1; j <= nj; ++j) {
      const auto& f = data_.f[j];
      const auto& rot = data_.oMi[j].rotation();
      const long e = out_.entry(Family::bearing, k, j - 1);
      vec3(Series::bearing_force_local, e) = f.linear();
      vec3(Series::bearing_moment_local, e) = f.angular();
      // World axes; the moment stays about the bearing centre.
      vec3(Series::bearing_force, e) = rot * f.linear();
      vec3(Series::bearing_moment, e) = rot * f.angular();
    }
    const Eigen::Index nb = static_cast<Eigen::Index>(s_.frame_parent.size());
    for (Eigen::Index b = 0; b < nb; ++b) {
      // Each link is rigid on a joint: its pose is the joint's placement times a constant one.
      const pinocchio::SE3 pose = data_.oMi[s_.frame_parent[b]] * s_.frame_placement[b];
      const long e = out_.entry(Family::body, k, b);
      vec3(Series::body_position, e) = pose.translation();
      const Eigen::Quaterniond quat(pose.rotation());
      Eigen::Map<Eigen::Vector4d>(&out_.at(Series::body_quaternion, e)) = quat.coeffs();
    }
    out_.at(Series::constraint_residual, k) = residual_;
    mv_.noalias() = mass_ * v_;
    out_.at(Series::kinetic, k) = 0.5 * v_.dot(mv_);
    double potential = 0.0;
    for (const auto& e : elements_) potential += e->potential(sv);
    out_.at(Series::potential_spring, k) = potential;
    out_.at(Series::work_applied, k) = ledger_.applied;
    out_.at(Series::work_drivers, k) = ledger_.drivers;
    out_.at(Series::work_springs, k) = ledger_.springs;
    out_.at(Series::work_gravity, k) = ledger_.gravity;
    out_.at(Series::work_constraints, k) = ledger_.constraints;
    out_.at(Series::dissipated, k) = ledger_.dissipated;
    double parametric = 0.0;
    for (const auto& e : elements_) parametric += e->parametric_work();
    out_.at(Series::work_parametric, k) = parametric;
  }

  // Sample k of a joint series, as a vector of nv.
  Eigen::Map<Eigen::VectorXd> joint_row(Series s, long k) const {
    return Eigen::Map<Eigen::VectorXd>(&out_.at(s, out_.entry(Family::joint, k)), nv_);
  }

  // Entry e of a 3-vector series.
  Eigen::Map<Vec3> vec3(Series s, long e) const { return Eigen::Map<Vec3>(&out_.at(s, e)); }

  // The generalized-α step (time_step.hpp), with the work of each force over the step at the
  // mid-step speed (with which the kinetic-energy change of a step equals the work of its forces
  // when M is constant) and the constraints' own states (the transmission error along the rigid
  // rows).
  void advance() {
    const double h = s_.dt;
    v_next_ = v_ + a_ * h;
    mid_ = (0.5 * h) * (v_ + v_next_);
    dq_ = h * v_ + weights_.step_gain * a_;
    if (weights_.memory_gain != 0.0) dq_ += weights_.memory_gain * accel_memory_;
    StepWork elements;
    const StepView sv = view();
    v_mid_ = mid_ / h;
    for (const auto& e : elements_) {
      const StepWork w = e->work(sv, v_next_, v_mid_);
      elements.elastic += w.elastic;
      elements.dissipated += w.dissipated;
      elements.applied += w.applied;
    }
    EnergyLedger step;
    step.applied = tau_applied_.dot(mid_) + elements.applied;
    step.springs = elements.elastic;
    // M ā = f + Jᵀλ + c₂ M (ā − a_n): the inertia's memory does work on the kinetic energy
    // that no force does, the method's own dissipation. It joins the springs' work, so that
    // ``numerical`` = −(ΔU_spring + W_springs) holds all of the integrator's loss.
    if (weights_.memory != 0.0) {
      mv_.noalias() = mass_ * (a_ - accel_memory_);
      step.springs += weights_.memory * mv_.dot(mid_);
    }
    step.gravity = -gravity_step_.dot(mid_);
    step.dissipated = elements.dissipated;
    for (size_t c = 0; c < constraints_.size(); ++c) {
      constraints_[c]->work(sv, rows_of(jac_, c), rows_of(lam_, c), mid_, step);
    }
    ledger_ += step;
    for (size_t c = 0; c < constraints_.size(); ++c) {
      constraints_[c]->advance(sv, rows_of(jac_, c), dq_);
    }
    for (auto& e : elements_) e->advance(sv, v_next_);
    // a_{n+1} = (ā − (1 − γ) a_n)/γ.
    accel_memory_ = (a_ - (1.0 - method_.gamma) * accel_memory_) / method_.gamma;
    pinocchio::integrate(s_.model, q_, dq_, q_next_);
    q_ = q_next_;
    v_ = v_next_;
  }

  StepperSetup s_;
  pinocchio::Data data_;
  long samples_;
  Outputs out_{};
  EnergyLedger ledger_;
  Eigen::Index nv_, nm_, rows_;
  ConstrainedQp qp_;
  std::vector<std::unique_ptr<Element>> elements_;
  std::vector<std::unique_ptr<Constraint>> constraints_;
  std::vector<Eigen::Index> offset_, size_;  // each constraint's first row and row count
  std::vector<size_t> varying_;  // the constraints whose rows depend on the state
  GeneralizedAlpha method_;
  StepWeights weights_;
  bool first_step_ = true;
  Eigen::VectorXd dq_free_, dq_, accel_memory_;  // dq₀, Δq and a_n (time_step.hpp)
  Eigen::VectorXd q_, q_next_, v_, v_next_, mid_, v_mid_;
  MeshRows rows_data_;
  std::vector<Vec3> origin_;
  std::vector<Eigen::Matrix3d> rot_;
  BodyForces fext_;  // the constraints' and elements' forces on the bodies
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Inertia) composite_, body_;  // world inertias
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Motion) accel_, drift_;
  PINOCCHIO_ALIGNED_STD_VECTOR(pinocchio::Force) body_force_, subtree_, weight_;
  Eigen::VectorXd nle_;
  Eigen::VectorXd nle_step_, gravity_step_, nle_last_, gravity_last_;  // weighted_bias
  Eigen::Matrix<double, 6, Eigen::Dynamic> momenta_;
  Eigen::MatrixXd jac_, mass_, hessian_;
  Eigen::VectorXd bias_, target_now_, target_next_, jv_, mv_;
  Eigen::VectorXd tau_applied_, elements_force_, gravity_, force_explicit_, force_, rhs_;
  Eigen::VectorXd a_, lam_;
  double residual_ = 0.0;
  double time_ = 0.0;
  const double* inputs_ = nullptr;
  const double *target_row_ = nullptr, *target_next_row_ = nullptr;
};

}  // namespace pinwind
