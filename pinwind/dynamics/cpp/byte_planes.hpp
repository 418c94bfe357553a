// The byte planes of float64 series: the log's columns (docs/log_format.md, "Columns", layout 3)
// store n values as byte 0 of every value, then byte 1 of every value, ..., byte 7 (the
// "shuffle" filter of Blosc and HDF5, numcodecs.Shuffle(elementsize=8)). The high bytes of a
// smooth series (sign, exponent, leading mantissa bits) then repeat in long runs: zstd -1 stores
// the columns in 0.6 of the bytes it needs without the shuffle, compresses them 1.6 times and
// decompresses them twice as fast (benchmarks/README.md, read_log.py).
#pragma once

#include <cstdint>
#include <cstring>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define PINWIND_BYTE_PLANES_SSE2 1
#endif

namespace pinwind {

#ifdef PINWIND_BYTE_PLANES_SSE2
// One step of the 16 × 8 byte transpose: the 128 bytes of x[0..7] (x[k] byte j at address
// 16 k + j, 7 bits a6..a0) move to address a5..a0 a6 (a left rotation by one bit). Values
// 2k, 2k + 1 in x[k] have value bits in a6..a3 and byte bits in a2..a0; planes (plane b in x[b],
// value i in byte i) have them the other way round: four steps make planes of values, three make
// values of planes (seven steps are the identity).
inline void rotate_addresses(__m128i* x) {
  __m128i y[8];
  for (int v = 0; v < 4; ++v) {
    y[2 * v] = _mm_unpacklo_epi8(x[v], x[v + 4]);
    y[2 * v + 1] = _mm_unpackhi_epi8(x[v], x[v + 4]);
  }
  for (int k = 0; k < 8; ++k) x[k] = y[k];
}
#endif

// Writes byte b of values[i] (little-endian) to planes[b * stride + i], for i < n.
inline void shuffle_bytes(const double* values, long n, std::uint8_t* planes, long stride) {
  long i = 0;
#ifdef PINWIND_BYTE_PLANES_SSE2
  for (; i + 16 <= n; i += 16) {
    __m128i x[8];
    for (int k = 0; k < 8; ++k) {
      x[k] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(values + i + 2 * k));
    }
    for (int step = 0; step < 4; ++step) rotate_addresses(x);
    for (int b = 0; b < 8; ++b) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(planes + b * stride + i), x[b]);
    }
  }
#endif
  for (; i < n; ++i) {
    std::uint64_t v;
    std::memcpy(&v, values + i, 8);
    for (int b = 0; b < 8; ++b) planes[b * stride + i] = static_cast<std::uint8_t>(v >> (8 * b));
  }
}

inline double unshuffle_one(const std::uint8_t* planes, long stride, long i) {
  std::uint64_t v = 0;
  for (int b = 0; b < 8; ++b) v |= std::uint64_t{planes[b * stride + i]} << (8 * b);
  double value;
  std::memcpy(&value, &v, 8);
  return value;
}

// The inverse: values[i] from planes[b * stride + i], b = 0..7, for i < n.
//
// stream: write around the caches (non-temporal stores) where the values go to memory that is
// not read soon, e.g. a whole log read into new arrays: a write through the cache first reads
// each line the kernel has just zeroed back from memory.
inline void unshuffle_bytes(const std::uint8_t* planes, long stride, long n, double* values,
                            bool stream = false) {
  long i = 0;
#ifdef PINWIND_BYTE_PLANES_SSE2
  if (stream && n >= 32 && reinterpret_cast<std::uintptr_t>(values) % 8 == 0) {
    for (; reinterpret_cast<std::uintptr_t>(values + i) % 16 != 0; ++i) {
      values[i] = unshuffle_one(planes, stride, i);
    }
  }
  const bool aligned = reinterpret_cast<std::uintptr_t>(values + i) % 16 == 0;
  for (; i + 16 <= n; i += 16) {
    __m128i x[8];
    for (int b = 0; b < 8; ++b) {
      x[b] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(planes + b * stride + i));
    }
    for (int step = 0; step < 3; ++step) rotate_addresses(x);
    __m128i* out = reinterpret_cast<__m128i*>(values + i);
    if (stream && aligned) {
      for (int k = 0; k < 8; ++k) _mm_stream_si128(out + k, x[k]);
    } else {
      for (int k = 0; k < 8; ++k) _mm_storeu_si128(out + k, x[k]);
    }
  }
  if (stream) _mm_sfence();  // the streamed stores are seen before what follows
#endif
  for (; i < n; ++i) values[i] = unshuffle_one(planes, stride, i);
}

// values[0 .. n) = value; streamed as in unshuffle_bytes.
inline void fill_values(double* values, long n, double value, bool stream = false) {
  long i = 0;
#ifdef PINWIND_BYTE_PLANES_SSE2
  if (stream && n >= 32 && reinterpret_cast<std::uintptr_t>(values) % 8 == 0) {
    if (reinterpret_cast<std::uintptr_t>(values) % 16 != 0) values[i++] = value;
    const __m128d pair = _mm_set1_pd(value);
    for (; i + 2 <= n; i += 2) _mm_stream_pd(values + i, pair);
    _mm_sfence();
  }
#endif
  for (; i < n; ++i) values[i] = value;
}

}  // namespace pinwind
