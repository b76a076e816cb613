// Streaming Welch estimator on a multi-rate cascade (docs/estimator.md): increments of x
// go through a chain of half-band decimators; each band differences its own stream
// kBandDifferences times, windows, transforms, and divides by the exact transfer.
#include "slidespec/estimator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "estimator/design.hpp"
#include "estimator/real_fft.hpp"
#include "io/binary.hpp"
#include "slidespec/parameters.hpp"

namespace slidespec {

namespace detail = estimator_detail;

// ---------------------------------------------------------------------------------------
// Accumulator: per output point the sums of a segment's bin-averaged C and of its square;
// per band the number of segments and of same-stream segment pairs 1..kOverlapLags hops
// apart (what the overlap correction of the error bar needs). All of it adds on merge.

struct SpectrumAccumulator::Impl {
  std::shared_ptr<const detail::Layout> layout;
  std::vector<double> sum_q, sum_q2;
  std::vector<std::uint64_t> segments;
  std::vector<std::uint64_t> pairs;  // [band * kOverlapLags + lag - 1]

  explicit Impl(std::shared_ptr<const detail::Layout> shape)
      : layout(std::move(shape)),
        sum_q(layout->points.size(), 0.0),
        sum_q2(layout->points.size(), 0.0),
        segments(layout->band_count, 0),
        pairs(static_cast<std::size_t>(layout->band_count) * detail::kOverlapLags, 0) {}
};

SpectrumAccumulator::SpectrumAccumulator() = default;
SpectrumAccumulator::~SpectrumAccumulator() = default;
SpectrumAccumulator::SpectrumAccumulator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SpectrumAccumulator::SpectrumAccumulator(const SpectrumAccumulator& other)
    : impl_(other.impl_ ? std::make_unique<Impl>(*other.impl_) : nullptr) {}
SpectrumAccumulator& SpectrumAccumulator::operator=(const SpectrumAccumulator& other) {
  if (this != &other) impl_ = other.impl_ ? std::make_unique<Impl>(*other.impl_) : nullptr;
  return *this;
}
SpectrumAccumulator::SpectrumAccumulator(SpectrumAccumulator&&) noexcept = default;
SpectrumAccumulator& SpectrumAccumulator::operator=(SpectrumAccumulator&&) noexcept = default;

namespace {

std::string describe(const EstimatorConfig& c) {
  char text[200];
  std::snprintf(text, sizeof text, "dt=%.17g omega=[%.17g, %.17g] points/decade=%d input=%s",
                c.dt, c.omega_min, c.omega_max, c.points_per_decade,
                c.input == SampleKind::value ? "value" : "increment");
  return text;
}

// E[s] = c4 sigma for n Gaussian units: undoes the low bias of the square root.
double c4(double n) {
  return std::sqrt(2.0 / (n - 1)) * std::exp(std::lgamma(0.5 * n) - std::lgamma(0.5 * (n - 1)));
}

// Slope and curvature of ln C against ln omega at point i, from the quadratic through
// it and its two nearest neighbours. Bounded: at a line or a resonance narrower than a
// log bin there is no smooth local shape to correct for.
std::pair<double, double> local_shape(const std::vector<SpectrumPoint>& points,
                                      const std::vector<double>& C, std::size_t i) {
  constexpr double kSlopeBound = 16, kCurvatureBound = 8;
  const std::size_t n = points.size();
  if (n < 2) return {0.0, 0.0};
  std::size_t first = i == 0 ? 0 : i - 1;
  if (n >= 3) first = std::min(first, n - 3);
  const std::size_t used = std::min<std::size_t>(3, n);
  double u[3] = {}, l[3] = {};
  for (std::size_t k = 0; k < used; ++k) {
    if (!(C[first + k] > 0)) return {0.0, 0.0};
    u[k] = std::log(points[first + k].omega / points[i].omega);
    l[k] = std::log(C[first + k]);
  }
  const double f01 = (l[1] - l[0]) / (u[1] - u[0]);
  if (used == 2) return {std::clamp(f01, -kSlopeBound, kSlopeBound), 0.0};
  const double f12 = (l[2] - l[1]) / (u[2] - u[1]);
  const double f012 = (f12 - f01) / (u[2] - u[0]);
  const double slope = f01 - f012 * (u[0] + u[1]);
  return {std::clamp(slope, -kSlopeBound, kSlopeBound),
          std::clamp(2 * f012, -kCurvatureBound, kCurvatureBound)};
}

}  // namespace

void SpectrumAccumulator::merge(const SpectrumAccumulator& other) {
  if (!other.impl_) return;
  if (!impl_) {
    impl_ = std::make_unique<Impl>(*other.impl_);
    return;
  }
  if (!detail::same_config(impl_->layout->config, other.impl_->layout->config))
    throw InputError("spectrum accumulator: cannot merge " + describe(other.impl_->layout->config) +
                     " into " + describe(impl_->layout->config));
  for (std::size_t k = 0; k < impl_->sum_q.size(); ++k) {
    impl_->sum_q[k] += other.impl_->sum_q[k];
    impl_->sum_q2[k] += other.impl_->sum_q2[k];
  }
  for (std::size_t b = 0; b < impl_->segments.size(); ++b) impl_->segments[b] += other.impl_->segments[b];
  for (std::size_t i = 0; i < impl_->pairs.size(); ++i) impl_->pairs[i] += other.impl_->pairs[i];
}

namespace {

// A point averages C over its log bin, and the window smooths C over ~1 bin (on the
// whitened band stream, so only slightly): replaces each point's raw mean (its C) by the
// corrected value, scaling its error bar alike. Shared by spectrum() and expected().
void correct_for_smoothing(const detail::Layout& layout, const std::vector<int>& index, PointValue value,
                           std::vector<SpectrumPoint>& out) {
  if (value == PointValue::window_smoothed) return;
  // For a steep C the bin average differs from C(omega) (17% for omega^-8 at 8 points per
  // decade). Both corrections use the local shape
  // ln C = ln C_k + s u + c u^2/2 (u = ln omega/omega_k) fitted through the point and its
  // neighbours, iterating so that the neighbours are corrected too.
  const std::size_t count = out.size();
  std::vector<double> mean(count), centre(count), average(count), model_error(count, 0.0);
  for (std::size_t i = 0; i < count; ++i) mean[i] = centre[i] = average[i] = out[i].C;
  for (int iteration = 0; iteration < 4 && count >= 2; ++iteration) {
    std::vector<double> next(count);
    for (std::size_t i = 0; i < count; ++i) {
      const auto [slope, curvature] = local_shape(out, centre, i);
      const detail::OutputPoint& point = layout.points[index[i]];
      const detail::BandLayout& band = layout.bands[point.band];
      auto shape = [&](double omega) {
        const double u = std::log(omega / point.omega);
        return std::exp(u * (slope + 0.5 * curvature * u));
      };
      auto straight = [&](double omega) { return std::pow(omega / point.omega, slope); };
      double smoothed = 0, relative_smoothing = 0, smoothed_straight = 0;
      for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j) {
        const double omega = layout.bin_omega(point.band, j);
        const double h = band.kernel_width;
        // E[periodogram]/C(omega_k) at bin j: the window averages T*C over +-h.
        const double e = 0.5 * (shape(omega + h) * band.transfer_above[j] +
                                shape(omega - h) * band.transfer_below[j]) / band.transfer_center[j];
        smoothed += e;
        relative_smoothing += e / shape(omega);
        smoothed_straight += 0.5 * (straight(omega + h) * band.transfer_above[j] +
                                    straight(omega - h) * band.transfer_below[j]) / band.transfer_center[j];
      }
      next[i] = mean[i] * point.bin_count / smoothed;
      // The curvature part is the least certain (a quadratic through noisy neighbours,
      // extrapolated at the ends): half of it counts as the correction's model error.
      model_error[i] = 0.5 * std::abs(next[i] - mean[i] * point.bin_count / smoothed_straight);
      average[i] = mean[i] * point.bin_count / relative_smoothing;
    }
    centre = next;
  }
  const std::vector<double>& chosen = value == PointValue::centre ? centre : average;
  for (std::size_t i = 0; i < count; ++i) {
    if (mean[i] > 0) out[i].standard_error *= chosen[i] / mean[i];
    if (value == PointValue::centre) out[i].standard_error = std::hypot(out[i].standard_error, model_error[i]);
    out[i].C = chosen[i];
  }
}

}  // namespace

