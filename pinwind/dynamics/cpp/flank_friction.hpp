// Coulomb friction on the tooth flanks of a compliant mesh (issue 41 item 1): each tooth pair in
// contact takes a friction force μ F_j across the line of action, opposite to its sliding
// velocity, so that it reverses at the pitch point (ISO/TR 14179-2:2001 §5 takes the mesh loss
// from the same picture, Ohlendorf 1958's tooth-loss factor H_V).
//
// Frame: the mesh's transverse plane, in world axes. On flank f (line of action n, mesh_rows.hpp)
// the pairs in contact sit along the path of contact at x_j = x_0 + j p_b from its start A
// (mesh_path.hpp); the pitch point P at x_P. Pair j touches at
//
//     X_j = P + d_j m,    d_j = x_j − x_P,    m = ±n the direction in which x grows,
//
// m = n sgn(s_f r_b,A (k × (P − C_A))·n): the contact moves along the line as gear A turns,
// at r_b,A per radian (an involute turned by dψ moves along its normal by r_b dψ), x_f by
// +r_b,A dψ_A on the front flank and −r_b,A dψ_A on the back one (path_state). The flanks
// slide along e = k × n; B's flank slides on A's at
//
//     v_s,j = e·(v_B(X_j) − v_A(X_j)) = J_e,j v,   J_e,j = J_e(P) + d_j σ_m J_k,
//
// J_e(P) = −s cos α J_r + ε sin α J_t the row of e at P (from the mesh rows' t and r̂ parts),
// J_k = k·(J_ω,B − J_ω,A) the relative spin, σ_m = m·n = ±1 (X × e = P × e + d σ_m k). With
// the axes fixed, P is the instantaneous centre of the relative motion, so
//
//     v_s,j = σ_m d_j (ω_B − ω_A)·k:
//         external pair (ω's of opposite sense): |v_s,j| = (|ω₁| + |ω₂|) |d_j|,
//         internal pair (the same sense):         |v_s,j| = |ω₁ − ω₂| |d_j|,
//
// zero at the pitch point and growing with the distance from it (Niemann & Winter 1983 §21.2).
//
// Force: on B −μ F_j σ_j e at X_j, on A the opposite, σ_j = sgn(d_j σ_m ω_rel) with ω_rel =
// J_k v: the sign of v_s,j in rigid rolling, taken from the contact position rather than from
// v_s,j itself, so that it flips exactly where the pair crosses the pitch point and the
// vibration of a floating or compliantly borne gear about it (whose centre's velocity enters
// v_s,j) does not make it chatter; below a relative spin of kStandstill (a train at rest or
// in a static solve) there is no sliding and no friction. Its generalised force is
//
//     f = −μ F Σ_j s_j σ_j J_e,jᵀ = −μ F (S₀ J_e(P) + σ_m S₁ J_k)ᵀ,
//     S₀ = Σ s_j σ_j,   S₁ = Σ s_j σ_j d_j,
//
// F_j = s_j F the pair's share of the flank's force (mesh_path.hpp pair_shares): two numbers a
// flank whatever its pair count. Its moment about gear i's axis is μ F_j ρ_i,j, ρ_i,j the
// distance from i's base-circle tangency point to X_j (the flank's radius of curvature), and its
// force on each centre changes the bearing reactions (add_body_forces).
//
// Timing: the force is explicit over the step, F the flank's force predicted at this step's
// state with the last step's J ā, F = b − w (J ā)_{n−1} (compliant_mesh.hpp: the force over the
// step is b − w J ā, so this carries the stiffness and deflection of the step and lags only
// the acceleration's change), and the sign and pairs those of the step's start. The ledger
// books exactly the work of the force applied, μ F g·v_mid h (friction_loss), so that
// W_in − W_out = Σ losses holds with the numerical loss apart; it is ≥ 0 but where a pair
// crosses the pitch point within the step.
#pragma once

#include <cmath>
#include <vector>

#include "elements.hpp"
#include "mesh_path.hpp"

