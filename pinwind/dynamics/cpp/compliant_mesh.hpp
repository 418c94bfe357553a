// Compliant gear meshes: a spring-damper along the line of action of each flank, with the
// deflection taken from the bodies' positions (IFToMM 2018 eqs. 2-6;
// Jørgensen 2014 eqs. 14-19; pinwind/dynamics/compliant.py documents
// the model):
//
//     F_n = k(x) δ + c δ̇   on each flank in contact, F_n ≥ 0 (teeth never pull).
//
// Each flank has its own contact: both push at once where the centres come closer than the teeth
// allow (zero or small backlash, a gear in a compliant bearing, floating members), so that the
// contact is the gradient of U = Σ_flanks ½ k δ₊² (a contact potential) and an
// undamped train keeps its energy through any number of flank changes.
//
// Deflection from positions. With ψ_A, ψ_B the gear angles about the axis relative to the
// centre line (mesh_path.hpp), the front flank's overlap along its line of action is
//
//     δ_f = wrap(T − T_ref + e_T) + R + e_R,      δ_b = −wrap(T − T_ref + e_T) + R + e_R − j
//     T   = r_A ψ_A − r_B ψ_B + tan β_b Z           (signed base radii, rolling part)
//     R   = κ (r_b,B ± r_b,A) (inv α'(a) − inv α'(a_ref)),  cos α'(a) = (r_b,B ± r_b,A)/a
//
// (κ = −1 external, +1 internal: moving an internal pair's centres apart pushes the teeth
// together), Z the axial position of B's flank relative to A's at the pitch point
// (mesh_rows.hpp axial_offset; a helical mesh's: an axial shift dz of B moves its flank along
// the line of action as a turn would, by tan β_b dz, on the two flanks opposite ways), e_T, e_R the position errors of the gears along the line of action, j the
// backlash; wrap() keeps the tooth pair in mesh, modulo one base pitch. δ̇ = −J v with J the
// flank's rigid row (mesh_rows.hpp), so the rigid and compliant meshes share one line of action.
//
// Implicit force. Stiff meshes (1e8 to 5e9 N/m on gears of a few kg) put modes in the kHz,
// where an explicit spring is stable only at tiny steps. The force over the step is taken at
// the time step's weighted state (time_step.hpp): deflection δ_n − J (dq₀ + κ_q ā), speed
// −J (v_n + κ_v ā),
//
//     F = k (δ_n − J dq₀ − κ_q J ā) − c J (v_n + κ_v ā)
//       = b − w J ā,   b = k (δ_n − J dq₀) − c J v_n,   w = k κ_q + c κ_v,
//
// so the mesh adds w JᵀJ to the QP's Hessian and Jᵀ b to its force: the same proxsuite solve
// gives its force over the step (a soft constraint with compliance 1/w; as k → ∞ it becomes
// the rigid row). With ρ∞ = 1 (the trapezoidal rule: κ_q = h²/4, κ_v = h/2, dq₀ = h v_n/2)
// w = h (h k/4 + c/2) and F = k (δ_n + δ_{n+1})/2 − c J (v_n + v_{n+1})/2 for a constant J: the
// mesh keeps its energy to rounding, where the former semi-implicit Euler step (w = h (h k/2 +
// c)) acted as an extra dashpot k h/2.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <nanobind/nanobind.h>

#include "element_kind.hpp"
#include "elements.hpp"
#include "flank_friction.hpp"
#include "mesh_path.hpp"

namespace pinwind {

struct CompliantMeshSpec {
  long mesh = 0;                  // index of the mesh in the model's mesh list
  double stiffness = 0.0;         // mesh stiffness when the path has no pair table [N/m]
  double damping = 0.0;           // c [N·s/m]
  double backlash = 0.0;          // j along the line of action [m]
  double base_radius_a = 0.0;     // signed base radii: T = r_A ψ_A − r_B ψ_B [m]
  double base_radius_b = 0.0;
  Vec3 reference_b = Vec3::UnitX();  // unit vector ⟂ axis fixed in gear B's joint frame
  double tangential_ref = 0.0;    // T at the reference pose, less its axial part [m]
  double axial_ref = 0.0;         // Z at the reference pose (mesh_rows.hpp axial_offset) [m]
  double base_radius_sum = 0.0;   // r_b,B ± r_b,A = a cos α' [m]
  double radial_sign = -1.0;      // κ
  double involute_ref = 0.0;      // inv α' at the reference centre distance
  double tangential_offset = 0.0; // e_T [m]
  double radial_offset = 0.0;     // e_R [m]
  double friction = 0.0;          // μ, the flanks' coefficient of friction [-] (FlankFriction)
  // μ at the operating point (flank_friction.hpp flank_mu): FrictionLaw::iso14179 takes
  // ISO/TR 14179-2's μ_mz from the flank's force and these; friction is then unused.
  FrictionLaw friction_law = FrictionLaw::constant;
  double iso_face_width = 0.0;             // b [m]
  double iso_reduced_radius = 0.0;         // ρ_redC, normal section, at the pitch point [m]
  double iso_sum_velocity_per_spin = 0.0;  // c_v: v_Σc = c_v |ω_B − ω_A| [m]
  double iso_viscosity = 0.0;              // η of the oil at its temperature [Pa·s]
  double iso_roughness = 0.0;              // Ra = (Ra1 + Ra2)/2 [m]
  double iso_lubricant_factor = 1.0;       // X_L [-]
  // Δ = b tan β_b: the span of a single helical contact line along the path, over which each
  // pair's friction is integrated (flank_friction.hpp ContactLine); 0: a point pair [m].
  double contact_line_span = 0.0;
  bool rubs() const { return friction != 0.0 || friction_law != FrictionLaw::constant; }
  // Slices across the face width (sliced_mesh.hpp); 1: the single contact line above.
  long slices = 1;
  Vec3 axis_b = Vec3::UnitZ();    // gear B's axis in its joint frame
  Eigen::VectorXd slice_offset;   // z_s: each slice's centre from the face centre along k [m]
  Eigen::VectorXd slice_gap;      // e_s: the lead modifications' gap at each slice, front [m]
  Eigen::VectorXd slice_gap_back; // e_s of the back flank [m]
  // Helical slices (SlicedMeshes): each slice's face section lags the front face section by
  // ζ_s tan β_b along the path; empty: a spur mesh, every slice at the same roll position.
  Eigen::VectorXd slice_shift;       // the entering pair's shift of each slice, front flank [m]
  Eigen::VectorXd slice_shift_back;  // the same on the back flank [m]
  double slice_path_length = 0.0;    // g_α: the transverse path a slice's pairs touch over [m]
  // One pair's stiffness along a slice's path over the whole face (N slices share it) [m, N/m];
  // empty: the constant mesh stiffness.
  Eigen::VectorXd slice_pair_position, slice_pair_stiffness;
  double face_width = 0.0;           // b, for the line loads [m]; 0: not written
};

// inv α = tan α − α of the angle α whose cosine is c (0 < c ≤ 1), with tan α = √(1 − c²) / c:
// the same value as tan(acos c) to rounding, at a fifth of its cost (floating centres evaluate it
// every step).
inline double involute_of_cosine(double c) {
  return std::sqrt((1.0 - c) * (1.0 + c)) / c - std::acos(c);
}

// The angles and centre distance of mesh sp at the state s (compliant_mesh.hpp's header).
struct MeshPose {
  double psi_a = 0.0;            // ψ_A, gear A's angle from the centre line [rad]
  double rolling = 0.0;          // T − T_ref + e_T, wrapped into one base pitch [m]
  double centre_distance = 0.0;  // a, ⟂ to the axis [m]
};

inline MeshPose mesh_pose(const StepView& s, const CompliantMeshSpec& sp, const MeshPathSpec& path) {
  const auto& mc = s.meshes;
  const Eigen::Index m = sp.mesh;
  const Vec3 k = s.rows.axis.row(m).transpose();
  const Vec3 u = mc.sigma[m] * s.rows.radial.row(m).transpose();
  const auto& rot_a = s.data.oMi[mc.joint_a[m]].rotation();
  const auto& rot_b = s.data.oMi[mc.joint_b[m]].rotation();
  MeshPose pose;
  pose.psi_a = angle_about(k, u, rot_a * path.reference_a);
  const double psi_b = angle_about(k, u, rot_b * sp.reference_b);
  const double pitch = path.base_pitch;
  // Rolling part, wrapped into one base pitch centred on the middle of the backlash gap.
  double rolling = sp.base_radius_a * pose.psi_a - sp.base_radius_b * psi_b - sp.tangential_ref +
                   sp.tangential_offset;
  if (mc.tan_beta_b[m] != 0.0) {
    // The helical part tan β_b (Z − Z_ref), whose rate is the mesh row's axial part.
    const Vec3 k_b = rot_b * sp.axis_b;
    const double z = axial_offset(k, k_b, s.rows.centre_a.row(m).transpose(),
                                  s.rows.centre_b.row(m).transpose(),
                                  s.rows.pitch_point.row(m).transpose());
    rolling += mc.tan_beta_b[m] * (z - sp.axial_ref);
  }
  rolling -= pitch * std::round((rolling + 0.5 * sp.backlash) / pitch);
  pose.rolling = rolling;
  const double distance = (s.rows.centre_b.row(m) - s.rows.centre_a.row(m)).norm();
  const double along_axis = (s.rows.centre_b.row(m) - s.rows.centre_a.row(m)).dot(k);
  pose.centre_distance =
      std::sqrt(std::max(0.0, distance * distance - along_axis * along_axis));
  return pose;
}

// R + e_R of mesh sp at centre distance a [m], κ (r_b,B ± r_b,A) (inv α'(a) − inv α'(a_ref))
// + e_R, with cos α'(a) and sin α'(a) (CompliantMeshes::radial_overlap says why).
inline double radial_part(const CompliantMeshSpec& sp, double centre_distance, double& cos_out,
                          double& sin_out) {
  const double cos_w = std::min(1.0, sp.base_radius_sum / centre_distance);
  cos_out = cos_w;
  sin_out = std::sqrt((1.0 - cos_w) * (1.0 + cos_w));
  return sp.radial_sign * sp.base_radius_sum * (involute_of_cosine(cos_w) - sp.involute_ref) +
         sp.radial_offset;
}

class CompliantMeshes : public Element {
 public:
  CompliantMeshes(std::vector<CompliantMeshSpec> specs, const std::vector<MeshPathSpec>& paths,
                  Eigen::Index nv)
      : specs_(std::move(specs)) {
    const auto n = static_cast<Eigen::Index>(specs_.size());
    for (const auto& s : specs_) paths_.push_back(paths[static_cast<size_t>(s.mesh)]);
    contact_.setZero(n, 2);
    last_flank_.assign(specs_.size(), 1.0);
    delta_.setZero(n, 2);
    row_.resize(2 * specs_.size());
    for (auto& r : row_) r.setZero(nv);
    span_.assign(specs_.size(), {0, 0});
    moving_.resize(specs_.size());
    path_.resize(2 * specs_.size());
    last_path_.resize(2 * specs_.size());
    b_.setZero(n, 2);
    w_.setZero(n, 2);
    normal_.setZero(n, 2);
    elastic_.setZero(n, 2);
    viscous_.setZero(n, 2);
    last_k_.setZero(n, 2);
    radial_distance_.setConstant(n, -1.0);
    radial_.setZero(n);
    cos_w_.setOnes(n);
    sin_w_.setZero(n);
    friction_.resize(2 * specs_.size());
    last_ja_.setZero(n, 2);
    for (const auto& sp : specs_) rubbing_ = rubbing_ || sp.rubs();
  }