std::vector<SpectrumPoint> SpectrumAccumulator::spectrum(PointValue value) const {
  if (!impl_) return {};
  const detail::Layout& layout = *impl_->layout;
  std::vector<SpectrumPoint> out;
  std::vector<int> index;
  for (int k = 0; k < static_cast<int>(layout.points.size()); ++k) {
    const detail::OutputPoint& point = layout.points[k];
    const std::uint64_t segments = impl_->segments[point.band];
    if (segments < detail::kMinimumSegments) continue;
    const double n = static_cast<double>(segments);
    const double mean = impl_->sum_q[k] / n;
    const double scatter = std::max(0.0, impl_->sum_q2[k] - n * mean * mean);
    // Overlapping segments of one stream are correlated (rho, exact for the window):
    // it inflates the variance of the mean and deflates the sample variance.
    double overlap = 0;
    for (int lag = 1; lag <= detail::kOverlapLags; ++lag)
      overlap += point.overlap_correlation[lag - 1] *
                 static_cast<double>(impl_->pairs[point.band * detail::kOverlapLags + lag - 1]);
    overlap *= 2.0 / n;
    const double unit_variance = scatter / ((n - 1) - overlap);
    const double standard_error = std::sqrt(unit_variance / n * (1 + overlap)) / c4(n);
    const detail::BandLayout& band = layout.bands[point.band];
    const double resolution = layout.bin_omega(point.band, 1);
    out.push_back({point.omega, mean, standard_error, n * point.bin_count, band.enbw,
                   (point.first_bin - 0.5) * resolution,
                   (point.first_bin + point.bin_count - 0.5) * resolution, resolution, point.bin_count});
    index.push_back(k);
  }

  correct_for_smoothing(layout, index, value, out);
  return out;
}

