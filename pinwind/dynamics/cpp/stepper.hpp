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
// both built by the factories of their kinds (element_kind.hpp; the kinds are listed in
// element_kinds.hpp, each in a header of its own), and iterates them.
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
//
// This header declares the Stepper; its work is compiled in units by concern: the step loop
// (stepper_run.cpp), the static equilibrium (stepper_equilibrium.cpp), the start and the checks'
// assembly (stepper_assembly.cpp), the kinds' factories (element_kinds.cpp); the QP solves are in
// constrained_qp.cpp, Pinocchio's algorithms behind the functions of joint_algorithms.hpp. In one
// unit they needed 4.4 GB of compiler memory at once.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <pinocchio/multibody.hpp>

#include "constrained_qp.hpp"
#include "constraints.hpp"
#include "element_kind.hpp"
#include "elements.hpp"
#include "mesh_path.hpp"
#include "mesh_rows.hpp"
#include "series.hpp"
#include "time_step.hpp"

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
  // Each kind's specs bound to its factory (element_kinds.hpp add_kinds), in the order of the
  // kinds: the order the elements' forces are summed in and the constraints' rows stacked in.
  std::vector<Factory<Elements>> elements;
  std::vector<Factory<Constraints>> constraints;
  long input_columns = 0;                 // per-sample inputs the elements read (wind speeds)
  std::vector<long> bearing_joints;  // the joints whose reactions are the bearing series
  std::vector<long> frame_parent;  // body frames: parent joint and placement in it
  std::vector<pinocchio::SE3> frame_placement;
  double dt = 1e-3;
  double projection_tol = 1e-14;
  double rho_infinity = 1.0;       // the time step's spectral radius ρ∞ (time_step.hpp)
  SolverSettings solver;
};

// How a static start went (Stepper::equilibrium).
struct EquilibriumStatus {
  long iterations = 0;       // Newton iterations taken
  bool converged = false;    // the last correction fell below the tolerance
  double correction = 0.0;   // max |Δq| of the last iteration [rad or m]
  double displacement = 0.0; // max |q − q₀| over the joints [rad or m]
  long largest = 0;          // the velocity coordinate where |q − q₀| is largest
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

// The elements' forces at one state and their derivatives (Stepper::element_forces).
struct ElementForces {
  Eigen::VectorXd force;      // Σ f_e: the elements' generalised force at (q, v) [N·m or N]
  Eigen::MatrixXd stiffness;  // K = −∂f/∂q as the step takes it (the implicit weights at κ_q = 1)
  Eigen::MatrixXd damping;    // C = −∂f/∂v likewise (at κ_v = 1)
  double potential = 0.0;     // Σ U_e: the stored energy at q [J]
};

// A run's state between two samples, saved by Stepper::save and taken back by Stepper::restore:
// what the next step reads of the steps before it. The state (q_k, v_k), the generalized-α
// memory a_k and whether the consistent a_0 is still to come, the weighted bias's last sample,
// the energy ledger, each element's and constraint's copy (their internal states: contact
// flanks, fluxes, controllers, predictions) and the solver's factorisations and warm start;
// M and the constant rows too (taken once). Its size is the model's, whatever the run's length.
struct StepperState {
  unsigned long long run = 0;  // the stepper it was saved from (another refuses it)
  Eigen::VectorXd q, v, accel_memory, nle_last, gravity_last, a, lam, bias;
  Eigen::MatrixXd mass, jac;
  bool first_step = true;
  EnergyLedger ledger;
  Elements elements;
  Constraints constraints;
  std::unique_ptr<ConstrainedQp> qp;
};

class Stepper {
 public:
  // samples: how many samples the whole run has (the last one is recorded, not stepped from).
  Stepper(StepperSetup setup, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, long samples);

  // The samples of [k0, k1) a run keeping every stride-th sample from 0 and the last records.
  long kept_rows(long k0, long k1, long stride) const {
    if (stride <= 1) return k1 - k0;
    const long last = (k1 == samples_ && (samples_ - 1) % stride != 0) ? 1 : 0;
    return (k1 + stride - 1) / stride - (k0 + stride - 1) / stride + last;
  }

  // Steps samples [k0, k1), writing sample k into row k − k0 of out; with stride > 1 only every
  // stride-th sample from 0 and the run's last are recorded (their bearing reactions computed),
  // into consecutive rows of out. torque: (k1 − k0, nv) applied torques [N·m] at t_k, or
  // (1, nv) held over the block; target: (k1 − k0 + 1, drivers) driver speeds [rad/s] at t_k
  // and t_{k1} (locks 0); inputs: (k1 − k0, input_columns) the elements' inputs at t_k, or
  // (1, input_columns) held.
  RunStatus run(long k0, long k1, const RowMat& torque, const RowMat& target, const Outputs& out,
                const RowMat& inputs, long stride = 1);

  // Joint-space inertia at q (for checks against Pinocchio's own): always the full CRBA.
  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q);

