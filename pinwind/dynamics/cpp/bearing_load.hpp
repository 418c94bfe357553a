// A bearing's reaction split about its axis (pinwind/dynamics/bearing_load.py): the force or
// moment along the axis, v·k, and its part normal to it, |v − (v·k) k|, for every sample and
// bearing of a block, in one pass.
#pragma once

#include <cmath>

namespace pinwind {

// v·k and |v − (v·k) k| of the vectors v (samples, bearings, 3) about their bearings' unit axes
// k (bearings, 3, contiguous), into (samples, bearings) C-contiguous `along` and `across`, either
// null (not computed). v's strides s0, s1, s2 are in doubles.
//
// The operations are numpy's of the formula, in its order and without fused multiply-adds
// (the module is built for baseline x86-64, which has none): along = (v_x k_x + v_y k_y) +
// v_z k_z; n = v − along k; across = √((n_x² + n_y²) + n_z²). So every value, zeros' signs and
// NaN for a non-finite component included, is the one numpy's element-wise formula gives.
inline void split_about_axes(const double* v, long samples, long bearings, long s0, long s1,
                             long s2, const double* k, double* along, double* across) {
  for (long i = 0; i < samples; ++i) {
    const double* row = v + i * s0;
    for (long b = 0; b < bearings; ++b) {
      const double* x = row + b * s1;
      const double* axis = k + 3 * b;
      const double vx = x[0], vy = x[s2], vz = x[2 * s2];
      double dot = vx * axis[0];
      dot += vy * axis[1];
      dot += vz * axis[2];
      if (along != nullptr) along[i * bearings + b] = dot;
      if (across != nullptr) {
        double nx = dot * axis[0];
        nx = vx - nx;
        double ny = dot * axis[1];
        ny = vy - ny;
        double nz = dot * axis[2];
        nz = vz - nz;
        double square = nx * nx;
        square += ny * ny;
        square += nz * nz;
        across[i * bearings + b] = std::sqrt(square);
      }
    }
  }
}

}  // namespace pinwind
