// Constrained dynamics of one step as an equality QP, solved through the Schur complement of its
// KKT system (minimum-norm multipliers for redundant rows), or with proxsuite's proximal method
// for redundant rows when SolverSettings.iterative is set.
//
// Gauss's principle (design.md §2):
//
//     minimise ½ aᵀ M a − (τ − b)ᵀ a     subject to   J a = r
//
// proxsuite's stationarity condition is M a − (τ − b) + Jᵀ y = 0, so the constraint forces are
// λ = −y: the generalised force of the constraints is Jᵀ λ. Rigid multi-planet stages give
// redundant rows (a 3-planet stage's 6 mesh rows have rank 4): the KKT matrix is singular and a
// plain KKT solve fails, but the proximal method of multipliers converges, and because its dual
// updates stay in range(J M⁻¹ Jᵀ) it returns the minimum-norm multipliers, i.e. equal load
// sharing in a symmetric stage. What keeps that property:
//
// - no preconditioner: proxsuite's Ruiz equilibration rescales the rows, and the multipliers it
//   returns are then minimum-norm in the scaled rows, not in newtons;
// - a fresh solve starts from proxsuite's equality-constrained initial guess, the solution of the
//   regularised KKT system, which lies in range(J M⁻¹ Jᵀ); later solves warm-start from the
//   previous solution. Neither has a null-space component and the dual updates add none. Warm
//   starting also brings a step down to zero to two proximal iterations;
// - the right-hand side is projected onto range(J): redundant rows have right-hand sides that
//   agree only up to rounding, and left as they are the system is inconsistent at the 1e-12
//   level, the proximal iterations cannot converge and the multipliers of the redundant
//   directions drift.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/Core>
#include <Eigen/SVD>
#include <proxsuite/proxqp/dense/dense.hpp>

namespace pinwind {

struct SolverSettings {
  double eps_abs = 1e-13;
  double eps_rel = 0.0;
  long max_iter = 1000;
  // Redundant rows by proxsuite's proximal iterations instead of the pseudo-inverse of the
  // Schur complement (both give the minimum-norm multipliers).
  bool iterative = false;
};

struct QpSolution {
  Eigen::VectorXd acceleration;  // a [rad/s²]
  Eigen::VectorXd multipliers;   // λ [N for mesh rows, N·m for driver rows]
  double primal_residual = 0.0;  // ‖J a − r‖∞
  double dual_residual = 0.0;    // ‖M a − (τ − b) − Jᵀ λ‖∞ [N·m]
  long iterations = 0;
  bool solved = true;
  std::string status = "unconstrained";
};

// A power of two within a factor two of x (x > 0): dividing by it is exact.
inline double power_of_two(double x) {
  int exponent = 0;
  std::frexp(x, &exponent);
  return std::ldexp(1.0, exponent);
}

inline std::string status_name(proxsuite::proxqp::QPSolverOutput status) {
  using proxsuite::proxqp::QPSolverOutput;
  switch (status) {
    case QPSolverOutput::PROXQP_SOLVED:
      return "PROXQP_SOLVED";
    case QPSolverOutput::PROXQP_MAX_ITER_REACHED:
      return "PROXQP_MAX_ITER_REACHED";
    case QPSolverOutput::PROXQP_PRIMAL_INFEASIBLE:
      return "PROXQP_PRIMAL_INFEASIBLE";
    case QPSolverOutput::PROXQP_DUAL_INFEASIBLE:
      return "PROXQP_DUAL_INFEASIBLE";
    case QPSolverOutput::PROXQP_NOT_RUN:
      return "PROXQP_NOT_RUN";
    default:
      return "PROXQP_STATUS_" + std::to_string(static_cast<int>(status));
  }
}

// A proxsuite dense QP of fixed size reused for every step.
class ConstrainedQp {
 public:
  using QP = proxsuite::proxqp::dense::QP<double>;

  ConstrainedQp(Eigen::Index nv, Eigen::Index rows, SolverSettings settings)
      : nv_(nv), rows_(rows), settings_(settings) {}

