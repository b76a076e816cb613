// Streaming spectrum estimator: many lanes (one realization each) of a sampled process
// in, C(omega) on a log-spaced axis out, by the convention of docs/model.md (MODEL.md
// section 3): two-sided, angular frequency, integral over all omega = variance.
//
// Memory is independent of the stream's length: the estimator keeps one segment buffer
// per lane per band and additive accumulators, never the trajectory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace slidespec {

/// What each sample of the stream is.
enum class SampleKind {
  value,      ///< x_n itself
  increment,  ///< x_n - x_{n-1}: the spectrum of x is recovered exactly by dividing by
              ///< |1 - exp(-i omega dt)|^2, and huge low-frequency power never enters
};

struct EstimatorConfig {
  double dt = 1.0;                 ///< sample interval [s]
  double omega_min = 0.0;          ///< lowest output omega [rad/s]; 0 = the longest segment allows
  double omega_max = 0.0;          ///< highest output omega [rad/s]; 0 = a safe fraction of Nyquist
  int points_per_decade = 8;       ///< output points evenly spaced in log omega
  SampleKind input = SampleKind::value;
};

/// One output point.
struct SpectrumPoint {
  double omega;      ///< centre of the output bin [rad/s]
  double C;          ///< spectrum estimate [unit^2 s]
  double standard_error;  ///< its statistical standard error [unit^2 s]
  double n_avg;      ///< number of periodogram values (segments x FFT bins) averaged
  double bandwidth;  ///< resolution bandwidth behind the point [rad/s]
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

  /// Adds `other`; throws std::invalid_argument if it was made with another configuration.
  void merge(const SpectrumAccumulator& other);

  /// The estimate, points with no data yet left out.
  std::vector<SpectrumPoint> spectrum() const;

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
  /// Throws InputError when the configuration cannot work (dt <= 0, band outside Nyquist).
  SpectrumEstimator(const EstimatorConfig& config, int lanes);
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

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// Derived columns of MODEL.md section 5 for a displacement spectrum C_x.
inline double velocity_spectrum(double omega, double C_x) { return omega * omega * C_x; }
inline double force_spectrum(double omega, double C_x, double block_mass) {
  return block_mass * block_mass * omega * omega * omega * omega * C_x;
}

}  // namespace slidespec
