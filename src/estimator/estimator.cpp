// Streaming Welch estimator on a multi-rate cascade (docs/estimator.md): increments of x
// go through a chain of half-band decimators; each band differences its own stream
// kBandDifferences times, windows, transforms, and divides by the exact transfer.
#include "slidespec/estimator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstring>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "estimator/design.hpp"
#include "estimator/kernels.hpp"
#include "util/binary.hpp"
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
  std::snprintf(text, sizeof text, "dt=%.17g omega=[%.17g, %.17g] points/decade=%d input=%s", c.dt, c.omega_min,
                c.omega_max, c.points_per_decade, c.input == SampleKind::value ? "value" : "increment");
  return text;
}

// E[s] = c4 sigma for n Gaussian units: undoes the low bias of the square root.
double c4(double n) { return std::sqrt(2.0 / (n - 1)) * std::exp(std::lgamma(0.5 * n) - std::lgamma(0.5 * (n - 1))); }

// Slope and curvature of ln C against ln omega at point i, from the quadratic through
// it and its two nearest neighbours. Bounded: at a line or a resonance narrower than a
// log bin there is no smooth local shape to correct for.
std::pair<double, double> local_shape(const std::vector<SpectrumPoint>& points, const std::vector<double>& C,
                                      std::size_t i) {
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
  return {std::clamp(slope, -kSlopeBound, kSlopeBound), std::clamp(2 * f012, -kCurvatureBound, kCurvatureBound)};
}

}  // namespace

void SpectrumAccumulator::merge(const SpectrumAccumulator& other) {
  if (!other.impl_) return;
  if (!impl_) {
    impl_ = std::make_unique<Impl>(*other.impl_);
    return;
  }
  if (!detail::same_config(impl_->layout->config, other.impl_->layout->config))
    throw InputError("spectrum accumulator: cannot merge " + describe(other.impl_->layout->config) + " into " +
                     describe(impl_->layout->config));
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
        const double e = 0.5 * (shape(omega + h) * band.transfer_above[j] + shape(omega - h) * band.transfer_below[j]) /
                         band.transfer_center[j];
        smoothed += e;
        relative_smoothing += e / shape(omega);
        smoothed_straight +=
            0.5 * (straight(omega + h) * band.transfer_above[j] + straight(omega - h) * band.transfer_below[j]) /
            band.transfer_center[j];
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
                   (point.first_bin - 0.5) * resolution, (point.first_bin + point.bin_count - 0.5) * resolution,
                   resolution, point.bin_count});
    index.push_back(k);
  }

  correct_for_smoothing(layout, index, value, out);
  return out;
}

