#include "estimator/design.hpp"

#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "slidespec/parameters.hpp"
#include "util/numbers.hpp"

namespace slidespec::estimator_detail {

namespace {

constexpr double kPi = std::numbers::pi;

double bessel_i0(double x) { return std::cyl_bessel_i(0.0, x); }

double four_sin_squared(double theta) {
  const double s = std::sin(0.5 * theta);
  return 4.0 * s * s;
}

// Correlation between the bin-averaged periodograms of two segments `shift` samples
// apart, for a locally white process: sum over bin pairs of |A_shift(m)|^2 relative to
// the same sum for shift 0, with A_D(m) = sum_n w_n w_{n+D} exp(-2 pi i m n / L).
double overlap_correlation(const std::vector<double>& w, int shift, int bins) {
  const int L = static_cast<int>(w.size());
  // exp(-2 pi i m n / L) depends on m n mod L only: L cosines and sines, not bins L^2.
  std::vector<double> cosines(L), sines(L);
  for (int k = 0; k < L; ++k) {
    cosines[k] = std::cos(-2.0 * kPi * k / L);
    sines[k] = std::sin(-2.0 * kPi * k / L);
  }
  auto paired_power = [&](int D) {
    double total = 0;
    for (int m = 0; m < bins; ++m) {  // |A(-m)| = |A(m)| for a real window
      double re = 0, im = 0;
      for (int n = 0; n + D < L; ++n) {
        const int phase = static_cast<int>((static_cast<long>(m) * n) % L);
        const double p = w[n] * w[n + D];
        re += p * cosines[phase];
        im += p * sines[phase];
      }
      total += (m == 0 ? 1 : 2) * (bins - m) * (re * re + im * im);
    }
    return total;
  };
  return paired_power(shift) / paired_power(0);
}

// The correlations at every lag for points of `bins` FFT bins. They depend only on the
// fixed window and the bin count, and cost ~10^5 sines each; a run makes one layout per
// batch of realizations, so they are computed once per process (at most L/2 entries).
std::array<double, kOverlapLags> overlap_correlations(const std::vector<double>& w, int bins) {
  static std::mutex guard;
  static std::map<int, std::array<double, kOverlapLags>> by_bins;
  std::lock_guard<std::mutex> lock(guard);
  auto found = by_bins.find(bins);
  if (found == by_bins.end()) {
    std::array<double, kOverlapLags> rho{};
    for (int lag = 1; lag <= kOverlapLags; ++lag) rho[lag - 1] = overlap_correlation(w, lag * kSegmentHop, bins);
    found = by_bins.emplace(bins, rho).first;
  }
  return found->second;
}

}  // namespace

std::vector<double> kaiser_window(int length, double beta) {
  // DFT-even (periodic) form: the segment's FFT sees one period of a smooth taper.
  std::vector<double> w(length);
  const double norm = bessel_i0(beta);
  for (int n = 0; n < length; ++n) {
    const double t = 2.0 * n / length - 1.0;
    w[n] = bessel_i0(beta * std::sqrt(std::max(0.0, 1.0 - t * t))) / norm;
  }
  return w;
}

std::vector<double> half_band_taps() {
  const int K = kHalfBandReach;
  std::vector<double> h(2 * K + 1, 0.0);
  const double norm = bessel_i0(kHalfBandBeta);
  double sum = 0;
  for (int n = -K; n <= K; ++n) {
    const double ideal = n == 0 ? 0.5 : (n % 2 == 0 ? 0.0 : std::sin(0.5 * kPi * n) / (kPi * n));
    const double t = static_cast<double>(n) / (K + 1);
    h[n + K] = ideal * bessel_i0(kHalfBandBeta * std::sqrt(1.0 - t * t)) / norm;
    sum += h[n + K];
  }
  for (double& tap : h) tap /= sum;  // unit gain at DC
  return h;
}

double half_band_power(const std::vector<double>& taps, double theta) {
  // sum over odd n of 2 h_n cos(n theta) by Clenshaw's recurrence on cos((2j+1) theta),
  // which steps by 2 cos(2 theta): one cosine per call instead of one per tap.
  const int K = (static_cast<int>(taps.size()) - 1) / 2;
  const double cosine = std::cos(theta);
  const double twice_cos_2theta = 2.0 * (2.0 * cosine * cosine - 1.0);
  double next = 0, after_next = 0;  // b_{j+1}, b_{j+2}
  for (int n = K - (K % 2 == 0 ? 1 : 0); n >= 1; n -= 2) {
    const double b = 2.0 * taps[K + n] + twice_cos_2theta * next - after_next;
    after_next = next;
    next = b;
  }
  const double amplitude = taps[K] + cosine * (next - after_next);
  return amplitude * amplitude;
}

bool same_config(const EstimatorConfig& a, const EstimatorConfig& b) {
  return a.dt == b.dt && a.omega_min == b.omega_min && a.omega_max == b.omega_max &&
         a.points_per_decade == b.points_per_decade && a.input == b.input;
}

double Layout::bin_omega(int band, int bin) const { return 2.0 * kPi * bin / (kSegmentLength * bands[band].interval); }

int Layout::band_for(double omega) const {
  int band = 0;
  while (band + 1 < kMaximumBands && omega < full_rate_band_floor(config.dt) / std::ldexp(1.0, band)) ++band;
  return band;
}

double Layout::transfer(int band, double omega) const {
  double t = four_sin_squared(omega * config.dt);  // x -> increments
  for (int s = 0; s < band; ++s) t *= half_band_power(taps, omega * std::ldexp(config.dt, s));
  const double difference = four_sin_squared(omega * bands[band].interval);
  for (int k = 0; k < kBandDifferences; ++k) t *= difference;
  return t;
}

namespace {

std::shared_ptr<const Layout> build_layout(const EstimatorConfig& requested) {
  EstimatorConfig c = requested;
  if (!(c.dt > 0) || !std::isfinite(c.dt))
    throw InputError("estimator: dt must be a positive finite number of seconds");
  const double nyquist = kPi / c.dt;
  if (c.omega_max == 0) c.omega_max = 0.5 * nyquist;
  if (!(c.omega_max > 0) || !(c.omega_max <= 0.8 * nyquist))
    throw InputError("{omega_max} " + util::format_number(c.omega_max) + " must lie in (0, 0.8 pi/dt] = (0, " +
                     util::format_number(0.8 * nyquist) + "] rad/s");
  if (c.omega_min == 0) c.omega_min = c.omega_max / 100;
  if (!(c.omega_min > 0) || !(c.omega_min <= c.omega_max))
    throw InputError("{omega_min} " + util::format_number(c.omega_min) + " must lie in (0, {omega_max}]");
  if (c.points_per_decade < 1 || c.points_per_decade > 1000)
    throw InputError("estimator: points per decade must be between 1 and 1000");

  auto layout = std::make_shared<Layout>();
  layout->config = c;
  layout->window = kaiser_window(kSegmentLength, kWindowBeta);
  layout->taps = half_band_taps();
  const auto& w = layout->window;
  double window_sum = 0, step_power = 0;
  for (int n = 0; n < kSegmentLength; ++n) {
    window_sum += w[n];
    layout->window_power += w[n] * w[n];
    const double previous = n == 0 ? 0.0 : w[n - 1];
    step_power += (w[n] - previous) * (w[n] - previous);
  }
  step_power += w.back() * w.back();
  // Second moment of |W(theta)|^2 in theta^2, via sum |w_n - w_{n-1}|^2 (Parseval).
  const double kernel_variance = step_power / layout->window_power;

  const int ppd = c.points_per_decade;
  const long steps = std::lround(std::floor(std::log10(c.omega_max / c.omega_min) * ppd + 1e-9));
  const double half_bin = std::pow(10.0, 0.5 / ppd);
  const int lowest_bin = (kSegmentLength + 9) / 10;
  for (long k = 0; k <= steps; ++k) {
    const double omega = c.omega_min * std::pow(10.0, static_cast<double>(k) / ppd);
    int band = 0;
    while (omega < nyquist / std::ldexp(4.0, band)) {
      if (++band >= kMaximumBands) throw InputError("estimator: omega-min is more than 60 octaves below pi/dt");
    }
    const double resolution = 2.0 * kPi / (kSegmentLength * std::ldexp(c.dt, band));
    int first = static_cast<int>(std::ceil(omega / half_bin / resolution));
    int last = static_cast<int>(std::ceil(omega * half_bin / resolution)) - 1;
    first = std::max(first, lowest_bin);
    last = std::min(last, band == 0 ? kSegmentLength / 2 - 1 : 3 * kSegmentLength / 10);
    if (last < first) continue;  // log bin narrower than one FFT bin here
    OutputPoint point{omega, band, first, last - first + 1, {}};
    point.overlap_correlation = overlap_correlations(w, point.bin_count);
    layout->points.push_back(point);
    layout->band_count = std::max(layout->band_count, band + 1);
  }
  if (layout->points.empty()) throw InputError("estimator: no output point between omega-min and omega-max");

  layout->bands.resize(layout->band_count);
  for (int b = 0; b < layout->band_count; ++b) {
    BandLayout& band = layout->bands[b];
    band.interval = std::ldexp(c.dt, b);
    band.enbw = 2.0 * kPi * layout->window_power / (window_sum * window_sum * band.interval);
    band.kernel_width = std::sqrt(kernel_variance) / band.interval;
    const int half = kSegmentLength / 2 + 1;
    band.bin_factor.assign(half, 0.0);
    band.transfer_center.assign(half, 0.0);
    band.transfer_below.assign(half, 0.0);
    band.transfer_above.assign(half, 0.0);
  }
  for (int k = 0; k < static_cast<int>(layout->points.size()); ++k) {
    const OutputPoint& point = layout->points[k];
    BandLayout& band = layout->bands[point.band];
    band.points.push_back(k);
    for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j) {
      const double omega = layout->bin_omega(point.band, j);
      const double t = layout->transfer(point.band, omega);
      band.transfer_center[j] = t;
      band.transfer_below[j] = layout->transfer(point.band, omega - band.kernel_width);
      band.transfer_above[j] = layout->transfer(point.band, omega + band.kernel_width);
      // docs/model.md §3: C = interval/(2 pi) |sum w z e^{-i omega t}|^2 / sum w^2.
      band.bin_factor[j] = band.interval / (2.0 * kPi * layout->window_power) / t;
    }
  }
  return layout;
}
}  // namespace

std::shared_ptr<const Layout> Layout::make(const EstimatorConfig& requested) {
  // A run makes one estimator per batch of 8 realizations, with a handful of
  // configurations: each layout (transfer functions at every bin, ~10^4 cosines) is built
  // once and shared, as it is immutable. A few recent ones are kept, so memory stays bounded.
  constexpr std::size_t kRecentLayouts = 16;
  static std::mutex guard;
  static std::vector<std::pair<EstimatorConfig, std::shared_ptr<const Layout>>> recent;
  {
    std::lock_guard<std::mutex> lock(guard);
    for (const auto& [config, layout] : recent)
      if (same_config(config, requested)) return layout;
  }
  std::shared_ptr<const Layout> layout = build_layout(requested);
  std::lock_guard<std::mutex> lock(guard);
  if (recent.size() >= kRecentLayouts) recent.erase(recent.begin());
  recent.emplace_back(requested, layout);
  return layout;
}

}  // namespace slidespec::estimator_detail
