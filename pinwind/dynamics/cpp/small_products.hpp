// Matrix-vector products of the step's small dynamic matrices (nv of 6 to 40, a few rows), as
// plain loops: at these sizes Eigen's general kernel (general_matrix_vector_product) costs more
// in its call, blocking and remainder handling than the arithmetic.
//
// Each element is summed over the columns in order from 0, y_i = ((a_i0 x_0 + a_i1 x_1) + …),
// as Eigen's column-major kernel sums it (one accumulator per row, added to y at the end), so a
// product taken here equals Eigen's to the last bit.
#pragma once

#include <cstring>
#include <type_traits>

#include <Eigen/Core>

namespace pinwind {

enum class Accumulate { assign, add, subtract };

// Two doubles in one vector register (GCC's and Clang's vector extension).
typedef double Pair __attribute__((vector_size(16)));

// y_b … y_b+7 = rows b … b + 7 of A x, A column-major (its columns `stride` apart from `column`,
// row b's entry of column 0): the eight sums kept in four registers of pairs through the
// columns, each summed over the columns in order from 0 (the vector extension rounds each
// product and sum as the scalar operation does). With `skip_zeros`, a zero x_j is skipped: it
// would add ±0 to each sum, which leaves a sum as it is (a sum from +0.0 is never −0.0) as long
// as A is finite.
template <bool skip_zeros = false, class X>
inline void eight_rows_product(const double* column, Eigen::Index stride, Eigen::Index cols,
                               const X& x, double* y) {
  Pair s0 = {0.0, 0.0}, s1 = s0, s2 = s0, s3 = s0;
  for (Eigen::Index j = 0; j < cols; ++j, column += stride) {
    if constexpr (skip_zeros) {
      if (x[j] == 0.0) continue;
    }
    const Pair xj = {x[j], x[j]};
    Pair c0, c1, c2, c3;
    std::memcpy(&c0, column, sizeof(Pair));
    std::memcpy(&c1, column + 2, sizeof(Pair));
    std::memcpy(&c2, column + 4, sizeof(Pair));
    std::memcpy(&c3, column + 6, sizeof(Pair));
    s0 += c0 * xj;
    s1 += c1 * xj;
    s2 += c2 * xj;
    s3 += c3 * xj;
  }
  std::memcpy(y, &s0, sizeof(Pair));
  std::memcpy(y + 2, &s1, sizeof(Pair));
  std::memcpy(y + 4, &s2, sizeof(Pair));
  std::memcpy(y + 6, &s3, sizeof(Pair));
}

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
      // Eight rows at a time, their sums in four registers of pairs through the columns (the
      // same chains, element by element: GCC's and Clang's vector extension rounds each
      // product and sum as the scalar operation does); the sums in memory, as for the rows
      // left over, cost a load and a store per entry (callgrind, the drivetrain's 9 × 8 rows
      // times a vector: 0.41k -> 0.2k instructions).
      Eigen::Index b = 0;
      for (; b + 8 <= rows; b += 8) {
        eight_rows_product(a.data() + b, a.outerStride(), cols, x, s + b);
      }
      if (b < rows) {
        for (Eigen::Index i = b; i < rows; ++i) s[i] = 0.0;
        for (Eigen::Index j = 0; j < cols; ++j) {
          const double* column = a.data() + j * a.outerStride();
          const double xj = x[j];
          for (Eigen::Index i = b; i < rows; ++i) s[i] += column[i] * xj;
        }
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
