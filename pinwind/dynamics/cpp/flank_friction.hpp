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
// W_in − W_out = Σ losses holds with the numerical loss apart. It is ≥ 0 but where a pair
// crosses the pitch point within the step, or where the gears' vibration reverses a pair's
// actual sliding near the pitch point while the force keeps its rigid-rolling sign (on the
// NREL 5 MW model's sun meshes at rated, down to −1.1 % of the mesh's mean loss for a moment).
//
// Helical pairs (issue 41 item 1). A helical pair touches along a straight line in the plane of
// action, inclined at β_b: the section ζ from side I (the front face section) touches at
// y(ζ) = x − ζ tan β_b along the transverse path, x the pair's front-section position (its path
// coordinate on a single contact line, mesh_path.hpp and pinwind/dynamics/compliant.py
// overlap_span), so the line covers [x − Δ, x] ∩ [0, g_α] of the path, Δ = b tan β_b = ε_β p_bt
// (the ContactLine). Each point slides at σ_m u J_k v, u = y − y_P its distance from the pitch
// point, and the mesh's stiffness per unit length of contact line is uniform (ISO 6336-1's, the
// contact-line law), so the pair's share s_j of the flank's force is spread evenly over its
// clipped line [u₀, u₁]. Integrated along the line, the pair's friction is that of a point pair
// with its sign and its signed offset averaged over the line:
//
//     A_j = (1/L) ∫ σ(u) du = sgn(t) (|u₁| − |u₀|) / L,
//     B_j = (1/L) ∫ σ(u) u du = sgn(t) (u₁|u₁| − u₀|u₀|) / (2L),     L = u₁ − u₀,
//
// σ(u) = sgn(u t), t = σ_m J_k v; S₀ = Σ s_j A_j, S₁ = Σ s_j B_j (a point pair, Δ = 0: A_j = σ_j,
// B_j = σ_j d_j, the spur law above). Taking the pair at one point of its line instead (its
// mid-face point, the single line's d_j) put its friction up to Δ/2 beyond the path's ends.
// Sliced helical meshes take each slice's pairs as points at the slice's section (the midpoint
// rule across the face of the same integral), each slice its force F_s at its z_s.
//
// Normal force. The tooth force of a helical pair is normal to the flanks, F_n = F_bt / cos β_b
// (mesh_rows.hpp tooth_force_on_b: F_bt along n and F_bt tan β_b along the axis); the flanks
// slide along e, in the transverse plane and tangent to both flanks, so the friction is
// μ F_bt / cos β_b = μ F_bt √(1 + tan² β_b) (ISO/TR 14179-2's H_V has the same 1/cos β_b).
//
// μ at the operating point (issue 41 item 2): FrictionLaw::iso14179 takes μ = μ_mz of
// ISO/TR 14179-2 (iso14179_friction_coefficient, pinwind/losses/mesh_friction.py
// mean_friction_coefficient restated) at the flank's predicted force F_bt, the sum velocity at
// the pitch point v_Σc = c_v |J_k v| (c_v = 2 sin α_w r_w,A r_w,B / |r_w,A + r_w,B|, signed radii)
// and the mesh's constant ρ_redC, η, Ra, X_L and b; μ F_bt ∝ F_bt^1.2 → 0 as the load goes,
// and μ is held at or below kMaxFlankFriction where v_Σc → 0 (the fit grows without bound there).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "elements.hpp"
#include "mesh_path.hpp"

