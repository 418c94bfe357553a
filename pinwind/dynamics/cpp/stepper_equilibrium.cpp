// The Stepper's static start: Stepper::equilibrium (stepper.hpp).
#include <algorithm>
#include <cmath>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "joint_algorithms.hpp"
#include "stepper.hpp"

namespace pinwind {

EquilibriumStatus Stepper::equilibrium(const RowMat& torque, const RowMat& target,
                                       const RowMat& inputs, long max_iterations,
                                       double tolerance, long load_steps) {
  EquilibriumStatus st;
  time_ = 0.0;
  inputs_ = s_.input_columns ? inputs.row(0).data() : nullptr;
  const Eigen::VectorXd tau_full = torque.row(0).transpose();
  const long steps = std::max(load_steps, 1L);
  target_row_ = target.cols() ? target.row(0).data() : nullptr;
  target_next_row_ = target.cols() ? target.row(1).data() : nullptr;
  targets();
  const Eigen::VectorXd q_start = q_;
  weights_ = StepWeights::static_solve();
  dq_free_.setZero(nv_);
  RunStatus unused;
  constexpr int kPasses = 8;
  for (long step = 1; step <= steps; ++step) {
    tau_applied_ = tau_full * (static_cast<double>(step) / static_cast<double>(steps));
    st.converged = false;
    for (long it = 0; it < max_iterations; ++it) {
      assemble_positions();
      if (residual() > s_.projection_tol * (1.0 + v_.cwiseAbs().maxCoeff()) &&
          !project(0, 0.0, unused)) {
        break;
      }
      assemble_velocities();
      const StepView sv = view();
      elements_force_.setZero(nv_);
      for (auto& e : elements_) {
        e->prepare(sv);
        e->add_force(sv, elements_force_);
      }
      Eigen::VectorXd dq;
      for (int pass = 0; pass < kPasses; ++pass) {
        hessian_.setZero(nv_, nv_);
        force_ = tau_applied_ + elements_force_ - nle_;
        for (auto& e : elements_) e->add_implicit(sv, hessian_, force_);
        hessian_.triangularView<Eigen::StrictlyUpper>() = hessian_.transpose();
        dq = static_displacement(st);
        // The rigid meshes take the flanks the step takes (Stepper::dynamics): a row whose
        // multiplier pulls hands its load to the other flank. Where an axis can move (a planet on
        // a compliant bearing) the other flank's line of action is the mirror image about the
        // centre line (n = s cos α_w t + ε sin α_w r̂), not the same line reversed: left on the
        // pulling flank, a planet's sun and ring forces added their radial parts instead of
        // cancelling them, and the first step found that start out of equilibrium by the planet's
        // whole radial deflection (~200 m/s² on its slides).
        RowSwitch change = RowSwitch::none;
        for (size_t c = 0; c < constraints_.size(); ++c) {
          change = std::max(change, constraints_[c]->switch_rows(sv, rows_of(lam_, c)));
        }
        if (change != RowSwitch::none) constraint_matrix();
        bool settled = true;
        for (auto& e : elements_) settled = !e->settle(sv, dq, pass + 1 == kPasses) && settled;
        if (change == RowSwitch::none && settled) break;
        ++st.flank_switches;
        // A flip on fixed axes is the same row reversed: Δq and ā carry over.
        if (change != RowSwitch::solve && settled) break;
      }
      integrate(s_.model, q_, dq, q_next_);
      q_ = q_next_;
      ++st.iterations;
      st.correction = dq.cwiseAbs().maxCoeff();
      Eigen::VectorXd moved(nv_);
      difference(s_.model, q_start, q_, moved);
      st.displacement = moved.cwiseAbs().maxCoeff(&st.largest);
      if (st.correction <= tolerance * st.displacement || st.correction == 0.0) {
        st.converged = true;
        break;
      }
    }
    // A step that stops short of the tolerance (a contact that keeps changing near its switch)
    // still hands the next one a start near its equilibrium; one that diverged does not.
    if (!std::isfinite(st.correction) || st.correction > st.displacement) break;
  }
  return st;
}

Eigen::VectorXd Stepper::static_displacement(EquilibriumStatus& st) {
  const Eigen::Index n = nv_, r = rows_;
  // Each coordinate in its own units: ā_i = s_i â_i and Δq_i = (s_i / κ_i) ŷ_i with
  // s_i = 1/√M_ii and κ_i = K_ii / M_ii (ω_i², the coordinate's own spring over its own mass),
  // each force row i times s_i and each row K ā = 0 times s_i / κ_i: the blocks M and K of
  // every coordinate have unit diagonals, so that the rank decision sees a soft spring (a
  // tower, a torque arm, a coupling) beside the stiffest bearing as it sees the stiff one.
  // Unscaled, the pivot of a soft coordinate's block [[M, K], [K, 0]] is K²/M: springs ~1e6
  // times softer than the stiffest fell below the rank threshold and took no load. A
  // coordinate without stiffness takes the geometric mean of the others' κ.
  const Eigen::VectorXd m = mass_.diagonal(), k = hessian_.diagonal();
  if (!(k.maxCoeff() > 0.0)) return Eigen::VectorXd::Zero(nv_);
  double log_sum = 0.0;
  long sprung = 0;
  const double mass_floor = m.maxCoeff() * 1e-300;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (k[i] > 0.0) {
      log_sum += std::log(k[i] / std::max(m[i], mass_floor));
      ++sprung;
    }
  }
  const double kappa_free = std::exp(log_sum / static_cast<double>(sprung));
  Eigen::VectorXd s(n), kappa(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double mi = m[i] > 0.0 ? m[i] : m.maxCoeff();
    s[i] = 1.0 / std::sqrt(mi);
    kappa[i] = k[i] > 0.0 ? k[i] / mi : kappa_free;
  }
  const Eigen::VectorXd dq_scale = s.cwiseQuotient(kappa);  // Δq_i = dq_scale_i ŷ_i
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n + 2 * r, 2 * n + r);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * n + 2 * r);
  a.topLeftCorner(n, n) = s.asDiagonal() * mass_ * s.asDiagonal();
  a.block(0, n, n, n) = s.asDiagonal() * hessian_ * dq_scale.asDiagonal();
  a.block(0, 2 * n, n, r) = -(s.asDiagonal() * jac_.transpose());
  a.block(n, 0, r, n) = jac_ * s.asDiagonal();
  a.block(n + r, n, r, n) = jac_ * dq_scale.asDiagonal();
  a.block(n + 2 * r, 0, n, n) = dq_scale.asDiagonal() * hessian_ * s.asDiagonal();
  b.head(n) = s.cwiseProduct(force_);
  b.segment(n, r) = (target_next_ - target_now_) / s_.dt - bias_;
  // The rows' own units: each row of J ā = r and J Δq = 0 and each multiplier's column to a
  // largest entry of 1 (which leaves ā and Δq as they are).
  for (Eigen::Index i = n; i < n + 2 * r; ++i) {
    const double norm = a.row(i).cwiseAbs().maxCoeff();
    if (norm > 0.0) {
      a.row(i) /= norm;
      b[i] /= norm;
    }
  }
  Eigen::VectorXd multiplier_scale = Eigen::VectorXd::Ones(r);
  for (Eigen::Index j = 2 * n; j < 2 * n + r; ++j) {
    const double norm = a.col(j).cwiseAbs().maxCoeff();
    if (norm > 0.0) {
      a.col(j) /= norm;
      multiplier_scale[j - 2 * n] = norm;
    }
  }
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  cod.setThreshold(1e-12);
  cod.compute(a);
  const Eigen::VectorXd x = cod.solve(b);
  st.residual = (a * x - b).norm() / std::max(b.norm(), 1e-300);
  // The rows' multipliers λ [N or N·m] in lam_, unscaled, for the rigid rows' flanks.
  lam_ = x.segment(2 * n, r).cwiseQuotient(multiplier_scale);
  const Eigen::VectorXd dq = dq_scale.cwiseProduct(x.segment(n, n));
  return dq - free_part(dq);
}

Eigen::VectorXd Stepper::free_part(const Eigen::VectorXd& dq) const {
  // The motions no element and no row resists: the null space of [K; J], each row scaled to a
  // largest entry of 1 (which leaves the null space as it is).
  const Eigen::Index n = nv_, r = rows_;
  Eigen::MatrixXd stacked(n + r, n);
  stacked << hessian_, jac_;
  for (Eigen::Index i = 0; i < stacked.rows(); ++i) {
    const double norm = stacked.row(i).cwiseAbs().maxCoeff();
    if (norm > 0.0) stacked.row(i) /= norm;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(stacked, Eigen::ComputeFullV);
  svd.setThreshold(1e-10);
  const Eigen::Index rank = svd.rank();
  if (rank == n) return Eigen::VectorXd::Zero(n);
  const auto free = svd.matrixV().rightCols(n - rank);
  return free * (free.transpose() * dq);
}

}  // namespace pinwind
