// Rigid gear-mesh constraint rows of all meshes at one state, and the tooth wrenches they apply.
//
// The formulation is documented in pinwind/dynamics/mesh.py: one row per mesh along the
// direction of the tooth force on B, f = n − s tan β_b k, the transverse line of action
// n = s cos α_w t + ε sin α_w r̂ and, for helical teeth, the axial part −s tan β_b k
// (tooth_force_on_b), kept as its t, r̂ and k parts so that switching the loaded flank s costs
// nothing; the bias is the exact time derivative of the row at zero joint acceleration,
//
//     ċ − J q̈ = ḟ·Δv + f·Δa_s(P) + f·((ω_B − ω_A) × Ṗ),
//
// with spatial velocities taken at the world origin in world axes (Pinocchio's world Jacobian
// J and its time variation J̇ from computeJointJacobiansTimeVariation).
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // the cross products

namespace pinwind {

using Eigen::Index;
using Vec3 = Eigen::Vector3d;
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Geometry constants of every mesh (pinwind/dynamics/mesh.py MeshSet).
struct MeshConstants {
  // Pinocchio joint ids that carry a meshing gear; a mesh refers to them by slot.
  std::vector<long> joint_ids;
  std::vector<long> slot_a, slot_b;
  Rows3 centre_a, centre_b;  // gear centres in their joint frames [m]
  Rows3 axis_a;              // axis of gear A in its joint frame
  Rows3 axis_b;              // axis of gear B in its joint frame (a helical row's axial part)
  Eigen::VectorXd mu;        // pitch point P = C_A + mu (C_B − C_A)⊥
  Eigen::VectorXd sigma;     // r̂ = sigma (C_B − C_A)⊥ / |·|
  RowMat support;            // support(i, k) = 1 when velocity k moves the body of slot i
  // Working pressure angle α_w (cos, sin), ε (−1 when A is internal), tan β_b of gear A (base
  // helix angle, signed like β).
  Eigen::VectorXd cos_a, sin_a, eps, tan_beta_b;
  std::vector<long> joint_a, joint_b;  // Pinocchio joint ids of gear A and gear B

  Index count() const { return static_cast<Index>(slot_a.size()); }
};

// Rows of all meshes at one state, split along t and r̂ (pinwind/dynamics/mesh.py MeshRows).
struct MeshRows {
  // The rows' parts along t, r̂ and k (jac_k, bias_k: helical meshes only, tan β_b ≠ 0; zero
  // for the others, whose row has no axial part).
  RowMat jac_t, jac_r, jac_k;
  Eigen::VectorXd bias_t, bias_r, bias_k;
  Rows3 tangent, radial, pitch_point, axis;
  Rows3 axis_b;              // gear B's axis k_B in world (helical meshes only)
  Rows3 centre_a, centre_b;  // gear centres in world [m]
  // Work space: spatial velocity and acceleration at q̈ = 0 of each slot's body.
  std::vector<Eigen::Matrix<double, 6, 1>> twist, accel;
  // Meshes whose geometry is fixed in one joint's frame (the Stepper's, fixed_mesh_frames in
  // stepper_assembly.cpp): frame[m] is that joint (0: the world), or -1 for a mesh evaluated in
  // full at every state; empty: every mesh in full. A fixed mesh's rows J_t, J_r are the same at
  // every q and kept from the first evaluation, its bias is 0 (γ = J̇ v with J̇ = 0), and its
  // geometry is the frame's placement applied to the constants below (that frame's axes).
  std::vector<long> frame;
  Rows3 local_tangent, local_radial, local_pitch_point, local_axis, local_centre_a,
      local_centre_b;

