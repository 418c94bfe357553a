// Constrained dynamics of one step as an equality QP, solved through the Schur complement of its
// KKT system (minimum-norm multipliers for redundant rows), or with proxsuite's proximal method
// for redundant rows when SolverSettings.iterative is set.
//
// Gauss's principle, the constrained equations of motion of Saleh 2017 (eqs. 1-28) as a QP:
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
//
// The solver's work is compiled in constrained_qp.cpp, the one unit that includes proxsuite
// (whose headers alone cost the compiler 1 GB).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/Core>
#include <Eigen/SVD>

#include "small_cholesky.hpp"

namespace proxsuite::proxqp::dense {
template <typename T>
struct QP;
}  // namespace proxsuite::proxqp::dense

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
  // ‖M a − (τ − b) − Jᵀ λ‖∞ [N·m] of an iterative solve; a direct one gives 0 (its
  // substitutions satisfy it to rounding), NaN for a non-finite a.
  double dual_residual = 0.0;
  long iterations = 0;
  bool solved = true;
  std::string status = "unconstrained";
};

// An owned object copied whole with its owner (std::unique_ptr's copy): proxsuite's QP, whose
// type is complete only in constrained_qp.cpp, where ConstrainedQp's copies are compiled.
template <class T>
class CopiedPtr {
 public:
  CopiedPtr() = default;
  CopiedPtr(const CopiedPtr& o) : p_(o.p_ ? std::make_unique<T>(*o.p_) : nullptr) {}
  CopiedPtr& operator=(const CopiedPtr& o) {
    if (this == &o) return *this;
    if (p_ && o.p_) {
      *p_ = *o.p_;  // the same sizes: the buffers kept
    } else {
      p_ = o.p_ ? std::make_unique<T>(*o.p_) : nullptr;
    }
    return *this;
  }
  CopiedPtr& operator=(std::unique_ptr<T> p) {
    p_ = std::move(p);
    return *this;
  }
  void reset() { p_.reset(); }
  T* operator->() const { return p_.get(); }
  bool operator!() const { return !p_; }

 private:
  std::unique_ptr<T> p_;
};

// A proxsuite dense QP of fixed size reused for every step.
class ConstrainedQp {
 public:
  using QP = proxsuite::proxqp::dense::QP<double>;

  ConstrainedQp(Eigen::Index nv, Eigen::Index rows, SolverSettings settings);
  ~ConstrainedQp();  // in constrained_qp.cpp, where proxsuite's QP is complete
  // Copies, proxsuite's QP with them: every factorisation, cache and warm start, so that a copy
  // solves the next step to the same bits as the original (a saved state of a run).
  ConstrainedQp(const ConstrainedQp&);
  ConstrainedQp& operator=(const ConstrainedQp&);

  // Solves M a = force + Jᵀ λ, J a = rhs.
  //
  // mass: joint-space inertia M [kg·m²], its lower triangle read (the step's Hessian is
  // assembled there, elements.hpp); force: τ − b [N·m]; jac: rows J; rhs: r.
  const QpSolution& solve(const Eigen::MatrixXd& mass, const Eigen::VectorXd& force,
                          const Eigen::MatrixXd& jac, const Eigen::VectorXd& rhs);

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
  // other change of M costs two small Cholesky factorisations (small_cholesky.hpp). A correction that would amplify
  // rounding (a diagonal of I + Eᵀ Z D below ½: a weight far below M₀'s) refactorises instead.
  const QpSolution& solve_direct(const Eigen::MatrixXd& mass, const Eigen::VectorXd& force,
                                 const Eigen::MatrixXd&, const Eigen::VectorXd& rhs,
                                 bool rows_changed);

  // The solution as a linear map of the data, kept while M and the rows stay: with M and J
  // constant, [a; λ] = [G_f G_r] [f; r], G's columns the solutions above for unit f and unit r
  // (the same substitutions, taken once), so a step costs one small product instead of the
  // substitutions' chains of divisions (drivetrain: 8 joints, 9 rows of rank 7). Built once a
  // factorisation has served kMapAfter solves (a run that switches flanks every few steps keeps
  // the substitutions); not with a Woodbury correction, nor if an entry is not finite (the
  // return value: whether the map is used). The sums differ from the substitutions' by
  // rounding: the closed-form mesh forces of benchmarks/step_rate.py are as accurate (Saleh
  // 2017 planetary 5.1e-16, drivetrain 1.1e-15 relative), the carriers' accelerations within
  // what one ulp of the input torques moves them by.
  bool build_map();

  // Uᵀ r into projected_rhs_.
  void project_rhs(const Eigen::VectorXd& rhs);

  // Factorises M (and the Schur complement over the current rows); forgets the responses. With
  // `force`, also solves M free_ = force.
  //
  // Compliant meshes change M every step (their weights follow the mesh stiffness), so this
  // runs once per step there: M⁻¹ J_bᵀ and M⁻¹ f up to four columns at a time (their
  // substitutions interleaved) and S_b by lazy products, because at these sizes (nv of 6 to 20, a few rows)
  // Eigen's blocked matrix solve and GEMM spend more on packing and temporaries than on the
  // arithmetic.
  void factorise(const Eigen::MatrixXd& mass, const Eigen::VectorXd* force = nullptr);

