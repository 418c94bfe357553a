// Compliant gear meshes: a spring-damper along the line of action of each flank, with the
// deflection taken from the bodies' positions (001_2d0e0f624d8db633.txt eqs. 2-6,
// 003_83d3049daebcd276.txt eqs. 14-19; pinwind/dynamics/compliant.py documents the model):
//
//     F_n = k(x) δ + c δ̇   on the flank in contact, F_n ≥ 0 (teeth never pull).
//
// Deflection from positions. With ψ_A, ψ_B the gear angles about the axis relative to the
// centre line (mesh_path.hpp), the front flank's overlap along its line of action is
//
//     δ_f = wrap(T − T_ref + e_T) + R + e_R,      δ_b = −wrap(T − T_ref + e_T) + R + e_R − j
//     T   = r_A ψ_A − r_B ψ_B                       (signed base radii, rolling part)
//     R   = κ (r_b,B ± r_b,A) (inv α'(a) − inv α'(a_ref)),  cos α'(a) = (r_b,B ± r_b,A)/a
//
// (κ = −1 external, +1 internal: moving an internal pair's centres apart pushes the teeth
// together), e_T, e_R the position errors of the gears along the line of action, j the
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
#include <vector>

#include "elements.hpp"
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
  double tangential_ref = 0.0;    // T at the reference pose [m]
  double base_radius_sum = 0.0;   // r_b,B ± r_b,A = a cos α' [m]
  double radial_sign = -1.0;      // κ
  double involute_ref = 0.0;      // inv α' at the reference centre distance
  double tangential_offset = 0.0; // e_T [m]
  double radial_offset = 0.0;     // e_R [m]
};

// inv α = tan α − α of the angle α whose cosine is c (0 < c ≤ 1), with tan α = √(1 − c²) / c:
// the same value as tan(acos c) to rounding, at a fifth of its cost (floating centres evaluate it
// every step).
inline double involute_of_cosine(double c) {
  return std::sqrt((1.0 - c) * (1.0 + c)) / c - std::acos(c);
}

class CompliantMeshes : public Element {
 public:
  CompliantMeshes(std::vector<CompliantMeshSpec> specs, const std::vector<MeshPathSpec>& paths,
                  Eigen::Index nv)
      : specs_(std::move(specs)) {
    const size_t n = specs_.size();
    for (const auto& s : specs_) paths_.push_back(paths[static_cast<size_t>(s.mesh)]);
    state_.assign(n, 0);
    last_flank_.assign(n, 1.0);
    delta_.setZero(n, 2);
    row_.resize(2 * n);
    for (auto& r : row_) r.setZero(nv);
    path_.resize(2 * n);
    b_.setZero(n);
    w_.setZero(n);
    normal_.setZero(n);
    elastic_.setZero(n);
    viscous_.setZero(n);
    last_k_.setZero(n, 2);
    radial_distance_.setConstant(n, -1.0);
    radial_.setZero(n);
  }

