// A decompressed chunk of a pinwind log's columns (docs/log_format.md, "Columns", layout 3)
// placed into a read's arrays in one pass: its message records parsed, each columns record's
// varying series unshuffled (byte_planes.hpp) into their rows, its constant series filled, and
// its poses gathered, as pinwind/io/log_columns.py's decode_chunk and ColumnSink.place do for
// one block at a time in Python (whose per-block calls cost a drivetrain read ~2 ms of CPU).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "byte_planes.hpp"

namespace pinwind {

// A columns payload's header: layout byte, samples m, posed samples p.
constexpr long kColumnsHead = 9;
// A message record's header: opcode, length, channel, sequence, log and publish time.
constexpr long kMessageHead = 31;
constexpr std::uint8_t kMessageOpcode = 0x05;
constexpr std::uint8_t kColumnsLayout = 3;

// Where a read's values go: `data` is (height, width) float64 with contiguous rows `stride`
// apart; series j of the columns goes to row row_of[j] (< 0: not read).
struct ColumnTarget {
  double* data;
  long height, width, stride;
  const std::int64_t* row_of;  // (columns width,)
  // rows from zeroed_from on hold +0.0 wherever nothing is placed (new pages, or the part of an
  // earlier read's memory that it left at +0.0): a series constant at +0.0 is not written there;
  // in the rows before it every value is written
  long zeroed_from = 0;
};

// One columns record of a chunk, checked (pointers into the chunk).
struct ColumnRecord {
  long m = 0, p = 0, vary = 0, constant = 0;
  const std::uint8_t* bits = nullptr;    // constant-series bits, little bit order
  const std::uint8_t* planes = nullptr;  // 8 · vary · m bytes
  const std::uint8_t* constants = nullptr;  // constant float64 values
  const std::uint8_t* poses = nullptr;      // (pose_width, p) float64 values
  std::vector<double> time;                 // the m sample times [s]
  long first = 0, count = 0;                // the samples in the window
};

inline std::uint64_t load_le(const std::uint8_t* at, int bytes) {
  std::uint64_t v = 0;
  for (int b = 0; b < bytes; ++b) v |= std::uint64_t{at[b]} << (8 * b);
  return v;
}

inline double load_double(const std::uint8_t* at) {
  double value;
  std::memcpy(&value, at, 8);
  return value;
}

inline bool is_constant(const std::uint8_t* bits, long j) { return (bits[j >> 3] >> (j & 7)) & 1; }

// numpy's order of float64, NaN last (its searchsorted and sort).
inline bool numpy_less(double a, double b) { return a < b || (b != b && a == a); }

// The columns records of channel `channel` in the chunk's `size` bytes, checked against the
// lengths they give, with their times and the samples with start ≤ t ≤ stop (a bound is left
// out where has_start / has_stop is false). Returns "" or why the chunk is damaged, in the words
// of log_columns.decode_chunk; `consecutive` is false when a record's samples in the window are
// not consecutive (a foreign file: the caller places them another way).
inline std::string parse_columns_chunk(const std::uint8_t* data, std::uint64_t size, int channel,
                                       long width, long pose_width, bool has_start, double start,
                                       bool has_stop, double stop,
                                       std::vector<ColumnRecord>& records, bool& consecutive) {
  const std::uint64_t flags = 8 * ((static_cast<std::uint64_t>(width) + 63) / 64);
  consecutive = true;
  std::uint64_t pos = 0;
  while (pos < size) {
    if (size - pos < 9) return "a record at byte " + std::to_string(pos) + " of the chunk is cut";
    const std::uint64_t length = load_le(data + pos + 1, 8);
    if (length > size - pos - 9) {
      return "a record at byte " + std::to_string(pos) + " of the chunk runs past its end";
    }
    const std::uint64_t end = pos + 9 + length;
    if (data[pos] == kMessageOpcode && length >= 22 &&
        static_cast<int>(load_le(data + pos + 9, 2)) == channel) {
      const std::uint64_t at = pos + kMessageHead;
      const std::string where = "a columns record at byte " + std::to_string(at);
      if (end - at < kColumnsHead + flags || data[at] != kColumnsLayout) {
        return where + " has an unknown layout";
      }
      ColumnRecord r;
      r.m = static_cast<long>(load_le(data + at + 1, 4));
      r.p = static_cast<long>(load_le(data + at + 5, 4));
      if (!(r.m == 0 && r.p == 0 && end - at == kColumnsHead + flags)) {  // else: a block's end
        r.bits = data + at + kColumnsHead;
        for (long j = 0; j < width; ++j) r.constant += is_constant(r.bits, j);
        r.vary = width - r.constant;
        const std::uint64_t doubles = static_cast<std::uint64_t>(r.vary) * r.m + r.constant +
                                      static_cast<std::uint64_t>(pose_width) * r.p;
        const std::uint64_t start_at = at + kColumnsHead + flags;
        if (end - start_at != 8 * doubles || (r.m == 0 && r.constant)) {
          return where + " holds " + std::to_string(end - at) + " bytes, not the " +
                 std::to_string(start_at - at + 8 * doubles) + " of " + std::to_string(r.m) +
                 " samples (" + std::to_string(r.constant) + " series constant) and " +
                 std::to_string(r.p) + " poses";
        }
        r.planes = data + start_at;
        r.constants = r.planes + 8 * r.vary * r.m;
        r.poses = r.constants + 8 * r.constant;
        r.time.resize(r.m);
        if (r.m && !is_constant(r.bits, 0)) {  // the time varies: the first varying series
          unshuffle_bytes(r.planes, r.vary * r.m, r.m, r.time.data());
        } else if (r.m) {
          const double t = load_double(r.constants);
          for (auto& value : r.time) value = t;
        }
        // the samples in the window, as log_reader._window
        long first = -1, last = -1, inside = 0;
        for (long i = 0; i < r.m; ++i) {
          const double t = r.time[i];
          if ((!has_start || t >= start) && (!has_stop || t <= stop)) {
            if (first < 0) first = i;
            last = i;
            ++inside;
          }
        }
        if (inside && last - first + 1 != inside) consecutive = false;
        r.first = inside ? first : 0;
        r.count = inside;
        records.push_back(std::move(r));
      }
    }
    pos = end;
  }
  return "";
}

// A posed sample found in the window: its sample of the arrays, and its pose values.
struct PosedSample {
  std::int64_t row;
  const std::uint8_t* poses;  // the record's (pose_width, p) float64 values
  long p, k;                  // posed samples of the record, and which one
};

// Places a parsed record's samples in the window at samples at .. at + count of `to`: the
// varying series unshuffled, the constant ones filled but for +0.0 in the rows from
// to.zeroed_from on (all bits zero: new arrays start as zeros, and pages nobody writes are never
// touched), both around the caches. Raises `highest` to the last row given a value other than
// +0.0 (a varying series counts as such). Appends the posed samples in the window (at + their
// sample) to `found`, as ColumnSink.place.
inline void place_columns_record(const ColumnRecord& r, const ColumnTarget& to, long width,
                                 long at, bool posed, std::vector<PosedSample>& found,
                                 long& highest) {
  long slot_vary = 0, slot_constant = 0;
  for (long j = 0; j < width; ++j) {
    const std::int64_t row = to.row_of[j];
    if (is_constant(r.bits, j)) {
      const std::uint8_t* value = r.constants + 8 * slot_constant++;
      const bool zero = load_le(value, 8) == 0;
      if (row >= 0 && (!zero || row < to.zeroed_from)) {
        fill_values(to.data + row * to.stride + at, r.count, load_double(value), true);
        if (!zero && row > highest) highest = static_cast<long>(row);
      }
    } else {
      if (row >= 0) {
        unshuffle_bytes(r.planes + slot_vary * r.m + r.first, r.vary * r.m, r.count,
                        to.data + row * to.stride + at, true);
        if (row > highest) highest = static_cast<long>(row);
      }
      ++slot_vary;
    }
  }
  if (!posed || r.p == 0) return;
  const double* time = r.time.data() + r.first;
  for (long k = 0; k < r.p; ++k) {
    const double t = load_double(r.poses + 8 * k);  // pose series 0: the time
    long lo = 0, hi = r.count;  // searchsorted(time, t, side="left")
    while (lo < hi) {
      const long mid = lo + (hi - lo) / 2;
      if (numpy_less(time[mid], t)) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    const long where = lo < r.count - 1 ? lo : r.count - 1;
    if (time[where] == t) found.push_back({at + where, r.poses, r.p, k});
  }
}

}  // namespace pinwind
