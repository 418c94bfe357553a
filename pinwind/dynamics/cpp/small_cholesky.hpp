// The Cholesky factorisation H = L Lᵀ of the step QP's small symmetric positive definite
// matrices (its Hessian c₁ M + Σ w JᵀJ, n = nv of 6 to 30, and the Schur complement over its
// rows), in plain loops over contiguous memory: row j of L is kept as column j of a
// column-major array, so every inner product of the factorisation and of the forward
// substitution runs along two contiguous arrays, and the back substitution is a column update.
// At these sizes Eigen's pivoted LDLT spends as much again as the arithmetic on its pivot
// search and on a matrix-vector product call per column (callgrind, a 16 × 16 Hessian
// factorised and one solve: 17.7k instructions against 8.8k). A matrix that is not positive definite to working precision
// (a pivot that is not > 0, or not finite) is factorised by Eigen's pivoted LDLT instead, as
// every matrix was before.
//
// Reads the lower triangle of H, as Eigen's LDLT does.
#pragma once

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace pinwind {

class SmallCholesky {
 public:
  void compute(const Eigen::MatrixXd& h) {
    const Eigen::Index n = h.rows();
    lower_t_.resize(n, n);
    diagonal_.resize(n);
    cholesky_ = true;
    Eigen::Index j = 0;
    for (; j + 3 < n; j += 4) {
      // Rows j to j + 3 of L together: each entry is a chain of products ending in a division
      // by the pivot, which the next entry of the row waits for; four rows' chains interleaved
      // keep the divider busy and share each load of row i (two rows at a time: a 16 x 16
      // factorisation and solve 1.77 -> 1.20 µs; four: 4.9k -> 4.2k instructions), with each
      // entry's operations, and so its rounding, those of one row at a time.
      double* l0 = lower_t_.col(j).data();
      double* l1 = lower_t_.col(j + 1).data();
      double* l2 = lower_t_.col(j + 2).data();
      double* l3 = lower_t_.col(j + 3).data();
      for (Eigen::Index i = 0; i < j; ++i) {
        const double* li = lower_t_.col(i).data();
        double s0 = h(j, i), s1 = h(j + 1, i), s2 = h(j + 2, i), s3 = h(j + 3, i);
        for (Eigen::Index m = 0; m < i; ++m) {
          s0 -= li[m] * l0[m];
          s1 -= li[m] * l1[m];
          s2 -= li[m] * l2[m];
          s3 -= li[m] * l3[m];
        }
        l0[i] = s0 / diagonal_[i];
        l1[i] = s1 / diagonal_[i];
        l2[i] = s2 / diagonal_[i];
        l3[i] = s3 / diagonal_[i];
      }
      // The block's own triangle, column by column: each column's pivot, then the entries
      // below it in the block.
      if (!pivot(h, j)) return;
      entry(h, j + 1, j);
      entry(h, j + 2, j);
      entry(h, j + 3, j);
      if (!pivot(h, j + 1)) return;
      entry(h, j + 2, j + 1);
      entry(h, j + 3, j + 1);
      if (!pivot(h, j + 2)) return;
      entry(h, j + 3, j + 2);
      if (!pivot(h, j + 3)) return;
    }
    for (; j + 1 < n; j += 2) {
      double* lj = lower_t_.col(j).data();
      double* lk = lower_t_.col(j + 1).data();
      for (Eigen::Index i = 0; i < j; ++i) {
        const double* li = lower_t_.col(i).data();
        double s = h(j, i), t = h(j + 1, i);
        for (Eigen::Index m = 0; m < i; ++m) {
          s -= li[m] * lj[m];
          t -= li[m] * lk[m];
        }
        lj[i] = s / diagonal_[i];
        lk[i] = t / diagonal_[i];
      }
      if (!pivot(h, j)) return;
      entry(h, j + 1, j);
      if (!pivot(h, j + 1)) return;
    }
    if (j < n) {
      double* lj = lower_t_.col(j).data();
      for (Eigen::Index i = 0; i < j; ++i) {
        const double* li = lower_t_.col(i).data();
        double s = h(j, i);
        for (Eigen::Index m = 0; m < i; ++m) s -= li[m] * lj[m];
        lj[i] = s / diagonal_[i];
      }
      pivot(h, j);
    }
  }

  // x = H⁻¹ b; x may be a contiguous block (a column of a matrix).
  template <class Rhs, class Out>
  void solve(const Rhs& b, Out&& x) const {
    x = b;
    double* y = x.data();
    solve_in_place<1>(&y);
  }

  // y_k ← H⁻¹ y_k for K vectors of length n in place (K ≤ 4 at a time, y[k] their data): each
  // substitution is a chain of n dependent divisions, and K of them interleaved take about the
  // time of one. Each vector's operations, and so its values, are those of a solve of its own.
  void solve_in_place(double* const* y, int count) const {
    for (; count >= 4; count -= 4, y += 4) solve_in_place<4>(y);
    if (count == 3) solve_in_place<3>(y);
    if (count == 2) solve_in_place<2>(y);
    if (count == 1) solve_in_place<1>(y);
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    Eigen::VectorXd x(b.size());
    solve(b, x);
    return x;
  }

 private:
  template <int K>
  void solve_in_place(double* const* y) const {
    const Eigen::Index n = lower_t_.cols();
    if (!cholesky_) {
      for (int k = 0; k < K; ++k) {
        Eigen::Map<Eigen::VectorXd> v(y[k], n);
        v = ldlt_.solve(Eigen::VectorXd(v));
      }
      return;
    }
    double s[K];
    for (Eigen::Index j = 0; j < n; ++j) {  // L z = y
      const double* lj = lower_t_.col(j).data();
      for (int k = 0; k < K; ++k) s[k] = y[k][j];
      for (Eigen::Index m = 0; m < j; ++m) {
        for (int k = 0; k < K; ++k) s[k] -= lj[m] * y[k][m];
      }
      for (int k = 0; k < K; ++k) y[k][j] = s[k] / diagonal_[j];
    }
    for (Eigen::Index j = n - 1; j >= 0; --j) {  // Lᵀ x = z
      const double* lj = lower_t_.col(j).data();
      for (int k = 0; k < K; ++k) s[k] = y[k][j] / diagonal_[j];
      for (int k = 0; k < K; ++k) y[k][j] = s[k];
      for (Eigen::Index m = 0; m < j; ++m) {
        for (int k = 0; k < K; ++k) y[k][m] -= lj[m] * s[k];
      }
    }
  }

  // L's entry (r, c), c < r, from the entries left of it in rows r and c (c's pivot known).
  void entry(const Eigen::MatrixXd& h, Eigen::Index r, Eigen::Index c) {
    double* lr = lower_t_.col(r).data();
    const double* lc = lower_t_.col(c).data();
    double t = h(r, c);
    for (Eigen::Index m = 0; m < c; ++m) t -= lc[m] * lr[m];
    lr[c] = t / diagonal_[c];
  }

  // L's diagonal entry j from row j's entries left of it; a matrix that is not positive
  // definite to working precision goes to Eigen's pivoted LDLT instead (returns false).
  bool pivot(const Eigen::MatrixXd& h, Eigen::Index j) {
    double* lj = lower_t_.col(j).data();
    double d = h(j, j);
    for (Eigen::Index k = 0; k < j; ++k) d -= lj[k] * lj[k];
    if (!(d > 0.0 && std::isfinite(d))) {
      cholesky_ = false;
      ldlt_.compute(h);
      return false;
    }
    diagonal_[j] = lj[j] = std::sqrt(d);
    return true;
  }

  Eigen::MatrixXd lower_t_;    // Lᵀ: column j holds row j of L (its upper triangle is used)
  Eigen::VectorXd diagonal_;   // L's diagonal
  bool cholesky_ = true;       // false: not positive definite, ldlt_ holds the factors
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
};

}  // namespace pinwind