namespace {

// The window's spectral kernel, sampled kSub times per FFT bin out to kReach bins and
// normalised to unit area: E[periodogram at bin j] = int C T kernel / T(omega_j).
constexpr int kSub = 16, kReach = 24;

// The window is fixed by the design, so its kernel (4e5 complex exponentials) is
// computed once per process rather than at every call.
const std::vector<double>& window_kernel(const std::vector<double>& window) {
  static const std::vector<double> kernel = [&] {
    const int L = detail::kSegmentLength;
    std::vector<double> k(2 * kSub * kReach + 1);
    double area = 0;
    for (std::size_t m = 0; m < k.size(); ++m) {
      const double delta = (static_cast<double>(m) - kSub * kReach) / kSub;  // in bins
      std::complex<double> sum = 0;
      for (int n = 0; n < L; ++n) sum += window[n] * std::polar(1.0, -2 * M_PI * delta * n / L);
      k[m] = std::norm(sum);
      area += k[m] / kSub;
    }
    for (double& value : k) value /= area;
    return k;
  }();
  return kernel;
}

}  // namespace

std::vector<SpectrumPoint> SpectrumAccumulator::expected(const std::function<double(double)>& true_spectrum,
                                                         PointValue value) const {
  const std::vector<SpectrumPoint> measured = spectrum(value);
  if (measured.empty()) return {};
  const detail::Layout& layout = *impl_->layout;
  const std::vector<double>& kernel = window_kernel(layout.window);

  std::vector<SpectrumPoint> out;
  std::vector<int> index;
  for (const SpectrumPoint& m : measured) {
    int k = 0;
    while (layout.points[k].omega != m.omega) ++k;
    const detail::OutputPoint& point = layout.points[k];
    const double spacing = layout.bin_omega(point.band, 1);
    // C T on the fine grid once, shared by every bin of the point.
    const int first = (point.first_bin - kReach) * kSub;
    const int last = (point.first_bin + point.bin_count - 1 + kReach) * kSub;
    std::vector<double> weighted(static_cast<std::size_t>(last - first + 1), 0.0);
    for (int g = first; g <= last; ++g) {
      const double omega = g * spacing / kSub;
      if (omega > 0) weighted[g - first] = true_spectrum(omega) * layout.transfer(point.band, omega);
    }
    double mean = 0;
    for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j) {
      double integral = 0;
      for (std::size_t mm = 0; mm < kernel.size(); ++mm)
        integral += weighted[(j - kReach) * kSub + mm - first] * kernel[mm] / kSub;
      mean += integral / layout.transfer(point.band, layout.bin_omega(point.band, j)) / point.bin_count;
    }
    SpectrumPoint e = m;
    e.C = mean;
    e.standard_error = 0;
    out.push_back(e);
    index.push_back(k);
  }
  correct_for_smoothing(layout, index, value, out);
  return out;
}

