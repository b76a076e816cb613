// The estimator's streaming loops, compiled once per instruction-set path (kernels.inc,
// through simd/path.cpp.in) and reached through the path's table. Each element's
// arithmetic is the same on every path and nothing contracts to FMA (-ffp-contract=off),
// so every path gives the same bits.
#pragma once

#include <cstddef>

namespace slidespec::estimator_detail {

struct StreamKernels {
  /// target[i] = source[i] - source[i - 1] for i in [from, to).
  void (*difference)(const double* source, double* target, std::ptrdiff_t from, std::ptrdiff_t to);
  /// The half-band filter on split input: out[j] = h[reach] centre[j] + sum over odd t of
  /// h[reach + t] (side[j - (t+1)/2] + side[j + (t-1)/2]), summed in the order of t.
  void (*half_band)(const double* taps, const double* centre, const double* side, std::ptrdiff_t outputs,
                    double* out);
  /// in[n] = window[n] * segment[n] for n < count.
  void (*window)(const double* window, const double* segment, double* in, std::size_t count);
};

}  // namespace slidespec::estimator_detail
