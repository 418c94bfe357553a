// Matrix-vector products of the step's small dynamic matrices (nv of 6 to 40, a few rows), as
// plain loops: at these sizes Eigen's general kernel (general_matrix_vector_product) costs more
// in its call, blocking and remainder handling than the arithmetic.
//
// Each element is summed over the columns in order from 0, y_i = ((a_i0 x_0 + a_i1 x_1) + …),
// as Eigen's column-major kernel sums it (one accumulator per row, added to y at the end), so a
// product taken here equals Eigen's to the last bit.
#pragma once

#include <Eigen/Core>

namespace pinwind {

enum class Accumulate { assign, add, subtract };

// y = A x, y += A x or y −= A x (mode), y already sized to A's rows.
template <Accumulate mode = Accumulate::assign, class Mat, class Vec, class Out>
inline void small_product(const Mat& a, const Vec& x, Out&& y) {
  const Eigen::Index rows = a.rows(), cols = a.cols();
  for (Eigen::Index i = 0; i < rows; ++i) {
    double s = 0.0;
    for (Eigen::Index j = 0; j < cols; ++j) s += a(i, j) * x[j];
    if constexpr (mode == Accumulate::assign) {
      y[i] = s;
    } else if constexpr (mode == Accumulate::add) {
      y[i] += s;
    } else {
      y[i] -= s;
    }
  }
}

}  // namespace pinwind