std::vector<SpectrumAccumulator::PointSum> SpectrumAccumulator::point_sums() const {
  std::vector<PointSum> out;
  if (!impl_) return out;
  const detail::Layout& layout = *impl_->layout;
  for (std::size_t k = 0; k < layout.points.size(); ++k)
    out.push_back({layout.points[k].omega, impl_->sum_q[k], impl_->segments[layout.points[k].band]});
  return out;
}

// ---------------------------------------------------------------------------------------
// File format (docs/estimator.md): host byte order (little-endian on every supported
// platform), fixed-width fields, no padding.

namespace {

constexpr char kMagic[8] = {'S', 'L', 'S', 'P', 'E', 'C', 'A', 'C'};
constexpr std::uint32_t kFormatVersion = 1;

using io::put;

}  // namespace

std::string SpectrumAccumulator::save() const {
  if (!impl_) throw std::logic_error("spectrum accumulator: nothing to save (never configured)");
  const detail::Layout& layout = *impl_->layout;
  std::string bytes(kMagic, sizeof kMagic);
  put<std::uint32_t>(bytes, kFormatVersion);
  put<double>(bytes, layout.config.dt);
  put<double>(bytes, layout.config.omega_min);
  put<double>(bytes, layout.config.omega_max);
  put<std::int32_t>(bytes, layout.config.points_per_decade);
  put<std::int32_t>(bytes, layout.config.input == SampleKind::value ? 0 : 1);
  put<std::int32_t>(bytes, detail::kSegmentLength);
  put<std::int32_t>(bytes, detail::kSegmentHop);
  put<std::int32_t>(bytes, detail::kBandDifferences);
  put<std::int32_t>(bytes, detail::kHalfBandReach);
  put<double>(bytes, detail::kWindowBeta);
  put<double>(bytes, detail::kHalfBandBeta);
  put<std::uint32_t>(bytes, static_cast<std::uint32_t>(impl_->segments.size()));
  put<std::uint32_t>(bytes, static_cast<std::uint32_t>(impl_->sum_q.size()));
  for (std::uint64_t s : impl_->segments) put<std::uint64_t>(bytes, s);
  for (std::uint64_t p : impl_->pairs) put<std::uint64_t>(bytes, p);
  for (double s : impl_->sum_q) put<double>(bytes, s);
  for (double s : impl_->sum_q2) put<double>(bytes, s);
  return bytes;
}

