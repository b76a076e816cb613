// The short-record estimator: Welch's average of Hann-windowed periodograms of half-overlapping
// segments, taken of the first differences and divided by their exact transfer function
// (prewhitening), with FFTW's real transforms. Method, error bars and leakage: docs/analysis.md.
#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>

#include "util/numbers.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec {

namespace {

// Eight half-overlapping segments: the textbook choice (Welch 1967), error bars of ~35% at the
// lowest points, and the lowest point, bin 2 of a segment, at 9 x 2 pi / T.
constexpr int kTargetSegments = 8;
// The fewest segments a lower --omega-min may buy: below this the error bar is ~60% and the
// chi-square distribution of a point is too skewed for a symmetric error bar.
constexpr int kFewestSegments = 4;
// Bin 1 of a segment shares its window with the segment mean removed; bin 2 is the first clean one.
constexpr std::size_t kLowestBin = 2;
// Leakage is flagged where the window's far side lobes carry more than this share of a
// point's standard error into it.
constexpr double kLeakageShareOfError = 0.3;
// The Hann side lobes fall as omega^-6; a difference spectrum falling faster than omega^-4
// over an octave either side is within reach of them.
constexpr double kSteepestDifferenceSlope = -4;
// The Hann kernel's main lobe: the two bins either side are the window's smoothing, not leakage.
constexpr std::size_t kMainLobeBins = 2;

/// FFTW's planner is not thread-safe; plans are made under this lock, executed outside it.
std::mutex& planner_lock() {
  static std::mutex lock;
  return lock;
}

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};

/// The plans made so far, destroyed with the process's statics (so that leak checkers see
/// them freed, not dropped).
struct PlanCache {
  std::map<std::size_t, fftw_plan> plans;
  PlanCache() = default;
  PlanCache(const PlanCache&) = delete;
  PlanCache& operator=(const PlanCache&) = delete;
  ~PlanCache() {
    for (const auto& [length, plan] : plans)
      if (plan) fftw_destroy_plan(plan);
  }
};

/// The real-to-complex plan of one length, made once and kept for the process's life (a plan
/// is a few twiddle tables; a record's lengths are few): FFTW_ESTIMATE, so the same plan and
/// bitwise the same numbers on every run. It runs on any arrays from fftw_alloc_* (FFTW's
/// alignment) with fftw_execute_dft_r2c, from any thread.
fftw_plan r2c_plan(std::size_t length) {
  static PlanCache cache;
  const std::lock_guard guard(planner_lock());
  fftw_plan& plan = cache.plans[length];
  if (!plan) {
    const std::unique_ptr<double, FftwFree> in(fftw_alloc_real(length));
    const std::unique_ptr<fftw_complex, FftwFree> out(fftw_alloc_complex(length / 2 + 1));
    plan = fftw_plan_dft_r2c_1d(static_cast<int>(length), in.get(), out.get(), FFTW_ESTIMATE);
  }
  return plan;
}