namespace {

// The window's spectral kernel, sampled kSub times per FFT bin out to kReach bins and
// normalised to unit area: E[periodogram at bin j] = int C T kernel / T(omega_j).
constexpr int kSub = 16, kReach = 24;

// The window is fixed by the design, so its kernel is computed once per process rather
// than at every call.
const std::vector<double>& window_kernel(const std::vector<double>& window) {
  static const std::vector<double> kernel = [&] {
    const int L = detail::kSegmentLength;
    std::vector<double> k(2 * kSub * kReach + 1);
    // The phase -2 pi delta n / L with delta = j / kSub is a multiple of 2 pi / (kSub L):
    // kSub L complex exponentials, not one per (m, n).
    std::vector<std::complex<double>> turns(static_cast<std::size_t>(kSub * L));
    for (std::size_t t = 0; t < turns.size(); ++t)
      turns[t] = std::polar(1.0, -2 * M_PI * static_cast<double>(t) / (kSub * L));
    double area = 0;
    for (std::size_t m = 0; m < k.size(); ++m) {
      const long j = static_cast<long>(m) - kSub * kReach;  // delta = j / kSub bins
      std::complex<double> sum = 0;
      for (int n = 0; n < L; ++n) {
        const long t = (j * n) % (kSub * L);
        sum += window[n] * turns[static_cast<std::size_t>(t < 0 ? t + kSub * L : t)];
      }
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
  // C T on the band's fine grid, shared by every bin of a point and by the next point of
  // the same band, whose grid overlaps this one's by 2 kReach bins (points ascend).
  int grid_band = -1, grid_first = 0;
  std::vector<double> weighted;
  for (const SpectrumPoint& m : measured) {
    int k = 0;
    while (layout.points[k].omega != m.omega) ++k;
    const detail::OutputPoint& point = layout.points[k];
    const double spacing = layout.bin_omega(point.band, 1);
    const int first = (point.first_bin - kReach) * kSub;
    const int last = (point.first_bin + point.bin_count - 1 + kReach) * kSub;
    if (point.band != grid_band || first < grid_first) {
      grid_band = point.band;
      grid_first = first;
      weighted.clear();
    }
    for (int g = grid_first + static_cast<int>(weighted.size()); g <= last; ++g) {
      const double omega = g * spacing / kSub;
      weighted.push_back(omega > 0 ? true_spectrum(omega) * layout.transfer(point.band, omega) : 0.0);
    }
    double mean = 0;
    for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j) {
      double integral = 0;
      for (std::size_t mm = 0; mm < kernel.size(); ++mm)
        integral += weighted[(j - kReach) * kSub + mm - grid_first] * kernel[mm] / kSub;
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

using util::put;

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
  util::Reader in(bytes, "spectrum accumulator file");
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
  const bool same_design =
      in.get<std::int32_t>() == detail::kSegmentLength && in.get<std::int32_t>() == detail::kSegmentHop &&
      in.get<std::int32_t>() == detail::kBandDifferences && in.get<std::int32_t>() == detail::kHalfBandReach &&
      in.get<double>() == detail::kWindowBeta && in.get<double>() == detail::kHalfBandBeta;
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

namespace estimator_detail {

// The transform's twiddles, from long double and exact at the quadrants, so that no
// path and no libm can round them differently.
const FourierTables& fourier_tables() {
  static const FourierTables tables = [] {
    FourierTables t{};
    constexpr int L = kSegmentLength;
    for (int m = 0; m < L; ++m) {
      const long double angle = 2.0L * std::numbers::pi_v<long double> * m / L;
      t.cosine[m] = static_cast<double>(std::cos(angle));
      t.sine[m] = static_cast<double>(std::sin(angle));
      if (m % (L / 4) == 0) {
        const int quadrant = m / (L / 4);
        t.cosine[m] = quadrant == 0 ? 1.0 : quadrant == 2 ? -1.0 : 0.0;
        t.sine[m] = quadrant == 1 ? 1.0 : quadrant == 3 ? -1.0 : 0.0;
      }
    }
    for (int m = 0; m < L / 2; ++m) {
      int reversed = 0;
      for (int bit = 1, rest = m; bit < L / 2; bit <<= 1, rest >>= 1) reversed = (reversed << 1) | (rest & 1);
      t.bit_reverse[m] = static_cast<std::uint16_t>(reversed);
    }
    return t;
  }();
  return tables;
}

}  // namespace estimator_detail

// ---------------------------------------------------------------------------------------
// Estimator: the lanes side by side (a structure of arrays, row n = sample n of every
// lane, `stride` = lanes padded to the path's width), so every streaming pass runs
// across lanes on whole vectors. Per band: the last 2*reach samples of its increment
// stream in front of the new ones, a segment ring, and counters shared by all lanes.

namespace {

constexpr int kHistory = 2 * detail::kHalfBandReach;
constexpr std::size_t kSegmentMask = detail::kSegmentLength - 1;
static_assert((detail::kSegmentLength & (detail::kSegmentLength - 1)) == 0);
static_assert(detail::kSegmentLength % detail::kSegmentHop == 0);
static_assert(detail::kBandDifferences <= kHistory);
// Rows (steps) processed at a time: bounds the scratch memory whatever push() gets.
constexpr std::size_t kChunk = 1024;

struct BandStream {
  // Rows [0, kHistory): the stream's previous samples (zeros before the start); new
  // samples are written after them, and the last kHistory rows moved back afterwards.
  std::vector<double> extended;
  std::vector<double> ring;       // [kSegmentLength][stride], bands that transform only
  std::uint64_t received = 0;     // samples of the band's increment stream so far
  std::uint64_t differenced = 0;  // samples of its differenced stream so far
};

}  // namespace

struct SpectrumEstimator::Impl {
  std::shared_ptr<const detail::Layout> layout;
  detail::StreamKernels kernels;  // of the chosen instruction-set path
  int lane_count = 0;
  std::size_t stride = 0;
  std::vector<BandStream> bands;
  std::vector<SpectrumAccumulator::Impl> statistics;  // [lane]
  std::vector<double> last_value;                     // [stride], SampleKind::value
  bool has_last_value = false;

  // Scratch of one band's call, reused by the next band.
  std::vector<double> transform_work;  // [kSegmentLength][stride]
  std::vector<double> power;           // [kSegmentLength / 2 + 1][stride]
  std::vector<double> point_average;   // [stride]

  double* row(std::vector<double>& rows, std::ptrdiff_t r) {
    return rows.data() + static_cast<std::ptrdiff_t>(stride) * r;
  }
  void feed(int band, std::size_t n);
  void difference_into_segments(int band, std::size_t n);
  std::size_t decimate(int band, std::size_t n);
  void close_segment(int band);
};

namespace {

// A band's segments and same-stream segment pairs are counted whether or not the band
// serves an output point, so the saved statistics never depend on which bands transform.
void count_segment(SpectrumAccumulator::Impl& stats, int b) {
  const std::uint64_t index = stats.segments[b]++;
  for (int lag = 1; lag <= detail::kOverlapLags; ++lag)
    if (index >= static_cast<std::uint64_t>(lag)) ++stats.pairs[b * detail::kOverlapLags + lag - 1];
}

}  // namespace

void SpectrumEstimator::Impl::close_segment(int b) {
  for (SpectrumAccumulator::Impl& stats : statistics) count_segment(stats, b);
  const detail::BandLayout& band = layout->bands[b];
  if (band.points.empty()) return;
  BandStream& stream = bands[b];
  // The ring's oldest row, at `start`, is the segment's first sample.
  const auto lag = static_cast<std::ptrdiff_t>(stride);
  // Only the bins the band's points average (points ascend in omega).
  const detail::OutputPoint& lowest = layout->points[band.points.front()];
  const detail::OutputPoint& highest = layout->points[band.points.back()];
  kernels.segment_power(detail::fourier_tables(), layout->window.data(), stream.ring.data(),
                        stream.differenced & kSegmentMask, lowest.first_bin, highest.first_bin + highest.bin_count - 1,
                        transform_work.data(), power.data(), lag);
  for (int k : band.points) {
    const detail::OutputPoint& point = layout->points[k];
    kernels.bin_average(power.data(), band.bin_factor.data(), point.first_bin, point.bin_count, lag,
                        point_average.data());
    for (int l = 0; l < lane_count; ++l) {
      const double q = point_average[l];
      statistics[l].sum_q[k] += q;
      statistics[l].sum_q2[k] += q * q;
    }
  }
}

// Band b's n new rows are in its extended buffer after its history: difference them into
// the segments, decimate them into band b + 1's buffer, keep the last rows as history,
// and go on with band b + 1.
void SpectrumEstimator::Impl::feed(int b, std::size_t n) {
  for (; b < layout->band_count && n > 0; ++b) {
    BandStream& stream = bands[b];
    difference_into_segments(b, n);
    const std::size_t produced = b + 1 < layout->band_count ? decimate(b, n) : 0;
    std::copy_n(row(stream.extended, static_cast<std::ptrdiff_t>(n)), kHistory * stride, stream.extended.data());
    stream.received += n;
    n = produced;
  }
}

// Differencing whitens the band before the window sees it; the first samples lack
// history and are dropped rather than differenced against zeros. The differences go
// straight into the segment ring, forming exactly the same differences of differences as
// sample-by-sample differencing would.
void SpectrumEstimator::Impl::difference_into_segments(int b, std::size_t n) {
  constexpr int D = detail::kBandDifferences;
  BandStream& stream = bands[b];
  // A band that serves no output point (in a run, the two fastest: they only decimate
  // for the bands below) keeps its segment count but never differences or transforms.
  const bool transformed = !layout->bands[b].points.empty();
  const auto lag = static_cast<std::ptrdiff_t>(stride);
  const double* source = row(stream.extended, kHistory);

  const std::uint64_t received = stream.received;
  std::size_t i = received < static_cast<std::uint64_t>(D) ? std::min<std::size_t>(n, D - received) : 0;
  constexpr std::uint64_t L = detail::kSegmentLength, hop = detail::kSegmentHop;
  while (i < n) {
    // A segment closes whenever the differenced count reaches L, L + hop, L + 2 hop, ...
    const std::uint64_t done = stream.differenced;
    const std::uint64_t next_close = done < L ? L : L + ((done - L) / hop + 1) * hop;
    const std::size_t take = static_cast<std::size_t>(std::min<std::uint64_t>(n - i, next_close - done));
    // At most one wrap of the ring: two contiguous runs of rows.
    const std::size_t at = done & kSegmentMask, before_wrap = std::min(take, detail::kSegmentLength - at);
    if (transformed) {
      const double* from = source + static_cast<std::ptrdiff_t>(i) * lag;
      kernels.third_difference(from, row(stream.ring, static_cast<std::ptrdiff_t>(at)),
                               static_cast<std::ptrdiff_t>(before_wrap), lag);
      kernels.third_difference(from + static_cast<std::ptrdiff_t>(before_wrap) * lag, stream.ring.data(),
                               static_cast<std::ptrdiff_t>(take - before_wrap), lag);
    }
    stream.differenced += take;
    i += take;
    if (stream.differenced == next_close) close_segment(b);
  }
}

// Half-band decimation by two into band b + 1: an output at every even stream index
// from kHistory on, centred kHalfBandReach samples back.
std::size_t SpectrumEstimator::Impl::decimate(int b, std::size_t n) {
  constexpr int reach = detail::kHalfBandReach;
  const std::uint64_t received = bands[b].received;
  std::size_t first = received >= kHistory ? 0 : static_cast<std::size_t>(kHistory - received);
  if (((received + first) & 1) != 0) ++first;
  if (first >= n) return 0;
  const auto outputs = static_cast<std::ptrdiff_t>((n - first + 1) / 2);
  const double* centre = row(bands[b].extended, kHistory + static_cast<std::ptrdiff_t>(first) - reach);
  kernels.half_band(layout->taps.data(), centre, outputs, static_cast<std::ptrdiff_t>(stride),
                    row(bands[b + 1].extended, kHistory));
  return static_cast<std::size_t>(outputs);
}

namespace {

// A run makes an estimator per batch of realizations (~0.4 MB of streams and scratch for
// 8 lanes): the buffers of finished estimators are kept for the next, since freeing and
// reallocating them costs page faults and heap trimming (~5% of a run). A few per process.
constexpr std::size_t kPooledEstimators = 8;
std::mutex pool_guard;
std::vector<std::unique_ptr<SpectrumEstimator::Impl>>& estimator_pool() {
  static std::vector<std::unique_ptr<SpectrumEstimator::Impl>> pool;
  return pool;
}

}  // namespace

SpectrumEstimator::SpectrumEstimator(const EstimatorConfig& config, int lanes, SimdPath simd) {
  if (lanes < 1) throw InputError("estimator: need at least one lane");
  auto layout = detail::Layout::make(config);
  {
    std::lock_guard<std::mutex> lock(pool_guard);
    auto& pool = estimator_pool();
    if (!pool.empty()) {
      impl_ = std::move(pool.back());
      pool.pop_back();
    }
  }
  if (!impl_) impl_ = std::make_unique<Impl>();
  // Every field is set below: a recycled Impl keeps only its buffers' capacity.
  Impl& s = *impl_;
  s.layout = layout;
  s.has_last_value = false;
  // Automatic: the widest path no wider than the lanes (a path pads the lanes to its
  // width, and every path gives the same bits).
  if (simd == SimdPath::automatic) {
    simd = SimdPath::scalar;
    for (SimdPath candidate : available_simd_paths())
      if (lane_width(candidate) <= lanes) simd = candidate;
  }
  s.kernels = estimator_detail::stream_kernels(simd);
  const int width = lane_width(simd);
  s.lane_count = lanes;
  s.stride = static_cast<std::size_t>((lanes + width - 1) / width * width);
  s.statistics.assign(static_cast<std::size_t>(lanes), SpectrumAccumulator::Impl(layout));
  s.last_value.assign(s.stride, 0.0);
  s.bands.resize(layout->band_count);
  std::size_t capacity = kChunk;  // rows a band receives per call at most
  for (int b = 0; b < layout->band_count; ++b) {
    BandStream& band = s.bands[b];
    band.received = band.differenced = 0;
    band.extended.assign((kHistory + capacity) * s.stride, 0.0);
    if (!layout->bands[b].points.empty())
      band.ring.assign(detail::kSegmentLength * s.stride, 0.0);
    else
      band.ring.clear();
    capacity = capacity / 2 + 1;
  }
  s.transform_work.assign(detail::kSegmentLength * s.stride, 0.0);
  s.power.assign((detail::kSegmentLength / 2 + 1) * s.stride, 0.0);
  s.point_average.assign(s.stride, 0.0);
}

SpectrumEstimator::~SpectrumEstimator() {
  if (!impl_) return;
  std::lock_guard<std::mutex> lock(pool_guard);
  if (estimator_pool().size() < kPooledEstimators) estimator_pool().push_back(std::move(impl_));
}

SpectrumEstimator::SpectrumEstimator(SpectrumEstimator&&) noexcept = default;
SpectrumEstimator& SpectrumEstimator::operator=(SpectrumEstimator&&) noexcept = default;

int SpectrumEstimator::lanes() const { return impl_->lane_count; }
const EstimatorConfig& SpectrumEstimator::config() const { return impl_->layout->config; }

void SpectrumEstimator::push(const double* data, std::size_t steps) {
  Impl& s = *impl_;
  const auto lanes = static_cast<std::size_t>(s.lane_count);
  const bool values = s.layout->config.input == SampleKind::value;
  for (std::size_t start = 0; start < steps; start += kChunk) {
    const std::size_t n = std::min(kChunk, steps - start);
    // Band 0's new rows, after its history; padding lanes stay zero.
    double* y = s.row(s.bands[0].extended, kHistory);
    if (!values && s.stride == lanes) {
      std::copy_n(data + start * lanes, n * lanes, y);
      s.feed(0, n);
      continue;
    }
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double* step = data + (start + i) * lanes;
      if (values) {
        if (s.has_last_value)
          for (std::size_t l = 0; l < lanes; ++l) y[m * s.stride + l] = step[l] - s.last_value[l];
        for (std::size_t l = 0; l < lanes; ++l) s.last_value[l] = step[l];
        m += s.has_last_value ? 1 : 0;
        s.has_last_value = true;
      } else {
        for (std::size_t l = 0; l < lanes; ++l) y[m * s.stride + l] = step[l];
        ++m;
      }
    }
    s.feed(0, m);
  }
}

SpectrumAccumulator SpectrumEstimator::accumulator(int lane) const {
  if (lane < 0 || lane >= lanes()) throw std::out_of_range("estimator: no such lane");
  return SpectrumAccumulator(std::make_unique<SpectrumAccumulator::Impl>(impl_->statistics[lane]));
}

double SpectrumEstimator::segment_duration(double omega) const {
  const detail::Layout& layout = *impl_->layout;
  return detail::kSegmentLength * std::ldexp(layout.config.dt, layout.band_for(omega));
}

std::uint64_t SpectrumEstimator::segments_after(std::uint64_t steps, double omega) const {
  const detail::Layout& layout = *impl_->layout;
  // Values give band 0 their differences, one fewer than the values.
  std::uint64_t received = layout.config.input == SampleKind::value && steps > 0 ? steps - 1 : steps;
  // decimate(): an output at every even index from kHistory on.
  constexpr auto history = static_cast<std::uint64_t>(kHistory);
  for (int b = 0; b < layout.band_for(omega); ++b) received = received > history ? (received - history + 1) / 2 : 0;
  constexpr std::uint64_t D = detail::kBandDifferences, L = detail::kSegmentLength, hop = detail::kSegmentHop;
  const std::uint64_t differenced = received > D ? received - D : 0;
  return differenced < L ? 0 : (differenced - L) / hop + 1;
}

SpectrumAccumulator SpectrumEstimator::merged() const {
  SpectrumAccumulator all = accumulator(0);
  for (int l = 1; l < lanes(); ++l) all.merge(accumulator(l));
  return all;
}

}  // namespace slidespec
