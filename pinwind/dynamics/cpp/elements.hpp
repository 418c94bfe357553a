// The element interface of the step loop: everything that adds forces per step (torsional
// springs, bearing damping, compliant meshes, generator and rotor laws) is an Element.
// The stepper iterates them; it does not know any by name (design.md §2 "Elements").
//
// A step at (q_k, v_k) with time step h finds a_k from
//
//     (M + Σ W_e) a = τ − b + Σ f_e + Jᵀ λ,     J a = r      (rigid rows: constrained_qp.hpp)
//
// where each element contributes an explicit force f_e and, if it is stiff, an implicit part
// W_e: its force over the step is f_e − W_e a, linear in the step's acceleration because
// v_{k+1} = v_k + h a and q_{k+1} = q_k ⊕ h v_{k+1} (semi-implicit Euler). Elements with a
// contact condition (teeth never pull) settle their active set after each solve; the stepper
// solves again while any element changes its set.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <pinocchio/multibody.hpp>

#include "mesh_rows.hpp"

namespace pinwind {

// Where each sample's outputs go: row-major arrays of the Result, n samples long.
struct Outputs {
  double *time, *angle, *speed, *acceleration, *torque;
  double *mesh_normal, *mesh_tangential, *mesh_radial, *mesh_axial, *mesh_flank;
  double *transmission_error, *mesh_force_on_b, *pitch_point;
  double *mesh_deflection, *mesh_contact_position, *mesh_pairs, *mesh_single_tooth_force;
  double *bearing_force, *bearing_moment, *bearing_force_local, *bearing_moment_local;
  double *body_position, *body_quaternion, *constraint_residual;
  double *kinetic, *potential_spring;
  // Cumulative work [J]: applied, drivers, springs, gravity, constraints, dissipated.
  double* work[6];
  long samples;
  // Per generator and per rotor, in the order of their specs: (n, generators) and (n, rotors).
  double* generator_torque = nullptr;  // T_gen on the shaft [N·m], > 0 generating
  double *rotor_torque = nullptr, *rotor_power = nullptr;  // [N·m], [W]
  double *rotor_tip_speed_ratio = nullptr, *rotor_power_coefficient = nullptr;  // λ, C_p [-]
  double* rotor_wind_speed = nullptr;  // [m/s]
  long generators = 0, rotors = 0;
};

// Writes mesh m's forces of sample k (n_meshes per sample) for F_n on flank s: the same
// outputs for rigid and compliant meshes.
inline void record_mesh_force(const Outputs& out, const MeshConstants& mc, const MeshRows& rows,
                              long k, Eigen::Index m, double normal, double flank) {
  const long i = k * static_cast<long>(mc.count()) + static_cast<long>(m);
  const double tangential = normal * mc.cos_a[m];
  out.mesh_normal[i] = normal;
  out.mesh_tangential[i] = tangential;
  out.mesh_radial[i] = normal * mc.sin_a[m];
  out.mesh_axial[i] = tangential * std::abs(mc.tan_beta[m]);
  out.mesh_flank[i] = flank;
  const Vec3 f = tooth_force_on_b(mc, rows, m, flank, normal);
  for (int c = 0; c < 3; ++c) {
    out.mesh_force_on_b[3 * i + c] = f[c];
    out.pitch_point[3 * i + c] = rows.pitch_point(m, c);
  }
}

// The state of a step that elements read.
struct StepView {
  const Eigen::VectorXd& q;
  const Eigen::VectorXd& v;
  double dt;
  const pinocchio::Data& data;  // joint placements oMi at q
  const MeshConstants& meshes;
  const MeshRows& rows;  // every mesh's geometry and rows at (q, v)
  double time = 0.0;                // t_k [s]
  const double* inputs = nullptr;   // this sample's input columns (wind speed, ...), or null
};

// Work of an element's forces over one step [J], split as the energy ledger keeps it.
struct StepWork {
  double elastic = 0.0;      // conservative (spring) forces: joins work_springs
  double dissipated = 0.0;   // damping: joins dissipated (counted positive when lost)
  double applied = 0.0;      // external loads (rotor, generator): joins work_applied
};

// Forces on bodies (for the bearing reactions by RNEA): a force f [N] applied at world point p
// to the body of joint j.
class BodyForces {
 public:
  virtual ~BodyForces() = default;
  virtual void add(long joint, const Vec3& point, const Vec3& force) = 0;
};

class Element {
 public:
  virtual ~Element() = default;

  // Evaluates what the element needs at (q_k, v_k); called once per step before assembly.
  virtual void prepare(const StepView&) {}
  // Adds the explicit generalised force f_e [N·m or N] to force.
  virtual void add_force(const StepView&, Eigen::VectorXd&) {}
  // Adds W_e to hessian and the force at a = 0 to force, for the current active set.
  virtual void add_implicit(const StepView&, Eigen::MatrixXd&, Eigen::VectorXd&) {}
  // Fixes the forces for the solved acceleration a; true if the active set changed, which
  // asks for another solve. last: no more solves will follow; settle for good.
  virtual bool settle(const StepView&, const Eigen::VectorXd&, bool) { return false; }
  // Forces on bodies, for the reactions.
  virtual void add_body_forces(const StepView&, BodyForces&) const {}
  // Stored energy at q_k [J].
  virtual double potential(const StepView&) const { return 0.0; }
  // Work over the step from (q_k, v_k) to v_{k+1}; v_mid = (v_k + v_{k+1})/2.
  virtual StepWork work(const StepView&, const Eigen::VectorXd& v_next,
                        const Eigen::VectorXd& v_mid) const {
    (void)v_next;
    (void)v_mid;
    return {};
  }
  // Writes the element's outputs of sample k.
  virtual void record(const StepView&, long, const Outputs&) const {}
  // Moves the element's own states (generator fluxes, ...) from t_k to t_{k+1}, given v_{k+1}.
  virtual void advance(const StepView&, const Eigen::VectorXd& v_next) { (void)v_next; }
};

}  // namespace pinwind