  void prepare(const StepView& s) override {
    const auto& mc = s.meshes;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const Eigen::Index m = sp.mesh;
      const MeshPose pose = mesh_pose(s, sp, paths_[i]);
      const double psi_a = pose.psi_a, rolling = pose.rolling;
      const double radial = radial_overlap(i, pose.centre_distance);
      delta_(i, 0) = rolling + radial;
      delta_(i, 1) = -rolling + radial - sp.backlash;
      if (!started_) {
        // The span of the rows' entries that can be non-zero: the joints that move one gear
        // and not the other (MeshConstants::support), the same for both flanks and every
        // state; the rows are written, and add_implicit adds w JᵀJ, over those columns alone.
        const auto moves = [&](Eigen::Index c) {
          return mc.support(mc.slot_b[m], c) != mc.support(mc.slot_a[m], c);
        };
        Eigen::Index lo = 0, hi = row_[2 * i].size();
        while (lo < hi && !moves(lo)) ++lo;
        while (hi > lo && !moves(hi - 1)) --hi;
        span_[i] = {lo, hi};
        moving_[i].clear();
        for (Eigen::Index c = lo; c < hi; ++c) {
          if (moves(c)) moving_[i].push_back(c);
        }
      }
      double unused;
      for (int f = 0; f < 2; ++f) {
        flank_row(mc, s.rows, m, flank_sign(f), cos_w_[i], sin_w_[i], row_[2 * i + f], unused,
                  &moving_[i]);
        path_[2 * i + f] = path_state(paths_[i], psi_a, flank_sign(f));
        if (modified(i)) engage(paths_[i], path_[2 * i + f], delta_(i, f));
      }
      if (!started_) {
        // Start in contact on every flank that overlaps (both at once where the centres are
        // closer than the teeth allow: zero backlash, floating members); a mesh at rest with
        // zero deflection starts on both flanks carrying no force, and the first step releases
        // the one that would pull. A static solve with neither flank overlapping starts on the
        // one nearer to contact and closes the gap if the loads ask for it.
        for (int f = 0; f < 2; ++f) contact_(i, f) = delta_(i, f) - gap(i, f) >= 0.0;
        if (!contact_.row(i).any() && s.weights.statics) contact_(i, nearer(i)) = 1;
      }
      // The work the stiffness's change puts in since the last sample, ½ (k_n − k_{n−1}) δ_n²
      // on each overlapping flank (δ_n at the new sample): the parametric excitation, which
      // the energy ledger keeps apart from the integrator's loss. With profile modifications
      // the pairs' gaps move too: U(δ_n) of the pairs where they are now less U(δ_n) of the
      // pairs where they were. Repeated calls at one state add nothing.
      for (int f = 0; f < 2; ++f) {
        const double k = stiffness(i, f), d = std::max(0.0, delta_(i, f));
        if (!first_ && !s.weights.statics) {
          parametric_ += modified(i)
                             ? pairs_potential(paths_[i], path_[2 * i + f], delta_(i, f)) -
                                   pairs_potential(paths_[i], last_path_[2 * i + f], delta_(i, f))
                             : 0.5 * (k - last_k_(i, f)) * d * d;
        }
        if (!s.weights.statics) {
          last_k_(i, f) = k;
          last_path_[2 * i + f] = path_[2 * i + f];
        }
        if (contact_(i, f)) coefficients(s, i, f);
      }
    }
    started_ = true;
    if (!s.weights.statics) first_ = false;
  }