  // Solves M a = force + Jᵀ λ, J a = rhs.
  //
  // mass: joint-space inertia M [kg·m²]; force: τ − b [N·m]; jac: rows J; rhs: r.
  const QpSolution& solve(const Eigen::MatrixXd& mass, const Eigen::VectorXd& force,
                          const Eigen::MatrixXd& jac, const Eigen::VectorXd& rhs) {
    QpSolution& out = solution_;
    if (rows_ == 0) {
      out.acceleration = mass.ldlt().solve(force);
      out.multipliers.resize(0);
      return out;
    }
    const bool rows_changed = refresh_rows(jac);
    if (full_rank_ || !settings_.iterative) {
      return solve_direct(mass, force, jac, rhs, rows_changed);
    }
    rhs_.resize(rhs.size());
    rhs_.noalias() = range_ * rhs;
    // Scale the QP to unit size with powers of two, which are exact in floating point: the cost
    // by the largest inertia (so the dual residual is in rad/s² like the primal one), the
    // unknowns by the size of the data. One absolute tolerance then means the same relative
    // accuracy in every run, and a uniform scaling keeps the multipliers minimum-norm. A change
    // of the data scale restarts the solve like new rows do.
    const double previous_mass_scale = mass_scale_;
    const bool mass_changed = refresh_mass(mass);
    g_ = -force / mass_scale_;
    const double size = std::max(g_.cwiseAbs().maxCoeff(), rhs_.cwiseAbs().maxCoeff());
    const double data_scale = size > 0.0 ? power_of_two(size) : 1.0;
    const bool restart = rows_changed || data_scale != data_scale_ ||
                         mass_scale_ != previous_mass_scale || !qp_;
    data_scale_ = data_scale;
    g_ /= data_scale;
    rhs_ /= data_scale;
    if (restart) {
      start(jac_cache_);
    } else {
      // Unchanged H and A are not passed again: proxsuite then keeps its factorisation.
      if (mass_changed) {
        qp_->update(h_, g_, proxsuite::nullopt, rhs_, proxsuite::nullopt, proxsuite::nullopt,
                    proxsuite::nullopt, false);
      } else {
        qp_->update(proxsuite::nullopt, g_, proxsuite::nullopt, rhs_, proxsuite::nullopt,
                    proxsuite::nullopt, proxsuite::nullopt, false);
      }
      qp_->solve();
      if (qp_->results.info.status != proxsuite::proxqp::QPSolverOutput::PROXQP_SOLVED) {
        start(jac_cache_);
      }
    }
    const auto& res = qp_->results;
    out.acceleration = data_scale * res.x;
    out.multipliers = -(mass_scale_ * data_scale) * res.y;
    out.solved = res.info.status == proxsuite::proxqp::QPSolverOutput::PROXQP_SOLVED;
    out.status = status_name(res.info.status);
    // proxsuite's residuals (∞-norms) of the scaled problem, back in SI units.
    out.primal_residual = res.info.pri_res * data_scale;
    out.dual_residual = res.info.dua_res * data_scale * mass_scale_;
    out.iterations = static_cast<long>(res.info.iter);
    return out;
  }

 private:
  // The KKT system through the Schur complement, its factorisations kept while M and J stay the
  // same (as they do for gears on fixed or carrier-borne axes). The rows are first reduced to an
  // orthonormal basis of their span, J = U J_b with U (rows × rank) from the SVD of J (taken only
  // when J changes), so that the Schur complement S_b = J_b M⁻¹ J_bᵀ has full rank even for the
  // redundant rows of a rigid multi-planet stage:
  //
  //     μ = S_b⁻¹ (Uᵀ r − J_b M⁻¹ f),   a = M⁻¹ (f + J_bᵀ μ),   λ = U μ.
  //
  // λ lies in range(J) = range(J M⁻¹ Jᵀ): the minimum-norm multipliers, the same that
  // proxsuite's proximal iterations converge to (module comment), in one step; Uᵀ r projects
  // the right-hand side onto range(J).
  //
  // A Hessian that differs from the factorised one M₀ only on a few diagonal entries,
  // M = M₀ + E D Eᵀ (a torque law's implicit weight on its joint changing every step,
  // joint_torque.hpp), keeps M₀'s factorisations: with (a₀, μ₀) the solution for M₀ and Z the
  // constrained responses to unit forces on those joints (columns of E, right-hand side 0),
  //
  //     c = (I + Eᵀ Z D)⁻¹ Eᵀ a₀,   a = a₀ − Z D c,   μ = μ₀ − Z_μ D c
  //
  // (Woodbury's identity on the KKT system: exact, the same solution up to rounding). Any
  // other change of M costs two small LDLT factorisations. A correction that would amplify
  // rounding (a diagonal of I + Eᵀ Z D below ½: a weight far below M₀'s) refactorises instead.
  const QpSolution& solve_direct(const Eigen::MatrixXd& mass, const Eigen::VectorXd& force,
                                 const Eigen::MatrixXd&, const Eigen::VectorXd& rhs,
                                 bool rows_changed) {
    QpSolution& out = solution_;
    const bool refactor = rows_changed || !direct_ready_ || !diagonal_change(mass);
    if (refactor) factorise(mass);
    free_ = mass_ldlt_.solve(force);
    projected_rhs_.noalias() = row_basis_.transpose() * rhs;
    reduced_rhs_ = projected_rhs_;
    reduced_rhs_.noalias() -= reduced_jac_ * free_;
    mu_ = schur_ldlt_.solve(reduced_rhs_);
    out.acceleration = free_;
    out.acceleration.noalias() += minv_jt_ * mu_;
    if (!changed_.empty() && !correct(out.acceleration)) {
      factorise(mass);
      return solve_direct(mass, force, reduced_jac_, rhs, false);
    }
    out.multipliers.noalias() = row_basis_ * mu_;
    // The residuals in work vectors: a product inside a larger expression would allocate.
    primal_.noalias() = reduced_jac_ * out.acceleration;
    out.primal_residual = (primal_ - projected_rhs_).cwiseAbs().maxCoeff();
    dual_.noalias() = mass * out.acceleration;
    dual_ -= force;
    dual_.noalias() -= reduced_jac_.transpose() * mu_;
    out.dual_residual = dual_.cwiseAbs().maxCoeff();
    out.iterations = 0;
    out.solved = std::isfinite(out.primal_residual) && std::isfinite(out.dual_residual);
    out.status = "direct";
    // A later iterative step starts proxsuite afresh.
    qp_.reset();
    return out;
  }