SpectrumAccumulator SpectrumAccumulator::load(const std::string& bytes) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw InputError("spectrum accumulator file: not a slidespec spectrum accumulator");
  io::Reader in(bytes, "spectrum accumulator file");
  for (std::size_t i = 0; i < sizeof kMagic; ++i) in.get<char>();
  const auto version = in.get<std::uint32_t>();
  if (version != kFormatVersion)
    throw InputError("spectrum accumulator file: format version " + std::to_string(version) +
                     ", this build reads version " + std::to_string(kFormatVersion));
  EstimatorConfig config;
  config.dt = in.get<double>();
  config.omega_min = in.get<double>();
  config.omega_max = in.get<double>();
  config.points_per_decade = in.get<std::int32_t>();
  const auto input = in.get<std::int32_t>();
  if (input != 0 && input != 1) throw InputError("spectrum accumulator file: unknown input kind");
  config.input = input == 0 ? SampleKind::value : SampleKind::increment;
  const bool same_design = in.get<std::int32_t>() == detail::kSegmentLength &&
                           in.get<std::int32_t>() == detail::kSegmentHop &&
                           in.get<std::int32_t>() == detail::kBandDifferences &&
                           in.get<std::int32_t>() == detail::kHalfBandReach &&
                           in.get<double>() == detail::kWindowBeta &&
                           in.get<double>() == detail::kHalfBandBeta;
  if (!same_design)
    throw InputError("spectrum accumulator file: made with another estimator design (segment, window or filter)");
  auto impl = std::make_unique<Impl>(detail::Layout::make(config));
  const auto bands = in.get<std::uint32_t>();
  const auto points = in.get<std::uint32_t>();
  if (bands != impl->segments.size() || points != impl->sum_q.size())
    throw InputError("spectrum accumulator file: band or point count does not match its configuration");
  for (auto& s : impl->segments) s = in.get<std::uint64_t>();
  for (auto& p : impl->pairs) p = in.get<std::uint64_t>();
  for (auto& s : impl->sum_q) s = in.get<double>();
  for (auto& s : impl->sum_q2) s = in.get<double>();
  if (!in.at_end()) throw InputError("spectrum accumulator file: trailing bytes after the data");
  return SpectrumAccumulator(std::move(impl));
}

// ---------------------------------------------------------------------------------------
// Estimator: per lane and band a segment ring buffer, the last 2*reach samples of the
// band's increment stream (decimator and differencing history) and sample counters.