  // Flank friction (flank_friction.hpp): explicit over the step, on each flank in contact at the
  // step's start, with the flank's force predicted as b − w (J ā)_{n−1}. None in a static solve
  // (nothing slides).
  void add_force(const StepView& s, Eigen::VectorXd& force) override {
    if (!rubbing_) return;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      if (!sp.rubs()) continue;
      const auto [lo, hi] = span_[i];
      const ContactLine line = single_line(paths_[i], sp.contact_line_span);
      for (int f = 0; f < 2; ++f) {
        FlankFriction& fr = friction_[2 * i + f];
        fr.force = 0.0;
        const double normal =
            contact_(i, f) && !s.weights.statics ? b_(i, f) - w_(i, f) * last_ja_(i, f) : 0.0;
        if (normal <= 0.0) continue;
        if (!friction_begin(s.meshes, s.rows, paths_[i], s.data.J, s.v, sp.mesh, flank_sign(f),
                            cos_w_[i], sin_w_[i], lo, hi, fr)) {
          continue;
        }
        add_contact_pairs(paths_[i], path_[2 * i + f], delta_(i, f), line, 1.0, 0.0, fr);
        friction_end(s.meshes, s.rows, s.data.J, sp.mesh, flank_sign(f), cos_w_[i], sin_w_[i],
                     flank_mu(sp, normal, fr.spin), normal, lo, hi, fr);
        for (Eigen::Index c = lo; fr.force > 0.0 && c < hi; ++c) force[c] -= fr.force * fr.row[c];
      }
    }
  }

  void add_implicit(const StepView&, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      for (int f = 0; f < 2; ++f) {
        if (!contact_(i, f)) continue;
        const auto& row = row_[2 * i + f];
        // w rowᵀ row entry by entry, over the columns that move one gear and not the other
        // (the row is zero elsewhere: evaluate_mesh_geometry) and in the lower triangle only
        // (Element::add_implicit): Eigen's outer-product path allocates a temporary per call,
        // which at nv of 6 to 20 costs more than the products. The entries left out would add
        // a zero product: the same sums, fewer of them (a planet's sun mesh with five
        // compliant bearings: 9 of the span's 16 columns, 45 entries of 136).
        const auto& cols = moving_[i];
        const size_t count = cols.size();
        for (size_t p = 0; p < count; ++p) {
          const Eigen::Index c = cols[p];
          const double wc = w_(i, f) * row[c];
          if (wc == 0.0) continue;
          double* column = hessian.col(c).data();
          for (size_t q = p; q < count; ++q) column[cols[q]] += row[cols[q]] * wc;
        }
        const double b = b_(i, f);
        for (const Eigen::Index c : cols) force[c] += b * row[c];
      }
    }
  }

  // Each flank settles on its own (the contact is the gradient of Σ_flanks ½ k δ₊²): a flank in
  // contact whose force at the end of the step would pull leaves it, a free flank whose force
  // would push closes.
  bool settle(const StepView& s, const Eigen::VectorXd& a, bool last) override {
    bool changed = false;
    if (!last) {
      for (size_t i = 0; i < specs_.size(); ++i) {
        const bool front_was = contact_(i, 0), back_was = contact_(i, 1);
        for (int f = 0; f < 2; ++f) {
          const double force = end_force(s, a, i, f);
          if (contact_(i, f) ? force < 0.0 : force > 0.0) {
            contact_(i, f) = !contact_(i, f);
            if (contact_(i, f)) coefficients(s, i, f);
            changed = true;
          }
        }
        // A static solve (a = Δq) keeps one flank in contact, or nothing would hold the gears'
        // relative turn: a flank that would pull hands the load to the other one.
        if (s.weights.statics && !contact_.row(i).any()) {
          const int f = front_was == back_was
                            ? (end_force(s, a, i, 0) >= end_force(s, a, i, 1) ? 0 : 1)
                            : (front_was ? 1 : 0);
          contact_(i, f) = 1;
          coefficients(s, i, f);
        }
      }
    }
    if (changed || s.weights.statics) return changed;
    // Final forces of the step.
    for (size_t i = 0; i < specs_.size(); ++i) {
      for (int f = 0; f < 2; ++f) {
        if (!contact_(i, f)) {
          normal_(i, f) = elastic_(i, f) = viscous_(i, f) = last_ja_(i, f) = 0.0;
          continue;
        }
        const auto& row = row_[2 * i + f];
        last_ja_(i, f) = row.dot(a);  // the next step's friction predicts its force with it
        elastic_(i, f) = stiffness(i, f) * (delta_(i, f) - gap(i, f) -
                                            row.dot(s.dq_free + s.weights.position_gain * a));
        viscous_(i, f) = -specs_[i].damping * row.dot(s.v + s.weights.speed_gain * a);
        normal_(i, f) = std::max(0.0, elastic_(i, f) + viscous_(i, f));
      }
      if (normal_(i, 0) > 0.0 || normal_(i, 1) > 0.0) {
        last_flank_[i] = normal_(i, 0) >= normal_(i, 1) ? 1.0 : -1.0;
      }
    }
    return false;
  }

  void add_body_forces(const StepView& s, BodyForces& out) const override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const Eigen::Index m = specs_[i].mesh;
      for (int f = 0; f < 2; ++f) {
        if (normal_(i, f) == 0.0) continue;
        const Vec3 force = tooth_force_on_b(s.meshes, s.rows, m, flank_sign(f), normal_(i, f),
                                            cos_w_[i], sin_w_[i]);
        const Vec3 p = s.rows.pitch_point.row(m).transpose();
        out.add(s.meshes.joint_b[m], p, force);
        out.add(s.meshes.joint_a[m], p, -force);
      }
      for (int f = 0; rubbing_ && f < 2; ++f) add_friction_forces(s, m, friction_[2 * i + f], out);
    }
  }

  double parametric_work() const override { return parametric_; }

  // U = Σ_flanks ½ k(x) δ₊² [J]: the potential whose gradient the flanks' forces are; with
  // profile modifications Σ_pairs ½ k_j (δ − e_j)₊² (mesh_path.hpp engage).
  double potential(const StepView&) const override {
    double energy = 0.0;
    for (size_t i = 0; i < specs_.size(); ++i) {
      for (int f = 0; f < 2; ++f) {
        if (modified(i)) {
          energy += pairs_potential(paths_[i], path_[2 * i + f], delta_(i, f));
          continue;
        }
        const double d = std::max(0.0, delta_(i, f));
        energy += 0.5 * stiffness(i, f) * d * d;
      }
    }
    return energy;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    StepWork w;
    for (size_t i = 0; i < specs_.size(); ++i) {
      for (int f = 0; f < 2; ++f) {
        if (!contact_(i, f) || normal_(i, f) == 0.0) continue;
        const double jv = row_[2 * i + f].dot(v_mid) * s.dt;
        // The generalised force Jᵀ F_n does work F_n J v_mid h (F_n > 0: not clipped).
        w.elastic += elastic_(i, f) * jv;
        w.dissipated -= viscous_(i, f) * jv;
      }
      // Friction's force −μ F gᵀ, applied over the whole step, takes μ F g·v_mid h.
      for (int f = 0; rubbing_ && f < 2; ++f) {
        const FlankFriction& fr = friction_[2 * i + f];
        if (fr.force != 0.0) w.friction += fr.force * fr.row.dot(v_mid) * s.dt;
      }
    }
    return w;
  }

  // The mesh's series are those of its loaded flank (the one pushing harder, or the last one
  // that pushed): rating reads them. Each flank's own force is in normal_front and normal_back,
  // and force_on_b is the resultant of both.
  void record(const StepView& s, long k, const Outputs& out) const override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const long m = specs_[i].mesh;
      const int f = last_flank_[i] > 0 ? 0 : 1;
      record_mesh_force(out, s.meshes, s.rows, k, m, normal_(i, f), last_flank_[i], cos_w_[i],
                        sin_w_[i]);
      const long e = out.entry(Family::mesh, k, m);
      out.at(Series::mesh_normal_front, e) = normal_(i, 0);
      out.at(Series::mesh_normal_back, e) = normal_(i, 1);
      if (normal_(i, 1 - f) > 0.0) {
        const Vec3 resultant =
            tooth_force_on_b(s.meshes, s.rows, m, 1.0, normal_(i, 0), cos_w_[i], sin_w_[i]) +
            tooth_force_on_b(s.meshes, s.rows, m, -1.0, normal_(i, 1), cos_w_[i], sin_w_[i]);
        for (int c = 0; c < 3; ++c) out.at(Series::mesh_force_on_b, e, c) = resultant[c];
      }
      const PathState& p = path_[2 * i + f];
      out.at(Series::mesh_deflection, e) =
          contact_(i, f) ? delta_(i, f) : std::max(delta_(i, 0), delta_(i, 1));
      out.at(Series::transmission_error, e) = delta_(i, 0);
      out.at(Series::mesh_contact_position, e) = paths_[i].roll_start + p.entering;
      out.at(Series::mesh_pairs, e) = p.pairs;
      out.at(Series::mesh_single_tooth_force, e) = normal_(i, f) * p.share;
      // One contact line: its load is uniform across the face, centred.
      out.at(Series::mesh_face_load_factor, e) = normal_(i, f) > 0.0 ? 1.0 : 0.0;
      out.at(Series::mesh_load_centre, e) = 0.0;
      const double line_load =
          specs_[i].face_width > 0.0 ? normal_(i, f) / specs_[i].face_width : 0.0;
      out.at(Series::mesh_peak_line_load, e) = line_load;
      out.at(Series::mesh_mean_line_load, e) = line_load;
      // The entering pair's sliding speed (kinematic, with or without friction) and the friction.
      record_friction(s, out, k, m, paths_[i], p, last_flank_[i], cos_w_[i], sin_w_[i],
                      span_[i].first, span_[i].second, friction_[2 * i], friction_[2 * i + 1]);
    }
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override {
    return copy_of<CompliantMeshes, Element>(*this);
  }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  static double flank_sign(int f) { return f == 0 ? 1.0 : -1.0; }

  double stiffness(size_t i, int f) const {
    return paths_[i].pair_position.size() ? path_[2 * i + f].stiffness : specs_[i].stiffness;
  }

  // Whether mesh i's flanks are modified (a gap table along its path).
  bool modified(size_t i) const { return paths_[i].gap_position.size() != 0; }

  // E of flank f of mesh i: its engaged pairs' mean gap [m] (0 for unmodified flanks).
  double gap(size_t i, int f) const { return path_[2 * i + f].gap; }

  // The flank of mesh i nearer to contact (the larger overlap), 0 front, 1 back.
  int nearer(size_t i) const { return delta_(i, 0) >= delta_(i, 1) ? 0 : 1; }

  // The force flank f of mesh i would carry at the end of the step for the acceleration a (a
  // static solve: for the displacement a), whether it is in contact or not [N].
  double end_force(const StepView& s, const Eigen::VectorXd& a, size_t i, int f) const {
    const auto& row = row_[2 * i + f];
    return stiffness(i, f) *
               (delta_(i, f) - gap(i, f) - row.dot(s.dq_free + s.weights.position_gain * a)) -
           specs_[i].damping * row.dot(s.v + s.weights.speed_gain * a);
  }

  // R + e_R of mesh i at centre distance a [m]: the overlap of moving the centres from the
  // reference, κ (r_b,B ± r_b,A) (inv α'(a) − inv α'(a_ref)) + e_R; with it cos α'(a) and
  // sin α'(a), whose line of action (mesh_rows.hpp) is the overlap's gradient: d/da of
  // (r_b,B ± r_b,A) inv α'(a) is sin α'(a), as the line's radial part. Kept while a stays within
  // 1e-14 relative of the distance it was computed at: gears on fixed or carrier-borne axes
  // keep their centre distance to rounding, and the acos and square root then cost a quarter of the
  // mesh's geometry; the value kept is off by r_b tan α' · 1e-14 (< 1e-14 m), far below any
  // deflection.
  double radial_overlap(size_t i, double centre_distance) {
    if (std::abs(centre_distance - radial_distance_[i]) <= 1e-14 * centre_distance) {
      return radial_[i];
    }
    radial_distance_[i] = centre_distance;
    radial_[i] = radial_part(specs_[i], centre_distance, cos_w_[i], sin_w_[i]);
    return radial_[i];
  }

  // b and w of flank f of mesh i at this step's state (its force b − w J ā in contact).
  void coefficients(const StepView& s, size_t i, int f) {
    const double k = stiffness(i, f), c = specs_[i].damping;
    const auto& row = row_[2 * i + f];
    b_(i, f) = k * (delta_(i, f) - gap(i, f) - row.dot(s.dq_free)) - c * row.dot(s.v);
    w_(i, f) = k * s.weights.position_gain + c * s.weights.speed_gain;
  }

  std::vector<CompliantMeshSpec> specs_;
  std::vector<MeshPathSpec> paths_;
  Eigen::Matrix<int, Eigen::Dynamic, 2> contact_;   // 1 where a flank is in contact (front, back)
  std::vector<double> last_flank_;   // the flank last loaded (+1 front, −1 back)
  Eigen::Matrix<double, Eigen::Dynamic, 2> delta_;  // overlaps δ_f, δ_b [m]
  std::vector<Eigen::RowVectorXd> row_;             // J of each flank (mesh i: 2i, 2i + 1)
  std::vector<std::pair<Eigen::Index, Eigen::Index>> span_;  // each mesh's rows' span
  std::vector<std::vector<Eigen::Index>> moving_;  // the columns in the span that move a gear
  std::vector<PathState> path_;
  std::vector<PathState> last_path_;  // each flank's path state at the last sample
  // Each flank's b [N] and w [N·s²/m] (coefficients) and its final force and parts [N].
  Eigen::Matrix<double, Eigen::Dynamic, 2> b_, w_, normal_, elastic_, viscous_;
  Eigen::Matrix<double, Eigen::Dynamic, 2> last_k_;  // each flank's stiffness at the last sample
  Eigen::VectorXd radial_distance_, radial_;  // radial_overlap's centre distance [m] and value [m]
  Eigen::VectorXd cos_w_, sin_w_;  // the working pressure angle α' at that centre distance
  std::vector<FlankFriction> friction_;  // each flank's friction over the step (mesh i: 2i, 2i + 1)
  Eigen::Matrix<double, Eigen::Dynamic, 2> last_ja_;  // each flank's J ā at the last step [m/s²]
  bool rubbing_ = false;  // some mesh has μ > 0
  double parametric_ = 0.0;  // work of the stiffness's changes since t = 0 [J]
  bool first_ = true;     // no dynamic step prepared yet
  bool started_ = false;  // contact_ set from the first state prepared (static or dynamic)
};