  // Factorises M (and the Schur complement over the current rows); forgets the responses.
  //
  // Compliant meshes change M every step (their weights follow the mesh stiffness), so this
  // runs once per step there: M⁻¹ J_bᵀ column by column and S_b by lazy products, because at
  // these sizes (nv of 6 to 20, a few rows) Eigen's blocked matrix solve and GEMM spend more
  // on packing and temporaries than on the arithmetic.
  void factorise(const Eigen::MatrixXd& mass) {
    direct_mass_ = mass;
    mass_ldlt_.compute(mass);
    minv_jt_.resize(reduced_jac_.cols(), reduced_jac_.rows());
    for (Eigen::Index r = 0; r < reduced_jac_.rows(); ++r) {
      minv_jt_.col(r) = mass_ldlt_.solve(reduced_jac_.row(r).transpose());
    }
    schur_.resize(reduced_jac_.rows(), reduced_jac_.rows());
    schur_.noalias() = reduced_jac_.lazyProduct(minv_jt_);
    schur_ldlt_.compute(schur_);
    direct_ready_ = true;
    responses_.clear();
    changed_.clear();
  }

  // Whether M differs from the factorised M₀ on at most kMaxCorrections diagonal entries and
  // nowhere else; fills changed_ with those entries and their differences.
  bool diagonal_change(const Eigen::MatrixXd& mass) {
    changed_.clear();
    if (direct_mass_.rows() != mass.rows() || direct_mass_.cols() != mass.cols()) return false;
    for (Eigen::Index j = 0; j < mass.cols(); ++j) {
      for (Eigen::Index i = 0; i < mass.rows(); ++i) {
        const double d = mass(i, j) - direct_mass_(i, j);
        if (d == 0.0) continue;
        if (i != j || changed_.size() == kMaxCorrections) return false;
        changed_.push_back({i, d});
      }
    }
    return true;
  }

  // The constrained response (a, μ) to a unit force on joint i with J a = 0, kept per joint
  // while M₀ and the rows stay.
  const std::pair<Eigen::VectorXd, Eigen::VectorXd>& response(Eigen::Index i) {
    for (const auto& r : responses_) {
      if (r.first == i) return r.second;
    }
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(direct_mass_.rows());
    unit[i] = 1.0;
    Eigen::VectorXd a = mass_ldlt_.solve(unit);
    const Eigen::VectorXd mu = schur_ldlt_.solve(-(reduced_jac_ * a));
    a.noalias() += minv_jt_ * mu;
    responses_.push_back({i, {a, mu}});
    return responses_.back().second;
  }