  bool fixed(Index m) const { return !frame.empty() && frame[static_cast<size_t>(m)] >= 0; }
  // Per fixed mesh whose gear A and frame hang from the world through joints that each turn
  // about the mesh's axis or do not turn (revolute about ±k, or prismatic), gear A's angle ψ_A
  // about k from the centre line (mesh_path.hpp gear_a_angle) as an affine function of q, up
  // to whole turns: ψ_A = angle_offset[m] + Σ w q_j over angle_terms[m] (j, w = ±1): gear A's
  // turn about k less the frame's. Empty terms and a NaN offset: not affine (atan2 instead);
  // empty vectors: no mesh is.
  std::vector<std::vector<std::pair<Index, double>>> angle_terms;
  std::vector<double> angle_offset;
  bool angle_affine(Index m) const {
    return !angle_offset.empty() && !std::isnan(angle_offset[static_cast<size_t>(m)]);
  }
  // Per mesh, the columns that move one gear and not the other, each with its w (support of B
  // less support of A), taken from MeshConstants::support by evaluate_mesh_geometry's first
  // call; the rows' other entries stay the zeros resize wrote.
  std::vector<std::vector<std::pair<Index, double>>> moving;
  // The same less the pure translations (every column where translation is not known): those
  // whose angular part can turn a gear.
  std::vector<std::vector<std::pair<Index, double>>> turning;
  // Per column of J: whether it is a pure translation at every q (a compliant bearing's slide,
  // joint_algorithms.hpp slide_axes), its angular part 0; empty where the caller does not say.
  std::vector<char> translation;