// Sliced compliant meshes (issue 40 item 1; pinwind/gears/face_load.py is the static reference):
// the contact line of a spur mesh cut into N slices of width b/N across the face, each slice s a
// spring k(x)/N and dashpot c/N at z_s (its centre from the face centre, along gear A's axis k)
// with its own contact. Its overlap is the mesh's plus the gears' relative tilt and less the lead
// modifications' gap there,
//
//     δ_s = δ − z_s θ − e_s,     θ = (k × k_B)·(k × n),
//
// with k_B gear B's axis and n the flank's line of action: θ is B's tilt relative to A about
// k × n (small angles), the turn that moves B's flank at +z_s away from A's along n. Its row
// follows from the velocity of the contact point P + z_s k of each gear,
//
//     δ̇_s = −n·(v_B(P + z_s k) − v_A(P + z_s k)) = −(J + z_s a) v,   a = (k × n)ᵀ (J_ω,B − J_ω,A),
//
// the derivative of θ being (k × n)·(ω_B − ω_A) while the axes stay parallel to first order; so
// the slice's force F_s acts at P + z_s k and tilts both gears. The implicit force of each slice
// is that of CompliantMeshes, F_s = b_s − w_s J_s ā; summed over the slices in contact,
//
//     Σ w_s J_sᵀJ_s = W₀ JᵀJ + W₁ (Jᵀa + aᵀJ) + W₂ aᵀa,   Σ b_s J_s = B₀ J + B₁ a,
//
// W_p = Σ w_s z_sᵖ, B_p = Σ b_s z_sᵖ: N slices cost three outer products, not N. With θ = 0 and
// no lead modification every slice carries F/N and the mesh is CompliantMeshes' to rounding.
//
// Profile relief (issue 40 item 2 on slices): the relief runs along the profile, the same at
// every slice, so each slice's pairs take the gap table of the single-line mesh: slice s engages
// its pairs at its own overlap δ_s (mesh_path.hpp engage), its force (K_s/N)(δ_s − E_s) and its
// potential Σ_j ½ (k_j/N)(δ_s − e_j)₊². With θ = 0 every slice engages the single line's pairs.
//
// Helical slices: each slice is a thin spur section of the face whose pairs roll along the
// transverse path g_α (the slice path: slice_path_length and slice_pair_*), its section lagging
// the front face section (side I, ζ = z + b/2) by ζ_s tan β_b along the front flank's path and by
// (b − ζ_s) tan β_b along the back flank's (the tooth's twist moves the two flanks' contacts
// opposite ways along their paths); the contact lines are inclined across the face, so the pairs
// in contact and the slices' stiffnesses differ. With the pair stiffness k_ℓ = c̄ p_bt / g_α on the
// slice path (c̄ the mean mesh stiffness) the slices' sum is the midpoint rule over the face of
// the single-line helical law (pinwind/gears/mesh_stiffness.py contact_line_pair_stiffness).
// The mesh's path series (pairs, contact position, single-tooth force) and flank friction stay the
// single contact line's. Each slice then has its own w_s: W_p = Σ w_s z_sᵖ as above. Profile
// relief on helical slices: the gap table runs along g_α, the slices' path, so slice s's pairs,
// at their own shifted roll, engage behind the single spur line's gaps there (as above).
class SlicedMeshes : public Element {
 public:
  SlicedMeshes(std::vector<CompliantMeshSpec> specs, const std::vector<MeshPathSpec>& paths,
               Eigen::Index nv)
      : specs_(std::move(specs)) {
    for (const auto& s : specs_) {
      paths_.push_back(paths[static_cast<size_t>(s.mesh)]);
      MeshPathSpec slice_path = paths_.back();
      const bool helical = s.slice_shift.size() != 0;
      if (helical) {
        slice_path.path_length = s.slice_path_length;
        slice_path.pair_position = s.slice_pair_position;
        slice_path.pair_stiffness = s.slice_pair_stiffness;
        // The profile relief's gap table runs along the transverse path g_α, which is the
        // slices' path: each slice's pairs take it at their own shifted roll. The single line's
        // path (its series and friction) runs over g_α + Δ in front-section positions, where
        // one gap per pair does not hold: it stays unmodified.
        paths_.back().gap_position.resize(0);
        paths_.back().gap_value.resize(0);
      }
      slice_paths_.push_back(std::move(slice_path));
      helical_.push_back(helical);
      for (int f = 0; f < 2; ++f) {
        Flank fl;
        fl.k.setZero(s.slices);
        fl.gap.setZero(s.slices);
        fl.w.setZero(s.slices);
        fl.last_k.setZero(s.slices);
        fl.paths.resize(static_cast<size_t>(s.slices));
        fl.last_paths.resize(static_cast<size_t>(s.slices));
        fl.row.setZero(nv);
        fl.tilt_row.setZero(nv);
        fl.contact.setZero(s.slices);
        fl.delta.setZero(s.slices);
        fl.b.setZero(s.slices);
        fl.normal.setZero(s.slices);
        fl.elastic.setZero(s.slices);
        fl.viscous.setZero(s.slices);
        fl.friction_load.setZero(s.slices);
        flanks_.push_back(std::move(fl));
      }
    }
    // Each mesh's first column in the slice family: the meshes' slices one after the other
    // (CompliantMeshesKind::count).
    long column = 0;
    for (const auto& sp : specs_) {
      first_slice_.push_back(column);
      column += static_cast<long>(sp.slices);
    }
    last_flank_.assign(specs_.size(), 1.0);
    span_.assign(specs_.size(), {0, 0});
    spin_b_.assign(specs_.size(), {});
    radial_.assign(specs_.size(), Radial{});
    friction_.resize(2 * specs_.size());
    for (const auto& sp : specs_) rubbing_ = rubbing_ || sp.rubs();
  }

