// Where the teeth of a mesh are along the path of contact, from the gear angles: the roll
// position of the entering tooth pair, the number of pairs in contact and each pair's share of
// the mesh stiffness (Jørgensen 2014 §2.4, Figs. 7-8). Used by rigid and compliant
// meshes alike.
//
// The path of contact runs from A (the driven gear's tip circle) to E along the line of action,
// g_α = ε_α p_b long (pinwind/gears/contact.py). A pair enters at A and leaves at E; the next
// pair follows one base pitch p_b behind. With the entering pair at x ∈ [0, p_b), the pairs in
// contact sit at x, x + p_b, … ≤ g_α. When gear A turns by Δψ relative to the centre line, its
// teeth roll by r_b,A Δψ along the line of action of the front flank, and by −r_b,A Δψ along
// the back flank's.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "mesh_rows.hpp"

namespace pinwind {

struct MeshPathSpec {
  double base_pitch = 0.0;    // p_bt [m]
  double path_length = 0.0;   // g_α [m]
  double roll_start = 0.0;    // roll length from gear A's tangency point to A [m]
  double roll_radius_a = 0.0; // base radius of gear A [m]
  double pitch_position = 0.0;  // x of the pitch point: its distance from A along the path [m]
  double entering_front = 0.0, entering_back = 0.0;  // x at ψ_A = angle_ref_a [m]
  double angle_ref_a = 0.0;   // ψ_A with reference_a pointing at the pitch point [rad]
  Vec3 reference_a = Vec3::UnitX();  // unit vector ⟂ axis fixed in gear A's joint frame
  // Stiffness of one tooth pair along the path (positions from A [m], stiffness [N/m]),
  // piecewise linear; empty: a constant mesh stiffness (the pair count still from geometry).
  Eigen::VectorXd pair_position, pair_stiffness;
  // The gap the gears' profile modifications leave a tooth pair along the path (positions from
  // A [m], gap [m], piecewise linear; pinwind/gears/flank_modification.py profile_gap); empty:
  // unmodified flanks. Needs the pair table.
  Eigen::VectorXd gap_position, gap_value;
};

// Angle from u to e about k [rad], in (−π, π].
inline double angle_about(const Vec3& k, const Vec3& u, const Vec3& e) {
  return std::atan2(k.dot(u.cross(e)), u.dot(e));
}

// x mod p in [0, p).
inline double wrap_positive(double x, double p) {
  const double r = std::fmod(x, p);
  return r < 0.0 ? r + p : r;
}

// x mod p in [0, p) for |x| below 2⁶² p, as x − n p with n = x/p truncated and one correction:
// without fmod's exact, bit-by-bit remainder (a loop of one step per bit of x/p), and equal to
// it but for the rounding of n p (ulp(x)).
inline double wrap_positive_near(double x, double p) {
  const double n = static_cast<double>(static_cast<long long>(x / p));
  double r = x - n * p;
  if (r < 0.0) r += p;
  if (r >= p) r -= p;
  return r;
}

// Where path_state's last table look-ups of one mesh ended (the interval of each pair in the
// stiffness table), to start the next from: the pairs move by a fraction of an interval per
// step, so the look-up is mostly one comparison instead of a binary search whose branches the
// processor cannot predict. The values found are the same.
struct PathHint {
  static constexpr int kPairs = 8;
  Eigen::Index interval[kPairs] = {};
};

struct PathState {
  double entering = 0.0;     // x of the entering pair [m]
  int pairs = 1;             // pairs in contact
  double stiffness = 1.0;    // mesh stiffness: the sum over the pairs [N/m] (1 if no table)
  double share = 1.0;        // the entering pair's stiffness / the mesh stiffness
  double gap = 0.0;          // E: the engaged pairs' stiffness-weighted gap (engage) [m]
};

// A piecewise-linear table at x, held at its ends. hint: an interval i to try first (s[i − 1]
// ≤ x < s[i], the one the search finds), and where the interval found is written.
inline double table_at(const Eigen::VectorXd& s, const Eigen::VectorXd& k, double x,
                       Eigen::Index* hint = nullptr) {
  const Eigen::Index n = s.size();
  if (x <= s[0]) return k[0];
  if (x >= s[n - 1]) return k[n - 1];
  Eigen::Index i = hint ? *hint : 0;
  if (!(i > 0 && i < n && s[i - 1] <= x && x < s[i])) {
    const auto* it = std::upper_bound(s.data(), s.data() + n, x);
    i = static_cast<Eigen::Index>(it - s.data());
    if (hint) *hint = i;
  }
  const double w = (x - s[i - 1]) / (s[i] - s[i - 1]);
  return (1.0 - w) * k[i - 1] + w * k[i];
}

inline double pair_stiffness_at(const MeshPathSpec& p, double x, Eigen::Index* hint = nullptr) {
  return table_at(p.pair_position, p.pair_stiffness, x, hint);
}

inline double pair_gap_at(const MeshPathSpec& p, double x) {
  return table_at(p.gap_position, p.gap_value, x);
}

// With profile modifications each pair j carries k_j max(0, δ − e_j), so the flank's force is
// K (δ − E) with K = Σ k_j and E = Σ k_j e_j / K over the pairs engaged at the overlap δ (those
// with e_j < δ; where none is, those at the smallest gap, so that a flank closes when δ passes
// it): the same law as pinwind/gears/loaded_contact.py, held over a step like the stiffness.
// The share becomes the entering pair's part of the force at δ.
inline void engage(const MeshPathSpec& p, PathState& st, double delta) {
  double smallest = pair_gap_at(p, st.entering);
  for (int j = 1; j < st.pairs; ++j) {
    smallest = std::min(smallest, pair_gap_at(p, st.entering + j * p.base_pitch));
  }
  const double limit = std::max(delta, smallest);
  double k_sum = 0.0, ke_sum = 0.0, entering_force = 0.0, force = 0.0;
  for (int j = 0; j < st.pairs; ++j) {
    const double x = st.entering + j * p.base_pitch;
    const double e = pair_gap_at(p, x);
    if (e > limit) continue;
    const double k = pair_stiffness_at(p, x);
    k_sum += k;
    ke_sum += k * e;
    const double f = k * std::max(0.0, delta - e);
    force += f;
    if (j == 0) entering_force = f;
  }
  st.stiffness = k_sum;
  st.gap = ke_sum / k_sum;
  if (force > 0.0) st.share = entering_force / force;
}

// U = Σ_j ½ k_j max(0, δ − e_j)² of the pairs of a path state at overlap δ [J].
inline double pairs_potential(const MeshPathSpec& p, const PathState& st, double delta) {
  double energy = 0.0;
  for (int j = 0; j < st.pairs; ++j) {
    const double x = st.entering + j * p.base_pitch;
    const double d = std::max(0.0, delta - pair_gap_at(p, x));
    energy += 0.5 * pair_stiffness_at(p, x) * d * d;
  }
  return energy;
}

// Each pair's share s_j of the flank's force at overlap δ, entering pair first: 1/pairs without
// a stiffness table; k_j / Σ k over the pairs with one; k_j (δ − e_j)₊ / Σ with profile
// modifications (engage's law). Flank friction (flank_friction.hpp) loads each pair by it.
inline void pair_shares(const MeshPathSpec& p, const PathState& st, double delta,
                        std::vector<double>& out) {
  out.assign(static_cast<size_t>(st.pairs), 1.0 / st.pairs);
  if (p.pair_position.size() == 0) return;
  const bool modified = p.gap_position.size() != 0;
  double total = 0.0;
  for (int j = 0; j < st.pairs; ++j) {
    const double x = st.entering + j * p.base_pitch;
    const double k = pair_stiffness_at(p, x);
    out[static_cast<size_t>(j)] = modified ? k * std::max(0.0, delta - pair_gap_at(p, x)) : k;
    total += out[static_cast<size_t>(j)];
  }
  if (total <= 0.0) {
    out.assign(static_cast<size_t>(st.pairs), 1.0 / st.pairs);
    return;
  }
  for (auto& share : out) share /= total;
}

// Path state for gear A's angle ψ_A relative to the centre line, on flank s (±1); shift [m]
// moves the entering pair along the path (a helical mesh's slice: its face section's lag,
// compliant_mesh.hpp SlicedMeshes). hint: the mesh's PathHint (the same state, found sooner);
// near_wrap: the roll wrapped by wrap_positive_near instead of fmod's exact remainder.
inline PathState path_state(const MeshPathSpec& p, double angle_a, double flank,
                            double shift = 0.0, PathHint* hint = nullptr,
                            bool near_wrap = false) {
  PathState st;
  if (p.base_pitch <= 0.0) return st;
  const double roll = p.roll_radius_a * (angle_a - p.angle_ref_a);
  const double x = flank > 0 ? p.entering_front + roll + shift : p.entering_back - roll + shift;
  st.entering = near_wrap ? wrap_positive_near(x, p.base_pitch) : wrap_positive(x, p.base_pitch);
  const double tol = 1e-12 * p.base_pitch;
  st.pairs = 0;
  for (double x = st.entering; x <= p.path_length + tol; x += p.base_pitch) ++st.pairs;
  st.pairs = std::max(st.pairs, 1);
  if (p.pair_position.size() == 0) {
    st.share = 1.0 / st.pairs;
    return st;
  }
  const bool hinted = hint && st.pairs <= PathHint::kPairs;
  const double entering = pair_stiffness_at(p, st.entering, hinted ? &hint->interval[0] : nullptr);
  st.stiffness = entering;
  for (int j = 1; j < st.pairs; ++j) {
    st.stiffness += pair_stiffness_at(p, st.entering + j * p.base_pitch,
                                      hinted ? &hint->interval[j] : nullptr);
  }
  st.share = entering / st.stiffness;
  return st;
}

// ψ_A of a mesh with MeshRows::angle_affine, from q without atan2: the affine form, less whole
// turns, in [−π, π] (gear_a_angle's range, so that path_state's roll and its wrap stay as
// small): equal to gear_a_angle's up to the rounding of q's own size (|q| ε) and whole turns,
// which path_state's wrap by the base pitch removes (a turn rolls z_A base pitches).
inline double affine_angle(const MeshRows& rows, Eigen::Index m, const Eigen::VectorXd& q) {
  constexpr double kTwoPi = 6.283185307179586;
  const auto i = static_cast<size_t>(m);
  double psi = rows.angle_offset[i];
  for (const auto& [j, w] : rows.angle_terms[i]) psi += w * q[j];
  const double turns = psi * (1.0 / kTwoPi);
  const auto whole = static_cast<long long>(turns + (turns >= 0.0 ? 0.5 : -0.5));
  return psi - kTwoPi * static_cast<double>(whole);
}

// ψ_A: the angle of gear A about the mesh axis relative to the centre line towards B.
inline double gear_a_angle(const MeshConstants& mc, const MeshRows& rows, const MeshPathSpec& p,
                           const Eigen::Matrix3d& rot_a, Eigen::Index m) {
  const Vec3 k = rows.axis.row(m).transpose();
  const Vec3 u = mc.sigma[m] * rows.radial.row(m).transpose();
  return angle_about(k, u, rot_a * p.reference_a);
}

}  // namespace pinwind