/// The largest length <= n whose prime factors are 2, 3, 5 and 7 (FFTW's fast kernels), even.
std::size_t fft_friendly(std::size_t n) {
  for (std::size_t m = n - n % 2; m >= 2; m -= 2) {
    std::size_t r = m;
    for (const std::size_t p : {2, 3, 5, 7})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
  return 2;
}

/// The Hann power kernel averaged over one bin at offset d (in bins), normalised to unit sum
/// over all offsets: |sinc(f) / (1 - f^2)|^2 / 1.5 integrated over [d - 1/2, d + 1/2].
double hann_bin_kernel(std::size_t d) {
  const auto power = [](double f) {
    if (std::fabs(f) < 1e-9) return 1.0;
    if (std::fabs(std::fabs(f) - 1) < 1e-9) return 0.25;
    const double s = std::sin(std::numbers::pi * f) / (std::numbers::pi * f) / (1 - f * f);
    return s * s;
  };
  if (d > 20) {  // side lobes: sin^2 averages to 1/2 over a bin
    const double f = static_cast<double>(d);
    return 0.5 / (std::numbers::pi * std::numbers::pi * f * f * (f * f - 1) * (f * f - 1)) / 1.5;
  }
  constexpr int kSteps = 64;  // Simpson's rule
  const double a = static_cast<double>(d) - 0.5, h = 1.0 / kSteps;
  double sum = power(a) + power(a + 1);
  for (int i = 1; i < kSteps; ++i) sum += (i % 2 ? 4 : 2) * power(a + i * h);
  return sum * h / 3 / 1.5;
}

// An error bar spans two standard deviations either side, as a chi-square interval.
constexpr double kBarSigmas = 2;

/// The chi-square quantile with `dof` degrees of freedom at the normal deviate z
/// (Wilson-Hilferty: within 1% for dof >= 3).
double chi_square_quantile(double dof, double z) {
  const double a = 2 / (9 * dof);
  return dof * std::pow(std::max(0.0, 1 - a + z * std::sqrt(a)), 3);
}

/// sum over bins j >= 1 beyond the main lobe (|j - centre| > kMainLobeBins) of
/// periodogram[j] kernel[|j - centre|]: two branch-free runs with four partial sums each.
double side_lobe_sum(const std::vector<double>& periodogram, const std::vector<double>& kernel, std::size_t centre) {
  double sum[4] = {0, 0, 0, 0};
  // Below the centre: j = centre - d for d from centre - 1 down to kMainLobeBins + 1.
  const std::size_t below = centre > kMainLobeBins + 1 ? centre - kMainLobeBins - 1 : 0;  // bins 1 .. below
  std::size_t j = 1;
  for (; j + 3 <= below; j += 4)
    for (std::size_t i = 0; i < 4; ++i) sum[i] += periodogram[j + i] * kernel[centre - j - i];
  for (; j <= below; ++j) sum[0] += periodogram[j] * kernel[centre - j];
  // Above it: j = centre + d for d from kMainLobeBins + 1.
  const std::size_t bins = periodogram.size();
  for (j = centre + kMainLobeBins + 1; j + 3 < bins; j += 4)
    for (std::size_t i = 0; i < 4; ++i) sum[i] += periodogram[j + i] * kernel[j + i - centre];
  for (; j < bins; ++j) sum[0] += periodogram[j] * kernel[j - centre];
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

}  // namespace

std::size_t welch_segment_samples(std::size_t samples, double dt, double omega_min) {
  const std::size_t differences = samples - 1;
  std::size_t length = fft_friendly(2 * differences / (kTargetSegments + 1));
  if (omega_min > 0) {
    // Bin 2 at or below omega_min, if the record holds enough segments for it.
    const double wanted = kLowestBin * 2 * std::numbers::pi / (omega_min * dt);
    const std::size_t longest = fft_friendly(2 * differences / (kFewestSegments + 1));
    if (wanted > static_cast<double>(longest)) {
      const double reachable = kLowestBin * 2 * std::numbers::pi / (static_cast<double>(longest) * dt);
      throw InputError("{omega_min} " + util::format_number(omega_min) + ": the record (" + std::to_string(samples) +
                       " samples, T = " + util::format_number(static_cast<double>(samples) * dt) +
                       " s) reaches down to " + util::format_number(reachable) + " rad/s (bin 2 of " +
                       std::to_string(kFewestSegments) +
                       " half-overlapping segments); a lower omega needs a longer record");
    }
    if (wanted > static_cast<double>(length)) {
      length = std::size_t(std::ceil(wanted));
      length += length % 2;
      // Round up to a fast length that still fits the record.
      for (std::size_t m = length; m <= longest; m += 2)
        if (fft_friendly(m) == m) {
          length = m;
          break;
        }
      length = std::min(length, longest);
    }
  }
  return length;
}

namespace {

/// The Hann window of `length` samples, and its power, the sum of its squares.
std::vector<double> hann_window(std::size_t length, double& power) {
  std::vector<double> window(length);
  for (std::size_t j = 0; j < length; ++j) {
    window[j] = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * double(j) / double(length));
    power += window[j] * window[j];
  }
  return window;
}

/// The mean Hann-windowed periodogram of the first differences of the segments starting at
/// `starts` (window.size() + 1 samples each), each segment's mean difference removed,
/// normalised as C (docs/model.md §3).
std::vector<double> difference_periodogram(const std::vector<const double*>& starts, double dt,
                                           const std::vector<double>& window, double window_power,
                                           const std::atomic<bool>* stop) {
  const std::size_t segments = starts.size();
  const std::size_t length = window.size(), bins = length / 2 + 1;
  const std::unique_ptr<double, FftwFree> in(fftw_alloc_real(length));
  const std::unique_ptr<fftw_complex, FftwFree> spectrum(fftw_alloc_complex(bins));
  const fftw_plan plan = r2c_plan(length);
  std::vector<double> periodogram(bins, 0.0);
  for (std::size_t s = 0; s < segments; ++s) {
    hear_stop(stop);
    const double* segment = starts[s];
    // The segment's mean difference is its mean slope: removing it removes each segment's trend.
    double mean = 0;
    for (std::size_t j = 0; j < length; ++j) mean += segment[j + 1] - segment[j];
    mean /= double(length);
    for (std::size_t j = 0; j < length; ++j) in.get()[j] = window[j] * (segment[j + 1] - segment[j] - mean);
    fftw_execute_dft_r2c(plan, in.get(), spectrum.get());
    for (std::size_t k = 0; k < bins; ++k)
      periodogram[k] += spectrum.get()[k][0] * spectrum.get()[k][0] + spectrum.get()[k][1] * spectrum.get()[k][1];
  }
  // docs/model.md §3: C = dt / (2 pi) |sum w x e^{-i omega t}|^2 / sum w^2, of the differences.
  const double scale = dt / (2 * std::numbers::pi * window_power * double(segments));
  for (double& p : periodogram) p *= scale;
  return periodogram;
}

/// Variance of a point relative to C^2: segments overlapping by half share rho_s of their
/// power; neighbouring bins of one window share rho_b(d) (Hann: 4/9, 1/36).
struct PointVariance {
  double segment_factor = 0;
  std::vector<double> rho_b;

  /// Of a point over m bins: sum over i, j < m of rho_b(|i - j|), each offset d occurring
  /// m - d times either way.
  double relative(std::size_t bins) const {
    const double m = double(bins);
    double bin_factor = m * rho_b[0];
    for (std::size_t d = 1; d < rho_b.size() && d < bins; ++d) bin_factor += 2 * (m - double(d)) * rho_b[d];
    bin_factor /= m * m;
    return segment_factor * bin_factor;
  }
};

/// Of `segments` segments of which `overlapping_pairs` pairs overlap by `hop` (one piece of
/// record: segments - 1; independent pieces share none across).
PointVariance point_variance(const std::vector<double>& window, double window_power, std::size_t hop,
                             std::size_t segments, std::size_t overlapping_pairs) {
  const std::size_t length = window.size();
  const auto overlap = [&](std::size_t shift) {
    double sum = 0;
    for (std::size_t j = 0; j + shift < length; ++j) sum += window[j] * window[j + shift];
    return sum * sum / (window_power * window_power);
  };
  const double rho_s = overlap(hop);
  const double segment_factor = (1 + 2 * rho_s * double(overlapping_pairs) / double(segments)) / double(segments);
  std::vector<double> rho_b(4, 0.0);
  for (std::size_t d = 0; d < rho_b.size(); ++d) {
    // The phase advanced by multiplication: no sine or cosine per sample.
    const std::complex<double> step = std::polar(1.0, -2 * std::numbers::pi * double(d) / double(length));
    std::complex<double> sum = 0, phase = 1;
    for (std::size_t j = 0; j < length; ++j, phase *= step) sum += window[j] * window[j] * phase;
    rho_b[d] = std::norm(sum) / (window_power * window_power);
  }
  return {segment_factor, rho_b};
}

/// Power the window cannot see (trends inside a segment) leaks with the side lobes' own
/// omega^-6 and hides from each point's leakage sum; it shows as a difference spectrum as steep
/// as that. Flags such points and an octave above them.
void flag_steep(std::vector<WelchPoint>& points, const std::vector<double>& point_differences) {
  std::vector<bool> steep(points.size(), false);
  for (std::size_t k = 0; k < points.size(); ++k) {
    std::size_t low = k, high = k;
    while (low > 0 && points[low].omega > points[k].omega / 2) --low;
    while (high + 1 < points.size() && points[high].omega < 2 * points[k].omega) ++high;
    if (high == low || !(point_differences[low] > 0 && point_differences[high] > 0)) continue;
    const double slope =
        std::log(point_differences[high] / point_differences[low]) / std::log(points[high].omega / points[low].omega);
    steep[k] = slope < kSteepestDifferenceSlope;
  }
  // The leaked power reaches past the steep part: an octave above a steep point is suspect too.
  for (std::size_t k = 0; k < points.size(); ++k)
    for (std::size_t j = k + 1; j-- > 0 && points[j].omega >= points[k].omega / 2;)
      points[k].leaky = points[k].leaky || steep[j];
}

}  // namespace