namespace pinwind {

// Relative spin below which the flanks do not slide [rad/s]: a train at rest.
inline constexpr double kStandstill = 1e-9;

// What the friction of one flank of a mesh applies over a step.
struct FlankFriction {
  double force = 0.0;        // μ F, F the flank's predicted normal force [N]
  double sum0 = 0.0;         // S₀ = Σ s_j σ_j
  double sum1 = 0.0;         // S₁ = Σ s_j σ_j d_j [m]
  Eigen::RowVectorXd row;    // g = S₀ J_e(P) + σ_m S₁ J_k: the generalised force is −μ F gᵀ
  Vec3 along = Vec3::Zero(); // m: the direction of growing x [unit, world]
  Vec3 slide = Vec3::Zero(); // e = k × n [unit, world]
  double centre_offset = 0.0;  // z_c: where across the face it acts, along k [m] (sliced meshes)
  std::vector<double> offset, share, sign;  // d_j [m], s_j, σ_j of the pairs in contact
};

// J_k v = (ω_B − ω_A)·k over the velocities that move one gear and not the other [rad/s].
template <class Jac>
double relative_spin(const MeshConstants& mc, const MeshRows& rows, const Jac& jac,
                     Index m, const Eigen::VectorXd& v, Index lo, Index hi) {
  const Vec3 k = rows.axis.row(m).transpose();
  const double* on_b = mc.support.row(mc.slot_b[m]).data();
  const double* on_a = mc.support.row(mc.slot_a[m]).data();
  double spin = 0.0;
  for (Index c = lo; c < hi; ++c) {
    const double w = on_b[c] - on_a[c];
    if (w == 0.0) continue;
    const double* ang = jac.data() + 6 * c + 3;  // the column's angular part (column-major 6 × nv)
    spin += w * v[c] * (k[0] * ang[0] + k[1] * ang[1] + k[2] * ang[2]);
  }
  return spin;
}

// m of flank s: the world direction in which the path coordinate x grows (header).
inline Vec3 path_direction(const MeshConstants& mc, const MeshRows& rows, const MeshPathSpec& p,
                           Index m, double flank, double cos_w, double sin_w) {
  const Vec3 n = line_of_action(mc, rows, m, flank, cos_w, sin_w);
  const Vec3 k = rows.axis.row(m).transpose();
  const Vec3 from_a = rows.pitch_point.row(m) - rows.centre_a.row(m);
  return flank * p.roll_radius_a * k.cross(from_a).dot(n) >= 0.0 ? n : Vec3(-n);
}

// Fills fr for flank s of mesh m at the state (s.v, s.data.J) with the flank's predicted force
// F [N] and friction coefficient μ: pairs, shares, signs, S₀, S₁ and the row g over the span
// [lo, hi) of the columns that move one gear and not the other.
template <class Jac>
void flank_friction(const MeshConstants& mc, const MeshRows& rows, const MeshPathSpec& p,
                           const PathState& st, const Jac& jac,
                           const Eigen::VectorXd& v, Index m, double flank, double cos_w,
                           double sin_w, double mu, double normal, double delta, Index lo,
                           Index hi, FlankFriction& fr) {
  fr.force = 0.0;
  fr.sum0 = fr.sum1 = fr.centre_offset = 0.0;
  if (normal <= 0.0 || mu == 0.0) return;
  // J_k over the span, kept in fr.row (zero outside it: those columns move neither gear or
  // both), and the relative spin J_k v.
  if (fr.row.size() != jac.cols()) fr.row.setZero(jac.cols());
  const Vec3 k = rows.axis.row(m).transpose();
  const double* on_b = mc.support.row(mc.slot_b[m]).data();
  const double* on_a = mc.support.row(mc.slot_a[m]).data();
  double* row = fr.row.data();
  double spin = 0.0;
  for (Index c = lo; c < hi; ++c) {
    const double w = on_b[c] - on_a[c];
    const double* ang = jac.data() + 6 * c + 3;  // the column's angular part (column-major 6 × nv)
    row[c] = w == 0.0 ? 0.0 : w * (k[0] * ang[0] + k[1] * ang[1] + k[2] * ang[2]);
    spin += row[c] * v[c];
  }
  if (std::abs(spin) <= kStandstill) return;
  const Vec3 n = line_of_action(mc, rows, m, flank, cos_w, sin_w);
  const Vec3 from_a = rows.pitch_point.row(m) - rows.centre_a.row(m);
  const double sigma_m = flank * p.roll_radius_a * k.cross(from_a).dot(n) >= 0.0 ? 1.0 : -1.0;
  fr.along = sigma_m * n;  // path_direction's
  fr.slide = k.cross(n);
  pair_shares(p, st, delta, fr.share);
  const auto pairs = static_cast<size_t>(st.pairs);
  fr.offset.resize(pairs);
  fr.sign.resize(pairs);
  const double turning = sigma_m * spin;
  for (size_t j = 0; j < pairs; ++j) {
    const double d = st.entering + double(j) * p.base_pitch - p.pitch_position;
    const double sign = d * turning > 0.0 ? 1.0 : (d * turning < 0.0 ? -1.0 : 0.0);
    fr.offset[j] = d;
    fr.sign[j] = sign;
    fr.sum0 += fr.share[j] * sign;
    fr.sum1 += fr.share[j] * sign * d;
  }
  fr.force = mu * normal;
  // g = S₀ J_e(P) + σ_m S₁ J_k, J_e(P) = −s cos α J_r + ε sin α J_t (header).
  const double ct = fr.sum0 * sin_w * mc.eps[m], cr = -fr.sum0 * flank * cos_w;
  const double spin_weight = sigma_m * fr.sum1;
  const double* t = rows.jac_t.row(m).data();
  const double* r = rows.jac_r.row(m).data();
  for (Index c = lo; c < hi; ++c) row[c] = ct * t[c] + cr * r[c] + spin_weight * row[c];
}

// v_s of the entering pair (x_0) of flank s: J_e(P) v + d_0 σ_m J_k v [m/s] (header).
template <class Jac>
double entering_sliding_velocity(const MeshConstants& mc, const MeshRows& rows,
                                        const MeshPathSpec& p, const PathState& st,
                                        const Jac& jac, const Eigen::VectorXd& v,
                                        Index m, double flank, double cos_w, double sin_w,
                                        Index lo, Index hi) {
  const double cr = -flank * cos_w, ct = sin_w * mc.eps[m];
  const double at_pitch = ct * rows.jac_t.row(m).dot(v) + cr * rows.jac_r.row(m).dot(v);
  const double sigma_m = path_direction(mc, rows, p, m, flank, cos_w, sin_w)
                             .dot(line_of_action(mc, rows, m, flank, cos_w, sin_w));
  const double d = st.entering - p.pitch_position;
  return at_pitch + d * sigma_m * relative_spin(mc, rows, jac, m, v, lo, hi);
}

// The friction of flank fr of mesh m on the bodies: −μ F_j σ_j e on B at each pair's contact
// point X_j = P + d_j m + z_c k, its opposite on A (for the bearing reactions). The pairs'
// forces are parallel: on B, force f e and moment Y × e about the world origin, f = Σ f_j and
// Y = Σ f_j X_j (f_j = −μ F s_j σ_j), whether or not they cancel.
inline void add_friction_forces(const StepView& s, Index m, const FlankFriction& fr,
                                BodyForces& out) {
  if (fr.force == 0.0) return;
  const Vec3 p = s.rows.pitch_point.row(m).transpose();
  const Vec3 k = s.rows.axis.row(m).transpose();
  double f = 0.0, fd = 0.0;
  for (size_t j = 0; j < fr.offset.size(); ++j) {
    const double fj = -fr.force * fr.share[j] * fr.sign[j];
    f += fj;
    fd += fj * fr.offset[j];
  }
  const Vec3 force = f * fr.slide;
  const Vec3 moment = (f * (p + fr.centre_offset * k) + fd * fr.along).cross(fr.slide);
  auto& on_b = out.of_joint[s.meshes.joint_b[m]];
  auto& on_a = out.of_joint[s.meshes.joint_a[m]];
  on_b.linear() += force;
  on_b.angular() += moment;
  on_a.linear() -= force;
  on_a.angular() -= moment;
}

// Writes mesh m's friction series of sample k: the entering pair's sliding speed on the loaded
// flank (±1) from the bodies' velocities, the loaded flank's friction on A along e (μ F S₀) and
// both flanks' loss μ F g·v [W].
inline void record_friction(const StepView& s, const Outputs& out, long k, Index m,
                            const MeshPathSpec& p, const PathState& loaded_path, double flank,
                            double cos_w, double sin_w, Index lo, Index hi,
                            const FlankFriction& front, const FlankFriction& back) {
  const long e = out.entry(Family::mesh, k, m);
  out.at(Series::mesh_sliding_velocity, e) = entering_sliding_velocity(
      s.meshes, s.rows, p, loaded_path, s.data.J, s.v, m, flank, cos_w, sin_w, lo, hi);
  const FlankFriction& loaded = flank > 0.0 ? front : back;
  out.at(Series::mesh_friction_force, e) = loaded.force * loaded.sum0;
  double power = 0.0;
  for (const FlankFriction* fr : {&front, &back}) {
    if (fr->force != 0.0) power += fr->force * fr->row.dot(s.v);
  }
  out.at(Series::mesh_friction_power, e) = power;
}

}  // namespace pinwind
