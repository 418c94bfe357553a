// The element interface of the step loop: everything that adds forces per step (torsional
// springs, bearing damping, compliant meshes, generator and rotor laws) is an Element; the
// rows the accelerations satisfy exactly (rigid meshes, speed drivers) are Constraints
// (constraints.hpp). The stepper builds both by their kinds' factories (element_kind.hpp) and
// iterates them; it does not know any by name. Elements write their outputs by series
// (series.hpp) and book their work in the energy ledger's named terms (EnergyLedger below).
//
// A step at (q_n, v_n) with time step h finds the step's mean acceleration ā from
//
//     (c₁ M + Σ W_e) ā = τ − b − c₂ M a_n + Σ f_e + Jᵀ λ,     J ā = r   (constrained_qp.hpp)
//
// (the generalized-α method, time_step.hpp, which derives c₁, c₂ and the gains below), where
// each element contributes an explicit force f_e and, if it is stiff, an implicit part W_e: its
// force is taken at the weighted state q_n ⊕ (dq₀ + κ_q ā), v_n + κ_v ā (StepView::weights,
// dq_free), f_e − W_e ā, linear in the step's acceleration. Elements with a contact condition
// (teeth never pull) settle their active set after each solve; the stepper solves again while
// any element changes its set.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <pinocchio/multibody.hpp>

#include "mesh_rows.hpp"
#include "series.hpp"
#include "time_step.hpp"

namespace pinwind {

// Writes mesh m's forces of sample k (n_meshes per sample) for F_n on flank s, the other flank
// carrying none: the same outputs for rigid and compliant meshes (a compliant mesh in contact
// on both flanks then writes each flank's force and the resultant on B, compliant_mesh.hpp).
// cos_w, sin_w: the working pressure angle (mesh_rows.hpp line_of_action).
inline void record_mesh_force(const Outputs& out, const MeshConstants& mc, const MeshRows& rows,
                              long k, Eigen::Index m, double normal, double flank, double cos_w,
                              double sin_w) {
  const double tangential = normal * cos_w;
  const long e = out.entry(Family::mesh, k, m);
  out.at(Series::mesh_normal, e) = normal;
  out.at(Series::mesh_tangential, e) = tangential;
  out.at(Series::mesh_radial, e) = normal * sin_w;
  out.at(Series::mesh_axial, e) = normal * std::abs(mc.tan_beta_b[m]);  // tooth_force_on_b
  out.at(Series::mesh_flank, e) = flank;
  out.at(Series::mesh_normal_front, e) = flank > 0.0 ? normal : 0.0;
  out.at(Series::mesh_normal_back, e) = flank > 0.0 ? 0.0 : normal;
  // The face's load of a rigid mesh is not modelled (0); a compliant one writes its own.
  out.at(Series::mesh_face_load_factor, e) = 0.0;
  out.at(Series::mesh_load_centre, e) = 0.0;
  out.at(Series::mesh_peak_line_load, e) = 0.0;
  out.at(Series::mesh_mean_line_load, e) = 0.0;
  // Flank friction is a compliant mesh's (flank_friction.hpp), which writes its own.
  out.at(Series::mesh_sliding_velocity, e) = 0.0;
  out.at(Series::mesh_friction_force, e) = 0.0;
  out.at(Series::mesh_friction_power, e) = 0.0;
  const Vec3 f = tooth_force_on_b(mc, rows, m, flank, normal, cos_w, sin_w);
  for (int c = 0; c < 3; ++c) {
    out.at(Series::mesh_force_on_b, e, c) = f[c];
    out.at(Series::pitch_point, e, c) = rows.pitch_point(m, c);
  }
}

inline void record_mesh_force(const Outputs& out, const MeshConstants& mc, const MeshRows& rows,
                              long k, Eigen::Index m, double normal, double flank) {
  record_mesh_force(out, mc, rows, k, m, normal, flank, mc.cos_a[m], mc.sin_a[m]);
}

// The state of a step that elements read.
struct StepView {
  const Eigen::VectorXd& q;
  const Eigen::VectorXd& v;
  double dt;
  const pinocchio::Data& data;  // joint placements oMi at q
  const MeshConstants& meshes;
  const MeshRows& rows;  // every mesh's geometry and rows at (q, v)
  const StepWeights& weights;     // the time step's weights (time_step.hpp)
  const Eigen::VectorXd& dq_free; // dq₀: the weighted state's displacement from q at ā = 0
  double time = 0.0;                // t_k [s]
  const double* inputs = nullptr;   // this sample's input columns (wind speed, ...), or null
  // This sample's driver speeds at t_k and t_{k+1} [rad/s] (constraints.hpp SpeedDrivers).
  const double* target_now = nullptr;
  const double* target_next = nullptr;
  const Eigen::MatrixXd* mass = nullptr;  // M(q_k) [kg·m²], for elements that scale by inertia
};

// Work of an element's forces over one step [J], split as the energy ledger keeps it.
struct StepWork {
  double elastic = 0.0;      // conservative (spring) forces: joins work_springs
  double dissipated = 0.0;   // damping: joins dissipated (counted positive when lost)
  double applied = 0.0;      // external loads (rotor, generator): joins work_applied
  double friction = 0.0;     // friction (tooth flanks, bearings): joins friction_loss (positive when lost)
};

// The energy ledger: the cumulative work of each kind of force since t = 0 [J]. With the
// kinetic and stored energies it closes the balance of a run (Result.energy).
struct EnergyLedger {
  double applied = 0.0;      // applied torques and the elements' external loads (rotor, generator)
  double drivers = 0.0;      // speed drivers and locks
  double springs = 0.0;      // the elements' conservative forces (springs, compliant meshes)
  // (the elements' parametric work is theirs to keep: Element::parametric_work)
  double gravity = 0.0;
  double constraints = 0.0;  // rigid mesh rows: zero but for the rows' drift over a step
  double dissipated = 0.0;   // damping, counted positive when lost
  double friction = 0.0;     // friction (StepWork::friction), counted positive when lost

