// Equilibration of a matrix: diagonal row and column scalings D_r, D_c such that every row and
// every column of D_r A D_c has the largest entry 1 (D. Ruiz, "A scaling algorithm to
// equilibrate both rows and columns norms in matrices", RAL-TR-2001-034, 2001: each sweep
// divides row i by √‖row i‖∞ and column j by √‖column j‖∞, which halves the logarithm of the
// imbalance, so that 30 sweeps take out a factor 10³⁰⁰). A rank-revealing factorisation of the
// scaled matrix decides the rank on the system's structure, not on the magnitudes of its entries:
// the static start (stepper_equilibrium.cpp) stacks springs of 1e4 N/m beside bearings of
// 1e12 N/m and masses of grams beside tonnes.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace pinwind {

struct Equilibration {
  Eigen::VectorXd rows;     // D_r's diagonal
  Eigen::VectorXd columns;  // D_c's diagonal
};

// Scales `a` in place to D_r a D_c and returns D_r and D_c; a row or column of zeros keeps the
// scale 1. Stops when every non-zero row and column's largest entry is within `tolerance` of 1.
inline Equilibration equilibrate(Eigen::MatrixXd& a, int sweeps = 30, double tolerance = 1e-3) {
  Equilibration out{Eigen::VectorXd::Ones(a.rows()), Eigen::VectorXd::Ones(a.cols())};
  Eigen::VectorXd r(a.rows()), c(a.cols());
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    bool balanced = true;
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double norm = a.row(i).cwiseAbs().maxCoeff();
      r[i] = norm > 0.0 ? 1.0 / std::sqrt(norm) : 1.0;
      if (norm > 0.0 && std::abs(1.0 - norm) > tolerance) balanced = false;
    }
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      const double norm = a.col(j).cwiseAbs().maxCoeff();
      c[j] = norm > 0.0 ? 1.0 / std::sqrt(norm) : 1.0;
      if (norm > 0.0 && std::abs(1.0 - norm) > tolerance) balanced = false;
    }
    if (balanced) break;
    a = r.asDiagonal() * a * c.asDiagonal();
    out.rows.array() *= r.array();
    out.columns.array() *= c.array();
  }
  return out;
}

}  // namespace pinwind
