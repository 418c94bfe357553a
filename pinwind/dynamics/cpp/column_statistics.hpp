// Statistics of the columns of a block of samples, in one pass: min, max, sum, sum of squares
// and last value of each column (pinwind/analysis/run_statistics.py folds the blocks of a run or
// of a log with them). Arrays come with their strides (in elements), so the sample-major blocks
// of the step loop and the series-major arrays of a read log are both read where they lie.
#pragma once

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace pinwind {

// A strided 2-D view: element (i, j) at data[i * s0 + j * s1].
struct Strided2 {
  const double* data;
  long rows, cols, s0, s1;
  double at(long i, long j) const { return data[i * s0 + j * s1]; }
};

// Output rows of a fold: min, max, sum, sum of squares, last value.
constexpr long kFoldRows = 5;

// Writes the statistics of each column j of the m × k block `values` to out(·, j), an
// (kFoldRows, k) view: out(0, j) = min, out(1, j) = max, out(2, j) = Σ v, out(3, j) = Σ v²,
// out(4, j) = the last value. A NaN anywhere in a column makes its min and max NaN, as numpy's
// reductions do (it makes the sum NaN; the comparisons alone would skip it).
//
// Four samples at a time into four partial results: the additions of one sum wait for each
// other, four sums do not (the sums are then added in another order than numpy's pairwise one:
// the same to a few units in the last place over a block).
template <class Value>
void fold_columns(long m, long k, Value value, double* out, long o0, long o1) {
  if (m <= 0) throw std::invalid_argument("a block to fold has no sample");
  constexpr double inf = std::numeric_limits<double>::infinity();
  constexpr long kLanes = 4;
  for (long j = 0; j < k; ++j) {
    double lo[kLanes], hi[kLanes], sum[kLanes], squares[kLanes];
    for (long l = 0; l < kLanes; ++l) {
      lo[l] = inf;
      hi[l] = -inf;
      sum[l] = squares[l] = 0.0;
    }
    long i = 0;
    for (; i + kLanes <= m; i += kLanes) {
      for (long l = 0; l < kLanes; ++l) {
        const double v = value(i + l, j);
        lo[l] = v < lo[l] ? v : lo[l];
        hi[l] = v > hi[l] ? v : hi[l];
        sum[l] += v;
        squares[l] += v * v;
      }
    }
    for (; i < m; ++i) {
      const double v = value(i, j);
      lo[0] = v < lo[0] ? v : lo[0];
      hi[0] = v > hi[0] ? v : hi[0];
      sum[0] += v;
      squares[0] += v * v;
    }
    for (long l = 1; l < kLanes; ++l) {
      lo[0] = lo[l] < lo[0] ? lo[l] : lo[0];
      hi[0] = hi[l] > hi[0] ? hi[l] : hi[0];
    }
    const double total = (sum[0] + sum[1]) + (sum[2] + sum[3]);
    const double total_squares = (squares[0] + squares[1]) + (squares[2] + squares[3]);
    if (std::isnan(total)) lo[0] = hi[0] = total;
    out[0 * o0 + j * o1] = lo[0];
    out[1 * o0 + j * o1] = hi[0];
    out[2 * o0 + j * o1] = total;
    out[3 * o0 + j * o1] = total_squares;
    out[4 * o0 + j * o1] = value(m - 1, j);
  }
}

// The same for a block whose rows are contiguous (the step loop's (m, k) arrays): a row at a
// time, each column's statistics in its own lane, so the columns go side by side through the
// vector unit. Row i goes to partial sum i mod 4 (the tail to 0), as in fold_columns, so both
// give the same numbers to the last bit.
inline void fold_rows(const Strided2& v, double* out, long o0, long o1) {
  if (v.rows <= 0) throw std::invalid_argument("a block to fold has no sample");
  constexpr double inf = std::numeric_limits<double>::infinity();
  constexpr long kLanes = 4;
  const long k = v.cols;
  const size_t size = static_cast<size_t>(kLanes * k);
  std::vector<double> lo(size, inf), hi(size, -inf), sum(size, 0.0), squares(size, 0.0);
  const long whole = v.rows - v.rows % kLanes;
  for (long i = 0; i < v.rows; ++i) {
    const double* row = v.data + i * v.s0;
    const long lane = i < whole ? i % kLanes : 0;
    double* l = lo.data() + lane * k;
    double* h = hi.data() + lane * k;
    double* s = sum.data() + lane * k;
    double* q = squares.data() + lane * k;
    for (long j = 0; j < k; ++j) {
      const double x = row[j];
      l[j] = x < l[j] ? x : l[j];
      h[j] = x > h[j] ? x : h[j];
      s[j] += x;
      q[j] += x * x;
    }
  }
  const double* last = v.data + (v.rows - 1) * v.s0;
  for (long j = 0; j < k; ++j) {
    double l = lo[j], h = hi[j];
    for (long lane = 1; lane < kLanes; ++lane) {
      l = lo[lane * k + j] < l ? lo[lane * k + j] : l;
      h = hi[lane * k + j] > h ? hi[lane * k + j] : h;
    }
    const double total = (sum[j] + sum[k + j]) + (sum[2 * k + j] + sum[3 * k + j]);
    const double total_squares =
        (squares[j] + squares[k + j]) + (squares[2 * k + j] + squares[3 * k + j]);
    const bool nan = std::isnan(total);
    out[0 * o0 + j * o1] = nan ? total : l;
    out[1 * o0 + j * o1] = nan ? total : h;
    out[2 * o0 + j * o1] = total;
    out[3 * o0 + j * o1] = total_squares;
    out[4 * o0 + j * o1] = last[j];
  }
}

// The columns themselves.
inline void fold_values(const Strided2& v, double* out, long o0, long o1) {
  if (v.s1 == 1 && v.cols > 1) {
    fold_rows(v, out, o0, o1);
    return;
  }
  fold_columns(v.rows, v.cols, [&](long i, long j) { return v.at(i, j); }, out, o0, o1);
}

// The magnitudes |(x, y, z)| of the m × e vectors of an (m, e, 3) array given as an
// (m, 3e) view whose columns 3j, 3j+1, 3j+2 are vector j's x, y, z; summed in that order
// (x² + y²) + z², as numpy's norm does.
inline void fold_magnitudes(const Strided2& v, double* out, long o0, long o1) {
  if (v.cols % 3 != 0) throw std::invalid_argument("vectors to fold need 3 components each");
  if (v.s1 == 1) {  // contiguous rows: the magnitudes of a row's vectors, then those rows
    const long e = v.cols / 3;
    std::vector<double> magnitudes(static_cast<size_t>(v.rows * e));
    for (long i = 0; i < v.rows; ++i) {
      const double* row = v.data + i * v.s0;
      for (long j = 0; j < e; ++j) {
        const double x = row[3 * j], y = row[3 * j + 1], z = row[3 * j + 2];
        magnitudes[static_cast<size_t>(i * e + j)] = std::sqrt(x * x + y * y + z * z);
      }
    }
    fold_values(Strided2{magnitudes.data(), v.rows, e, e, 1}, out, o0, o1);
    return;
  }
  auto magnitude = [&](long i, long j) {
    const double x = v.at(i, 3 * j), y = v.at(i, 3 * j + 1), z = v.at(i, 3 * j + 2);
    return std::sqrt(x * x + y * y + z * z);
  };
  fold_columns(v.rows, v.cols / 3, magnitude, out, o0, o1);
}

}  // namespace pinwind
