// The estimator's streaming loops, compiled once per instruction-set path (kernels.inc,
// through estimator/path.cpp.in) and reached through stream_kernels(). Each element's
// arithmetic is the same on every path and nothing contracts to FMA (-ffp-contract=off),
// so every path gives the same bits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "estimator/design.hpp"
#include "slidespec/simd.hpp"

namespace slidespec::estimator_detail {

/// exp(-2 pi i m / L) = cosine[m] - i sine[m] for the segment length L, exact at the
/// quadrants, and the bit reversal of the half-length complex transform's indices.
struct FourierTables {
  double cosine[kSegmentLength];
  double sine[kSegmentLength];
  std::uint16_t bit_reverse[kSegmentLength / 2];
};
/// The tables, computed once per process.
const FourierTables& fourier_tables();

// Every kernel works on rows of `stride` doubles (one sample of every lane, the lanes
// padded to a multiple of the path's width), so each row is whole vectors.
struct StreamKernels {
  /// Target row r = the third difference of source row r (rows -3 .. -1 of source are
  /// the ones before it), as differencing the stream three times forms it.
  void (*third_difference)(const double* source, double* target, std::ptrdiff_t rows, std::ptrdiff_t stride);
  /// The half-band filter, lane by lane: output row j is centred on row 2j of `centre`,
  /// out = h[reach] centre + sum over odd t of h[reach + t] (row 2j - t + row 2j + t),
  /// summed in the order of t.
  void (*half_band)(const double* taps, const double* centre, std::ptrdiff_t outputs, std::ptrdiff_t stride,
                    double* out);
  /// power row k = |X_k|^2 for k in [first_bin, last_bin] (within 0 .. L/2), X the DFT
  /// (unnormalized, e^{-i}) of the segment window[n] ring[(start + n) mod L]; work holds
  /// L rows.
  void (*segment_power)(const FourierTables& tables, const double* window, const double* ring, std::size_t start,
                        int first_bin, int last_bin, double* work, double* power, std::ptrdiff_t stride);
  /// q = sum over bins j of [first, first + count) of power row j * factor[j], in the
  /// order of j, divided by count.
  void (*bin_average)(const double* power, const double* factor, int first, int count, std::ptrdiff_t stride,
                      double* q);
};

/// The loops of resolve_simd_path(path); throws InputError for a path this CPU cannot run.
const StreamKernels& stream_kernels(SimdPath path);

}  // namespace slidespec::estimator_detail
