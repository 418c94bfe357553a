// Python bindings of the column helpers of pinwind.dynamics._native: statistics of a Result's
// columns and the byte planes of a log's series (module.cpp gathers the bindings).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "byte_planes.hpp"
#include "column_chunks.hpp"
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

// New memory of n values of T that a numpy array owns (freed with it).
template <class T>
std::pair<T*, nb::capsule> owned(std::size_t n) {
  T* data = new T[n ? n : 1];
  return {data, nb::capsule(data, [](void* p) noexcept { delete[] static_cast<T*>(p); })};
}

// A decompressed chunk of a log's columns placed into out (column_chunks.hpp): every columns
// record of `channel`, its samples with start ≤ t ≤ stop placed one record after the other from
// sample `at`. Returns (samples, pose rows, poses (pose series, posed samples), damage, highest):
// damage is "" or why the chunk is damaged (nothing placed); samples is -1 when a record's
// samples in the window are not consecutive (nothing placed), and when it is more than `room`
// nothing is placed either. Rows from `zeroed_from` on hold +0.0 wherever nothing is placed (new
// pages), so a series constant at +0.0 is not written there; in the rows before it (memory an
// earlier read used) every value is. `highest`: the last row given a value other than +0.0, -1
// for none. Without the GIL but to parse the arguments and make the results.
nb::tuple place_columns_chunk(const ConstBytes& chunk, int channel, long width, long pose_width,
                              const Indices& row_of, OutMatrix out, long at, long room,
                              std::optional<double> start, std::optional<double> stop,
                              const Indices& pose_series, bool posed, long zeroed_from) {
  const long height = static_cast<long>(out.shape(0)), samples = static_cast<long>(out.shape(1));
  if (static_cast<long>(row_of.shape(0)) != width) {
    throw std::invalid_argument("place_columns_chunk: " + std::to_string(row_of.shape(0)) +
                                " rows for " + std::to_string(width) + " series");
  }
  if (samples > 1 && out.stride(1) != 1) {
    throw std::invalid_argument("place_columns_chunk: the rows of out must be contiguous");
  }
  if (at < 0 || room < 0 || at + room > samples) {
    throw std::invalid_argument("place_columns_chunk: samples " + std::to_string(at) + " + " +
                                std::to_string(room) + " of out " + shape_text(height, samples));
  }
  const std::int64_t* rows = row_of.data();
  for (long j = 0; j < width; ++j) {
    if (rows[j] >= height) {
      throw std::invalid_argument("place_columns_chunk: row " + std::to_string(rows[j]) +
                                  " of out " + shape_text(height, samples));
    }
  }
  const long pose_count = static_cast<long>(pose_series.shape(0));
  const std::int64_t* pose_at = pose_series.data();
  for (long s = 0; s < pose_count; ++s) {
    if (pose_at[s] < 0 || pose_at[s] >= pose_width) {
      throw std::invalid_argument("place_columns_chunk: pose series " + std::to_string(pose_at[s]) +
                                  " of " + std::to_string(pose_width));
    }
  }
  const ColumnTarget to{out.data(), height, samples, static_cast<long>(out.stride(0)), rows,
                        zeroed_from};
  std::vector<ColumnRecord> records;
  std::vector<PosedSample> found;
  std::string damage;
  long filled = 0, highest = -1;
  {
    nb::gil_scoped_release release;
    bool consecutive = true;
    damage = parse_columns_chunk(chunk.data(), chunk.shape(0), channel, width, pose_width,
                                 start.has_value(), start.value_or(0.0), stop.has_value(),
                                 stop.value_or(0.0), records, consecutive);
    if (!damage.empty()) {
      filled = 0;
    } else if (!consecutive) {
      filled = -1;
    } else {
      long posed_at_most = 0;
      for (const auto& r : records) {
        filled += r.count;
        posed_at_most += r.p;
      }
      if (filled <= room) {
        found.reserve(posed ? posed_at_most : 0);
        long place = at;
        for (const auto& r : records) {
          if (!r.count) continue;
          place_columns_record(r, to, width, place, posed, found, highest);
          place += r.count;
        }
      }
    }
  }
  // the posed samples' rows, and their pose series (pose series, posed samples)
  const std::size_t n = found.size(), k = static_cast<std::size_t>(pose_count);
  auto [rows_out, rows_owner] = owned<std::int64_t>(n);
  auto [poses_out, poses_owner] = owned<double>(k * n);
  for (std::size_t q = 0; q < n; ++q) {
    const PosedSample& f = found[q];
    rows_out[q] = f.row;
    for (std::size_t s = 0; s < k; ++s) {
      poses_out[s * n + q] = load_double(f.poses + 8 * (pose_at[s] * f.p + f.k));
    }
  }
  return nb::make_tuple(filled, nb::ndarray<nb::numpy, std::int64_t, nb::ndim<1>>(rows_out, {n}, rows_owner),
                        nb::ndarray<nb::numpy, double, nb::ndim<2>>(poses_out, {k, n}, poses_owner),
                        damage, highest);
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
  m.def("place_columns_chunk", &place_columns_chunk, "chunk"_a, "channel"_a, "width"_a,
        "pose_width"_a, "row_of"_a, "out"_a, "at"_a, "room"_a, "start"_a.none(), "stop"_a.none(),
        "pose_series"_a, "posed"_a, "zeroed_from"_a = 0,
        "A decompressed chunk's columns records placed into out from sample at: (samples, pose "
        "rows, poses, damage, highest row given a value other than +0.0). Rows from zeroed_from "
        "on are +0.0 where nothing is placed (a constant +0.0 is not written there).");
}

}  // namespace pinwind
