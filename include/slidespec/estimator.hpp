// Streaming spectrum estimator: many lanes (one realization each) of a sampled process
// in, C(omega) on a log-spaced axis out, by the convention of docs/model.md §3:
// two-sided, angular frequency, integral over all omega = variance.
//
// Memory is independent of the stream's length: the estimator keeps one segment buffer
// per lane per band and additive accumulators, never the trajectory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "slidespec/simd.hpp"

namespace slidespec {

/// What each sample of the stream is.
enum class SampleKind {
  value,      ///< x_n itself
  increment,  ///< x_n - x_{n-1}: the spectrum of x is recovered exactly by dividing by
              ///< |1 - exp(-i omega dt)|^2, and huge low-frequency power never enters
};

struct EstimatorConfig {
  double dt = 1.0;            ///< sample interval [s]
  double omega_min = 0.0;     ///< lowest output omega [rad/s]; 0 = the longest segment allows
  double omega_max = 0.0;     ///< highest output omega [rad/s]; 0 = a safe fraction of Nyquist
  int points_per_decade = 8;  ///< output points evenly spaced in log omega
  SampleKind input = SampleKind::value;
};

/// The lowest omega the estimator's full-rate band reports, a quarter of the Nyquist
/// frequency: pi / (4 dt) [rad/s]. Lower points come from the decimated bands, band b
/// from pi / (4 dt 2^b).
inline double full_rate_band_floor(double dt) { return 0.25 * std::numbers::pi / dt; }

/// What an output point's C stands for.
enum class PointValue {
  bin_average,      ///< average of C over the point's FFT bins, [omega_low, omega_high]:
                    ///< compare with the exact C averaged over that interval
  centre,           ///< C at the point's omega: the bin average corrected for the local slope
                    ///< and curvature of ln C (for smooth spectra; see docs/estimator.md)
  window_smoothed,  ///< the plain mean of the periodogram over the point's bins: C averaged
                    ///< over the bins after the window's smoothing, with no model of the
                    ///< local shape; expected() of it is exact for any true spectrum
};

/// One output point.
struct SpectrumPoint {
  double omega;            ///< centre of the output bin [rad/s]
  double C;                ///< spectrum estimate [unit^2 s]
  double standard_error;   ///< its statistical standard error [unit^2 s]
  double n_avg;            ///< number of periodogram values (segments x FFT bins) averaged
  double bandwidth;        ///< resolution bandwidth behind the point [rad/s]
  double omega_low;        ///< lower edge of the FFT bins averaged [rad/s]
  double omega_high;       ///< upper edge of the FFT bins averaged [rad/s]
  double bin_spacing = 0;  ///< spacing of those FFT bins [rad/s]: their centres are
                           ///< omega_low + (j + 1/2) bin_spacing, j < bin_count
  int bin_count = 0;       ///< FFT bins averaged
};

/// The additive statistics of one or more realizations. Merging two accumulators gives
/// exactly what one estimator would have accumulated from both streams (up to rounding
/// of the sums, which callers make reproducible by merging in a fixed order).
class SpectrumAccumulator {
 public:
  SpectrumAccumulator();
  ~SpectrumAccumulator();
  SpectrumAccumulator(const SpectrumAccumulator&);
  SpectrumAccumulator& operator=(const SpectrumAccumulator&);
  SpectrumAccumulator(SpectrumAccumulator&&) noexcept;
  SpectrumAccumulator& operator=(SpectrumAccumulator&&) noexcept;

  /// Adds `other`; throws InputError (one line) if it was made with another configuration.
  void merge(const SpectrumAccumulator& other);

  /// The estimate. Points whose band has fewer than 12 segments (too few for an error
  /// bar) are left out; so are points of a log bin narrower than one FFT bin.
  std::vector<SpectrumPoint> spectrum(PointValue value = PointValue::bin_average) const;

  /// What spectrum(value) reports on average for a process whose true spectrum is
  /// `true_spectrum(omega)`: the window's exact smoothing and every transfer function of
  /// the cascade applied to it. Compare an estimate with this, point by point, to test it
  /// against a theory without the bin averaging or the smoothing in the way.
  std::vector<SpectrumPoint> expected(const std::function<double(double)>& true_spectrum,
                                      PointValue value = PointValue::bin_average) const;

  /// Raw statistics of every output point, for callers that combine realizations
  /// themselves: the sum over segments of each segment's bin-averaged periodogram (before
  /// the smoothing correction of spectrum()), and the segments behind it.
  struct PointSum {
    double omega;
    double sum;
    std::uint64_t segments;
  };
  std::vector<PointSum> point_sums() const;

  /// Versioned binary form; `load` throws InputError for another version or a corrupt file.
  std::string save() const;
  static SpectrumAccumulator load(const std::string& bytes);

  struct Impl;

 private:
  explicit SpectrumAccumulator(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
  friend class SpectrumEstimator;
};

class SpectrumEstimator {
 public:
  /// Throws InputError when the configuration cannot work (dt <= 0, band outside Nyquist)
  /// or this CPU cannot run `simd`. Every path gives bitwise the same statistics;
  /// `automatic` takes the widest path no wider than `lanes`.
  SpectrumEstimator(const EstimatorConfig& config, int lanes, SimdPath simd = SimdPath::automatic);
  ~SpectrumEstimator();
  SpectrumEstimator(SpectrumEstimator&&) noexcept;
  SpectrumEstimator& operator=(SpectrumEstimator&&) noexcept;

  int lanes() const;
  const EstimatorConfig& config() const;

  /// Feeds `steps` time steps of every lane, step-major: data[step * lanes() + lane].
  void push(const double* data, std::size_t steps);

  /// What lane `lane` has accumulated so far (whole segments only).
  SpectrumAccumulator accumulator(int lane) const;

  /// All lanes merged in lane order.
  SpectrumAccumulator merged() const;

  /// Duration of one segment of the band that serves `omega` [s]: a lane contributes
  /// its first segment there after this long, then one more every quarter of it.
  double segment_duration(double omega) const;

  /// Segments one lane has given the band that serves `omega` after `steps` samples from
  /// the start (the cascade's filters and differences take their own samples first).
  std::uint64_t segments_after(std::uint64_t steps, double omega) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// Derived columns of docs/model.md §3 for a displacement spectrum C_x.
inline double velocity_spectrum(double omega, double C_x) { return omega * omega * C_x; }
inline double force_spectrum(double omega, double C_x, double block_mass) {
  return block_mass * block_mass * omega * omega * omega * omega * C_x;
}

}  // namespace slidespec