namespace pinwind {

// Relative spin below which the flanks do not slide [rad/s]: a train at rest.
inline constexpr double kStandstill = 1e-9;

// The largest μ FrictionLaw::iso14179 gives [-]: boundary friction of steel on steel (Niemann &
// Winter 1983 §21.2: 0.1 to 0.2), where ISO/TR 14179-2's fit grows without bound as v_Σc → 0.
inline constexpr double kMaxFlankFriction = 0.2;

// How a compliant mesh's μ is found: a constant, or ISO/TR 14179-2's μ_mz at the operating point.
enum class FrictionLaw { constant = 0, iso14179 = 1 };

// μ_mz of ISO/TR 14179-2:2001 (Schlenk 1994, Michaelis), every argument SI:
//     μ_mz = 0.048 (F_bt/b / (v_Σc ρ_redC))^0.2 η^(−0.05) Ra^0.25 X_L
// in the standard's units (N/mm, m/s, mm, mPa·s, µm). force F_bt [N] ≥ 0, face_width b [m],
// sum_velocity v_Σc [m/s] > 0, reduced_radius ρ_redC [m], viscosity η [Pa·s], roughness Ra [m],
// lubricant_factor X_L [-]. The restatement of pinwind/losses/mesh_friction.py's
// mean_friction_coefficient (a test checks the two agree).
inline double iso14179_friction_coefficient(double force, double face_width, double sum_velocity,
                                            double reduced_radius, double viscosity,
                                            double roughness, double lubricant_factor) {
  const double line_load = force / (face_width * 1e3);  // N/mm
  const double group = line_load / (sum_velocity * reduced_radius * 1e3);
  return 0.048 * std::pow(group, 0.2) * std::pow(viscosity * 1e3, -0.05) *
         std::pow(roughness * 1e6, 0.25) * lubricant_factor;
}

// Where a flank's pairs touch along its path (header): a pair at x touches over
// [x − span, x] ∩ [0, length] (span 0: at x alone), the pitch point at pitch from the path's start.
struct ContactLine {
  double span = 0.0;    // Δ = b tan β_b of a single helical contact line, 0 for a point [m]
  double length = 0.0;  // g_α, the transverse path [m]
  double pitch = 0.0;   // y_P [m]
};

// The contact line of a mesh's single-line path p whose helical span is span [m].
inline ContactLine single_line(const MeshPathSpec& p, double span) {
  return {span, p.path_length - span, p.pitch_position - 0.5 * span};
}

// What the friction of one flank of a mesh applies over a step.
struct FlankFriction {
  double force = 0.0;        // μ F_n, F_n = F_bt / cos β_b the flanks' normal force [N]
  double spin = 0.0;         // J_k v [rad/s]
  double turning = 0.0;      // t = σ_m J_k v [rad/s]
  double sigma_m = 1.0;      // σ_m = m·n
  double sum0 = 0.0;         // S₀ = Σ s_j A_j
  double sum1 = 0.0;         // S₁ = Σ s_j B_j [m]
  double sum_face = 0.0;     // S_z = Σ s_j A_j z_j [m]
  Eigen::RowVectorXd row;    // g = S₀ J_e(P) + σ_m S₁ J_k − S_z a_n: the generalised force is −μ F gᵀ
  Vec3 along = Vec3::Zero(); // m: the direction of growing x [unit, world]
  Vec3 slide = Vec3::Zero(); // e = k × n [unit, world]
  // Each pair in contact (of each slice): its share s_j of the flank's force, A_j, B_j [m] and
  // its place across the face z_j [m, from the face centre along k].
  std::vector<double> share, mean_sign, moment, face;
  std::vector<double> pair_share;  // scratch: pair_shares' output
};

// J_k v = (ω_B − ω_A)·k over the velocities that move one gear and not the other [rad/s]. lo, hi:
// the span of those columns (the mesh's rows'), which holds every column of rows.turning.
template <class Jac>
double relative_spin(const MeshConstants& mc, const MeshRows& rows, const Jac& jac,
                     Index m, const Eigen::VectorXd& v, Index lo, Index hi) {
  const Vec3 k = rows.axis.row(m).transpose();
  double spin = 0.0;
  if (static_cast<Index>(rows.turning.size()) == mc.count()) {
    // The mesh's columns with w ≠ 0 in the same order less the pure translations (a compliant
    // bearing's slides), whose ω = 0 would add zeros (evaluate_mesh_geometry's list).
    for (const auto& [c, w] : rows.turning[static_cast<size_t>(m)]) {
      const double* ang = jac.data() + 6 * c + 3;  // the column's angular part (6 × nv)
      spin += w * v[c] * (k[0] * ang[0] + k[1] * ang[1] + k[2] * ang[2]);
    }
    return spin;
  }
  const double* on_b = mc.support.row(mc.slot_b[m]).data();
  const double* on_a = mc.support.row(mc.slot_a[m]).data();
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

// Starts flank s of mesh m at the state (v, jac): J_k over the span [lo, hi) of the columns that
// move one gear and not the other (kept in fr.row), the spin, σ_m, m and e; no pairs yet.
// False at a standstill (|J_k v| ≤ kStandstill): no sliding, no friction.
template <class Jac>
bool friction_begin(const MeshConstants& mc, const MeshRows& rows, const MeshPathSpec& p,
                    const Jac& jac, const Eigen::VectorXd& v, Index m, double flank,
                    double cos_w, double sin_w, Index lo, Index hi, FlankFriction& fr) {
  fr.force = fr.sum0 = fr.sum1 = fr.sum_face = 0.0;
  fr.share.clear();
  fr.mean_sign.clear();
  fr.moment.clear();
  fr.face.clear();
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
  fr.spin = spin;
  if (std::abs(spin) <= kStandstill) return false;
  const Vec3 n = line_of_action(mc, rows, m, flank, cos_w, sin_w);
  const Vec3 from_a = rows.pitch_point.row(m) - rows.centre_a.row(m);
  fr.sigma_m = flank * p.roll_radius_a * k.cross(from_a).dot(n) >= 0.0 ? 1.0 : -1.0;
  fr.along = fr.sigma_m * n;  // path_direction's
  fr.slide = k.cross(n);
  fr.turning = fr.sigma_m * spin;
  return true;
}

// Adds the pairs of path state st (overlap δ) to flank friction fr, the whole carrying the
// fraction weight of the flank's force at z across the face: each pair's share from
// pair_shares, its A_j and B_j over its line on line (header).
inline void add_contact_pairs(const MeshPathSpec& p, const PathState& st, double delta,
                              const ContactLine& line, double weight, double z,
                              FlankFriction& fr) {
  pair_shares(p, st, delta, fr.pair_share);
  const double direction = fr.turning > 0.0 ? 1.0 : -1.0;
  for (int j = 0; j < st.pairs; ++j) {
    const double x = st.entering + double(j) * p.base_pitch;
    double u0 = x - line.span, u1 = x;
    if (line.span > 0.0) {
      u0 = std::max(u0, 0.0);
      u1 = std::min(u1, line.length);
    }
    u0 -= line.pitch;
    u1 -= line.pitch;
    const double length = u1 - u0;
    double mean_sign, moment;
    if (length > 1e-12 * p.base_pitch) {
      mean_sign = direction * (std::abs(u1) - std::abs(u0)) / length;
      moment = direction * (u1 * std::abs(u1) - u0 * std::abs(u0)) / (2.0 * length);
    } else {  // a point (spur, or a helical pair at the very end of its line)
      const double d = 0.5 * (u0 + u1);
      mean_sign = d * fr.turning > 0.0 ? 1.0 : (d * fr.turning < 0.0 ? -1.0 : 0.0);
      moment = mean_sign * d;
    }
    const double share = weight * fr.pair_share[static_cast<size_t>(j)];
    fr.share.push_back(share);
    fr.mean_sign.push_back(mean_sign);
    fr.moment.push_back(moment);
    fr.face.push_back(z);
    fr.sum0 += share * mean_sign;
    fr.sum1 += share * moment;
    fr.sum_face += share * mean_sign * z;
  }
}

// Ends flank s of mesh m with the friction coefficient μ and the flank's transverse force F_bt
// [N]: fr.force = μ F_bt √(1 + tan² β_b) and the row g = S₀ J_e(P) + σ_m S₁ J_k − S_z a_n,
// J_e(P) = −s cos α J_r + ε sin α J_t (header), a_n = nᵀ(J_ω,B − J_ω,A) (the friction at z k
// about the axis k × n: X × e gains z k × e = −z n).
template <class Jac>
void friction_end(const MeshConstants& mc, const MeshRows& rows, const Jac& jac, Index m,
                  double flank, double cos_w, double sin_w, double mu, double normal, Index lo,
                  Index hi, FlankFriction& fr) {
  fr.force = 0.0;
  if (normal <= 0.0 || mu == 0.0 || fr.share.empty()) return;
  const double tan_b = mc.tan_beta_b[m];
  fr.force = mu * normal * std::sqrt(1.0 + tan_b * tan_b);
  const double ct = fr.sum0 * sin_w * mc.eps[m], cr = -fr.sum0 * flank * cos_w;
  const double spin_weight = fr.sigma_m * fr.sum1;
  const double* t = rows.jac_t.row(m).data();
  const double* r = rows.jac_r.row(m).data();
  double* row = fr.row.data();
  for (Index c = lo; c < hi; ++c) row[c] = ct * t[c] + cr * r[c] + spin_weight * row[c];
  if (fr.sum_face == 0.0) return;
  const Vec3 n = line_of_action(mc, rows, m, flank, cos_w, sin_w);
  const double* on_b = mc.support.row(mc.slot_b[m]).data();
  const double* on_a = mc.support.row(mc.slot_a[m]).data();
  for (Index c = lo; c < hi; ++c) {
    const double w = on_b[c] - on_a[c];
    if (w == 0.0) continue;
    const double* ang = jac.data() + 6 * c + 3;
    row[c] -= fr.sum_face * w * (n[0] * ang[0] + n[1] * ang[1] + n[2] * ang[2]);
  }
}

// μ of a compliant mesh at the flank's transverse force F_bt [N] and relative spin [rad/s]: the
// constant, or ISO/TR 14179-2's μ_mz (header), at most kMaxFlankFriction.
template <class Spec>
double flank_mu(const Spec& sp, double normal, double spin) {
  if (sp.friction_law == FrictionLaw::constant) return sp.friction;
  if (normal <= 0.0) return 0.0;
  const double speed = sp.iso_sum_velocity_per_spin * std::abs(spin);
  if (!(speed > 0.0)) return kMaxFlankFriction;
  return std::min(kMaxFlankFriction,
                  iso14179_friction_coefficient(normal, sp.iso_face_width, speed,
                                                sp.iso_reduced_radius, sp.iso_viscosity,
                                                sp.iso_roughness, sp.iso_lubricant_factor));
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

// The friction of flank fr of mesh m on the bodies: −μ F s_j A_j e on B at each pair's contact,
// its opposite on A (for the bearing reactions). The pairs' forces are parallel: on B, force
// f e and moment Y × e about the world origin, f = Σ f_j, Y = Σ f_j (P + z_j k) + Σ b_j m,
// f_j = −μ F s_j A_j, b_j = −μ F s_j B_j (a line's moment about P: header), whether or not
// they cancel.
inline void add_friction_forces(const StepView& s, Index m, const FlankFriction& fr,
                                BodyForces& out) {
  if (fr.force == 0.0) return;
  const Vec3 p = s.rows.pitch_point.row(m).transpose();
  const Vec3 k = s.rows.axis.row(m).transpose();
  const double f = -fr.force * fr.sum0, fd = -fr.force * fr.sum1, fz = -fr.force * fr.sum_face;
  const Vec3 force = f * fr.slide;
  const Vec3 moment = (f * p + fz * k + fd * fr.along).cross(fr.slide);
  auto& on_b = out.of_joint[s.meshes.joint_b[m]];
  auto& on_a = out.of_joint[s.meshes.joint_a[m]];
  on_b.linear() += force;
  on_b.angular() += moment;
  on_a.linear() -= force;
  on_a.angular() -= moment;
}

// Writes mesh m's friction series of sample k: the entering pair's sliding speed on the loaded
// flank (±1) from the bodies' velocities, the loaded flank's friction on A along e (μ F_n S₀)
// and both flanks' loss μ F_n g·v [W].
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