  void prepare(const StepView& s) override {
    const auto& mc = s.meshes;
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const Eigen::Index m = sp.mesh;
      const Vec3 k = s.rows.axis.row(m).transpose();
      const Vec3 u = mc.sigma[m] * s.rows.radial.row(m).transpose();
      const auto& rot_a = s.data.oMi[mc.joint_a[m]].rotation();
      const auto& rot_b = s.data.oMi[mc.joint_b[m]].rotation();
      const double psi_a = angle_about(k, u, rot_a * paths_[i].reference_a);
      const double psi_b = angle_about(k, u, rot_b * sp.reference_b);
      const double pitch = paths_[i].base_pitch;
      // Rolling part, wrapped into one base pitch centred on the middle of the backlash gap.
      double rolling = sp.base_radius_a * psi_a - sp.base_radius_b * psi_b - sp.tangential_ref +
                       sp.tangential_offset;
      rolling -= pitch * std::round((rolling + 0.5 * sp.backlash) / pitch);
      const double distance = (s.rows.centre_b.row(m) - s.rows.centre_a.row(m)).norm();
      const double along_axis = (s.rows.centre_b.row(m) - s.rows.centre_a.row(m)).dot(k);
      const double centre_distance = std::sqrt(std::max(0.0, distance * distance -
                                                                  along_axis * along_axis));
      const double radial = radial_overlap(i, centre_distance);
      delta_(i, 0) = rolling + radial;
      delta_(i, 1) = -rolling + radial - sp.backlash;
      double unused;
      flank_row(mc, s.rows, m, 1.0, row_[2 * i], unused);
      flank_row(mc, s.rows, m, -1.0, row_[2 * i + 1], unused);
      path_[2 * i] = path_state(paths_[i], psi_a, 1.0);
      path_[2 * i + 1] = path_state(paths_[i], psi_a, -1.0);
      if (state_[i] == 0 && first_) {
        // Start in contact on a flank that overlaps; a mesh at rest with zero deflection
        // starts on the front flank carrying no force. A static solve starts on the flank
        // nearer to contact and closes the gap if the loads ask for it.
        state_[i] = delta_(i, 0) >= 0.0 ? 1 : (delta_(i, 1) >= 0.0 ? -1 : 0);
        if (state_[i] == 0 && s.weights.statics) state_[i] = delta_(i, 0) >= delta_(i, 1) ? 1 : -1;
      }
      // The work the stiffness's change puts in since the last sample, ½ (k_n − k_{n−1}) δ_n²
      // on each overlapping flank (δ_n at the new sample): the parametric excitation, which
      // the energy ledger keeps apart from the integrator's loss. Repeated calls at one state
      // add nothing.
      for (int f = 0; f < 2; ++f) {
        const double k = stiffness(i, f), d = std::max(0.0, delta_(i, f));
        if (!first_ && !s.weights.statics) parametric_ += 0.5 * (k - last_k_(i, f)) * d * d;
        if (!s.weights.statics) last_k_(i, f) = k;
      }
      coefficients(s, i);
    }
    if (!s.weights.statics) first_ = false;
  }

  void add_implicit(const StepView&, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      if (state_[i] == 0) continue;
      const auto& row = row_[2 * i + (state_[i] > 0 ? 0 : 1)];
      // w rowᵀ row entry by entry, over the span of the row's non-zero entries (the joints of
      // the two gears' chains) and in the lower triangle only (Element::add_implicit): Eigen's
      // outer-product path allocates a temporary per call, which at nv of 6 to 20 costs more
      // than the products.
      Eigen::Index lo = 0, hi = row.size();
      while (lo < hi && row[lo] == 0.0) ++lo;
      while (hi > lo && row[hi - 1] == 0.0) --hi;
      for (Eigen::Index c = lo; c < hi; ++c) {
        const double wc = w_[i] * row[c];
        if (wc == 0.0) continue;
        double* column = hessian.col(c).data();
        for (Eigen::Index r = c; r < hi; ++r) column[r] += row[r] * wc;
      }
      force.noalias() += b_[i] * row.transpose();
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool last) override {
    bool changed = false;
    if (s.weights.statics) {
      // A static solve (a = Δq): a flank that would pull hands the load to the other one.
      for (size_t i = 0; i < specs_.size(); ++i) {
        const int f = state_[i] > 0 ? 0 : 1;
        if (b_[i] - w_[i] * row_[2 * i + f].dot(a) < 0.0 && !last) {
          state_[i] = -state_[i];
          coefficients(s, i);
          changed = true;
        }
      }
      return changed;
    }
    for (size_t i = 0; i < specs_.size(); ++i) {
      if (state_[i] != 0) {
        const int f = state_[i] > 0 ? 0 : 1;
        const double force = b_[i] - w_[i] * row_[2 * i + f].dot(a);
        if (force < 0.0 && !last) {
          state_[i] = 0;
          changed = true;
        }
      } else if (!last) {
        // A free mesh closes when the force it would carry at the end of the step pushes.
        for (int f = 0; f < 2; ++f) {
          const double flank = f == 0 ? 1.0 : -1.0;
          const auto& row = row_[2 * i + f];
          const double k = stiffness(i, f);
          const double trial = k * (delta_(i, f) - row.dot(s.dq_free + s.weights.position_gain * a)) -
                               specs_[i].damping * row.dot(s.v + s.weights.speed_gain * a);
          if (trial > 0.0) {
            // b and w of a mesh in contact already hold for this state (prepare).
            state_[i] = static_cast<int>(flank);
            coefficients(s, i);
            changed = true;
            break;
          }
        }
      }
    }
    if (changed) return true;
    // Final forces of the step.
    for (size_t i = 0; i < specs_.size(); ++i) {
      if (state_[i] == 0) {
        normal_[i] = elastic_[i] = viscous_[i] = 0.0;
        continue;
      }
      const int f = state_[i] > 0 ? 0 : 1;
      last_flank_[i] = state_[i];
      const double k = stiffness(i, f);
      const auto& row = row_[2 * i + f];
      elastic_[i] = k * (delta_(i, f) - row.dot(s.dq_free + s.weights.position_gain * a));
      viscous_[i] = -specs_[i].damping * row.dot(s.v + s.weights.speed_gain * a);
      normal_[i] = std::max(0.0, elastic_[i] + viscous_[i]);
    }
    return false;
  }

  void add_body_forces(const StepView& s, BodyForces& out) const override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      if (normal_[i] == 0.0) continue;
      const Eigen::Index m = specs_[i].mesh;
      const Vec3 f = tooth_force_on_b(s.meshes, s.rows, m, last_flank_[i], normal_[i]);
      const Vec3 p = s.rows.pitch_point.row(m).transpose();
      out.add(s.meshes.joint_b[m], p, f);
      out.add(s.meshes.joint_a[m], p, -f);
    }
  }

  double parametric_work() const override { return parametric_; }

  double potential(const StepView&) const override {
    double energy = 0.0;
    for (size_t i = 0; i < specs_.size(); ++i) {
      for (int f = 0; f < 2; ++f) {
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
      if (state_[i] == 0 || normal_[i] == 0.0) continue;
      const double jv = row_[2 * i + (state_[i] > 0 ? 0 : 1)].dot(v_mid) * s.dt;
      // The generalised force Jᵀ F_n does work F_n J v_mid h (F_n > 0: not clipped).
      w.elastic += elastic_[i] * jv;
      w.dissipated -= viscous_[i] * jv;
    }
    return w;
  }

  void record(const StepView& s, long k, const Outputs& out) const override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const long m = specs_[i].mesh;
      record_mesh_force(out, s.meshes, s.rows, k, m, normal_[i], last_flank_[i]);
      const long e = out.entry(Family::mesh, k, m);
      const int f = state_[i] != 0 ? (state_[i] > 0 ? 0 : 1) : (last_flank_[i] > 0 ? 0 : 1);
      const PathState& p = path_[2 * i + f];
      out.at(Series::mesh_deflection, e) =
          state_[i] != 0 ? delta_(i, f) : std::max(delta_(i, 0), delta_(i, 1));
      out.at(Series::transmission_error, e) = delta_(i, 0);
      out.at(Series::mesh_contact_position, e) = paths_[i].roll_start + p.entering;
      out.at(Series::mesh_pairs, e) = p.pairs;
      out.at(Series::mesh_single_tooth_force, e) = normal_[i] * p.share;
    }
  }

 private:
  double stiffness(size_t i, int f) const {
    return paths_[i].pair_position.size() ? path_[2 * i + f].stiffness : specs_[i].stiffness;
  }

  // R + e_R of mesh i at centre distance a [m]: the overlap of moving the centres from the
  // reference, κ (r_b,B ± r_b,A) (inv α'(a) − inv α'(a_ref)) + e_R. Kept while a stays within
  // 1e-14 relative of the distance it was computed at: gears on fixed or carrier-borne axes
  // keep their centre distance to rounding, and the acos and square root then cost a quarter of the
  // mesh's geometry; the value kept is off by r_b tan α' · 1e-14 (< 1e-14 m), far below any
  // deflection.
  double radial_overlap(size_t i, double centre_distance) {
    if (std::abs(centre_distance - radial_distance_[i]) <= 1e-14 * centre_distance) {
      return radial_[i];
    }
    const auto& sp = specs_[i];
    const double cos_w = std::min(1.0, sp.base_radius_sum / centre_distance);
    radial_distance_[i] = centre_distance;
    radial_[i] =
        sp.radial_sign * sp.base_radius_sum * (involute_of_cosine(cos_w) - sp.involute_ref) +
        sp.radial_offset;
    return radial_[i];
  }

  void coefficients(const StepView& s, size_t i) {
    if (state_[i] == 0) return;
    const int f = state_[i] > 0 ? 0 : 1;
    const double k = stiffness(i, f), c = specs_[i].damping;
    const auto& row = row_[2 * i + f];
    b_[i] = k * (delta_(i, f) - row.dot(s.dq_free)) - c * row.dot(s.v);
    w_[i] = k * s.weights.position_gain + c * s.weights.speed_gain;
  }

  std::vector<CompliantMeshSpec> specs_;
  std::vector<MeshPathSpec> paths_;
  std::vector<int> state_;           // +1 front flank, −1 back flank, 0 no contact
  std::vector<double> last_flank_;   // the flank last in contact
  Eigen::Matrix<double, Eigen::Dynamic, 2> delta_;  // overlaps δ_f, δ_b [m]
  std::vector<Eigen::RowVectorXd> row_;             // J of each flank
  std::vector<PathState> path_;
  Eigen::VectorXd b_, w_, normal_, elastic_, viscous_;
  Eigen::Matrix<double, Eigen::Dynamic, 2> last_k_;  // each flank's stiffness at the last sample
  Eigen::VectorXd radial_distance_, radial_;  // radial_overlap's centre distance [m] and value [m]
  double parametric_ = 0.0;  // work of the stiffness's changes since t = 0 [J]
  bool first_ = true;
};

}  // namespace pinwind