  void prepare(const StepView& s) override {
    const auto& mc = s.meshes;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const Eigen::Index m = sp.mesh;
      const MeshPose pose = mesh_pose(s, sp, paths_[i]);
      Radial& rad = radial_[i];
      if (std::abs(pose.centre_distance - rad.distance) > 1e-14 * pose.centre_distance) {
        rad.distance = pose.centre_distance;
        rad.value = radial_part(sp, pose.centre_distance, rad.cos_w, rad.sin_w);
      }
      const Vec3 k = s.rows.axis.row(m).transpose();
      const Vec3 k_b = s.data.oMi[mc.joint_b[m]].rotation() * sp.axis_b;
      const Vec3 tilt = k.cross(k_b);
      if (!started_) {
        const auto moves = [&](Eigen::Index c) {
          return mc.support(mc.slot_b[m], c) != mc.support(mc.slot_a[m], c);
        };
        Eigen::Index lo = 0, hi = flanks_[2 * i].row.size();
        while (lo < hi && !moves(lo)) ++lo;
        while (hi > lo && !moves(hi - 1)) --hi;
        span_[i] = {lo, hi};
        spin_b_[i] = spin_columns(s, mc.slot_a[m], mc.slot_b[m], k_b,
                                  s.rows.centre_b.row(m).transpose(), lo, hi);
      }
      const auto [lo, hi] = span_[i];
      for (int f = 0; f < 2; ++f) {
        Flank& fl = flanks_[2 * i + f];
        const double centre = f == 0 ? pose.rolling + rad.value
                                     : -pose.rolling + rad.value - sp.backlash;
        fl.centre = centre;
        double unused;
        flank_row(mc, s.rows, m, flank_sign(f), rad.cos_w, rad.sin_w, fl.row, unused);
        const Vec3 e = k.cross(line_of_action(mc, s.rows, m, flank_sign(f), rad.cos_w, rad.sin_w));
        for (Eigen::Index c = lo; c < hi; ++c) {
          const double w = mc.support(mc.slot_b[m], c) - mc.support(mc.slot_a[m], c);
          fl.tilt_row[c] = w * e.dot(s.data.J.col(c).template tail<3>());
        }
        // B turning about its own axis leaves that axis, and so θ, where it is: its spin's
        // column has no part in θ's rate (e·k_B of it would count the spin as tilt wherever
        // k_B leans against k).
        for (const Eigen::Index c : spin_b_[i]) fl.tilt_row[c] = 0.0;
        const double theta = tilt.dot(e);
        const auto& gap = f == 0 ? sp.slice_gap : sp.slice_gap_back;
        fl.delta = centre - theta * sp.slice_offset.array() - gap.array();
        fl.path = path_state(paths_[i], pose.psi_a, flank_sign(f));
        const double n_slices = double(sp.slices);
        const MeshPathSpec& sl = slice_paths_[i];
        const bool modified = sl.gap_position.size() != 0;
        // The single line's pairs engaged at the face centre's overlap: its series (the entering
        // pair's share) are CompliantMeshes'.
        if (modified && !helical_[i]) engage(sl, fl.path, centre);
        if (!helical_[i] && !modified) {
          fl.k.setConstant((paths_[i].pair_position.size() ? fl.path.stiffness : sp.stiffness) /
                           n_slices);
        } else {
          const auto& shift = f == 0 ? sp.slice_shift : sp.slice_shift_back;
          for (Eigen::Index j = 0; j < sp.slices; ++j) {
            PathState& st = fl.paths[static_cast<size_t>(j)];
            st = helical_[i] ? path_state(sl, pose.psi_a, flank_sign(f), shift[j]) : fl.path;
            if (modified) engage(sl, st, fl.delta[j]);
            fl.k[j] = (sl.pair_position.size() ? st.stiffness : sp.stiffness) / n_slices;
            fl.gap[j] = st.gap;
          }
        }
        if (!started_) {
          for (Eigen::Index j = 0; j < sp.slices; ++j) {
            fl.contact[j] = fl.delta[j] - fl.gap[j] >= 0.0;
          }
        }
        // The parametric work, ½ (k_n − k_{n−1}) δ_n² of each overlapping slice; with profile
        // relief U(δ_n) of the slice's pairs where they are now less where they were
        // (CompliantMeshes).
        if (!first_ && !s.weights.statics) {
          for (Eigen::Index j = 0; j < sp.slices; ++j) {
            const double d = std::max(0.0, fl.delta[j]);
            parametric_ +=
                modified ? (pairs_potential(sl, fl.paths[static_cast<size_t>(j)], fl.delta[j]) -
                            pairs_potential(sl, fl.last_paths[static_cast<size_t>(j)],
                                            fl.delta[j])) /
                               n_slices
                         : 0.5 * (fl.k[j] - fl.last_k[j]) * d * d;
          }
        }
        if (!s.weights.statics) {
          fl.last_k = fl.k;
          if (modified) fl.last_paths = fl.paths;
        }
      }
      if (!started_ && s.weights.statics && !any_contact(i)) {
        // A static solve starts on the slice nearest to contact (CompliantMeshes: the flank).
        Flank& a = flanks_[2 * i];
        Flank& b = flanks_[2 * i + 1];
        Eigen::Index ja, jb;
        const double da = (a.delta - a.gap).maxCoeff(&ja), db = (b.delta - b.gap).maxCoeff(&jb);
        (da >= db ? a.contact[ja] : b.contact[jb]) = 1;
      }
      for (int f = 0; f < 2; ++f) coefficients(s, i, f);
    }
    started_ = true;
    if (!s.weights.statics) first_ = false;
  }

  // Flank friction (flank_friction.hpp) on the slices: slice s's pair p touches at
  // X_p + z_s k, where e's row is J_e,p − z_s a_n (X × e gains z_s k × e = −z_s n), a_n =
  // nᵀ(J_ω,B − J_ω,A). Summed over the slices in contact, with their forces F_s predicted as
  // CompliantMeshes' are (b_s − w (J ā + z_s a ā)_{n−1}), the flank's friction carries
  // F = Σ F_s, each slice the fraction F_s / F at z_s: a spur mesh's slices share the single
  // line's pairs (so the friction is the single line's acting at the load centre z_c =
  // Σ F_s z_s / F), a helical or relieved mesh's slices each their own pairs, helical ones at
  // their section's place on the transverse path (points: the midpoint rule across the face of
  // the contact line's integral).
  void add_force(const StepView& s, Eigen::VectorXd& force) override {
    if (!rubbing_) return;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      if (!sp.rubs()) continue;
      const Eigen::Index m = sp.mesh;
      const auto [lo, hi] = span_[i];
      const Radial& rad = radial_[i];
      const MeshPathSpec& sl = slice_paths_[i];
      const bool own_pairs = helical_[i] || sl.gap_position.size() != 0;
      // A helical slice's pairs are points at its section's place q on the transverse path, the
      // pitch point at the single line's less half its span (single_line).
      const ContactLine line{0.0, sl.path_length,
                             paths_[i].pitch_position - 0.5 * sp.contact_line_span};
      for (int f = 0; f < 2; ++f) {
        Flank& fl = flanks_[2 * i + f];
        FlankFriction& fr = friction_[2 * i + f];
        fr.force = 0.0;
        double total = 0.0, moment = 0.0;
        for (Eigen::Index j = 0; j < sp.slices && !s.weights.statics; ++j) {
          const double z = sp.slice_offset[j];
          fl.friction_load[j] =
              fl.contact[j] ? std::max(0.0, fl.b[j] - fl.w[j] * (fl.last_ja + z * fl.last_ta))
                            : 0.0;
          total += fl.friction_load[j];
          moment += fl.friction_load[j] * z;
        }
        if (total <= 0.0) continue;
        if (!friction_begin(s.meshes, s.rows, paths_[i], s.data.J, s.v, m, flank_sign(f),
                            rad.cos_w, rad.sin_w, lo, hi, fr)) {
          continue;
        }
        if (!own_pairs) {
          add_contact_pairs(paths_[i], fl.path, fl.centre, line, 1.0, moment / total, fr);
        } else {
          for (Eigen::Index j = 0; j < sp.slices; ++j) {
            if (fl.friction_load[j] <= 0.0) continue;
            add_contact_pairs(sl, fl.paths[static_cast<size_t>(j)], fl.delta[j], line,
                              fl.friction_load[j] / total, sp.slice_offset[j], fr);
          }
        }
        friction_end(s.meshes, s.rows, s.data.J, m, flank_sign(f), rad.cos_w, rad.sin_w,
                     flank_mu(sp, total, fr.spin), total, lo, hi, fr);
        for (Eigen::Index c = lo; fr.force > 0.0 && c < hi; ++c) force[c] -= fr.force * fr.row[c];
      }
    }
  }

  void add_implicit(const StepView&, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& z = specs_[i].slice_offset;
      for (int f = 0; f < 2; ++f) {
        const Flank& fl = flanks_[2 * i + f];
        double w0 = 0.0, w1 = 0.0, w2 = 0.0, b0 = 0.0, b1 = 0.0;
        for (Eigen::Index j = 0; j < z.size(); ++j) {
          if (!fl.contact[j]) continue;
          w0 += fl.w[j];
          w1 += fl.w[j] * z[j];
          w2 += fl.w[j] * z[j] * z[j];
          b0 += fl.b[j];
          b1 += fl.b[j] * z[j];
        }
        if (w0 == 0.0 && b0 == 0.0) continue;
        const auto [lo, hi] = span_[i];
        const double* r = fl.row.data();
        const double* t = fl.tilt_row.data();
        for (Eigen::Index c = lo; c < hi; ++c) {
          double* column = hessian.col(c).data();
          for (Eigen::Index q = c; q < hi; ++q) {
            column[q] += w0 * r[q] * r[c] + w1 * (r[q] * t[c] + t[q] * r[c]) + w2 * t[q] * t[c];
          }
          force[c] += b0 * r[c] + b1 * t[c];
        }
      }
    }
  }

  // Each slice settles on its own, as each flank of CompliantMeshes does.
  bool settle(const StepView& s, const Eigen::VectorXd& a, bool last) override {
    end_state_.noalias() = s.dq_free + s.weights.position_gain * a;
    end_speed_.noalias() = s.v + s.weights.speed_gain * a;
    bool changed = false;
    if (!last) {
      for (size_t i = 0; i < specs_.size(); ++i) {
        for (int f = 0; f < 2; ++f) {
          Flank& fl = flanks_[2 * i + f];
          const EndDots d = end_dots(i, fl);
          for (Eigen::Index j = 0; j < fl.contact.size(); ++j) {
            const double force = end_force(i, f, j, d);
            if (fl.contact[j] ? force < 0.0 : force > 0.0) {
              fl.contact[j] = !fl.contact[j];
              changed = true;
            }
          }
        }
        // A static solve keeps one slice in contact: the one whose force would pull least.
        if (s.weights.statics && !any_contact(i)) {
          int best_f = 0;
          Eigen::Index best_j = 0;
          double best = -std::numeric_limits<double>::infinity();
          for (int f = 0; f < 2; ++f) {
            const EndDots d = end_dots(i, flanks_[2 * i + f]);
            for (Eigen::Index j = 0; j < flanks_[2 * i + f].contact.size(); ++j) {
              const double force = end_force(i, f, j, d);
              if (force > best) best = force, best_f = f, best_j = j;
            }
          }
          flanks_[2 * i + best_f].contact[best_j] = 1;
        }
      }
    }
    if (changed || s.weights.statics) return changed;
    for (size_t i = 0; i < specs_.size(); ++i) {
      double total[2];
      for (int f = 0; f < 2; ++f) {
        Flank& fl = flanks_[2 * i + f];
        const EndDots d = end_dots(i, fl);
        const double c_slice = damping(i);
        const auto& z = specs_[i].slice_offset;
        total[f] = 0.0;
        fl.last_ja = span_dot(i, fl.row, a);  // the next step's friction predicts its forces with them
        fl.last_ta = span_dot(i, fl.tilt_row, a);
        for (Eigen::Index j = 0; j < z.size(); ++j) {
          if (!fl.contact[j]) {
            fl.normal[j] = fl.elastic[j] = fl.viscous[j] = 0.0;
            continue;
          }
          fl.elastic[j] = fl.k[j] * (fl.delta[j] - fl.gap[j] - d.jx - z[j] * d.tx);
          fl.viscous[j] = -c_slice * (d.jv + z[j] * d.tv);
          fl.normal[j] = std::max(0.0, fl.elastic[j] + fl.viscous[j]);
          total[f] += fl.normal[j];
        }
      }
      if (total[0] > 0.0 || total[1] > 0.0) last_flank_[i] = total[0] >= total[1] ? 1.0 : -1.0;
    }
    return false;
  }

  void add_body_forces(const StepView& s, BodyForces& out) const override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const Eigen::Index m = specs_[i].mesh;
      const Vec3 p = s.rows.pitch_point.row(m).transpose();
      const Vec3 k = s.rows.axis.row(m).transpose();
      for (int f = 0; f < 2; ++f) {
        const Flank& fl = flanks_[2 * i + f];
        // The slices' forces share one direction u at points p + z_j k along the axis: their sum
        // Σ n_j u acts at p + (Σ n_j z_j / Σ n_j) k with the same moment, so one force per flank
        // (the direction once, not per slice: a fifth of the slices' bearing-reaction cost).
        double total = 0.0, lever = 0.0;
        for (Eigen::Index j = 0; j < fl.normal.size(); ++j) {
          total += fl.normal[j];
          lever += fl.normal[j] * specs_[i].slice_offset[j];
        }
        if (total > 0.0) {
          const Vec3 force = tooth_force_on_b(s.meshes, s.rows, m, flank_sign(f), total,
                                              radial_[i].cos_w, radial_[i].sin_w);
          const Vec3 at = p + (lever / total) * k;
          out.add(s.meshes.joint_b[m], at, force);
          out.add(s.meshes.joint_a[m], at, -force);
        }
        if (rubbing_) add_friction_forces(s, m, friction_[2 * i + f], out);
      }
    }
  }

  double parametric_work() const override { return parametric_; }

  // U = Σ_flanks Σ_slices ½ (k_s(x)/N) δ_s₊² [J]; with profile relief Σ_j ½ (k_j/N)(δ_s − e_j)₊²
  // over each slice's pairs.
  double potential(const StepView&) const override {
    double energy = 0.0;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const MeshPathSpec& sl = slice_paths_[i];
      const bool modified = sl.gap_position.size() != 0;
      const double n_slices = double(specs_[i].slices);
      for (int f = 0; f < 2; ++f) {
        const Flank& fl = flanks_[2 * i + f];
        for (Eigen::Index j = 0; j < fl.delta.size(); ++j) {
          if (modified) {
            energy += pairs_potential(sl, fl.paths[static_cast<size_t>(j)], fl.delta[j]) / n_slices;
            continue;
          }
          const double d = std::max(0.0, fl.delta[j]);
          energy += 0.5 * fl.k[j] * d * d;
        }
      }
    }
    return energy;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    StepWork w;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& z = specs_[i].slice_offset;
      for (int f = 0; f < 2; ++f) {
        const Flank& fl = flanks_[2 * i + f];
        const double jv = fl.row.dot(v_mid) * s.dt, tv = fl.tilt_row.dot(v_mid) * s.dt;
        for (Eigen::Index j = 0; j < z.size(); ++j) {
          if (!fl.contact[j] || fl.normal[j] == 0.0) continue;
          w.elastic += fl.elastic[j] * (jv + z[j] * tv);
          w.dissipated -= fl.viscous[j] * (jv + z[j] * tv);
        }
        const FlankFriction& fr = friction_[2 * i + f];
        if (fr.force != 0.0) w.friction += fr.force * fr.row.dot(v_mid) * s.dt;
      }
    }
    return w;
  }

  // The series of CompliantMeshes from the slices' sums, and the loaded flank's face load
  // factor K_Hβ = max_s w_s / w_m = N max_s F_s / Σ F_s and load centre Σ F_s z_s / Σ F_s [m,
  // from the face centre along gear A's axis]; both 0 where the mesh carries nothing.
  void record(const StepView& s, long k, const Outputs& out) const override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const long m = sp.mesh;
      const int f = last_flank_[i] > 0 ? 0 : 1;
      const Flank& fl = flanks_[2 * i + f];
      const double total[2] = {flanks_[2 * i].normal.sum(), flanks_[2 * i + 1].normal.sum()};
      const double cos_w = radial_[i].cos_w, sin_w = radial_[i].sin_w;
      record_mesh_force(out, s.meshes, s.rows, k, m, total[f], last_flank_[i], cos_w, sin_w);
      const long e = out.entry(Family::mesh, k, m);
      out.at(Series::mesh_normal_front, e) = total[0];
      out.at(Series::mesh_normal_back, e) = total[1];
      if (total[1 - f] > 0.0) {
        const Vec3 resultant =
            tooth_force_on_b(s.meshes, s.rows, m, 1.0, total[0], cos_w, sin_w) +
            tooth_force_on_b(s.meshes, s.rows, m, -1.0, total[1], cos_w, sin_w);
        for (int c = 0; c < 3; ++c) out.at(Series::mesh_force_on_b, e, c) = resultant[c];
      }
      const bool touching = fl.contact.any();
      out.at(Series::mesh_deflection, e) =
          touching ? fl.centre : std::max(flanks_[2 * i].centre, flanks_[2 * i + 1].centre);
      out.at(Series::transmission_error, e) = flanks_[2 * i].centre;
      out.at(Series::mesh_contact_position, e) = paths_[i].roll_start + fl.path.entering;
      out.at(Series::mesh_pairs, e) = fl.path.pairs;
      out.at(Series::mesh_single_tooth_force, e) = total[f] * fl.path.share;
      const bool loaded = total[f] > 0.0;
      out.at(Series::mesh_face_load_factor, e) =
          loaded ? double(sp.slices) * fl.normal.maxCoeff() / total[f] : 0.0;
      out.at(Series::mesh_load_centre, e) =
          loaded ? fl.normal.dot(sp.slice_offset) / total[f] : 0.0;
      // The line loads [N/m]: each slice's force on the loaded flank over its width b/N,
      // w_s = N F_s / b (0 for a slice out of contact, and at every slice when the mesh carries
      // nothing), in the slice columns; the peak line load is their largest and the mean line
      // load their width-weighted mean, Σ w_s (b/N) / b = Σ w_s / N = F_n / b (ratio K_Hβ).
      const bool width = loaded && sp.face_width > 0.0;
      const double per_width = width ? double(sp.slices) / sp.face_width : 0.0;
      double peak = 0.0, sum = 0.0;
      for (Eigen::Index j = 0; j < sp.slices; ++j) {
        const double w = per_width * fl.normal[j];
        out.at(Series::slice_line_load, out.entry(Family::slice, k, first_slice_[i] + j)) = w;
        peak = std::max(peak, w);
        sum += w;
      }
      out.at(Series::mesh_peak_line_load, e) = peak;
      out.at(Series::mesh_mean_line_load, e) = sum / double(sp.slices);
      record_friction(s, out, k, m, paths_[i], fl.path, last_flank_[i], cos_w, sin_w,
                      span_[i].first, span_[i].second, friction_[2 * i], friction_[2 * i + 1]);
    }
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<SlicedMeshes, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  struct Flank {
    Eigen::RowVectorXd row, tilt_row;  // J and a (class comment)
    Eigen::VectorXi contact;           // 1 where a slice is in contact
    Eigen::VectorXd delta;             // δ_s [m]
    Eigen::VectorXd b;                 // b_s [N]
    Eigen::VectorXd w;                 // w_s [N·s²/m]
    Eigen::VectorXd k, gap;            // each slice's stiffness k_s(x)/N [N/m] and gap E_s [m]
    Eigen::VectorXd last_k;            // k_s at the last sample [N/m]
    std::vector<PathState> paths, last_paths;  // each slice's pairs (helical or relieved)
    Eigen::VectorXd normal, elastic, viscous;  // the slices' final forces and parts [N]
    double centre = 0.0;               // δ of the flank at the face centre, unmodified [m]
    double last_ja = 0.0, last_ta = 0.0;  // J ā, a ā at the last step (friction's prediction)
    Eigen::VectorXd friction_load;     // each slice's predicted force for the friction [N]
    PathState path;
  };
  struct Radial {
    double distance = -1.0, value = 0.0, cos_w = 1.0, sin_w = 0.0;  // radial_part's
  };

  static double flank_sign(int f) { return f == 0 ? 1.0 : -1.0; }

  bool any_contact(size_t i) const {
    return flanks_[2 * i].contact.any() || flanks_[2 * i + 1].contact.any();
  }

  // J·x, a·x of a flank's rows at the end of the step's state x = dq₀ + κ_q a and speed
  // v + κ_v a (settle's end_state_, end_speed_).
  struct EndDots {
    double jx, tx, jv, tv;
  };
  EndDots end_dots(size_t i, const Flank& fl) const {
    return {span_dot(i, fl.row, end_state_), span_dot(i, fl.tilt_row, end_state_),
            span_dot(i, fl.row, end_speed_), span_dot(i, fl.tilt_row, end_speed_)};
  }

  // row·x over the columns mesh i's rows can be non-zero in (span_; outside it the gears'
  // supports agree and the row is 0), in column order: the slices take these dots several
  // times a step, and Eigen's reduction over all columns cost 5k instructions a step there.
  double span_dot(size_t i, const Eigen::RowVectorXd& row, const Eigen::VectorXd& x) const {
    const auto [lo, hi] = span_[i];
    double sum = 0.0;
    for (Eigen::Index c = lo; c < hi; ++c) sum += row[c] * x[c];
    return sum;
  }

  // The force slice j of flank f of mesh i would carry at the end of the step [N].
  double end_force(size_t i, int f, Eigen::Index j, const EndDots& d) const {
    const double z = specs_[i].slice_offset[j];
    const Flank& fl = flanks_[2 * i + f];
    return fl.k[j] * (fl.delta[j] - fl.gap[j] - d.jx - z * d.tx) -
           damping(i) * (d.jv + z * d.tv);
  }

  // c/N of a slice of mesh i [N·s/m].
  double damping(size_t i) const { return specs_[i].damping / double(specs_[i].slices); }

  // b_s and w of flank f of mesh i at this step's state.
  void coefficients(const StepView& s, size_t i, int f) {
    Flank& fl = flanks_[2 * i + f];
    const double c = damping(i);
    const auto& z = specs_[i].slice_offset.array();
    fl.b = fl.k.array() * (fl.delta.array() - fl.gap.array() - span_dot(i, fl.row, s.dq_free) -
                           z * span_dot(i, fl.tilt_row, s.dq_free)) -
           c * (span_dot(i, fl.row, s.v) + z * span_dot(i, fl.tilt_row, s.v));
    fl.w = fl.k.array() * s.weights.position_gain + c * s.weights.speed_gain;
  }

  std::vector<CompliantMeshSpec> specs_;
  std::vector<MeshPathSpec> paths_;
  std::vector<MeshPathSpec> slice_paths_;  // each mesh's slices' path (helical: the transverse one)
  std::vector<bool> helical_;  // the mesh's slices lag along the path (slice_shift)
  std::vector<long> first_slice_;  // each mesh's first column of the slice family
  std::vector<Flank> flanks_;  // mesh i: 2i front, 2i + 1 back
  std::vector<double> last_flank_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> span_;
  // Per mesh, the columns that turn gear B about its own axis through its centre (B's own
  // joint), found at the first state: prepare leaves them out of θ's rate.
  std::vector<std::vector<Eigen::Index>> spin_b_;

  // The columns in [lo, hi) that move gear B and not gear A as a turn about B's axis k_b through
  // its centre c_b (world): angular part parallel to k_b, no velocity at c_b (Pinocchio's world
  // Jacobian: v(p) = J_v + J_ω × p).
  static std::vector<Eigen::Index> spin_columns(const StepView& s, long slot_a, long slot_b,
                                                const Vec3& k_b, const Vec3& c_b, Eigen::Index lo,
                                                Eigen::Index hi) {
    std::vector<Eigen::Index> columns;
    for (Eigen::Index c = lo; c < hi; ++c) {
      if (s.meshes.support(slot_b, c) == 0.0 || s.meshes.support(slot_a, c) != 0.0) continue;
      const Vec3 jw = s.data.J.col(c).template tail<3>();
      const Vec3 at_centre = s.data.J.col(c).template head<3>() + jw.cross(c_b);
      const double turn = jw.norm();
      if (turn > 0.0 && jw.cross(k_b).norm() <= 1e-12 * turn &&
          at_centre.norm() <= 1e-12 * turn * (1.0 + c_b.norm())) {
        columns.push_back(c);
      }
    }
    return columns;
  }
  std::vector<Radial> radial_;
  Eigen::VectorXd end_state_, end_speed_;  // settle's dq₀ + κ_q a and v + κ_v a
  std::vector<FlankFriction> friction_;  // each flank's friction over the step (as CompliantMeshes)
  bool rubbing_ = false;
  double parametric_ = 0.0;
  bool first_ = true;
  bool started_ = false;
};