  void resize(Index meshes, Index nv) {
    moving.clear();
    turning.clear();
    jac_t.setZero(meshes, nv);
    jac_r.setZero(meshes, nv);
    jac_k.setZero(meshes, nv);
    bias_t.setZero(meshes);
    bias_r.setZero(meshes);
    bias_k.setZero(meshes);
    tangent.setZero(meshes, 3);
    radial.setZero(meshes, 3);
    pitch_point.setZero(meshes, 3);
    axis.setZero(meshes, 3);
    axis_b.setZero(meshes, 3);
    centre_a.setZero(meshes, 3);
    centre_b.setZero(meshes, 3);
  }
};

// The geometry (centres, axis, t, r̂, pitch point) and Jacobian rows of every mesh: they depend
// on the joint angles only.
//
// jac: world-frame J (6 × nv, [linear; angular]) of Pinocchio.
// origin, rot: world placement of the joint of each slot.
template <class Jac>
void evaluate_mesh_geometry(const MeshConstants& mc, const Jac& jac,
                            const std::vector<Vec3>& origin,
                            const std::vector<Eigen::Matrix3d>& rot, MeshRows& out) {
  const Index nv = jac.cols();
  if (static_cast<Index>(out.moving.size()) != mc.count()) {
    const bool known = static_cast<Index>(out.translation.size()) == nv;
    out.moving.assign(static_cast<size_t>(mc.count()), {});
    out.turning.assign(static_cast<size_t>(mc.count()), {});
    for (Index m = 0; m < mc.count(); ++m) {
      for (Index c = 0; c < nv; ++c) {
        const double w = mc.support(mc.slot_b[m], c) - mc.support(mc.slot_a[m], c);
        if (w == 0.0) continue;
        out.moving[static_cast<size_t>(m)].push_back({c, w});
        if (!known || !out.translation[static_cast<size_t>(c)]) {
          out.turning[static_cast<size_t>(m)].push_back({c, w});
        }
      }
    }
  }
  for (Index m = 0; m < mc.count(); ++m) {
    if (out.fixed(m)) continue;  // evaluate_fixed_mesh_geometry
    const long a = mc.slot_a[m], b = mc.slot_b[m];
    const Vec3 ca = origin[a] + rot[a] * mc.centre_a.row(m).transpose();
    const Vec3 cb = origin[b] + rot[b] * mc.centre_b.row(m).transpose();
    const Vec3 k = rot[a] * mc.axis_a.row(m).transpose();
    const Vec3 d = cb - ca;
    const double dk = d.dot(k);
    const Vec3 p = d - dk * k;  // centre distance vector, perpendicular to the axis
    const Vec3 u = p / p.norm();
    const Vec3 r = mc.sigma[m] * u;
    const Vec3 t = k.cross(r);
    const Vec3 x = ca + mc.mu[m] * p;
    out.tangent.row(m) = t.transpose();
    out.radial.row(m) = r.transpose();
    out.pitch_point.row(m) = x.transpose();
    out.axis.row(m) = k.transpose();
    out.centre_a.row(m) = ca.transpose();
    out.centre_b.row(m) = cb.transpose();

    // Row: n·(v_B(P) − v_A(P)) over the joint velocities, split along t and r̂ (and k for a
    // helical mesh: the axial part of its row, the same sums with k). A column that
    // moves one gear alone has w = ±1 (support is 0 or 1): its sign is applied to the sums
    // instead of to the six entries of J (each product and sum then only changes sign: the
    // same value); only the columns with w ≠ 0 are written (out.moving). A pure translation's
    // angular part is 0: its terms mt·ω, mr·ω, which would add zeros, are left out.
    const Vec3 mt = x.cross(t), mr = x.cross(r);
    double* row_t = &out.jac_t(m, 0);
    double* row_r = &out.jac_r(m, 0);
    const bool slides_known = static_cast<Index>(out.translation.size()) == nv;
    for (const auto& [c, w] : out.moving[static_cast<size_t>(m)]) {
      if (slides_known && out.translation[static_cast<size_t>(c)]) {
        const Vec3 lin = jac.col(c).template head<3>() * w;
        row_t[c] = t.dot(lin);
        row_r[c] = r.dot(lin);
        continue;
      }
      if (w == 1.0 || w == -1.0) {
        const Vec3 lin = jac.col(c).template head<3>();
        const Vec3 ang = jac.col(c).template tail<3>();
        row_t[c] = w * (t.dot(lin) + mt.dot(ang));
        row_r[c] = w * (r.dot(lin) + mr.dot(ang));
        continue;
      }
      const Vec3 lin = jac.col(c).template head<3>() * w;
      const Vec3 ang = jac.col(c).template tail<3>() * w;
      row_t[c] = t.dot(lin) + mt.dot(ang);
      row_r[c] = r.dot(lin) + mr.dot(ang);
    }
    if (mc.tan_beta_b[m] == 0.0) continue;  // spur: no axial part
    // The axial part: the rate of Z (axial_offset) with P held, k̃_B·v_B(P) − k·v_A(P),
    // k̃_B = k_B / (k·k_B): a gear's spin about its own axis leaves its mid-plane, and so Z,
    // where it is (k_B·(ω k_B × (P − C_B)) = 0), where the material points' k·v_B(P) would
    // count a tilted gear's spin as axial motion. With parallel axes it is k·(v_B(P) − v_A(P)).
    const Vec3 kb = rot[b] * mc.axis_b.row(m).transpose();
    out.axis_b.row(m) = kb.transpose();
    const Vec3 kt = kb / k.dot(kb);
    const Vec3 mk = x.cross(k), mkt = x.cross(kt);
    double* row_k = &out.jac_k(m, 0);
    for (const auto& [c, w] : out.moving[static_cast<size_t>(m)]) {
      const Vec3 lin = jac.col(c).template head<3>();
      const Vec3 ang = jac.col(c).template tail<3>();
      // w = +1: a column of B alone, −1: of A alone (support is 0 or 1)
      row_k[c] = w > 0.0 ? w * (kt.dot(lin) + mkt.dot(ang)) : w * (k.dot(lin) + mk.dot(ang));
    }
  }
}

// The geometry of the fixed meshes (MeshRows::frame) from the placements oMi of their frames'
// joints (Pinocchio's data.oMi): R x + o for the points, R x for the directions; their rows
// are kept, and so is the whole geometry of a mesh fixed in the world's frame (0).
template <class Placements>
void evaluate_fixed_mesh_geometry(const Placements& oMi, MeshRows& out) {
  // Row i of a Rows3 (contiguous) turned by R (column-major), plus o for a point: each entry
  // (R_r0 x_0 + R_r1 x_1) + R_r2 x_2 as Eigen's fixed 3 × 3 product sums it, without the
  // expressions' set-up for the rows of a dynamic matrix.
  const auto turn = [](const double* r, const Rows3& local, Rows3& world, Index i,
                       const double* o) {
    const double* x = &local(i, 0);
    double* y = &world(i, 0);
    for (int c = 0; c < 3; ++c) {
      const double s = r[c] * x[0] + r[3 + c] * x[1] + r[6 + c] * x[2];
      y[c] = o ? o[c] + s : s;
    }
  };
  for (size_t m = 0; m < out.frame.size(); ++m) {
    if (out.frame[m] <= 0) continue;
    const auto& placement = oMi[static_cast<size_t>(out.frame[m])];
    const double* rot = placement.rotation().data();
    const double* origin = placement.translation().data();
    const auto i = static_cast<Index>(m);
    turn(rot, out.local_tangent, out.tangent, i, nullptr);
    turn(rot, out.local_radial, out.radial, i, nullptr);
    turn(rot, out.local_axis, out.axis, i, nullptr);
    turn(rot, out.local_pitch_point, out.pitch_point, i, origin);
    turn(rot, out.local_centre_a, out.centre_a, i, origin);
    turn(rot, out.local_centre_b, out.centre_b, i, origin);
  }
}

// The bias ċ − J q̈ of every mesh from the spatial velocity (twist) and the acceleration at
// q̈ = 0 of each slot's body (world axes, at the world origin), with the geometry that
// evaluate_mesh_geometry left in ``out`` at the same angles.
inline void evaluate_mesh_bias_from(const MeshConstants& mc, MeshRows& out) {
  const auto& twist = out.twist;
  const auto& accel = out.accel;
  for (Index m = 0; m < mc.count(); ++m) {
    if (out.fixed(m)) continue;  // γ = 0, kept
    const long a = mc.slot_a[m], b = mc.slot_b[m];
    const Vec3 ca = out.centre_a.row(m).transpose(), cb = out.centre_b.row(m).transpose();
    const Vec3 k = out.axis.row(m).transpose();
    const Vec3 t = out.tangent.row(m).transpose(), r = out.radial.row(m).transpose();
    const Vec3 x = out.pitch_point.row(m).transpose();
    const Vec3 d = cb - ca;
    const double dk = d.dot(k);
    const Vec3 p = d - dk * k;
    const double rho = p.norm();
    const Vec3 u = p / rho;

    // Bias ċ − J q̈ = ṅ·Δv + n·Δa_s(P) + n·((ω_B − ω_A) × Ṗ).
    const Vec3 va = twist[a].head<3>(), wa = twist[a].tail<3>();
    const Vec3 vb = twist[b].head<3>(), wb = twist[b].tail<3>();
    const Vec3 dv = vb + wb.cross(x) - va - wa.cross(x);
    const Vec3 vca = va + wa.cross(ca), vcb = vb + wb.cross(cb);
    const Vec3 kd = wa.cross(k);
    const Vec3 dd = vcb - vca;
    const double ddk = dd.dot(k), dkd = d.dot(kd);
    const Vec3 pd = dd - ddk * k - dkd * k - dk * kd;
    const Vec3 rd = mc.sigma[m] * (pd - u.dot(pd) * u) / rho;
    const Vec3 xd = vca + mc.mu[m] * pd;
    const Vec3 td = kd.cross(r) + k.cross(rd);
    const Vec3 da = accel[b].head<3>() + Vec3(accel[b].tail<3>()).cross(x) - accel[a].head<3>() -
                    Vec3(accel[a].tail<3>()).cross(x);
    const Vec3 h = da + (wb - wa).cross(xd);
    out.bias_t[m] = td.dot(dv) + t.dot(h);
    out.bias_r[m] = rd.dot(dv) + r.dot(h);
    if (mc.tan_beta_b[m] != 0.0) {
      // The axial part's: d/dt of k̃_B·v_B(P) − k·v_A(P) at q̈ = 0 (evaluate_mesh_geometry).
      const Vec3 kb = out.axis_b.row(m).transpose();
      const double kk = k.dot(kb);
      const Vec3 kbd = wb.cross(kb);
      const Vec3 ktd = kbd / kk - kb * ((kd.dot(kb) + k.dot(kbd)) / (kk * kk));
      const Vec3 vbx = vb + wb.cross(x), vax = va + wa.cross(x);
      const Vec3 abx = accel[b].head<3>() + Vec3(accel[b].tail<3>()).cross(x) + wb.cross(xd);
      const Vec3 aax = accel[a].head<3>() + Vec3(accel[a].tail<3>()).cross(x) + wa.cross(xd);
      out.bias_k[m] = ktd.dot(vbx) + (kb / kk).dot(abx) - kd.dot(vax) - k.dot(aax);
    }
  }
}

// The bias of every mesh at joint speeds v: each slot's twist Σ J_k v_k and acceleration at
// q̈ = 0, Σ J̇_k v_k, over the velocities that move it; then evaluate_mesh_bias_from.
//
// jac, djac: world-frame J and J̇ (6 × nv, [linear; angular]) of Pinocchio.
template <class Jac>
void evaluate_mesh_bias(const MeshConstants& mc, const Jac& jac, const Jac& djac,
                        const Eigen::VectorXd& v, MeshRows& out) {
  const Index nv = v.size();
  const Index slots = static_cast<Index>(mc.joint_ids.size());
  out.twist.resize(slots);
  out.accel.resize(slots);
  for (Index s = 0; s < slots; ++s) {
    out.twist[s].setZero();
    out.accel[s].setZero();
    for (Index k = 0; k < nv; ++k) {
      if (mc.support(s, k) != 0.0) {
        out.twist[s] += jac.col(k) * v[k];
        out.accel[s] += djac.col(k) * v[k];
      }
    }
  }
  evaluate_mesh_bias_from(mc, out);
}

// Evaluates the rows of every mesh: geometry, Jacobian rows and bias.
template <class Jac>
void evaluate_mesh_rows(const MeshConstants& mc, const Jac& jac, const Jac& djac,
                        const Eigen::VectorXd& v, const std::vector<Vec3>& origin,
                        const std::vector<Eigen::Matrix3d>& rot, MeshRows& out) {
  evaluate_mesh_geometry(mc, jac, origin, rot, out);
  evaluate_mesh_bias(mc, jac, djac, v, out);
}

// The one implementation of a mesh's line of action and row for a flank (docs/model_format.md
// "Mesh sign convention"): n = s cos α_w t + ε sin α_w r̂, J = s cos α_w J_t + ε sin α_w J_r,
// shared by the rigid row, the compliant mesh force and the deflection rate δ̇ = −J v.
//
// The working pressure angle is the reference one (mc.cos_a, mc.sin_a), that of the centre
// distance the gears' axes keep, or, for gears whose centres move (compliant bearings, floating
// members), the one of the current centre distance a, cos α' = (r_b,B ± r_b,A) / a: the line
// tangent to both base circles, along which a compliant mesh's overlap changes (its row is then
// the exact gradient of the overlap, compliant_mesh.hpp). The pitch point C_A + μ (C_B − C_A)⊥,
// μ = r_b,A / (r_b,B ± r_b,A), lies on that line at any a.
inline Vec3 line_of_action(const MeshConstants& mc, const MeshRows& rows, Index m, double flank,
                           double cos_w, double sin_w) {
  return cos_w * flank * rows.tangent.row(m).transpose() +
         sin_w * mc.eps[m] * rows.radial.row(m).transpose();
}

inline Vec3 line_of_action(const MeshConstants& mc, const MeshRows& rows, Index m, double flank) {
  return line_of_action(mc, rows, m, flank, mc.cos_a[m], mc.sin_a[m]);
}

// The bias of mesh m's row on flank s (flank_row's), alone.
inline double flank_bias(const MeshConstants& mc, const MeshRows& rows, Index m, double flank,
                         double cos_w, double sin_w) {
  const double ct = cos_w * flank, cr = sin_w * mc.eps[m];
  const double bias = ct * rows.bias_t[m] + cr * rows.bias_r[m];
  if (mc.tan_beta_b[m] == 0.0) return bias;
  return bias - flank * mc.tan_beta_b[m] * rows.bias_k[m];
}

inline double flank_bias(const MeshConstants& mc, const MeshRows& rows, Index m, double flank) {
  return flank_bias(mc, rows, m, flank, mc.cos_a[m], mc.sin_a[m]);
}

// The row is that of the tooth force's direction on B, f = n − s tan β_b k (tooth_force_on_b):
// the contact's generalized force J_Bᵀ F − J_Aᵀ F at the pitch point P with F = F_bt f is
// F_bt Jᵀ, so a helical mesh's thrust pushes the gears along their axial slides and tilts them
// by its moment about each centre (P's lever), and the overlap rate δ̇ = −J v has the part
// s tan β_b Ż of the gears' relative axial motion at P (compliant_mesh.hpp mesh_pose): Ż =
// k·(v_B(P) − v_A(P)) while the axes are parallel, and with a tilted gear B the rate of its
// mid-plane's offset, k̃_B·v_B(P) − k·v_A(P) (evaluate_mesh_geometry), so that B's spin about its
// own axis does no work against the thrust. A spur mesh (tan β_b = 0) has the transverse row
// alone.
//
// columns: if given, only those entries of row are written (a compliant mesh's columns that move
// one gear and not the other; its row keeps the zeros of the others).
template <class Row>
void flank_row(const MeshConstants& mc, const MeshRows& rows, Index m, double flank, double cos_w,
               double sin_w, Row&& row, double& bias,
               const std::vector<Index>* columns = nullptr) {
  const double ct = cos_w * flank, cr = sin_w * mc.eps[m];
  // Column by column: Eigen's assignment of the expression to a row of a strided block cost
  // ~45 instructions an entry.
  const double* t = rows.jac_t.row(m).data();
  const double* r = rows.jac_r.row(m).data();
  if (mc.tan_beta_b[m] == 0.0) {
    const auto entry = [&](Index c) { row(c) = ct * t[c] + cr * r[c]; };
    if (columns != nullptr) {
      for (const Index c : *columns) entry(c);
    } else {
      for (Index c = 0; c < rows.jac_t.cols(); ++c) entry(c);
    }
  } else {
    const double ck = -flank * mc.tan_beta_b[m];
    const double* k = rows.jac_k.row(m).data();
    const auto entry = [&](Index c) { row(c) = ct * t[c] + cr * r[c] + ck * k[c]; };
    if (columns != nullptr) {
      for (const Index c : *columns) entry(c);
    } else {
      for (Index c = 0; c < rows.jac_t.cols(); ++c) entry(c);
    }
  }
  bias = flank_bias(mc, rows, m, flank, cos_w, sin_w);
}

template <class Row>
void flank_row(const MeshConstants& mc, const MeshRows& rows, Index m, double flank, Row&& row,
               double& bias) {
  flank_row(mc, rows, m, flank, mc.cos_a[m], mc.sin_a[m], std::forward<Row>(row), bias);
}

// The axial position Z [m] of gear B's flank relative to gear A's at the pitch point p, along
// gear A's axis k: the distance along k from p to B's mid-plane (through its centre c_b,
// normal to its axis k_b) less that to A's,
//
//     Z = (c_b − p)·k_b / (k·k_b) + (p − c_a)·k.
//
// While the axes are parallel its rate is k·(v_B(p) − v_A(p)), the material points' relative
// axial velocity at p (the axial part of the mesh row, flank_row); a tilt of either gear moves
// its flank at p axially by its lever from the centre. A compliant helical mesh's overlap has
// the part s tan β_b (Z − Z_ref) (compliant_mesh.hpp mesh_pose).
inline double axial_offset(const Vec3& k, const Vec3& k_b, const Vec3& c_a, const Vec3& c_b,
                           const Vec3& p) {
  return (c_b - p).dot(k_b) / k.dot(k_b) + (p - c_a).dot(k);
}

// Tooth force on gear B [N] in world for the transverse force F_bt (``normal``, along n) on
// flank s: F_bt n plus, for helical teeth, the axial thrust −s F_bt tan β_b k.
//
// Why β_b: the flanks of a helical pair touch along straight contact lines in the plane of
// action (tangent to both base cylinders), inclined at the base helix angle β_b to the axis;
// tan β_b = tan β cos α_t with α_t the reference transverse pressure angle. The contact force
// F_n is normal to the flanks, so it lies in the plane of action perpendicular to the contact
// lines: its part in the transverse plane, along the transverse line of action, is
// F_bt = F_n cos β_b and its axial part F_a = F_n sin β_b = F_bt tan β_b. The base cylinders
// alone fix both, so F_a does not depend on the centre distance. Only at the reference centre
// distance (α_w = α_t) is it F_t tan β; a profile-shifted pair at its working centre distance
// has F_a = F_tw tan β cos α_t / cos α_w. A right-hand gear A (tooth line along cos β k +
// sin β t at P) pushes B towards −s k.
inline Vec3 tooth_force_on_b(const MeshConstants& mc, const MeshRows& rows, Index m, double flank,
                             double normal, double cos_w, double sin_w) {
  return normal * line_of_action(mc, rows, m, flank, cos_w, sin_w) -
         (flank * normal * mc.tan_beta_b[m]) * rows.axis.row(m).transpose();
}

inline Vec3 tooth_force_on_b(const MeshConstants& mc, const MeshRows& rows, Index m, double flank,
                             double normal) {
  return tooth_force_on_b(mc, rows, m, flank, normal, mc.cos_a[m], mc.sin_a[m]);
}

}  // namespace pinwind