  // Whether M(q) is the same at every q (mass_is_constant), so that the step takes it once,
  // at its first assembly, instead of by CRBA at every step.
  bool constant_mass() const { return constant_mass_; }

  // Per mesh, the joint whose frame carries its geometry when its rows are the same at every q
  // (0: the world; stepper_assembly.cpp fixed_mesh_frames), taken once with γ = 0; -1: evaluated
  // at every step.
  const std::vector<long>& mesh_frames() const { return rows_data_.frame; }

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
  // the displacement Δq and the multipliers, in the least-squares sense with the system scaled
  // (every spring takes its load, the soft ones beside the stiff too), Δq with no part along
  // the train's free motion (which the loads do not determine), then q ← q ⊕ Δq. A compliant mesh
  // whose force would pull hands it to the other flank (closing the backlash), and a rigid mesh
  // row whose multiplier pulls switches to its other flank as the step does (on a body that
  // moves, a planet in a compliant bearing, the other flank is another line). The stiffness
  // follows the pairs in contact at each q, so the iteration ends when Δq stops changing.
  // With load_steps n > 1 the applied torques are taken in n equal steps (k/n of them, k = 1 … n),
  // each solved from the last one's end with up to max_iterations iterations (a continuation: a
  // load far beyond the one the model was made for can take the contacts and the large tilts
  // out of Newton's reach from the undeflected pose); the displacement and the convergence are
  // measured from the call's start, the iterations counted over all steps, converged says
  // whether the last step (the whole load) converged, and a step whose correction exceeds the
  // displacement (diverged) ends the call.
  EquilibriumStatus equilibrium(const RowMat& torque, const RowMat& target, const RowMat& inputs,
                                long max_iterations, double tolerance, long load_steps = 1);

  // The step's assembly alone at (q, v), with the rows' current flanks (for checks against
  // Pinocchio's own and finite differences); the run's state is kept.
  Assembly assemble(const Eigen::VectorXd& q, const Eigen::VectorXd& v);