namespace {

constexpr int kHistory = 2 * detail::kHalfBandReach;
constexpr std::size_t kSegmentMask = detail::kSegmentLength - 1;
static_assert((detail::kSegmentLength & (detail::kSegmentLength - 1)) == 0);
static_assert(detail::kSegmentLength % detail::kSegmentHop == 0);
static_assert(detail::kBandDifferences <= kHistory);
// Steps processed per lane at a time: bounds the scratch memory whatever push() gets.
constexpr std::size_t kChunk = 4096;

// The two streaming passes, cloned per instruction set by GCC (target_clones, resolved
// once at load time). Every element's arithmetic is the same at any vector width and no
// clone may contract to FMA (-ffp-contract=off), so all clones give the same bits.
#define SLIDESPEC_ESTIMATOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))

/// target[i] = source[i] - source[i - 1] for i in [from, to).
SLIDESPEC_ESTIMATOR_CLONES void difference(const double* source, double* target, std::ptrdiff_t from,
                                           std::ptrdiff_t to) {
  for (std::ptrdiff_t i = from; i < to; ++i) target[i] = source[i] - source[i - 1];
}

/// The half-band filter on split input: out[j] = h[reach] centre[j] + sum over odd t of
/// h[reach + t] (side[j - (t+1)/2] + side[j + (t-1)/2]), summed in the order of t.
SLIDESPEC_ESTIMATOR_CLONES void half_band(const double* taps, const double* centre, const double* side,
                                          std::ptrdiff_t outputs, double* out) {
  constexpr int reach = detail::kHalfBandReach;
  for (std::ptrdiff_t j = 0; j < outputs; ++j) out[j] = taps[reach] * centre[j];
  for (int t = 1; t <= reach; t += 2) {
    const double tap = taps[reach + t];
    const double* before = side - (t + 1) / 2;  // centre[-t]
    const double* after = side + (t - 1) / 2;   // centre[+t]
    for (std::ptrdiff_t j = 0; j < outputs; ++j) out[j] += tap * (before[j] + after[j]);
  }
}

/// in[n] = window[n] * segment[n] for n < count.
SLIDESPEC_ESTIMATOR_CLONES void window_into(const double* window, const double* segment, double* in,
                                            std::size_t count) {
  for (std::size_t n = 0; n < count; ++n) in[n] = window[n] * segment[n];
}

struct BandStream {
  std::array<double, detail::kSegmentLength> ring{};
  std::array<double, kHistory> history{};
  std::uint64_t received = 0;     // samples of the band's increment stream so far
  std::uint64_t differenced = 0;  // samples of its differenced stream so far
};

struct Lane {
  std::vector<BandStream> bands;
  double last_value = 0;
  bool has_last_value = false;
  SpectrumAccumulator::Impl statistics;
};

}  // namespace

struct SpectrumEstimator::Impl {
  std::shared_ptr<const detail::Layout> layout;
  std::vector<Lane> lanes;
  detail::RealFft fft{detail::kSegmentLength};
  std::vector<std::vector<double>> band_input;  // [band]: samples entering the band
  std::vector<std::vector<double>> extended;    // [band]: history followed by new samples

  // Scratch of one band's call, reused by the next band (kChunk + 2 * kHistory each).
  std::array<std::vector<double>, 2> difference_scratch;
  std::vector<double> decimator_centre, decimator_side;
  std::vector<double> lane_major;  // [lane][kChunk]: one chunk of push()'s data

  void feed(Lane& lane, int band, const double* increments, std::size_t n);
  void difference_into_segments(Lane& lane, int band, const double* y, std::size_t n);
  std::size_t decimate(const BandStream& stream, const double* y, std::size_t n, double* out);
  void close_segment(Lane& lane, int band);
};

void SpectrumEstimator::Impl::close_segment(Lane& lane, int b) {
  BandStream& stream = lane.bands[b];
  double* in = fft.input();
  // The segment is the whole ring, oldest sample at `start`: two contiguous pieces.
  const std::size_t start = stream.differenced & kSegmentMask;
  const std::size_t wrapped = detail::kSegmentLength - start;
  window_into(layout->window.data(), stream.ring.data() + start, in, wrapped);
  window_into(layout->window.data() + wrapped, stream.ring.data(), in + wrapped, start);
  fft.execute();
  const std::complex<double>* X = fft.output();
  const detail::BandLayout& band = layout->bands[b];
  SpectrumAccumulator::Impl& stats = lane.statistics;
  for (int k : band.points) {
    const detail::OutputPoint& point = layout->points[k];
    double sum = 0;
    for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j) {
      const double re = X[j].real(), im = X[j].imag();
      sum += (re * re + im * im) * band.bin_factor[j];
    }
    const double q = sum / point.bin_count;
    stats.sum_q[k] += q;
    stats.sum_q2[k] += q * q;
  }
  const std::uint64_t index = stats.segments[b]++;
  for (int lag = 1; lag <= detail::kOverlapLags; ++lag)
    if (index >= static_cast<std::uint64_t>(lag)) ++stats.pairs[b * detail::kOverlapLags + lag - 1];
}

