// Python bindings of the column helpers of pinwind.dynamics._native: statistics of a Result's
// columns and the byte planes of a log's series (module.cpp gathers the bindings).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "byte_planes.hpp"
#include "column_statistics.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

// Any float64 matrix, with its strides (a column of a Result, a view of a read log's arrays).
using AnyMatrix = nb::ndarray<const double, nb::ndim<2>, nb::device::cpu>;
using OutMatrix = nb::ndarray<double, nb::ndim<2>, nb::device::cpu>;

// Folds the columns of `values` (or the magnitudes of its x, y, z column triples) into `out`,
// a (5, columns) view (column_statistics.hpp), without the GIL.
void fold_block(const AnyMatrix& values, OutMatrix& out, bool magnitudes) {
  const Strided2 v{values.data(), static_cast<long>(values.shape(0)),
                   static_cast<long>(values.shape(1)), static_cast<long>(values.stride(0)),
                   static_cast<long>(values.stride(1))};
  const long k = magnitudes ? v.cols / 3 : v.cols;
  if (static_cast<long>(out.shape(0)) != kFoldRows || static_cast<long>(out.shape(1)) != k) {
    throw std::invalid_argument("fold: out must be (5, " + std::to_string(k) + "), not (" +
                                std::to_string(out.shape(0)) + ", " +
                                std::to_string(out.shape(1)) + ")");
  }
  double* data = out.data();
  const long o0 = static_cast<long>(out.stride(0)), o1 = static_cast<long>(out.stride(1));
  nb::gil_scoped_release release;
  if (magnitudes) {
    fold_magnitudes(v, data, o0, o1);
  } else {
    fold_values(v, data, o0, o1);
  }
}

using Bytes = nb::ndarray<std::uint8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using ConstBytes = nb::ndarray<const std::uint8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Indices = nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

