// The Stepper's step loop: Stepper::run and the assembly, solve, record and step it repeats, and
// the mass matrix the tests check (stepper.hpp documents the scheme).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "joint_algorithms.hpp"
#include "small_products.hpp"
#include "stepper.hpp"

namespace pinwind {
namespace {

// y = M x for a matrix M that is symmetric to the last bit (the step's M: mass_from_jacobian
// mirrors each entry), row i read as column i, which is contiguous: the products and their
// order are small_product's, y_i = ((m_i0 x_0 + m_i1 x_1) + …), without its strided loads.
void symmetric_product(const Eigen::MatrixXd& m, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const Eigen::Index n = m.rows();
  y.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* column = m.col(i).data();
    double s = 0.0;
    for (Eigen::Index j = 0; j < n; ++j) s += column[j] * x[j];
    y[i] = s;
  }
}

// The spatial products of the step's passes for one-column joints, entry by entry with the
// operations of Pinocchio's and Eigen's expressions (a × b as Eigen's cross, sums entry by
// entry, Pinocchio's products term by term), so that the values are the same to the bit.
// Pinocchio's expressions build each 6-vector as two 3-vectors in a temporary that is then read
// as three pairs: the pair across the linear part's last entry and the angular part's first is
// read from two stores, which the processor cannot forward (a stall of ~10 cycles each time, a
// third of these passes' time on the drivetrain). These functions are compiled without
// vectorisation (GCC), so that none of their own stores is read back as a pair either.
#if defined(__GNUC__) && !defined(__clang__)
#define PINWIND_SCALAR __attribute__((optimize("no-tree-vectorize")))
#else
#define PINWIND_SCALAR
#endif

PINWIND_SCALAR inline void cross3(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// S x for a symmetric 3 × 3 matrix stored as Pinocchio's Symmetric3 (xx, xy, yy, xz, yz, zz):
// Symmetric3::rhsMult.
PINWIND_SCALAR inline void symmetric_times(const double* s, const double* x, double* out) {
  out[0] = s[0] * x[0] + s[1] * x[1] + s[3] * x[2];
  out[1] = s[1] * x[0] + s[2] * x[1] + s[4] * x[2];
  out[2] = s[3] * x[0] + s[4] * x[1] + s[5] * x[2];
}

// The twist, J̇ column and drift of a one-column joint c below its parent: ov = ov_parent +
// J_c q̇_c, J̇_c = ov × J_c (Pinocchio's MotionDense::cross, J_c.motionAction(ov): (ov_lin ×
// J_ang + ov_ang × J_lin, ov_ang × J_ang)), drift = drift_parent + J̇_c q̇_c.
PINWIND_SCALAR void one_column_motion(const double* above, const double* drift_above,
                                      const double* column, double speed, double* ov,
                                      double* dj, double* drift) {
  double twist[6], a[3], b[3];
  for (int r = 0; r < 6; ++r) twist[r] = above[r] + column[r] * speed;
  cross3(twist, column + 3, a);
  cross3(twist + 3, column, b);
  double dcolumn[6];
  for (int r = 0; r < 3; ++r) dcolumn[r] = a[r] + b[r];
  cross3(twist + 3, column + 3, dcolumn + 3);
  for (int r = 0; r < 6; ++r) {
    ov[r] = twist[r];
    dj[r] = dcolumn[r];
    drift[r] = drift_above[r] + dcolumn[r] * speed;
  }
}

// out = above + column x: a one-column joint's motion below its parent's.
PINWIND_SCALAR void one_column_add(const double* above, const double* column, double x,
                                   double* out) {
  for (int r = 0; r < 6; ++r) out[r] = above[r] + column[r] * x;
}

// A body's weight as a force at the world origin, I (g, 0) for the base's upward acceleration
// g: (m g, c × m g), into weight and, if given, also into copy.
PINWIND_SCALAR void weight_force(const pinocchio::Inertia& body, const double* up, double* weight,
                                 double* copy) {
  double w[6];
  for (int r = 0; r < 3; ++r) w[r] = body.mass() * up[r];
  cross3(body.lever().data(), w, w + 3);
  for (int r = 0; r < 6; ++r) weight[r] = w[r];
  if (copy) {
    for (int r = 0; r < 6; ++r) copy[r] = w[r];
  }
}

// out = (I a + weight) + v ×* (I v) − external, as `body * a + weight + body.vxiv(v) -
// external` computes it, with a = a1 + a2 (a2 optional) and external optional; into out and,
// if given, also into copy. I a is Pinocchio's InertiaTpl::__mult__, (m (a_lin − c × a_ang),
// I_c a_ang + c × f_lin); v ×* (I v) its vxiv, (w × (m v_lin − m c × w), w × (c × (m v_lin −
// m c × w) + I_c w) − v_lin × (m c × w)), w = v_ang.
PINWIND_SCALAR void body_force(const pinocchio::Inertia& body, const double* a1,
                               const double* a2, const double* weight, const double* v,
                               const double* external, double* out, double* copy) {
  const double m = body.mass();
  const double* c = body.lever().data();
  const double* inertia = body.inertia().data().data();
  double a[6];
  for (int r = 0; r < 6; ++r) a[r] = a2 ? a1[r] + a2[r] : a1[r];
  double f[6], cw[3], iw[3], cf[3];
  cross3(c, a + 3, cw);
  for (int r = 0; r < 3; ++r) f[r] = m * (a[r] - cw[r]);
  symmetric_times(inertia, a + 3, iw);
  cross3(c, f, cf);
  for (int r = 0; r < 3; ++r) f[3 + r] = iw[r] + cf[r];
  const double* w = v + 3;
  double vf[6], mcxw[3], mv[3], cmv[3], sum[3], t2[3], t3[3];
  cross3(c, w, cw);
  for (int r = 0; r < 3; ++r) mcxw[r] = m * cw[r];
  for (int r = 0; r < 3; ++r) mv[r] = m * v[r] - mcxw[r];
  cross3(w, mv, vf);
  cross3(c, mv, cmv);
  symmetric_times(inertia, w, iw);
  for (int r = 0; r < 3; ++r) sum[r] = cmv[r] + iw[r];
  cross3(w, sum, t2);
  cross3(v, mcxw, t3);
  for (int r = 0; r < 3; ++r) vf[3 + r] = t2[r] - t3[r];
  for (int r = 0; r < 6; ++r) {
    double x = (f[r] + weight[r]) + vf[r];
    if (external) x = x - external[r];
    out[r] = x;
    if (copy) copy[r] = x;
  }
}

// sums += (elastic, dissipated, applied, friction) of w, read one field at a time: the caller,
// vectorised, read a returned StepWork's fields in pairs, each pair from two stores of the
// callee (a stalled forwarding after every element's work()).
PINWIND_SCALAR void add_work(const StepWork& w, double* sums) {
  sums[0] += w.elastic;
  sums[1] += w.dissipated;
  sums[2] += w.applied;
  sums[3] += w.friction;
}

}  // namespace

RunStatus Stepper::run(long k0, long k1, const RowMat& torque, const RowMat& target,
                       const Outputs& out, const RowMat& inputs, long stride) {
  RunStatus st;
  out_ = out;
  stride = std::max(stride, 1L);
  const long row0 = (k0 + stride - 1) / stride;  // the kept index of out's first row
  // One row of torques or inputs: held over the block (a session's held inputs).
  const bool held_torque = torque.rows() == 1, held_inputs = inputs.rows() == 1;
  if (held_torque) tau_applied_ = torque.row(0).transpose();
  for (long k = k0; k < k1; ++k) {
    const double t = k * s_.dt;
    st.sample = k;
    time_ = t;
    inputs_ = s_.input_columns ? inputs.row(held_inputs ? 0 : k - k0).data() : nullptr;
    if (!held_torque) tau_applied_ = torque.row(k - k0).transpose();
    target_row_ = target.cols() ? target.row(k - k0).data() : nullptr;
    target_next_row_ = target.cols() ? target.row(k - k0 + 1).data() : nullptr;
    targets();
    if (!solve(k, t, st)) return st;
    if (!std::isfinite(a_.squaredNorm() + lam_.squaredNorm())) {
      return fail(st, k, t, "the accelerations or constraint forces are not finite");
    }
    const bool reactions = hand_bearing_loads();
    if (k % stride == 0 || k + 1 == samples_) {
      if (!reactions) bearing_reactions();
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

Eigen::MatrixXd Stepper::mass_matrix(const Eigen::VectorXd& q) {
  // Always the full CRBA at q (the checks compare it with Pinocchio's), the step's M kept.
  const Eigen::MatrixXd kept = mass_;
  joint_jacobians(s_.model, data_, q, slide_axes_);
  mass_from_jacobian();
  Eigen::MatrixXd out = mass_;
  mass_ = kept;
  return out;
}

void Stepper::targets() {
  target_now_.setZero(rows_);
  target_next_.setZero(rows_);
  const StepView sv = view();
  for (size_t c = 0; c < constraints_.size(); ++c) {
    constraints_[c]->targets(sv, rows_of(target_now_, c), rows_of(target_next_, c));
  }
}

void Stepper::kinematics() {
  joint_jacobians(s_.model, data_, q_, slide_axes_);
  for (size_t i = 0; i < s_.meshes.joint_ids.size(); ++i) {
    origin_[i] = data_.oMi[s_.meshes.joint_ids[i]].translation();
    rot_[i] = data_.oMi[s_.meshes.joint_ids[i]].rotation();
  }
  if (nm_) {
    evaluate_mesh_geometry(s_.meshes, data_.J, origin_, rot_, rows_data_);
    evaluate_fixed_mesh_geometry(data_.oMi, rows_data_);
  }
}

void Stepper::velocity_kinematics() {
  const auto& model = s_.model;
  const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
  drift_.resize(nj);
  data_.ov[0].setZero();
  drift_[0].setZero();
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    const int idx = model.idx_vs[i], n = model.nvs[i];
    const auto parent = model.parents[i];
    if (slide_axes_[i] >= 0) {
      // A slide's column is a pure translation u: its twist adds u q̇ and its drift J̇ q̇ to
      // the linear parts alone (the angular parts would add zeros), and v × (u, 0) = (ω × u,
      // 0), Pinocchio's cross product with its zero terms left out.
      const double speed = v_[idx];
      data_.ov[i].linear() = data_.ov[parent].linear() + data_.J.col(idx).head<3>() * speed;
      data_.ov[i].angular() = data_.ov[parent].angular();
      auto column = data_.dJ.col(idx);
      column.head<3>() = data_.ov[i].angular().cross(data_.J.col(idx).head<3>());
      column.tail<3>().setZero();
      drift_[i].linear() = drift_[parent].linear() + column.head<3>() * speed;
      drift_[i].angular() = drift_[parent].angular();
      continue;
    }
    if (n == 1) {
      // (one_column_motion: the same operations as the general branch below)
      one_column_motion(data_.ov[parent].toVector().data(), drift_[parent].toVector().data(),
                        data_.J.col(idx).data(), v_[idx], data_.ov[i].toVector().data(),
                        data_.dJ.col(idx).data(), drift_[i].toVector().data());
      continue;
    }
    data_.ov[i] = data_.ov[parent] + pinocchio::Motion(joint_product(data_.J, v_, idx, n));
    for (int c = idx; c < idx + n; ++c) {
      data_.dJ.col(c) = data_.ov[i].cross(pinocchio::Motion(data_.J.col(c))).toVector();
    }
    drift_[i] = drift_[parent] + pinocchio::Motion(joint_product(data_.dJ, v_, idx, n));
  }
  if (gear_motion_) {
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

void Stepper::bias_forces() {
  const auto& model = s_.model;
  const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
  body_force_.resize(nj);
  subtree_.resize(nj);
  weight_.resize(nj);
  // gravity as an upward acceleration of the base, plus the drift J̇ v of velocity_kinematics
  const pinocchio::Motion up = -model.gravity;
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    if (massless_[i]) {
      weight_[i].setZero();
      subtree_[i] = body_force_[i] = pinocchio::Force::Zero();
      continue;
    }
    // I (g, 0) for the pure linear acceleration g: (m g, c × m g), Pinocchio's product without
    // its terms in the zero angular part, which add zeros (weight_force above).
    const pinocchio::Inertia& body = body_[i];
    weight_force(body, up.linear().data(), weight_[i].toVector().data(),
                 constant_mass_ ? subtree_[i].toVector().data() : nullptr);
    if (constant_mass_) continue;  // the body forces at q̈ = 0 are joint_forces' (below)
    // body * drift + weight + body.vxiv(ov) (body_force above)
    body_force(body, drift_[i].toVector().data(), nullptr, weight_[i].toVector().data(),
               data_.ov[i].toVector().data(), nullptr, body_force_[i].toVector().data(),
               subtree_[i].toVector().data());
  }
  nle_.resize(nv_);
  gravity_.resize(nv_);
  if (constant_mass_) {
    // M constant: C(q, v) v = Ṁ v − ½ ∂(vᵀ M v)/∂q = 0, so b = g(q), from the weights alone
    // (each body's own kept in weight_ for joint_forces; subtree_ sums them up the tree).
    for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
      const int idx = model.idx_vs[i], n = model.nvs[i];
      if (n == 1) {
        gravity_[idx] = data_.J.col(idx).dot(subtree_[i].toVector());
      } else {
        gravity_.segment(idx, n).noalias() =
            data_.J.middleCols(idx, n).transpose() * subtree_[i].toVector();
      }
      if (model.parents[i] > 0) subtree_[model.parents[i]] += subtree_[i];
    }
    nle_ = gravity_;
    return;
  }
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

void Stepper::joint_forces() {
  const auto& model = s_.model;
  const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
  accel_.resize(nj);
  accel_[0].setZero();
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    const int idx = model.idx_vs[i], n = model.nvs[i];
    if (n == 1) {
      one_column_add(accel_[model.parents[i]].toVector().data(), data_.J.col(idx).data(), a_[idx],
                     accel_[i].toVector().data());
    } else {
      accel_[i] = accel_[model.parents[i]] + pinocchio::Motion(joint_product(data_.J, a_, idx, n));
    }
    if (constant_mass_) {
      // The body's whole acceleration, J̇ v + J a, through its inertia at once (bias_forces
      // left the force at q̈ = 0 to here), less the external force: X − f is −f + X to the bit,
      // and assigned once (not −f first, then read back in pairs and added to).
      if (massless_[i]) {
        subtree_[i] = -fext_.of_joint[i];
      } else {
        // body * (drift + accel) + weight + body.vxiv(ov) − f_ext (body_force above)
        body_force(body_[i], drift_[i].toVector().data(), accel_[i].toVector().data(),
                   weight_[i].toVector().data(), data_.ov[i].toVector().data(),
                   fext_.of_joint[i].toVector().data(), subtree_[i].toVector().data(), nullptr);
      }
      continue;
    }
    subtree_[i] = body_force_[i] - fext_.of_joint[i];
    if (!massless_[i]) subtree_[i] += body_[i] * accel_[i];
  }
  for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
    if (model.parents[i] > 0) subtree_[model.parents[i]] += subtree_[i];
  }
}

void Stepper::world_inertias() {
  const auto& model = s_.model;
  const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
  body_.resize(nj);
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    if (fixed_inertia_[i]) continue;  // taken once (stepper_assembly.cpp fixed_inertias)
    body_[i] = massless_[i] ? pinocchio::Inertia::Zero() : data_.oMi[i].act(model.inertias[i]);
  }
}

void Stepper::mass_from_jacobian() {
  const auto& model = s_.model;
  const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
  world_inertias();
  composite_.assign(body_.begin(), body_.end());
  mass_.setZero(nv_, nv_);
  momenta_.resize(6, nv_);
  // A one-column joint's row of M is written into its column too as it is computed (a
  // contiguous store beside the row's): the lower triangle without a strided pass of its own
  // afterwards. A joint of several columns (a free flyer) fills its block row alone, and the
  // lower triangle is then mirrored from the upper at the end.
  bool mirror = false;
  for (pinocchio::JointIndex i = nj - 1; i > 0; --i) {
    const int idx = model.idx_vs[i], n = model.nvs[i], sub = data_.nvSubtree[i];
    if (slide_axes_[i] >= 0) {
      // A slide's column is a pure translation u: its momentum is m u at the centre of mass c,
      // (m u, c × m u), as Pinocchio's product with a zero angular part, and its row of M reads
      // only the linear parts of the subtree's momenta.
      const auto u = data_.J.col(idx).head<3>();
      auto momentum = momenta_.col(idx);
      momentum.head<3>() = composite_[i].mass() * u;
      momentum.tail<3>() = composite_[i].lever().cross(Eigen::Vector3d(momentum.head<3>()));
      for (int c = idx; c < idx + sub; ++c) {
        mass_(idx, c) = mass_(c, idx) = u.dot(momenta_.col(c).head<3>());
      }
    } else {
      for (int c = idx; c < idx + n; ++c) {
        momenta_.col(c) = (composite_[i] * pinocchio::Motion(data_.J.col(c))).toVector();
      }
      if (n == 1) {
        for (int c = idx; c < idx + sub; ++c) {
          mass_(idx, c) = mass_(c, idx) = data_.J.col(idx).dot(momenta_.col(c));
        }
      } else {
        mass_.block(idx, idx, n, sub).noalias() =
            data_.J.middleCols(idx, n).transpose() * momenta_.middleCols(idx, sub);
        mirror = true;
      }
    }
    const auto parent = model.parents[i];
    if (parent > 0) {
      // A massless parent (a compliant bearing's slide) holds its subtree alone: a copy, not
      // Pinocchio's sum of inertias about the combined centre of mass (a division and ~40
      // products).
      if (massless_[parent] && composite_[parent].mass() == 0.0) {
        composite_[parent] = composite_[i];
      } else {
        composite_[parent] += composite_[i];
      }
    }
  }
  mass_.diagonal() += model.armature;
  if (mirror) {
    mass_.triangularView<Eigen::StrictlyLower>() =
        mass_.transpose().triangularView<Eigen::StrictlyLower>();
  }
}

void Stepper::constraint_matrix() {
  const StepView sv = view();
  for (const size_t c : varying_) constraints_[c]->rows(sv, rows_of(jac_, c), rows_of(bias_, c));
}

double Stepper::residual() {
  if (!rows_) return 0.0;
  small_product(jac_, v_, jv_);
  return (jv_ - target_now_).cwiseAbs().maxCoeff();
}

bool Stepper::project(long k, double t, RunStatus& st) {
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

bool Stepper::check(long k, double t, const QpSolution& sol, RunStatus& st) {
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

const QpSolution* Stepper::solve_qp(long k, double t, RunStatus& st) {
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

void Stepper::assemble_positions() {
  kinematics();
  if (constant_mass_ && mass_.rows() == nv_) {
    world_inertias();
  } else {
    mass_from_jacobian();
  }
  constraint_matrix();
}

void Stepper::assemble_velocities() {
  velocity_kinematics();
  const StepView sv = view();
  for (const size_t c : varying_) constraints_[c]->biases(sv, rows_of(bias_, c));
  bias_forces();
}

bool Stepper::solve(long k, double t, RunStatus& st) {
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

void Stepper::weighted_bias() {
  if (nle_last_.size() != nv_) {
    nle_step_ = nle_;
    gravity_step_ = gravity_;
    return;
  }
  const double w = weights_.force_new;
  nle_step_ = nle_ + w * (nle_ - nle_last_);
  gravity_step_ = gravity_ + w * (gravity_ - gravity_last_);
}

bool Stepper::dynamics(long k, double t, RunStatus& st) {
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

void Stepper::bearing_reactions() {
  for (auto& f : fext_.of_joint) f.setZero();
  const StepView sv = view();
  for (size_t c = 0; c < constraints_.size(); ++c) {
    constraints_[c]->add_body_forces(sv, rows_of(lam_, c), fext_);
  }
  for (const auto& e : elements_) e->add_body_forces(sv, fext_);
  joint_forces();
}

bool Stepper::hand_bearing_loads() {
  bool wanted = false;
  for (const auto& e : elements_) wanted = wanted || e->wants_bearing_loads();
  if (!wanted) return false;
  bearing_reactions();
  const auto& bearings = s_.bearing_joints;
  bearing_loads_.resize(bearings.size());
  for (size_t b = 0; b < bearings.size(); ++b) {
    bearing_loads_[b] = data_.oMi[bearings[b]].actInv(subtree_[bearings[b]]).linear();
  }
  for (auto& r : row_loads_) r.setZero();
  for (const auto& e : elements_) e->row_forces(row_loads_);
  for (auto& e : elements_) e->bearing_loads(bearing_loads_, row_loads_);
  return true;
}

void Stepper::record(long k, double t) {
  // M v first, its dot with v last: the stores of M v are in the cache by then rather than
  // still in flight (read back in pairs by the dot, they would not forward).
  symmetric_product(mass_, v_, mv_);
  out_.at(Series::time, k) = t;
  // The joint rows copied as bytes (Eigen's copy of a dynamic vector into a Map peels for
  // alignment: a hundred instructions for eight values).
  const auto copy_row = [&](Series series, const Eigen::VectorXd& x) {
    const auto bytes = sizeof(double) * static_cast<size_t>(x.size());
    std::memcpy(joint_row(series, k).data(), x.data(), bytes);
  };
  copy_row(Series::angle, q_);
  copy_row(Series::speed, v_);
  // ā, the step's mean acceleration: the one the multipliers and bearing reactions of the
  // sample come from. a_k itself carries, at ρ∞ = 1, an error of alternating sign after a
  // jump in the forces (a torque step, a flank switch) that never decays; ā does not.
  copy_row(Series::acceleration, a_);
  copy_row(Series::torque, tau_applied_);
  const StepView sv = view();
  for (size_t c = 0; c < constraints_.size(); ++c) {
    constraints_[c]->record(sv, k, rows_of(lam_, c), out_);
  }
  for (const auto& e : elements_) e->record(sv, k, out_);
  const auto& bearings = s_.bearing_joints;
  for (size_t b = 0; b < bearings.size(); ++b) {
    // The joint's reaction (joint_forces leaves it in world axes, about the world origin):
    // in world axes about the bearing centre p, (f, m − p × f), and in the joint's own frame.
    // Component by component, in the operations and order of Eigen's expressions (p × f as
    // Eigen's cross; Rᵀ x as its vectorised dot of R's column with x, (R₀ᵢx₀ + R₁ᵢx₁) + R₂ᵢx₂),
    // so that no 3-vector is stored in parts and read back as pairs (a stalled store
    // forwarding: a fifth of record's time on the drivetrain).
    const pinocchio::SE3& joint = data_.oMi[bearings[b]];
    const pinocchio::Force& world = subtree_[bearings[b]];
    const double* f = world.linear().data();
    const double* a = world.angular().data();
    const double* p = joint.translation().data();
    const double moment[3] = {a[0] - (p[1] * f[2] - p[2] * f[1]),
                              a[1] - (p[2] * f[0] - p[0] * f[2]),
                              a[2] - (p[0] * f[1] - p[1] * f[0])};
    const long e = out_.entry(Family::bearing, k, static_cast<long>(b));
    double* force_out = &out_.at(Series::bearing_force, e);
    double* moment_out = &out_.at(Series::bearing_moment, e);
    double* force_local = &out_.at(Series::bearing_force_local, e);
    double* moment_local = &out_.at(Series::bearing_moment_local, e);
    const auto& r = joint.rotation();
    for (int i = 0; i < 3; ++i) {
      force_out[i] = f[i];
      moment_out[i] = moment[i];
      force_local[i] = (r(0, i) * f[0] + r(1, i) * f[1]) + r(2, i) * f[2];
      moment_local[i] = (r(0, i) * moment[0] + r(1, i) * moment[1]) + r(2, i) * moment[2];
    }
  }
  const Eigen::Index nb = static_cast<Eigen::Index>(s_.frame_parent.size());
  pinocchio::SE3 moved;
  for (Eigen::Index b = 0; b < nb; ++b) {
    // Each link is rigid on a joint: its pose is the joint's placement times a constant one.
    // The quaternion is converted into the output itself (Eigen's conversion, through a
    // Map), not into a local one copied after its parts were stored (store forwarding).
    const pinocchio::SE3& joint = data_.oMi[s_.frame_parent[b]];
    if (!frame_at_joint_[b]) {
      // joint * placement (Pinocchio's SE3 product: R R_p, t + R t_p) written into moved in
      // place, not built in a temporary and copied (its parts read back in pairs)
      const pinocchio::SE3& placement = s_.frame_placement[b];
      moved.rotation().noalias() = joint.rotation() * placement.rotation();
      moved.translation().noalias() = joint.rotation() * placement.translation();
      moved.translation() += joint.translation();
    }
    const pinocchio::SE3& pose = frame_at_joint_[b] ? joint : moved;
    const long e = out_.entry(Family::body, k, b);
    vec3(Series::body_position, e) = pose.translation();
    Eigen::Map<Eigen::Quaterniond>(&out_.at(Series::body_quaternion, e)) = pose.rotation();
  }
  out_.at(Series::constraint_residual, k) = residual_;
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
  out_.at(Series::friction_loss, k) = ledger_.friction;
  double parametric = 0.0;
  for (const auto& e : elements_) parametric += e->parametric_work();
  out_.at(Series::work_parametric, k) = parametric;
}

void Stepper::advance() {
  const double h = s_.dt;
  v_next_ = v_ + a_ * h;
  mid_ = (0.5 * h) * (v_ + v_next_);
  dq_ = h * v_ + weights_.step_gain * a_;
  if (weights_.memory_gain != 0.0) dq_ += weights_.memory_gain * accel_memory_;
  // Summed by add_work (above), in the elements' order from 0 as before.
  double sums[4] = {0.0, 0.0, 0.0, 0.0};
  const StepView sv = view();
  v_mid_ = mid_ / h;
  for (const auto& e : elements_) add_work(e->work(sv, v_next_, v_mid_), sums);
  StepWork elements;
  elements.elastic = sums[0];
  elements.dissipated = sums[1];
  elements.applied = sums[2];
  elements.friction = sums[3];
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
  step.friction = elements.friction;
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
  if (vector_space_) {
    q_ += dq_;  // every joint a plain coordinate: Pinocchio's integrate is q + dq
  } else {
    integrate(s_.model, q_, dq_, q_next_);
    q_ = q_next_;
  }
  v_ = v_next_;
}

}  // namespace pinwind