// The kind (element_kind.hpp): StepperSpec.compliant_meshes, each on a mesh of the model's list
// (its constants and path of contact in the KindContext), one element for all of them.
struct CompliantMeshesKind : KindBase {
  using Specs = std::vector<CompliantMeshSpec>;
  using Built = Elements;
  static constexpr const char* field = "compliant_meshes";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& spec : specs) {
      if (spec.mesh < 0 || spec.mesh >= c.meshes.count()) {
        throw std::invalid_argument("bad compliant mesh");
      }
      if (spec.slices < 1 || (spec.slices > 1 && (spec.slice_offset.size() != spec.slices ||
                                                  spec.slice_gap.size() != spec.slices ||
                                                  spec.slice_gap_back.size() != spec.slices))) {
        throw std::invalid_argument("compliant mesh slices: offsets and gaps need one per slice");
      }
      for (const auto* shift : {&spec.slice_shift, &spec.slice_shift_back}) {
        if (shift->size() != 0 && (spec.slices < 2 || shift->size() != spec.slices ||
                                   spec.slice_shift.size() != spec.slice_shift_back.size())) {
          throw std::invalid_argument("compliant mesh slices: shifts need one per slice");
        }
      }
      if (spec.slice_pair_position.size() != spec.slice_pair_stiffness.size() ||
          spec.slice_pair_position.size() == 1) {
        throw std::invalid_argument("compliant mesh slices: a pair table of >= 2 points");
      }
      if (!(spec.friction >= 0.0 && spec.friction < 1.0)) {
        throw std::invalid_argument("compliant mesh friction: μ in [0, 1)");
      }
      if (spec.friction_law == FrictionLaw::iso14179 &&
          !(spec.iso_face_width > 0.0 && spec.iso_reduced_radius > 0.0 &&
            spec.iso_sum_velocity_per_spin > 0.0 && spec.iso_viscosity > 0.0 &&
            spec.iso_roughness > 0.0 && spec.iso_lubricant_factor > 0.0)) {
        throw std::invalid_argument("compliant mesh friction iso14179: b, ρ, c_v, η, Ra, X_L > 0");
      }
      if (!(spec.contact_line_span >= 0.0)) {
        throw std::invalid_argument("compliant mesh friction: contact_line_span >= 0");
      }
    }
  }

  // The slice family's columns (series.hpp): the slices of each sliced mesh, in spec order.
  static void count(const Specs& specs, FamilyCounts& counts) {
    long slices = 0;
    for (const auto& spec : specs) slices += spec.slices > 1 ? static_cast<long>(spec.slices) : 0;
    counts[static_cast<size_t>(Family::slice)] = slices;
  }

  // Meshes of one slice make one CompliantMeshes element, sliced ones a SlicedMeshes element
  // (sliced_mesh.hpp): a mesh of one slice steps exactly as before slices existed.
  static void add(const Specs& specs, const KindContext& c, Elements& out) {
    Specs single, sliced;
    for (const auto& spec : specs) (spec.slices > 1 ? sliced : single).push_back(spec);
    if (!single.empty()) out.push_back(std::make_unique<CompliantMeshes>(single, c.paths, c.nv));
    if (!sliced.empty()) out.push_back(std::make_unique<SlicedMeshes>(sliced, c.paths, c.nv));
  }

  static void bind(nanobind::module_& m) {
    nanobind::enum_<FrictionLaw>(m, "FrictionLaw")
        .value("constant", FrictionLaw::constant)
        .value("iso14179", FrictionLaw::iso14179);
    m.def("iso14179_friction_coefficient", &iso14179_friction_coefficient, nanobind::arg("force"),
          nanobind::arg("face_width"), nanobind::arg("sum_velocity"),
          nanobind::arg("reduced_radius"), nanobind::arg("viscosity"), nanobind::arg("roughness"),
          nanobind::arg("lubricant_factor"),
          "ISO/TR 14179-2's μ_mz in SI (the step's restatement of "
          "pinwind.losses.mesh_friction.mean_friction_coefficient).");
    nanobind::class_<CompliantMeshSpec>(m, "CompliantMeshSpec")
        .def(nanobind::init<>())
        .def_rw("mesh", &CompliantMeshSpec::mesh)
        .def_rw("stiffness", &CompliantMeshSpec::stiffness)
        .def_rw("damping", &CompliantMeshSpec::damping)
        .def_rw("backlash", &CompliantMeshSpec::backlash)
        .def_rw("base_radius_a", &CompliantMeshSpec::base_radius_a)
        .def_rw("base_radius_b", &CompliantMeshSpec::base_radius_b)
        .def_rw("reference_b", &CompliantMeshSpec::reference_b)
        .def_rw("tangential_ref", &CompliantMeshSpec::tangential_ref)
        .def_rw("axial_ref", &CompliantMeshSpec::axial_ref)
        .def_rw("base_radius_sum", &CompliantMeshSpec::base_radius_sum)
        .def_rw("radial_sign", &CompliantMeshSpec::radial_sign)
        .def_rw("involute_ref", &CompliantMeshSpec::involute_ref)
        .def_rw("tangential_offset", &CompliantMeshSpec::tangential_offset)
        .def_rw("radial_offset", &CompliantMeshSpec::radial_offset)
        .def_rw("friction", &CompliantMeshSpec::friction)
        .def_rw("friction_law", &CompliantMeshSpec::friction_law)
        .def_rw("iso_face_width", &CompliantMeshSpec::iso_face_width)
        .def_rw("iso_reduced_radius", &CompliantMeshSpec::iso_reduced_radius)
        .def_rw("iso_sum_velocity_per_spin", &CompliantMeshSpec::iso_sum_velocity_per_spin)
        .def_rw("iso_viscosity", &CompliantMeshSpec::iso_viscosity)
        .def_rw("iso_roughness", &CompliantMeshSpec::iso_roughness)
        .def_rw("iso_lubricant_factor", &CompliantMeshSpec::iso_lubricant_factor)
        .def_rw("contact_line_span", &CompliantMeshSpec::contact_line_span)
        .def_rw("slices", &CompliantMeshSpec::slices)
        .def_rw("axis_b", &CompliantMeshSpec::axis_b)
        .def_rw("slice_offset", &CompliantMeshSpec::slice_offset)
        .def_rw("slice_gap", &CompliantMeshSpec::slice_gap)
        .def_rw("slice_gap_back", &CompliantMeshSpec::slice_gap_back)
        .def_rw("slice_shift", &CompliantMeshSpec::slice_shift)
        .def_rw("slice_shift_back", &CompliantMeshSpec::slice_shift_back)
        .def_rw("slice_path_length", &CompliantMeshSpec::slice_path_length)
        .def_rw("slice_pair_position", &CompliantMeshSpec::slice_pair_position)
        .def_rw("slice_pair_stiffness", &CompliantMeshSpec::slice_pair_stiffness)
        .def_rw("face_width", &CompliantMeshSpec::face_width);
  }
};

}  // namespace pinwind