std::string shape_text(long a, long b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

// The byte planes (byte_planes.hpp) of the rows `series` of the (k, m) `values` into `planes`
// (8 · V · m bytes, V = len(series)): the V rows' m values, one after the other, shuffled as one
// run of V · m values. Without the GIL.
void shuffle_series(const AnyMatrix& values, const Indices& series, Bytes planes) {
  const long k = static_cast<long>(values.shape(0)), m = static_cast<long>(values.shape(1));
  const long v = static_cast<long>(series.shape(0));
  if (m > 1 && values.stride(1) != 1) {
    throw std::invalid_argument("shuffle_series: the rows of values must be contiguous");
  }
  if (static_cast<long>(planes.shape(0)) != 8 * v * m) {
    throw std::invalid_argument("shuffle_series: planes must hold 8 · " + std::to_string(v) +
                                " · " + std::to_string(m) + " bytes, not " +
                                std::to_string(planes.shape(0)));
  }
  const std::int64_t* rows = series.data();
  for (long j = 0; j < v; ++j) {
    if (rows[j] < 0 || rows[j] >= k) {
      throw std::invalid_argument("shuffle_series: row " + std::to_string(rows[j]) +
                                  " of values " + shape_text(k, m));
    }
  }
  const double* data = values.data();
  const long s0 = static_cast<long>(values.stride(0));
  std::uint8_t* out = planes.data();
  nb::gil_scoped_release release;
  for (long j = 0; j < v; ++j) shuffle_bytes(data + rows[j] * s0, m, out + j * m, v * m);
}

// The inverse, for a read: samples first .. first + count of the V series in `planes` (each of m
// samples) into out[rows[j], at .. at + count], series j skipped where rows[j] < 0. Without the
// GIL (the reading threads place their chunks at once).
void unshuffle_series(const ConstBytes& planes, long m, long first, long count,
                      const Indices& rows, OutMatrix out, long at, bool stream) {
  const long v = static_cast<long>(rows.shape(0));
  const long height = static_cast<long>(out.shape(0)), width = static_cast<long>(out.shape(1));
  if (static_cast<long>(planes.shape(0)) != 8 * v * m) {
    throw std::invalid_argument("unshuffle_series: planes hold " +
                                std::to_string(planes.shape(0)) + " bytes, not 8 · " +
                                std::to_string(v) + " · " + std::to_string(m));
  }
  if (first < 0 || count < 0 || first + count > m || at < 0 || at + count > width) {
    throw std::invalid_argument("unshuffle_series: samples " + std::to_string(first) + " + " +
                                std::to_string(count) + " of " + std::to_string(m) + " to " +
                                std::to_string(at) + " of out " + shape_text(height, width));
  }
  if (count > 1 && out.stride(1) != 1) {
    throw std::invalid_argument("unshuffle_series: the rows of out must be contiguous");
  }
  const std::int64_t* dest = rows.data();
  for (long j = 0; j < v; ++j) {
    if (dest[j] >= height) {
      throw std::invalid_argument("unshuffle_series: row " + std::to_string(dest[j]) +
                                  " of out " + shape_text(height, width));
    }
  }
  const std::uint8_t* in = planes.data();
  double* data = out.data();
  const long s0 = static_cast<long>(out.stride(0));
  nb::gil_scoped_release release;
  for (long j = 0; j < v; ++j) {
    if (dest[j] >= 0) {
      unshuffle_bytes(in + j * m + first, v * m, count, data + dest[j] * s0 + at, stream);
    }
  }
}

// out[rows[j], at .. at + count] = values[j] for every j with rows[j] ≥ 0: a read log's series
// that are constant over a block, and the NaN of the poses between posed samples. Without the
// GIL.
void fill_rows(const nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>& values,
               const Indices& rows, OutMatrix out, long at, long count, bool stream) {
  const long c = static_cast<long>(rows.shape(0));
  const long height = static_cast<long>(out.shape(0)), width = static_cast<long>(out.shape(1));
  if (static_cast<long>(values.shape(0)) != c) {
    throw std::invalid_argument("fill_rows: " + std::to_string(values.shape(0)) +
                                " values for " + std::to_string(c) + " rows");
  }
  if (at < 0 || count < 0 || at + count > width || (count > 1 && out.stride(1) != 1)) {
    throw std::invalid_argument("fill_rows: samples " + std::to_string(at) + " + " +
                                std::to_string(count) + " of out " + shape_text(height, width) +
                                " (rows contiguous)");
  }
  const std::int64_t* dest = rows.data();
  for (long j = 0; j < c; ++j) {
    if (dest[j] >= height) {
      throw std::invalid_argument("fill_rows: row " + std::to_string(dest[j]) + " of out " +
                                  shape_text(height, width));
    }
  }
  const double* value = values.data();
  double* data = out.data();
  const long s0 = static_cast<long>(out.stride(0));
  nb::gil_scoped_release release;
  for (long j = 0; j < c; ++j) {
    if (dest[j] >= 0) fill_values(data + dest[j] * s0 + at, count, value[j], stream);
  }
}

}  // namespace

void bind_columns(nb::module_& m) {
  m.def(
      "fold_columns", [](const AnyMatrix& values, OutMatrix out) { fold_block(values, out, false); },
      "values"_a, "out"_a,
      "min, max, sum, sum of squares and last value of each column of an (m, k) block into the "
      "rows of out (5, k).");
  m.def(
      "fold_magnitudes",
      [](const AnyMatrix& values, OutMatrix out) { fold_block(values, out, true); }, "values"_a,
      "out"_a,
      "The same for the magnitudes of the vectors of an (m, 3e) block (x, y, z of each vector "
      "side by side) into out (5, e).");

  m.def("shuffle_series", &shuffle_series, "values"_a, "series"_a, "planes"_a,
        "The byte planes of the rows `series` of an (k, m) block, as one run of values.");
  m.def("unshuffle_series", &unshuffle_series, "planes"_a, "m"_a, "first"_a, "count"_a,
        "rows"_a, "out"_a, "at"_a, "stream"_a = false,
        "Samples first .. first + count of the shuffled series into out[rows[j], at ..].");

  m.def("fill_rows", &fill_rows, "values"_a, "rows"_a, "out"_a, "at"_a, "count"_a,
        "stream"_a = false,
        "out[rows[j], at .. at + count] = values[j] where rows[j] >= 0.");
}

}  // namespace pinwind