  EnergyLedger& operator+=(const EnergyLedger& w) {
    applied += w.applied;
    drivers += w.drivers;
    springs += w.springs;
    gravity += w.gravity;
    constraints += w.constraints;
    dissipated += w.dissipated;
    friction += w.friction;
    return *this;
  }
};

// Forces on bodies (for the bearing reactions by RNEA): per joint, the spatial force of what
// is applied to its body, in world axes about the world origin.
struct BodyForces {
  std::vector<pinocchio::Force> of_joint;

  // Adds a force f [N] applied at world point p to the body of joint j.
  void add(long joint, const Vec3& point, const Vec3& force) {
    of_joint[joint].linear() += force;
    of_joint[joint].angular() += point.cross(force);
  }
};

class Element {
 public:
  virtual ~Element() = default;

  // Evaluates what the element needs at (q_k, v_k); called once per step before assembly.
  virtual void prepare(const StepView&) {}
  // Adds the explicit generalised force f_e [N·m or N] to force.
  virtual void add_force(const StepView&, Eigen::VectorXd&) {}
  // Adds W_e to hessian and the force at a = 0 to force, for the current active set. Only the
  // lower triangle of hessian is read (the factorisations and the residuals read no other): an
  // element may leave the upper one out, and a caller that needs the whole matrix mirrors it.
  virtual void add_implicit(const StepView&, Eigen::MatrixXd&, Eigen::VectorXd&) {}
  // Fixes the forces for the solved acceleration a; true if the active set changed, which
  // asks for another solve. last: no more solves will follow; settle for good.
  virtual bool settle(const StepView&, const Eigen::VectorXd&, bool) { return false; }
  // Forces on bodies, for the reactions.
  virtual void add_body_forces(const StepView&, BodyForces&) const {}
  // Stored energy at q_k [J].
  virtual double potential(const StepView&) const { return 0.0; }
  // Work put into the stored energy by the element's own time-varying parameters since t = 0
  // (a mesh's stiffness changing as tooth pairs enter and leave) [J]: energy the physics
  // exchanges, not the integrator's loss.
  virtual double parametric_work() const { return 0.0; }
  // Work over the step from (q_k, v_k) to v_{k+1}; v_mid = (v_k + v_{k+1})/2.
  virtual StepWork work(const StepView&, const Eigen::VectorXd& v_next,
                        const Eigen::VectorXd& v_mid) const {
    (void)v_next;
    (void)v_mid;
    return {};
  }
  // Writes the element's outputs of sample k (series.hpp: out.at(Series::x, out.entry(...))).
  virtual void record(const StepView&, long, const Outputs&) const {}
  // Moves the element's own states (generator fluxes, ...) from t_n to t_{n+1}, given v_{n+1}.
  virtual void advance(const StepView&, const Eigen::VectorXd& v_next) { (void)v_next; }
  // Each compliant bearing row's force on its shaft in the settled step, (F_u, F_w, F_k) [N]
  // along its bearing's u, w and axis k, into rows[r] by row index (bearing_rows.hpp; the
  // series row_force): elements without rows leave rows as it is.
  virtual void row_forces(std::vector<Eigen::Vector3d>& rows) const { (void)rows; }
  // True if the element's forces follow the bearings' loads (bearing_friction.hpp): the
  // stepper then hands it the loads of each step's solve (bearing_loads), for the next step.
  virtual bool wants_bearing_loads() const { return false; }
  // The settled step's loads: each bearing's reaction force on its child body in its joint
  // frame [N] (StepperSpec.bearing_joints order; the series bearing_force_local) and each
  // row's force (row_forces).
  virtual void bearing_loads(const std::vector<Eigen::Vector3d>& bearings,
                             const std::vector<Eigen::Vector3d>& rows) {
    (void)bearings;
    (void)rows;
  }
  // A copy of the element, internal states and all (contact flanks, fluxes, controllers,
  // histories), for a saved state of the run (Stepper::save); null if the kind keeps none, and
  // the run's state then cannot be saved. A kind whose members are its states and constants
  // copies itself as a value: copy_of and restore_from below.
  virtual std::unique_ptr<Element> copy() const { return nullptr; }
  // Takes the states of saved, a copy() of this element (Stepper::restore).
  virtual void restore(const Element& saved) { (void)saved; }
};

// copy() and restore() of an element or constraint of class T that copies as a value: every
// member a state or a constant, pointers only to what outlives the run's saved states (the
// setup's paths, another element of the same list). Each leaf class overrides both with them,
// so that a copy is never sliced to its base (Stepper::save checks the copy's type).
template <class T, class Base>
std::unique_ptr<Base> copy_of(const T& self) {
  return std::make_unique<T>(self);
}
template <class T, class Base>
void restore_from(T& self, const Base& saved) {
  self = static_cast<const T&>(saved);
}

}  // namespace pinwind