  // Whether M differs from the factorised M₀ on at most kMaxCorrections diagonal entries and
  // nowhere else; fills changed_ with those entries and their differences.
  bool diagonal_change(const Eigen::MatrixXd& mass);

  // The constrained response (a, μ) to a unit force on joint i with J a = 0, kept per joint
  // while M₀ and the rows stay.
  const std::pair<Eigen::VectorXd, Eigen::VectorXd>& response(Eigen::Index i);

  // Applies the Woodbury correction of changed_ to (a, mu_); false if it would amplify rounding.
  bool correct(Eigen::VectorXd& a);

  // Rows that each fix one coordinate, c_r a_k = r_r on distinct joints k (speed drivers and
  // locks, speed_drivers.hpp: every row of a model whose meshes are compliant), solved by
  // eliminating those coordinates instead of through the Schur complement: with F the free
  // coordinates and K the fixed ones, a_K = r / c is known, and
  //
  //     M_FF a_F = f_F − M_FK a_K,   λ_r = (M_k· a − f_k) / c_r,
  //
  // the rows of M a = f + Jᵀ λ, the first the free ones, the second row k's. The same solution
  // as solve_direct's (J has full rank, so λ is unique) up to rounding, for one Cholesky
  // factorisation of M_FF and one solve, where solve_direct factorises the whole M and solves
  // it for f and each row: a 16 × 16 Hessian with two such rows (a planetary stage with five
  // compliant bearings, its ring locked and its sun driven): 10.8k → 6.5k instructions a step
  // for the solve with its factorisations and copies. M_FF's factorisation is kept while its
  // entries stay the same to the bit.
  const QpSolution& solve_fixed(const Eigen::MatrixXd& mass, const Eigen::VectorXd& force,
                                const Eigen::VectorXd& rhs);

  void start(const Eigen::MatrixXd& jac);

  // Whether J differs from the previous step's (to 1e-12); refreshes the range projector,
  // which is kept while J stays the same, as it does for gears on fixed or carrier-borne axes,
  // and whether each row fixes one coordinate of its own (solve_fixed).
  bool refresh_rows(const Eigen::MatrixXd& jac);

  // Whether M differs from the previous step's (to 1e-12); refreshes its scaled copy.
  bool refresh_mass(const Eigen::MatrixXd& mass);

  Eigen::Index nv_, rows_;
  SolverSettings settings_;
  CopiedPtr<QP> qp_;
  double data_scale_ = 0.0;
  double mass_scale_ = 1.0;
  Eigen::MatrixXd mass_cache_, h_, jac_cache_, range_;
  Eigen::VectorXd g_, rhs_;
  bool full_rank_ = true;
  QpSolution solution_;
  // Direct solve of full-rank rows.
  bool direct_ready_ = false;
  Eigen::MatrixXd direct_mass_, minv_jt_, schur_;
  SmallCholesky mass_factor_, schur_factor_;
  Eigen::MatrixXd row_basis_, reduced_jac_;
  Eigen::VectorXd free_, projected_rhs_, reduced_rhs_, mu_;
  Eigen::VectorXd primal_;  // solve_direct's residual J_b a
  std::vector<double*> solve_columns_;  // factorise's right-hand sides, solved in place
  // build_map's [G_f G_r] (nv + rows columns), and J_b and Uᵀ for the rows' residual, each
  // with zero rows padding its row count to a multiple of kBlock (product_by_blocks); the map's
  // input [f; r] and output [a; λ], J_b a and Uᵀ r; the solves that the current factorisation
  // has served.
  static constexpr long kMapAfter = 16;
  static constexpr Eigen::Index kBlock = 8;
  Eigen::MatrixXd map_, map_jac_, map_basis_t_;
  Eigen::VectorXd map_in_, map_out_, map_jac_a_, map_basis_r_;
  long factor_uses_ = 0;
  bool map_ready_ = false;
  // Diagonal entries where M differs from the factorised M₀, and the responses to them.
  static constexpr size_t kMaxCorrections = 2;
  std::vector<std::pair<Eigen::Index, double>> changed_;
  std::vector<std::pair<Eigen::Index, std::pair<Eigen::VectorXd, Eigen::VectorXd>>> responses_;
  // solve_fixed's: each row's coordinate and coefficient (refresh_rows), the free coordinates
  // in order, M_FF's lower triangle as last factorised, and the free part of the solve.
  bool fixed_rows_ = false;
  std::vector<Eigen::Index> fixed_column_, free_columns_;
  std::vector<double> fixed_coefficient_;
  bool fixed_ready_ = false;
  Eigen::MatrixXd free_mass_;
  SmallCholesky free_factor_;
  Eigen::VectorXd free_force_;
};

}  // namespace pinwind