void SpectrumEstimator::Impl::feed(Lane& lane, int b, const double* increments, std::size_t n) {
  if (n == 0) return;
  BandStream& stream = lane.bands[b];
  double* ext = extended[b].data();
  std::copy(stream.history.begin(), stream.history.end(), ext);
  std::copy(increments, increments + n, ext + kHistory);
  const double* y = ext + kHistory;  // y[-kHistory..-1] is the previous samples
  difference_into_segments(lane, b, y, n);
  const std::size_t produced = b + 1 < layout->band_count ? decimate(stream, y, n, band_input[b + 1].data()) : 0;
  std::copy(ext + n, ext + n + kHistory, stream.history.begin());
  stream.received += n;
  feed(lane, b + 1, band_input[b + 1 < layout->band_count ? b + 1 : b].data(), produced);
}

// Differencing whitens the band before the window sees it; the first samples lack
// history and are dropped rather than differenced against zeros. Each order is one pass
// over the whole call (contiguous, so it vectorizes), forming exactly the same
// differences of differences as sample-by-sample differencing would.
void SpectrumEstimator::Impl::difference_into_segments(Lane& lane, int b, const double* y, std::size_t n) {
  constexpr int D = detail::kBandDifferences;
  BandStream& stream = lane.bands[b];
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double* source = y;
  double* target = difference_scratch[0].data() + D;  // indices -D .. n-1
  for (int order = 1; order <= D; ++order) {
    difference(source, target, order - D, count);
    source = target;
    target = difference_scratch[order % 2].data() + D;
  }
  const double* differenced = source;

  const std::uint64_t received = stream.received;
  std::size_t i = received < static_cast<std::uint64_t>(D) ? std::min<std::size_t>(n, D - received) : 0;
  constexpr std::uint64_t L = detail::kSegmentLength, hop = detail::kSegmentHop;
  while (i < n) {
    // A segment closes whenever the differenced count reaches L, L + hop, L + 2 hop, ...
    const std::uint64_t done = stream.differenced;
    const std::uint64_t next_close = done < L ? L : L + ((done - L) / hop + 1) * hop;
    const std::size_t take = static_cast<std::size_t>(std::min<std::uint64_t>(n - i, next_close - done));
    // At most one wrap of the ring: two contiguous copies.
    const std::size_t at = done & kSegmentMask, before_wrap = std::min(take, detail::kSegmentLength - at);
    std::copy_n(differenced + i, before_wrap, stream.ring.data() + at);
    std::copy_n(differenced + i + before_wrap, take - before_wrap, stream.ring.data());
    stream.differenced += take;
    i += take;
    if (stream.differenced == next_close) close_segment(lane, b);
  }
}

// Half-band decimation by two: an output at every even stream index from kHistory on,
// centred kHalfBandReach samples back. Only the centre tap and odd offsets are nonzero,
// so the input is split into its centre (even) and side (odd) samples and every tap
// becomes one contiguous pass over all outputs; each output's sum keeps the tap order.
std::size_t SpectrumEstimator::Impl::decimate(const BandStream& stream, const double* y, std::size_t n,
                                              double* out) {
  constexpr int reach = detail::kHalfBandReach;
  constexpr int side_before = (reach + 1) / 2;  // side samples before the first centre
  const std::uint64_t received = stream.received;
  std::size_t first = received >= kHistory ? 0 : static_cast<std::size_t>(kHistory - received);
  if (((received + first) & 1) != 0) ++first;
  if (first >= n) return 0;
  const auto outputs = static_cast<std::ptrdiff_t>((n - first + 1) / 2);
  const double* centre_of_first = y + static_cast<std::ptrdiff_t>(first) - reach;
  double* centre = decimator_centre.data();
  double* side = decimator_side.data() + side_before;  // side[k] = centre_of_first[2k + 1]
  for (std::ptrdiff_t j = 0; j < outputs; ++j) centre[j] = centre_of_first[2 * j];
  for (std::ptrdiff_t k = -side_before; k < outputs + (reach - 1) / 2; ++k) side[k] = centre_of_first[2 * k + 1];
  half_band(layout->taps.data(), centre, side, outputs, out);
  return static_cast<std::size_t>(outputs);
}

