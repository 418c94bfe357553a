// Matrix-vector products of the step's small dynamic matrices (nv of 6 to 40, a few rows), as
// plain loops: at these sizes Eigen's general kernel (general_matrix_vector_product) costs more
// in its call, blocking and remainder handling than the arithmetic.
//
// Each element is summed over the columns in order from 0, y_i = ((a_i0 x_0 + a_i1 x_1) + …),
// as Eigen's column-major kernel sums it (one accumulator per row, added to y at the end), so a
// product taken here equals Eigen's to the last bit.
#pragma once

#include <type_traits>

#include <Eigen/Core>

namespace pinwind {

enum class Accumulate { assign, add, subtract };

// A column-major A of kColumnWiseMin to kColumnWiseRows rows is read column by column (with
// fewer rows, two for a compliant-mesh run's rows, the loop per column costs more than the
// strided loads it saves: callgrind, 2 x 16 rows, 0.26k -> 0.44k instructions).
inline constexpr Eigen::Index kColumnWiseMin = 4;
inline constexpr Eigen::Index kColumnWiseRows = 64;

// y = A x, y += A x or y −= A x (mode), y already sized to A's rows.
//
// A column-major A (every one of the step's but the mesh rows) is read along its columns, with
// one accumulator per row: each y_i is still the chain ((0 + a_i0 x_0) + a_i1 x_1) + …, the
// same operations in the same order, but its loads are contiguous and the rows' chains, each
// independent, go two at a time into the vector unit, where the row-by-row loop read A with a
// stride of its column length.
template <Accumulate mode = Accumulate::assign, class Mat, class Vec, class Out>
inline void small_product(const Mat& a, const Vec& x, Out&& y) {
  const Eigen::Index rows = a.rows(), cols = a.cols();
  using Plain = std::decay_t<Mat>;
  if constexpr (!Plain::IsRowMajor && (Plain::Flags & Eigen::DirectAccessBit) != 0) {
    if (rows >= kColumnWiseMin && rows <= kColumnWiseRows) {
      double s[kColumnWiseRows];
      for (Eigen::Index i = 0; i < rows; ++i) s[i] = 0.0;
      for (Eigen::Index j = 0; j < cols; ++j) {
        const double* column = a.data() + j * a.outerStride();
        const double xj = x[j];
        for (Eigen::Index i = 0; i < rows; ++i) s[i] += column[i] * xj;
      }
      for (Eigen::Index i = 0; i < rows; ++i) {
        if constexpr (mode == Accumulate::assign) {
          y[i] = s[i];
        } else if constexpr (mode == Accumulate::add) {
          y[i] += s[i];
        } else {
          y[i] -= s[i];
        }
      }
      return;
    }
  }
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