WelchSpectrum welch_spectrum(const std::vector<double>& x, double dt, const WelchRequest& request) {
  if (!(dt > 0)) throw InputError("welch: the sampling interval must be > 0");
  constexpr std::size_t kFewestSamples = 64;
  if (x.size() < kFewestSamples)
    throw InputError("the record (" + std::to_string(x.size()) +
                     " samples) is too short for a spectrum: need at least " + std::to_string(kFewestSamples));
  WelchRequest fixed = request;
  fixed.segment_samples =
      request.segment_samples > 0 ? request.segment_samples : welch_segment_samples(x.size(), dt, request.omega_min);
  return welch_spectrum(std::vector<std::vector<double>>{x}, dt, fixed);
}

namespace {

/// Where each segment of `length` samples (and the sample after it, for the difference)
/// starts: within a piece segments overlap by half (`hop`), pieces are independent of one
/// another. `overlapping_pairs` counts the pairs of neighbouring segments that overlap.
std::vector<const double*> segment_starts(const std::vector<std::vector<double>>& pieces, std::size_t length,
                                          std::size_t hop, std::size_t& overlapping_pairs) {
  std::vector<const double*> starts;
  for (const auto& piece : pieces) {
    const std::size_t in_piece = (piece.size() - 1 - length) / hop + 1;
    for (std::size_t s = 0; s < in_piece; ++s) starts.push_back(piece.data() + s * hop);
    overlapping_pairs += in_piece - 1;
  }
  return starts;
}

}  // namespace