SpectrumEstimator::SpectrumEstimator(const EstimatorConfig& config, int lanes) {
  if (lanes < 1) throw InputError("estimator: need at least one lane");
  auto layout = detail::Layout::make(config);
  impl_ = std::make_unique<Impl>();
  impl_->layout = layout;
  for (int l = 0; l < lanes; ++l) {
    impl_->lanes.push_back(Lane{std::vector<BandStream>(layout->band_count), 0.0, false,
                                SpectrumAccumulator::Impl(layout)});
  }
  impl_->band_input.resize(layout->band_count);
  impl_->extended.resize(layout->band_count);
  for (int b = 0; b < layout->band_count; ++b) {
    const std::size_t capacity = (kChunk >> std::min(b, 12)) + 2;
    impl_->band_input[b].assign(capacity, 0.0);
    impl_->extended[b].assign(capacity + kHistory, 0.0);
  }
  for (auto& scratch : impl_->difference_scratch) scratch.assign(kChunk + 2 * kHistory, 0.0);
  impl_->decimator_centre.assign(kChunk + 2 * kHistory, 0.0);
  impl_->decimator_side.assign(kChunk + 2 * kHistory, 0.0);
  impl_->lane_major.assign(kChunk * static_cast<std::size_t>(lanes), 0.0);
}

SpectrumEstimator::~SpectrumEstimator() = default;
SpectrumEstimator::SpectrumEstimator(SpectrumEstimator&&) noexcept = default;
SpectrumEstimator& SpectrumEstimator::operator=(SpectrumEstimator&&) noexcept = default;

int SpectrumEstimator::lanes() const { return static_cast<int>(impl_->lanes.size()); }
const EstimatorConfig& SpectrumEstimator::config() const { return impl_->layout->config; }

void SpectrumEstimator::push(const double* data, std::size_t steps) {
  const std::size_t lane_count = impl_->lanes.size();
  for (std::size_t start = 0; start < steps; start += kChunk) {
    const std::size_t n = std::min(kChunk, steps - start);
    // Lane-major once per chunk: one sequential read of the step-major data, where
    // reading each lane's column in place would pull every cache line in once per lane.
    double* lane_major = impl_->lane_major.data();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t l = 0; l < lane_count; ++l) lane_major[l * kChunk + i] = data[(start + i) * lane_count + l];
    for (std::size_t l = 0; l < lane_count; ++l) {
      Lane& lane = impl_->lanes[l];
      const double* column = lane_major + l * kChunk;
      if (impl_->layout->config.input == SampleKind::increment) {
        impl_->feed(lane, 0, column, n);
        continue;
      }
      double* y = impl_->band_input[0].data();
      std::size_t m = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const double value = column[i];
        if (lane.has_last_value) y[m++] = value - lane.last_value;
        lane.last_value = value;
        lane.has_last_value = true;
      }
      impl_->feed(lane, 0, y, m);
    }
  }
}

SpectrumAccumulator SpectrumEstimator::accumulator(int lane) const {
  if (lane < 0 || lane >= lanes()) throw std::out_of_range("estimator: no such lane");
  return SpectrumAccumulator(std::make_unique<SpectrumAccumulator::Impl>(impl_->lanes[lane].statistics));
}

double SpectrumEstimator::segment_duration(double omega) const {
  const detail::Layout& layout = *impl_->layout;
  return detail::kSegmentLength * std::ldexp(layout.config.dt, layout.band_for(omega));
}

SpectrumAccumulator SpectrumEstimator::merged() const {
  SpectrumAccumulator all = accumulator(0);
  for (int l = 1; l < lanes(); ++l) all.merge(accumulator(l));
  return all;
}

}  // namespace slidespec
