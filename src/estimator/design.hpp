// The fixed design of the estimator: segment length, window, band differencing and the
// half-band decimation filter, plus the layout (bands, output points, FFT bins, exact
// transfer functions) that follows from an EstimatorConfig. Shared by the estimator and
// by every accumulator made from it; immutable once built.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "slidespec/estimator.hpp"

namespace slidespec::estimator_detail {

// Samples per segment, in every band. Band b reports bins L/10 .. 0.3 L (band 0 up to
// omega_max), so the lowest reported bin sits 52 resolution widths above DC.
inline constexpr int kSegmentLength = 512;
// 75% overlap: the Kaiser window below is narrow (rms ~L/9), so segments a quarter
// apart are nearly independent (correlation ~0.06) and 4x more of them are averaged.
inline constexpr int kSegmentHop = 128;
inline constexpr int kOverlapLags = kSegmentLength / kSegmentHop - 1;
// Kaiser beta = 20: sidelobes below -150 dB, so leakage across a band is negligible.
inline constexpr double kWindowBeta = 20.0;
// Each band differences its stream this many more times (on top of x -> increments),
// which whitens spectra as steep as omega^-8 before the window and the FFT round.
inline constexpr int kBandDifferences = 3;
// Half-band decimator: 2 * kHalfBandReach + 1 taps, Kaiser-windowed sinc. Passband to
// 0.3 pi, stopband from 0.7 pi (what folds onto the reported part of the next band).
inline constexpr int kHalfBandReach = 27;
inline constexpr double kHalfBandBeta = 17.0;
// A point needs this many segments before its scatter makes a usable error bar.
inline constexpr std::uint64_t kMinimumSegments = 12;
inline constexpr int kMaximumBands = 64;

std::vector<double> kaiser_window(int length, double beta);
std::vector<double> half_band_taps();
/// |H(theta)|^2 of the (zero-phase) half-band filter at theta = omega * interval.
double half_band_power(const std::vector<double>& taps, double theta);

struct OutputPoint {
  double omega;
  int band;
  int first_bin;
  int bin_count;
  // Correlation of this point's bin-averaged periodogram between segments `lag` hops
  // apart, for a locally white spectrum (exact for the window; index lag - 1).
  std::array<double, kOverlapLags> overlap_correlation;
};

struct BandLayout {
  double interval;                 // sample interval of the band's stream [s]
  double enbw;                     // equivalent noise bandwidth [rad/s]
  std::vector<double> bin_factor;  // per FFT bin: normalisation / exact transfer
  // Exact transfer x -> band stream at bin omega and at omega -/+ the window's rms
  // spectral width, for the smoothing-bias correction of spectrum().
  std::vector<double> transfer_center, transfer_below, transfer_above;
  double kernel_width;      // rms width of the window's spectral kernel [rad/s]
  std::vector<int> points;  // output points this band serves
};

struct Layout {
  EstimatorConfig config;
  int band_count = 0;
  std::vector<double> window;
  double window_power = 0;  // sum w^2
  std::vector<double> taps;
  std::vector<OutputPoint> points;  // ascending omega
  std::vector<BandLayout> bands;

  /// Validates the configuration (InputError) and fills in omega_min/omega_max defaults.
  static std::shared_ptr<const Layout> make(const EstimatorConfig& config);
  double bin_omega(int band, int bin) const;
  /// The band whose reported range holds omega (band 0 from full_rate_band_floor(dt)).
  int band_for(double omega) const;
  /// Exact power transfer from x to band `band`'s differenced stream.
  double transfer(int band, double omega) const;
};

bool same_config(const EstimatorConfig& a, const EstimatorConfig& b);

}  // namespace slidespec::estimator_detail