  // The elements' forces, tangents and stored energy at (q, v), each element new, as at a run's
  // first sample (a contact in contact wherever it overlaps): for checks of each element's
  // force against its potential and of its tangent against finite differences. The elements
  // read no inputs (a rotor sees no wind); the run's state and elements are kept.
  ElementForces element_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v);

  // Whether every element and constraint copies its state (Element::copy): else save() throws.
  bool saves_state() const;

  // The run's state before its next sample (StepperState), for restore(): O(model) in time and
  // memory. std::logic_error if an element's kind keeps no copy (saves_state).
  std::unique_ptr<StepperState> save() const;

  // Takes the run back to a state save() gave: the next run() from the sample after it steps as
  // it did then, bit for bit. std::invalid_argument for a state of another stepper.
  void restore(const StepperState& state);

 private:
  static RunStatus& fail(RunStatus& st, long step, double time, const std::string& what) {
    st.code = RunCode::diverged;
    st.step = step;
    st.time = time;
    st.what = what;
    return st;
  }

  // What the kinds' factories read (element_kind.hpp).
  KindContext context() const { return {nv_, s_.meshes, s_.paths, s_.input_columns}; }

  // The elements and constraints the setup asks for, each new, in the order of their kinds.
  Elements build_elements() const;
  Constraints build_constraints() const;

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
  void targets();

  // Joint placements, world Jacobian J and the meshes' geometry and rows: what depends on the
  // angles only.
  void kinematics();

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
  void velocity_kinematics();

  // Recursive Newton-Euler in world axes about the world origin (Featherstone, Rigid Body
  // Dynamics Algorithms, 2008, §5.3; Pinocchio's world-convention passes), from the
  // J, J̇, joint velocities and world inertias the step has already computed: the bias forces
  // C(q, v) v + g(q), their gravity part g(q) on its own (for the energy ledger), and per body
  // the force at q̈ = 0 for the bearing reactions after the QP. Each pass over the joints is a
  // few spatial products; Pinocchio's computeGeneralizedGravity, nonLinearEffects and rnea
  // would each recompute the joint placements (two sines and cosines per joint).
  void bias_forces();

  // The force each joint transmits to its subtree at accelerations a_ under the external body
  // forces fext_, in subtree_ (world axes, about the world origin): record() takes the bearing
  // joints' into their joint frames about the joint origin, as Pinocchio's rnea leaves them in
  // data.f (the slides of a compliant bearing, not recorded, are not transformed).
  void joint_forces();

  // Each body's inertia in world axes about the world origin, body_, from the placements of
  // kinematics() (the bias forces and joint forces read them at every step).
  void world_inertias();

  // Joint-space inertia M(q) from the placements and J of kinematics(), as Pinocchio's CRBA in
  // world convention computes it (composite inertias Y_i of each subtree in world,
  // M(i, j) = J_iᵀ Y_j J_j for j in the subtree of i, plus the armature), without CRBA's own
  // pass over the joint placements.
  void mass_from_jacobian();

  // J and γ of every constraint's rows (constant ones are set at construction).
  void constraint_matrix();

  double residual();

  // M-orthogonal projection of v onto J v = target (pseudo-inverse: redundant rows).
  bool project(long k, double t, RunStatus& st);

  bool check(long k, double t, const QpSolution& sol, RunStatus& st);

  // The QP's Hessian and force for the elements' current active sets, then the solve.
  const QpSolution* solve_qp(long k, double t, RunStatus& st);

  // What depends on the angles: the kinematics, M and J.
  void assemble_positions();

  // What depends on the speeds too: the bias forces b and the rows' γ.
  void assemble_velocities();

  // Dynamics at (q, v, t): a, λ and the forces the recorder and the integrator need.
  bool solve(long k, double t, RunStatus& st);

  // b and g at the step's weighted state t_{n+1−αf}, extrapolated from the last two samples:
  // b_n + (1 − αf)(b_n − b_{n−1}), second order like the step (b at t_n alone is first order:
  // a pendulum's gravity work was 1e-3 m g d off at dt = 1e-4 s), for the cost of two vector
  // sums instead of a second pass over the joints at a predicted state. The first step, with
  // no sample before it, takes b_0.
  void weighted_bias();

  // Δq of one Newton iteration of equilibrium() from M, J, γ, the stiffness in hessian_ and
  // the force in force_: the least-squares solution of the stacked system with each coordinate
  // scaled by its own mass and stiffness (1/√M_ii, K_ii/M_ii), so that every spring takes its
  // load whatever its stiffness beside the stiffest, less its part along the train's free
  // motions (free_part). Also keeps the solve's multipliers, unscaled, in lam_.
  Eigen::VectorXd static_displacement(EquilibriumStatus& st);

  // The part of dq along the motions that neither the elements' stiffness nor the rows resist
  // (the null space of [K; J]), which the loads do not determine: a start is not turned by it.
  Eigen::VectorXd free_part(const Eigen::VectorXd& dq) const;

  // The step's ā and λ for the current weights, at the assembled state.
  bool dynamics(long k, double t, RunStatus& st);

  // The constraints' and elements' forces on the bodies (the tooth forces at the pitch
  // points), and the bearing reactions by RNEA with them: subtree_[j] is the spatial force
  // joint j transmits from its parent to its child (world axes, about the world origin).
  void bearing_reactions();

  // If an element's forces follow the bearings' loads (Element::wants_bearing_loads: the
  // bearings' friction), the bearing reactions of the solved step (bearing_reactions) and the
  // rows' forces, handed to every element for the next step; true if it computed the reactions.
  bool hand_bearing_loads();

  // Writes the state of the step into row k of the block's outputs.
  void record(long k, double t);

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
  void advance();

  StepperSetup s_;
  unsigned long long id_;  // this stepper among the process's (StepperState::run)
  pinocchio::Data data_;
  long samples_;
  Outputs out_{};
  EnergyLedger ledger_;
  Eigen::Index nv_, nm_;
  Elements elements_;
  Constraints constraints_;
  Eigen::Index rows_;  // the constraints' rows
  bool gear_motion_;   // a constraint reads the gears' motion (Constraint::reads_gear_motion)
  ConstrainedQp qp_;
  std::vector<Eigen::Index> offset_, size_;  // each constraint's first row and row count
  std::vector<size_t> varying_;  // the constraints whose rows depend on the state
  bool constant_mass_ = false;  // M(q) does not depend on q (mass_is_constant)
  bool vector_space_ = false;   // every joint's configuration is its coordinate (q ⊕ dq = q + dq)
  std::vector<bool> frame_at_joint_;  // body frames whose placement in their joint is identity
  GeneralizedAlpha method_;
  StepWeights weights_;
  bool first_step_ = true;
  Eigen::VectorXd dq_free_, dq_, accel_memory_;  // dq₀, Δq and a_n (time_step.hpp)
  Eigen::VectorXd q_, q_next_, v_, v_next_, mid_, v_mid_;
  MeshRows rows_data_;
  std::vector<Vec3> origin_;
  std::vector<Eigen::Matrix3d> rot_;
  BodyForces fext_;  // the constraints' and elements' forces on the bodies
  std::vector<pinocchio::Inertia> composite_, body_;  // world inertias
  std::vector<int> slide_axes_;  // per joint: a slide's axis, or -1 (joint_algorithms.hpp)
  std::vector<bool> massless_;  // joints whose body has no inertia (a compliant bearing's slides)
  // Bodies whose world inertia is the same at every q, taken once (stepper_assembly.cpp
  // fixed_inertias): world_inertias leaves their body_ as it is.
  std::vector<bool> fixed_inertia_;
  std::vector<pinocchio::Motion> accel_, drift_;
  std::vector<pinocchio::Force> body_force_, subtree_, weight_;
  std::vector<Eigen::Vector3d> bearing_loads_, row_loads_;  // hand_bearing_loads's [N]
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