  // Applies the Woodbury correction of changed_ to (a, mu_); false if it would amplify rounding.
  bool correct(Eigen::VectorXd& a) {
    const auto k = static_cast<Eigen::Index>(changed_.size());
    Eigen::MatrixXd c = Eigen::MatrixXd::Identity(k, k);
    Eigen::VectorXd y(k);
    for (Eigen::Index q = 0; q < k; ++q) {
      const auto& z = response(changed_[q].first).first;
      for (Eigen::Index p = 0; p < k; ++p) c(p, q) += z[changed_[p].first] * changed_[q].second;
      y[q] = a[changed_[q].first];
    }
    if (c.diagonal().minCoeff() < 0.5) return false;
    Eigen::VectorXd x(k);
    if (k == 1) {
      x[0] = y[0] / c(0, 0);
    } else if (k == 2) {
      const double det = c(0, 0) * c(1, 1) - c(0, 1) * c(1, 0);
      x[0] = (c(1, 1) * y[0] - c(0, 1) * y[1]) / det;
      x[1] = (c(0, 0) * y[1] - c(1, 0) * y[0]) / det;
    } else {
      x = c.partialPivLu().solve(y);
    }
    for (Eigen::Index q = 0; q < k; ++q) {
      const auto& r = response(changed_[q].first);
      const double s = changed_[q].second * x[q];
      a.noalias() -= s * r.first;
      mu_.noalias() -= s * r.second;
    }
    return true;
  }

  void start(const Eigen::MatrixXd& jac) {
    qp_ = std::make_unique<QP>(nv_, rows_, 0);
    qp_->settings.eps_abs = settings_.eps_abs;
    qp_->settings.eps_rel = settings_.eps_rel;
    qp_->settings.max_iter = settings_.max_iter;
    qp_->settings.verbose = false;
    qp_->settings.initial_guess =
        proxsuite::proxqp::InitialGuessStatus::EQUALITY_CONSTRAINED_INITIAL_GUESS;
    qp_->init(h_, g_, jac, rhs_, proxsuite::nullopt, proxsuite::nullopt, proxsuite::nullopt,
              false);
    qp_->solve();
    qp_->settings.initial_guess =
        proxsuite::proxqp::InitialGuessStatus::WARM_START_WITH_PREVIOUS_RESULT;
  }

  // Whether J differs from the previous step's (to 1e-12); refreshes the range projector,
  // which is kept while J stays the same, as it does for gears on fixed or carrier-borne axes.
  bool refresh_rows(const Eigen::MatrixXd& jac) {
    if (jac_cache_.rows() == jac.rows() && jac_cache_.cols() == jac.cols() &&
        (jac - jac_cache_).cwiseAbs().maxCoeff() <= 1e-12 * jac.cwiseAbs().maxCoeff()) {
      return false;
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(jac, Eigen::ComputeThinU);
    const auto& sv = svd.singularValues();
    Eigen::Index rank = 0;
    if (sv.size() && sv[0] > 0.0) {
      while (rank < sv.size() && sv[rank] > 1e-10 * sv[0]) ++rank;
    }
    row_basis_ = svd.matrixU().leftCols(rank);
    range_ = row_basis_ * row_basis_.transpose();
    reduced_jac_ = row_basis_.transpose() * jac;
    full_rank_ = rank == jac.rows();
    jac_cache_ = jac;
    return true;
  }

  // Whether M differs from the previous step's (to 1e-12); refreshes its scaled copy.
  bool refresh_mass(const Eigen::MatrixXd& mass) {
    if (mass_cache_.size() == mass.size() &&
        (mass - mass_cache_).cwiseAbs().maxCoeff() <= 1e-12 * mass_scale_) {
      return false;
    }
    mass_cache_ = mass;
    mass_scale_ = power_of_two(mass.cwiseAbs().maxCoeff());
    h_ = mass / mass_scale_;
    return true;
  }

  Eigen::Index nv_, rows_;
  SolverSettings settings_;
  std::unique_ptr<QP> qp_;
  double data_scale_ = 0.0;
  double mass_scale_ = 1.0;
  Eigen::MatrixXd mass_cache_, h_, jac_cache_, range_;
  Eigen::VectorXd g_, rhs_;
  bool full_rank_ = true;
  QpSolution solution_;
  // Direct solve of full-rank rows.
  bool direct_ready_ = false;
  Eigen::MatrixXd direct_mass_, minv_jt_, schur_;
  Eigen::LDLT<Eigen::MatrixXd> mass_ldlt_, schur_ldlt_;
  Eigen::MatrixXd row_basis_, reduced_jac_;
  Eigen::VectorXd free_, projected_rhs_, reduced_rhs_, mu_;
  Eigen::VectorXd primal_, dual_;  // solve_direct's residuals
  // Diagonal entries where M differs from the factorised M₀, and the responses to them.
  static constexpr size_t kMaxCorrections = 2;
  std::vector<std::pair<Eigen::Index, double>> changed_;
  std::vector<std::pair<Eigen::Index, std::pair<Eigen::VectorXd, Eigen::VectorXd>>> responses_;
};

}  // namespace pinwind