WelchSpectrum welch_spectrum(const std::vector<std::vector<double>>& pieces, double dt, const WelchRequest& request) {
  if (!(dt > 0)) throw InputError("welch: the sampling interval must be > 0");
  if (pieces.empty()) throw InputError("welch: no piece of record to estimate a spectrum of");
  std::size_t shortest = pieces.front().size();
  for (const auto& piece : pieces) shortest = std::min(shortest, piece.size());
  WelchSpectrum out;
  out.dt = dt;
  std::size_t length = request.segment_samples;
  // By default one segment of the shortest piece: the longest fast length that fits its differences.
  if (length == 0) length = shortest < 10 ? 0 : fft_friendly(shortest - 1);
  if (length < 8 || length + 1 > shortest)
    throw InputError("welch: segment of " + std::to_string(length) + " samples in a piece of " +
                     std::to_string(shortest));
  const std::size_t hop = length / 2;
  std::size_t overlapping_pairs = 0;
  const std::vector<const double*> starts = segment_starts(pieces, length, hop, overlapping_pairs);
  const std::size_t segments = starts.size();
  out.segment_samples = length;
  out.segments = segments;
  const std::size_t bins = length / 2 + 1;

  double window_power = 0;
  const std::vector<double> window = hann_window(length, window_power);
  std::vector<double> periodogram = difference_periodogram(starts, dt, window, window_power, request.stop);

  const PointVariance variance = point_variance(window, window_power, hop, segments, overlapping_pairs);
  std::vector<double> point_differences;  // each point's mean difference spectrum
  std::vector<double> kernel(bins);
  for (std::size_t d = 0; d < bins; ++d) kernel[d] = hann_bin_kernel(d);

  const double bin_spacing = 2 * std::numbers::pi / (double(length) * dt);
  const double nyquist = std::numbers::pi / dt;
  if (request.omega_max > nyquist * (1 + 1e-12))
    throw InputError("{omega_max} " + util::format_number(request.omega_max) + ": above the Nyquist frequency " +
                     util::format_number(nyquist) + " rad/s of the sampling");
  const double ratio = std::pow(10.0, 1.0 / request.points_per_decade);
  std::size_t first = kLowestBin;
  // The lowest point: the bin at or just below omega_min.
  if (request.omega_min > 0)
    first = std::max(first, std::size_t(std::floor(request.omega_min / bin_spacing * (1 + 1e-12))));
  const std::size_t top = bins - 2;  // the Nyquist bin is real: one degree of freedom, left out
  for (std::size_t k = first; k <= top;) {
    std::size_t end = std::max(k + 1, std::size_t(std::ceil(double(k) * ratio)));
    end = std::min(end, top + 1);
    if (top + 1 - end < (end - k) / 2) end = top + 1;  // a short remainder joins the last point
    WelchPoint p;
    p.first_bin = k;
    p.bins = end - k;
    double sum_omega = 0, sum_d = 0, sum_c = 0;
    for (std::size_t j = k; j < end; ++j) {
      const double omega = double(j) * bin_spacing;
      const double transfer = 4 * std::pow(std::sin(omega * dt / 2), 2);
      sum_omega += omega;
      sum_d += periodogram[j];
      sum_c += periodogram[j] / transfer;
    }
    const double m = double(p.bins);
    p.omega = sum_omega / m;
    if (request.omega_max > 0 && p.omega > request.omega_max) break;
    p.C = sum_c / m;
    const double relative_variance = variance.relative(p.bins);
    p.dof = 2 / relative_variance;
    p.standard_error = p.C * std::sqrt(relative_variance);
    p.lower = p.C * p.dof / chi_square_quantile(p.dof, kBarSigmas);
    p.upper = p.C * p.dof / chi_square_quantile(p.dof, -kBarSigmas);
    // What the far side lobes carry into the point's centre bin from the rest of the
    // (difference) spectrum, relative to that bin's own level.
    const std::size_t centre = k + p.bins / 2;
    const double leaked = side_lobe_sum(periodogram, kernel, centre);
    p.leakage = periodogram[centre] > 0 ? leaked / periodogram[centre] : 0;
    p.leaky = p.leakage > kLeakageShareOfError * std::sqrt(relative_variance);
    point_differences.push_back(sum_d / m);
    out.points.push_back(p);
    k = end;
  }
  flag_steep(out.points, point_differences);
  out.bin_spacing = bin_spacing;
  return out;
}

std::vector<double> welch_expected(const WelchSpectrum& spectrum, const std::function<double(double)>& true_spectrum) {
  std::vector<double> values;
  for (const WelchPoint& p : spectrum.points) {
    double sum = 0;
    for (std::size_t j = p.first_bin; j < p.first_bin + p.bins; ++j)
      sum += true_spectrum(double(j) * spectrum.bin_spacing);
    values.push_back(sum / double(p.bins));
  }
  return values;
}

}  // namespace slidespec
