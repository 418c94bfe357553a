// The constrained step QP's solves (constrained_qp.hpp documents the method).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <proxsuite/proxqp/dense/dense.hpp>

#include "constrained_qp.hpp"
#include "small_products.hpp"

namespace pinwind {
namespace {

// A power of two within a factor two of x (x > 0): dividing by it is exact.
double power_of_two(double x) {
  int exponent = 0;
  std::frexp(x, &exponent);
  return std::ldexp(1.0, exponent);
}

std::string status_name(proxsuite::proxqp::QPSolverOutput status) {
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

// y = A x for a column-major A whose row count is a multiple of 8 (zero rows padding it), y
// of that length: eight rows at a time by eight_rows_product (small_products.hpp), each y_i
// summed over the columns in order from 0, zero inputs skipped. small_product's loop for any
// row count keeps the sums in memory, and GCC's own vectorisation of this loop took two
// columns at a time and shuffled them (callgrind, the drivetrain's 15 × 15 map and two 8-row
// products: 1.76k and 1.96k instructions a step, against 0.8k here). A must be finite.
void product_by_blocks(const Eigen::MatrixXd& a, const double* x, double* y) {
  // zero inputs skipped: the rigid rows' r is 0 at constant speed targets
  for (Eigen::Index b = 0; b < a.rows(); b += 8) {
    eight_rows_product<true>(a.data() + b, a.rows(), a.cols(), x, y + b);
  }
}

}  // namespace

ConstrainedQp::ConstrainedQp(Eigen::Index nv, Eigen::Index rows, SolverSettings settings)
    : nv_(nv), rows_(rows), settings_(settings) {}

const QpSolution& ConstrainedQp::solve(const Eigen::MatrixXd& mass, const Eigen::VectorXd& force,
                                       const Eigen::MatrixXd& jac, const Eigen::VectorXd& rhs) {
  QpSolution& out = solution_;
  if (rows_ == 0) {
    out.acceleration = mass.ldlt().solve(force);
    out.multipliers.resize(0);
    return out;
  }
  const bool rows_changed = refresh_rows(jac);
  if (fixed_rows_) return solve_fixed(mass, force, rhs);
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

// Uᵀ r into projected_rhs_, each entry the dot of a column of U with r summed in order: a loop,
// where Eigen's general kernel cost more in its call and blocking than the few products
// (small_products.hpp).
void ConstrainedQp::project_rhs(const Eigen::VectorXd& rhs) {
  projected_rhs_.resize(row_basis_.cols());
  for (Eigen::Index j = 0; j < row_basis_.cols(); ++j) {
    const double* column = row_basis_.col(j).data();
    double s = 0.0;
    for (Eigen::Index i = 0; i < row_basis_.rows(); ++i) s += column[i] * rhs[i];
    projected_rhs_[j] = s;
  }
}

const QpSolution& ConstrainedQp::solve_direct(const Eigen::MatrixXd& mass,
                                              const Eigen::VectorXd& force, const Eigen::MatrixXd&,
                                              const Eigen::VectorXd& rhs, bool rows_changed) {
  QpSolution& out = solution_;
  const bool refactor = rows_changed || !direct_ready_ || !diagonal_change(mass);
  if (!refactor && changed_.empty() && (map_ready_ || ++factor_uses_ >= kMapAfter) &&
      (map_ready_ || build_map())) {
    // [a; λ] = [G_f G_r] [f; r] (build_map), then the rows' residual J_b a − Uᵀ r as below.
    const Eigen::Index nv = map_jac_.cols(), rows = map_basis_t_.cols();
    const Eigen::Index rank = reduced_jac_.rows();
    std::memcpy(map_in_.data(), force.data(), sizeof(double) * static_cast<size_t>(nv));
    std::memcpy(map_in_.data() + nv, rhs.data(), sizeof(double) * static_cast<size_t>(rows));
    product_by_blocks(map_, map_in_.data(), map_out_.data());
    out.acceleration.resize(nv);
    out.multipliers.resize(rows);
    std::memcpy(out.acceleration.data(), map_out_.data(), sizeof(double) * static_cast<size_t>(nv));
    std::memcpy(out.multipliers.data(), map_out_.data() + nv,
                sizeof(double) * static_cast<size_t>(rows));
    product_by_blocks(map_jac_, map_out_.data(), map_jac_a_.data());
    product_by_blocks(map_basis_t_, rhs.data(), map_basis_r_.data());
    double primal = 0.0;
    for (Eigen::Index i = 0; i < rank; ++i) {
      primal = std::max(primal, std::abs(map_jac_a_[i] - map_basis_r_[i]));
    }
    bool finite = true;
    for (Eigen::Index i = 0; i < nv; ++i) finite = finite && std::isfinite(map_out_[i]);
    // A NaN in J_b a − Uᵀ r fails the max above silently: checked as the substitutions' is.
    for (Eigen::Index i = 0; i < rank; ++i) {
      if (!std::isfinite(map_jac_a_[i] - map_basis_r_[i])) primal = NAN;
    }
    out.primal_residual = primal;
    out.dual_residual = finite ? 0.0 : NAN;
    out.iterations = 0;
    out.solved = std::isfinite(out.primal_residual) && std::isfinite(out.dual_residual);
    // (the string compared by its bytes: std::string's compare is a call of 70 instructions)
    if (out.status.size() != 6 || std::memcmp(out.status.data(), "direct", 6) != 0) {
      out.status = "direct";
    }
    qp_.reset();
    return out;
  }
  if (refactor) {
    factorise(mass, &force);  // solves M a = f on the way
  } else {
    mass_factor_.solve(force, free_);
  }
  project_rhs(rhs);
  reduced_rhs_ = projected_rhs_;
  small_product<Accumulate::subtract>(reduced_jac_, free_, reduced_rhs_);
  schur_factor_.solve(reduced_rhs_, mu_);
  out.acceleration = free_;
  small_product<Accumulate::add>(minv_jt_, mu_, out.acceleration);
  if (!changed_.empty() && !correct(out.acceleration)) {
    factorise(mass);
    return solve_direct(mass, force, reduced_jac_, rhs, false);
  }
  out.multipliers.resize(row_basis_.rows());
  small_product(row_basis_, mu_, out.multipliers);
  // The residual in a work vector: a product inside a larger expression would allocate. The
  // dual residual is that of the factorisations' substitutions, rounding, and is not formed
  // (QpSolution); a non-finite a (a = M⁻¹ f + M⁻¹ J_bᵀ μ) marks the solve failed.
  primal_.resize(reduced_jac_.rows());
  small_product(reduced_jac_, out.acceleration, primal_);
  out.primal_residual = primal_.size() ? (primal_ - projected_rhs_).cwiseAbs().maxCoeff() : 0.0;
  out.dual_residual = out.acceleration.allFinite() ? 0.0 : NAN;
  out.iterations = 0;
  out.solved = std::isfinite(out.primal_residual) && std::isfinite(out.dual_residual);
  if (out.status != "direct") out.status = "direct";
  // A later iterative step starts proxsuite afresh.
  qp_.reset();
  return out;
}

const QpSolution& ConstrainedQp::solve_fixed(const Eigen::MatrixXd& mass,
                                             const Eigen::VectorXd& force,
                                             const Eigen::VectorXd& rhs) {
  QpSolution& out = solution_;
  const auto nf = static_cast<Eigen::Index>(free_columns_.size());
  const auto rows = static_cast<Eigen::Index>(fixed_column_.size());
  const Eigen::Index* free = free_columns_.data();
  // M_FF's lower triangle (the step assembles its Hessian there, elements.hpp), refactorised
  // only if an entry changed: compared up to the first that did, copied from there on.
  bool changed = !fixed_ready_ || free_mass_.rows() != nf;
  free_mass_.resize(nf, nf);
  Eigen::Index j = 0, i = 0;
  for (; !changed && j < nf; ++j) {
    const double* column = mass.col(free[j]).data();
    const double* kept = free_mass_.col(j).data();
    for (i = j; i < nf && column[free[i]] == kept[i]; ++i) {
    }
    changed = i < nf;
    if (changed) break;
  }
  if (changed) {
    for (; j < nf; ++j, i = j) {
      const double* column = mass.col(free[j]).data();
      double* kept = free_mass_.col(j).data();
      for (; i < nf; ++i) kept[i] = column[free[i]];
    }
    free_factor_.compute(free_mass_);
  }
  fixed_ready_ = true;
  Eigen::VectorXd& a = out.acceleration;
  a.resize(nv_);
  for (Eigen::Index r = 0; r < rows; ++r) {
    a[fixed_column_[static_cast<size_t>(r)]] = rhs[r] / fixed_coefficient_[static_cast<size_t>(r)];
  }
  // f_F − M_FK a_K (a row's a_k = 0, a speed held or a lock, subtracts nothing), then
  // a_F = M_FF⁻¹ (f_F − M_FK a_K); M's entry (c, k) read from its lower triangle.
  free_force_.resize(nf);
  for (Eigen::Index f = 0; f < nf; ++f) free_force_[f] = force[free[f]];
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index k = fixed_column_[static_cast<size_t>(r)];
    const double ak = a[k];
    if (ak == 0.0) continue;
    for (Eigen::Index f = 0; f < nf; ++f) {
      const Eigen::Index c = free[f];
      free_force_[f] -= (c >= k ? mass(c, k) : mass(k, c)) * ak;
    }
  }
  double* y = free_force_.data();
  free_factor_.solve_in_place(&y, 1);
  for (Eigen::Index f = 0; f < nf; ++f) a[free[f]] = y[f];
  // λ_r = (M_k· a − f_k) / c_r, M's row k read from its lower triangle (row k left of the
  // diagonal, column k below it), and the rows' residual c_r a_k − r_r.
  out.multipliers.resize(rows);
  out.primal_residual = 0.0;
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index k = fixed_column_[static_cast<size_t>(r)];
    const double c = fixed_coefficient_[static_cast<size_t>(r)];
    double s = 0.0;
    for (Eigen::Index m = 0; m < k; ++m) s += mass(k, m) * a[m];
    const double* below = mass.col(k).data();
    for (Eigen::Index m = k; m < nv_; ++m) s += below[m] * a[m];
    out.multipliers[r] = (s - force[k]) / c;
    out.primal_residual = std::max(out.primal_residual, std::abs(c * a[k] - rhs[r]));
  }
  out.dual_residual = a.allFinite() ? 0.0 : NAN;
  out.iterations = 0;
  out.solved = std::isfinite(out.primal_residual) && std::isfinite(out.dual_residual);
  if (out.status != "direct") out.status = "direct";
  qp_.reset();  // a later iterative step starts proxsuite afresh
  direct_ready_ = false;  // solve_direct's factorisations are of other rows
  return out;
}

void ConstrainedQp::factorise(const Eigen::MatrixXd& mass, const Eigen::VectorXd* force) {
  direct_mass_ = mass;
  mass_factor_.compute(mass);
  const Eigen::Index rows = reduced_jac_.rows();
  // M⁻¹ f and M⁻¹ Jᵀ together (small_cholesky.hpp: a few columns take the time of one).
  minv_jt_ = reduced_jac_.transpose();
  solve_columns_.clear();
  if (force != nullptr) {
    free_ = *force;
    solve_columns_.push_back(free_.data());
  }
  for (Eigen::Index r = 0; r < rows; ++r) solve_columns_.push_back(minv_jt_.col(r).data());
  mass_factor_.solve_in_place(solve_columns_.data(), static_cast<int>(solve_columns_.size()));
  schur_.resize(reduced_jac_.rows(), reduced_jac_.rows());
  schur_.noalias() = reduced_jac_.lazyProduct(minv_jt_);
  schur_factor_.compute(schur_);
  direct_ready_ = true;
  responses_.clear();
  changed_.clear();
  factor_uses_ = 0;
  map_ready_ = false;
}

bool ConstrainedQp::build_map() {
  // Column by column, the substitutions of solve_direct for a unit f (r = 0) or a unit r
  // (f = 0): free = M⁻¹ f, μ = S_b⁻¹ (Uᵀ r − J_b free), a = free + M⁻¹ J_bᵀ μ, λ = U μ.
  const Eigen::Index nv = direct_mass_.rows(), rows = row_basis_.rows();
  const Eigen::Index rank = reduced_jac_.rows();
  const auto padded = [](Eigen::Index n) { return (n + kBlock - 1) / kBlock * kBlock; };
  map_.setZero(padded(nv + rows), nv + rows);
  map_jac_.setZero(padded(rank), nv);
  map_jac_.topRows(rank) = reduced_jac_;
  map_basis_t_.setZero(padded(rank), rows);
  map_basis_t_.topRows(rank) = row_basis_.transpose();
  map_in_.resize(nv + rows);
  map_out_.resize(map_.rows());
  map_jac_a_.resize(map_jac_.rows());
  map_basis_r_.resize(map_basis_t_.rows());
  Eigen::VectorXd f(nv), r(rows), free(nv), projected(row_basis_.cols()), mu(row_basis_.cols());
  for (Eigen::Index c = 0; c < nv + rows; ++c) {
    f.setZero();
    r.setZero();
    if (c < nv) {
      f[c] = 1.0;
    } else {
      r[c - nv] = 1.0;
    }
    mass_factor_.solve(f, free);
    projected.noalias() = row_basis_.transpose() * r;
    projected.noalias() -= reduced_jac_ * free;
    schur_factor_.solve(projected, mu);
    auto column = map_.col(c);
    column.head(nv) = free;
    column.head(nv).noalias() += minv_jt_ * mu;
    column.segment(nv, rows).noalias() = row_basis_ * mu;
  }
  // A map with a non-finite entry (M or S_b not positive definite to working precision) is not
  // used: the substitutions go on, and report a non-finite solution as before.
  map_ready_ = map_.allFinite() && map_jac_.allFinite() && map_basis_t_.allFinite();
  if (!map_ready_) factor_uses_ = std::numeric_limits<long>::min();
  return map_ready_;
}

bool ConstrainedQp::diagonal_change(const Eigen::MatrixXd& mass) {
  changed_.clear();
  if (direct_mass_.rows() != mass.rows() || direct_mass_.cols() != mass.cols()) return false;
  // The same M (a constant one, taken once by the step): one pass over its entries.
  if (std::memcmp(mass.data(), direct_mass_.data(), sizeof(double) * mass.size()) == 0) {
    return true;  // bit for bit
  }
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

const std::pair<Eigen::VectorXd, Eigen::VectorXd>& ConstrainedQp::response(Eigen::Index i) {
  for (const auto& r : responses_) {
    if (r.first == i) return r.second;
  }
  Eigen::VectorXd unit = Eigen::VectorXd::Zero(direct_mass_.rows());
  unit[i] = 1.0;
  Eigen::VectorXd a = mass_factor_.solve(unit);
  const Eigen::VectorXd mu = schur_factor_.solve(-(reduced_jac_ * a));
  a.noalias() += minv_jt_ * mu;
  responses_.push_back({i, {a, mu}});
  return responses_.back().second;
}

bool ConstrainedQp::correct(Eigen::VectorXd& a) {
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

void ConstrainedQp::start(const Eigen::MatrixXd& jac) {
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

bool ConstrainedQp::refresh_rows(const Eigen::MatrixXd& jac) {
  if (jac_cache_.rows() == jac.rows() && jac_cache_.cols() == jac.cols()) {
    // The same J bit for bit (rows taken once, mesh_rows.hpp MeshRows::frame): one compare.
    if (std::memcmp(jac.data(), jac_cache_.data(), sizeof(double) * jac.size()) == 0) {
      return false;
    }
    if ((jac - jac_cache_).cwiseAbs().maxCoeff() <= 1e-12 * jac.cwiseAbs().maxCoeff()) {
      return false;
    }
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
  // Rows that each fix one coordinate of their own (solve_fixed): one non-zero entry per row,
  // in distinct columns.
  fixed_column_.clear();
  fixed_coefficient_.clear();
  std::vector<bool> fixed(static_cast<size_t>(jac.cols()), false);
  fixed_rows_ = jac.rows() > 0;
  for (Eigen::Index r = 0; fixed_rows_ && r < jac.rows(); ++r) {
    Eigen::Index column = -1, nonzero = 0;
    for (Eigen::Index c = 0; c < jac.cols() && nonzero < 2; ++c) {
      if (jac(r, c) != 0.0) {
        column = c;
        ++nonzero;
      }
    }
    fixed_rows_ = nonzero == 1 && std::isfinite(jac(r, column)) &&
                  !fixed[static_cast<size_t>(column)];
    if (!fixed_rows_) break;
    fixed[static_cast<size_t>(column)] = true;
    fixed_column_.push_back(column);
    fixed_coefficient_.push_back(jac(r, column));
  }
  free_columns_.clear();
  for (Eigen::Index c = 0; fixed_rows_ && c < jac.cols(); ++c) {
    if (!fixed[static_cast<size_t>(c)]) free_columns_.push_back(c);
  }
  fixed_ready_ = false;
  return true;
}

bool ConstrainedQp::refresh_mass(const Eigen::MatrixXd& mass) {
  if (mass_cache_.size() == mass.size() &&
      (mass - mass_cache_).cwiseAbs().maxCoeff() <= 1e-12 * mass_scale_) {
    return false;
  }
  mass_cache_ = mass;
  // proxsuite reads the whole Hessian; the step assembles its lower triangle (elements.hpp).
  h_ = mass.selfadjointView<Eigen::Lower>();
  mass_scale_ = power_of_two(h_.cwiseAbs().maxCoeff());
  h_ /= mass_scale_;
  return true;
}

ConstrainedQp::~ConstrainedQp() = default;
ConstrainedQp::ConstrainedQp(const ConstrainedQp&) = default;
ConstrainedQp& ConstrainedQp::operator=(const ConstrainedQp&) = default;

}  // namespace pinwind
