// The Stepper's static start: Stepper::equilibrium (stepper.hpp).
#include <algorithm>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "equilibration.hpp"

#include "joint_algorithms.hpp"
#include "stepper.hpp"

namespace pinwind {

EquilibriumStatus Stepper::equilibrium(const RowMat& torque, const RowMat& target,
                                       const RowMat& inputs, long max_iterations,
                                       double tolerance) {
  EquilibriumStatus st;
  time_ = 0.0;
  inputs_ = s_.input_columns ? inputs.row(0).data() : nullptr;
  tau_applied_ = torque.row(0).transpose();
  target_row_ = target.cols() ? target.row(0).data() : nullptr;
  target_next_row_ = target.cols() ? target.row(1).data() : nullptr;
  targets();
  const Eigen::VectorXd q_start = q_;
  weights_ = StepWeights::static_solve();
  dq_free_.setZero(nv_);
  RunStatus unused;
  constexpr int kPasses = 8;
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
      bool settled = true;
      for (auto& e : elements_) settled = !e->settle(sv, dq, pass + 1 == kPasses) && settled;
      if (settled) break;
      ++st.flank_switches;
    }
    integrate(s_.model, q_, dq, q_next_);
    q_ = q_next_;
    st.iterations = it + 1;
    st.correction = dq.cwiseAbs().maxCoeff();
    Eigen::VectorXd moved(nv_);
    difference(s_.model, q_start, q_, moved);
    st.displacement = moved.cwiseAbs().maxCoeff();
    if (st.correction <= tolerance * st.displacement || st.correction == 0.0) {
      st.converged = true;
      break;
    }
  }
  return st;
}

Eigen::VectorXd Stepper::static_displacement(EquilibriumStatus& st) {
  if (!(hessian_.cwiseAbs().maxCoeff() > 0.0)) return Eigen::VectorXd::Zero(nv_);
  const Eigen::Index n = nv_, r = rows_;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n + 2 * r, 2 * n + r);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * n + 2 * r);
  a.topLeftCorner(n, n) = mass_;
  a.block(0, n, n, n) = hessian_;
  a.block(0, 2 * n, n, r) = -jac_.transpose();
  a.block(n, 0, r, n) = jac_;
  a.block(n + r, n, r, n) = jac_;
  a.block(n + 2 * r, 0, n, n) = hessian_;
  b.head(n) = force_;
  b.segment(n, r) = (target_next_ - target_now_) / s_.dt - bias_;
  // Scaled rows and columns (equilibration.hpp): a spring 1e8 times softer than the stiffest
  // has its own pivot. Unscaled, the block [[M, K], [K, 0]] of a soft coordinate has the pivot
  // K²/M, below the rank threshold for springs ~1e6 times softer than the stiffest.
  const Equilibration scale = equilibrate(a);
  b.array() *= scale.rows.array();
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  cod.setThreshold(1e-12);
  cod.compute(a);
  const Eigen::VectorXd x = cod.solve(b);
  st.residual = (a * x - b).norm() / std::max(b.norm(), 1e-300);
  const Eigen::VectorXd dq = scale.columns.segment(n, n).cwiseProduct(x.segment(n, n));
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
