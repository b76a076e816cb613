// The estimator against processes whose discrete-time spectra are known exactly.
// Tolerances come from the reported standard errors (and the statistics of z-scores),
// never from the answers.
#include "slidespec/estimator.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <functional>
#include <new>
#include <numbers>
#include <random>
#include <thread>

#include "estimator/design.hpp"
#include "estimator/kernels.hpp"
#include "slidespec/parameters.hpp"

// Every allocation in this binary is counted, so a test can show that push() allocates
// nothing once running: memory does not grow with the stream.
namespace {
std::atomic<std::size_t> g_allocations{0};
}
void* operator new(std::size_t bytes) {
  ++g_allocations;
  if (void* p = std::malloc(bytes == 0 ? 1 : bytes)) return p;
  throw std::bad_alloc();
}
// GCC cannot see that this operator new is malloc-based, hence the pragma.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace slidespec {
namespace {

constexpr double kPi = std::numbers::pi;

// Feeds `steps` steps of the per-lane generators into the estimator in blocks.
template <class Generator>
void feed(SpectrumEstimator& estimator, std::vector<Generator>& lanes, std::size_t steps, std::size_t block = 8192) {
  const int count = estimator.lanes();
  std::vector<double> data(block * count);
  for (std::size_t done = 0; done < steps; done += block) {
    const std::size_t n = std::min(block, steps - done);
    for (std::size_t i = 0; i < n; ++i)
      for (int l = 0; l < count; ++l) data[i * count + l] = lanes[l]();
    estimator.push(data.data(), n);
  }
}

// White Gaussian noise of standard deviation `sigma`.
struct WhiteNoise {
  std::mt19937_64 rng;
  double sigma;
  std::normal_distribution<double> normal{0.0, 1.0};
  WhiteNoise(std::uint64_t seed, double s) : rng(seed), sigma(s) {}
  double operator()() { return sigma * normal(rng); }
};

// AR(1): x_n = a x_{n-1} + e_n, started in its stationary state.
struct AutoRegressive {
  std::mt19937_64 rng;
  double a;
  std::normal_distribution<double> normal{0.0, 1.0};
  double x;
  AutoRegressive(std::uint64_t seed, double pole) : rng(seed), a(pole) { x = normal(rng) / std::sqrt(1 - a * a); }
  double operator()() { return x = a * x + normal(rng); }
  static double spectrum(double pole, double omega, double dt) {
    const std::complex<double> d = 1.0 - pole * std::exp(std::complex<double>(0, -omega * dt));
    return dt / (2 * kPi) / std::norm(d);
  }
};

// Increments of a random walk low-passed by `order` one-pole stages: the spectrum of the
// walk x falls as omega^-(2 + 2 order) above the pole, 30+ decades over 3 decades.
struct SteepIncrements {
  std::mt19937_64 rng;
  double a;
  std::normal_distribution<double> normal{0.0, 1.0};
  std::vector<double> stage;
  SteepIncrements(std::uint64_t seed, double pole, int order) : rng(seed), a(pole), stage(order, 0.0) {
    for (int warm = 0; warm < 200000; ++warm) (*this)();
  }
  double operator()() {
    double u = normal(rng);
    for (double& s : stage) u = s = a * s + u;
    return u;
  }
  static double spectrum(double pole, int order, double omega, double dt) {
    const std::complex<double> d = 1.0 - pole * std::exp(std::complex<double>(0, -omega * dt));
    const double s = std::sin(0.5 * omega * dt);
    return dt / (2 * kPi) / std::pow(std::norm(d), order) / (4 * s * s);
  }
};

struct Deviation {
  double worst_relative = 0;  // max |C/exact - 1|
  double worst_z = 0;         // max |C - exact| / standard_error
  int points = 0;
};

Deviation compare(const std::vector<SpectrumPoint>& spectrum, const std::function<double(double)>& exact) {
  Deviation d;
  for (const SpectrumPoint& p : spectrum) {
    const double truth = exact(p.omega);
    d.worst_relative = std::max(d.worst_relative, std::abs(p.C / truth - 1));
    d.worst_z = std::max(d.worst_z, std::abs(p.C - truth) / p.standard_error);
    ++d.points;
  }
  return d;
}

// With M points of independent standard normal z, P(max |z| > 4) ~ M * 6.3e-5: a bound
// that a correct estimator passes except about once in a thousand runs.
constexpr double kEveryPointZ = 4.0;

TEST(Estimator, WhiteNoiseLevelIsSigmaSquaredDtOverTwoPi) {
  const double dt = 1e-3, sigma = 2.0;
  SpectrumEstimator estimator({dt, 0, 0, 8, SampleKind::value}, 4);
  std::vector<WhiteNoise> lanes;
  for (int l = 0; l < 4; ++l) lanes.emplace_back(100 + l, sigma);
  feed(estimator, lanes, 400000);
  const auto spectrum = estimator.merged().spectrum(PointValue::centre);
  ASSERT_EQ(spectrum.size(), 17u);  // 2 decades at 8 per decade, both ends
  const double level = sigma * sigma * dt / (2 * kPi);
  const Deviation d = compare(spectrum, [&](double) { return level; });
  EXPECT_LT(d.worst_z, kEveryPointZ);
  for (const SpectrumPoint& p : spectrum) EXPECT_LT(p.standard_error / p.C, 0.05) << p.omega;
}

TEST(Estimator, SinusoidPowerAndPosition) {
  // A sinusoid of amplitude A carries A^2/4 at +omega0 (two-sided): the point holding
  // omega0 integrates to that over its FFT bins; its neighbours see only the noise.
  const double dt = 1e-2, amplitude = 3.0;
  const EstimatorConfig config{dt, 0, 0, 8, SampleKind::value};
  const auto layout = estimator_detail::Layout::make(config);
  const estimator_detail::OutputPoint& target = layout->points[12];
  const double resolution = layout->bin_omega(target.band, 1);
  const double omega0 = resolution * (target.first_bin + 0.5 * (target.bin_count - 1) + 0.25);
  SpectrumEstimator estimator(config, 1);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::size_t n = 0;
  auto signal = [&] {
    const double t = static_cast<double>(n++) * dt;
    return amplitude * std::sin(omega0 * t + 0.3) + 1e-3 * normal(rng);
  };
  std::vector<std::function<double()>> lanes{signal};
  feed(estimator, lanes, 300000);
  const auto spectrum = estimator.merged().spectrum(PointValue::bin_average);
  auto peak =
      std::max_element(spectrum.begin(), spectrum.end(), [](const auto& a, const auto& b) { return a.C < b.C; });
  EXPECT_DOUBLE_EQ(peak->omega, target.omega);
  const double power = peak->C * target.bin_count * resolution;
  // The window's leakage outside the point's bins is below 1e-4 of the line.
  EXPECT_NEAR(power / (amplitude * amplitude / 4), 1.0, 2e-3);
}

TEST(Estimator, AutoRegressiveAgainstExactSpectrum) {
  const double dt = 1e-3, pole = 0.995;
  SpectrumEstimator estimator({dt, 1.0, 1500.0, 8, SampleKind::value}, 4);
  std::vector<AutoRegressive> lanes;
  for (int l = 0; l < 4; ++l) lanes.emplace_back(200 + l, pole);
  feed(estimator, lanes, 1500000);
  const auto spectrum = estimator.merged().spectrum(PointValue::centre);
  ASSERT_GE(spectrum.size(), 20u);
  const Deviation d = compare(spectrum, [&](double w) { return AutoRegressive::spectrum(pole, w, dt); });
  EXPECT_LT(d.worst_z, kEveryPointZ);
  EXPECT_LT(d.worst_relative, 0.10);
}

TEST(Estimator, SteepProcessOverThirtyFiveDecades) {
  // Increments fed, as the stepper does. 5 poles: C_x falls ~35 decades over 3 decades.
  const double dt = 1.0, omega_max = 0.5 * kPi, omega_min = omega_max / 1000;
  const double pole = std::exp(-omega_min);
  const int order = 5;
  const int lane_count = 8;
  SpectrumEstimator estimator({dt, omega_min, omega_max, 8, SampleKind::increment}, lane_count);
  std::vector<SteepIncrements> lanes;
  for (int l = 0; l < lane_count; ++l) lanes.emplace_back(300 + l, pole, order);
  feed(estimator, lanes, 5000000);
  const auto spectrum = estimator.merged().spectrum(PointValue::centre);
  ASSERT_EQ(spectrum.size(), 25u);
  auto exact = [&](double w) { return SteepIncrements::spectrum(pole, order, w, dt); };
  const double decades = std::log10(exact(spectrum.front().omega) / exact(spectrum.back().omega));
  EXPECT_GT(decades, 30);
  const Deviation d = compare(spectrum, exact);
  if (std::getenv("SLIDESPEC_VERBOSE"))
    for (const auto& p : spectrum)
      std::printf("%10.4g %10.3e ratio %.4f z %6.2f se %.4f navg %g\n", p.omega, p.C, p.C / exact(p.omega),
                  (p.C - exact(p.omega)) / p.standard_error, p.standard_error / p.C, p.n_avg);
  EXPECT_LT(d.worst_relative, 0.05);
  EXPECT_LT(d.worst_z, kEveryPointZ);
  // The bin averages need no shape model: compare them with the exact C averaged over
  // the same FFT bins.
  const auto averages = estimator.merged().spectrum(PointValue::bin_average);
  ASSERT_EQ(averages.size(), spectrum.size());
  const auto layout = estimator_detail::Layout::make(estimator.config());
  double worst_average_z = 0;
  for (std::size_t k = 0; k < averages.size(); ++k) {
    const estimator_detail::OutputPoint& point = layout->points[k];
    ASSERT_DOUBLE_EQ(point.omega, averages[k].omega);
    double sum = 0;
    for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j)
      sum += exact(layout->bin_omega(point.band, j));
    const double z = (averages[k].C - sum / point.bin_count) / averages[k].standard_error;
    worst_average_z = std::max(worst_average_z, std::abs(z));
  }
  EXPECT_LT(worst_average_z, kEveryPointZ);
  std::printf(
      "steep: %.1f decades, centre: worst |C/exact-1| = %.3f, worst |z| = %.2f over %d points;"
      " bin averages: worst |z| = %.2f\n",
      decades, d.worst_relative, d.worst_z, d.points, worst_average_z);
}

// Step-major AR(1) data for `lanes` lanes, each lane from its own seed.
std::vector<double> ar1_data(int lanes, std::size_t steps, std::uint64_t seed) {
  std::vector<AutoRegressive> sources;
  for (int l = 0; l < lanes; ++l) sources.emplace_back(seed + l, 0.9);
  std::vector<double> data(steps * lanes);
  for (std::size_t i = 0; i < steps; ++i)
    for (int l = 0; l < lanes; ++l) data[i * lanes + l] = sources[l]();
  return data;
}

std::vector<double> lane_of(const std::vector<double>& data, int lanes, int lane) {
  std::vector<double> column(data.size() / lanes);
  for (std::size_t i = 0; i < column.size(); ++i) column[i] = data[i * lanes + lane];
  return column;
}

const EstimatorConfig kSmallConfig{1e-3, 5.0, 1500.0, 8, SampleKind::value};

TEST(Estimator, MergedEqualsOneEstimatorOnTheSameDataBitwise) {
  const auto data = ar1_data(3, 300000, 40);
  SpectrumEstimator together(kSmallConfig, 3);
  together.push(data.data(), 300000);
  SpectrumAccumulator separate;
  for (int l = 0; l < 3; ++l) {
    SpectrumEstimator alone(kSmallConfig, 1);
    const auto column = lane_of(data, 3, l);
    alone.push(column.data(), column.size());
    separate.merge(alone.accumulator(0));
  }
  EXPECT_EQ(separate.save(), together.merged().save());
  SpectrumAccumulator by_lane = together.accumulator(0);
  for (int l = 1; l < 3; ++l) by_lane.merge(together.accumulator(l));
  EXPECT_EQ(by_lane.save(), together.merged().save());
  EXPECT_FALSE(together.merged().spectrum().empty());
}

// What a run's planner asks before any work: the segments a realization of so many steps
// gives each point. Counted here by feeding one sample at a time, for values and
// increments, past the first segments of five bands (every threshold crossed).
TEST(Estimator, SegmentsAfterCountsTheSegmentsAPushGives) {
  for (const SampleKind input : {SampleKind::value, SampleKind::increment}) {
    EstimatorConfig config = kSmallConfig;
    config.input = input;
    SpectrumEstimator estimator(config, 1);
    std::mt19937_64 rng(7);
    std::uint64_t mismatches = 0, last_count = 0;
    for (std::uint64_t steps = 1; steps <= 20000; ++steps) {
      const double x = std::normal_distribution<double>()(rng);
      estimator.push(&x, 1);
      std::uint64_t count = 0;
      for (const auto& point : estimator.merged().point_sums()) {
        mismatches += estimator.segments_after(steps, point.omega) != point.segments;
        count += point.segments;
      }
      last_count = count;
    }
    EXPECT_EQ(mismatches, 0u) << (input == SampleKind::value ? "values" : "increments");
    EXPECT_GT(last_count, 0u);
  }
}

TEST(Estimator, ChunkingDoesNotChangeTheResultBitwise) {
  const std::size_t steps = 200000;
  const auto data = ar1_data(2, steps, 50);
  SpectrumEstimator whole(kSmallConfig, 2);
  whole.push(data.data(), steps);
  SpectrumEstimator single(kSmallConfig, 2);
  for (std::size_t i = 0; i < steps; ++i) single.push(data.data() + 2 * i, 1);
  SpectrumEstimator ragged(kSmallConfig, 2);
  std::mt19937_64 rng(3);
  for (std::size_t done = 0; done < steps;) {
    const std::size_t n = std::min<std::size_t>(steps - done, rng() % 10007);
    ragged.push(data.data() + 2 * done, n);
    done += n;
  }
  EXPECT_EQ(whole.merged().save(), single.merged().save());
  EXPECT_EQ(whole.merged().save(), ragged.merged().save());
}

TEST(Estimator, LaneDependsOnlyOnItsOwnDataBitwise) {
  const std::size_t steps = 150000;
  for (int lanes : {1, 3, 5, 9}) {
    const auto data = ar1_data(lanes, steps, 60);
    SpectrumEstimator many(kSmallConfig, lanes);
    many.push(data.data(), steps);
    const auto column = lane_of(data, lanes, 0);
    SpectrumEstimator one(kSmallConfig, 1);
    one.push(column.data(), steps);
    EXPECT_EQ(many.accumulator(0).save(), one.accumulator(0).save()) << lanes << " lanes";
  }
}

TEST(Estimator, EverySimdPathMatchesTheScalarPathBitwise) {
  // Lane counts around every width, both input kinds, and chunks that split the
  // decimators' outputs unevenly, so every kernel's leftover elements are exercised.
  for (SampleKind kind : {SampleKind::value, SampleKind::increment}) {
    EstimatorConfig config = kSmallConfig;
    config.input = kind;
    for (int lanes : {1, 3, 8, 9}) {
      const std::size_t steps = 120000;
      const auto data = ar1_data(lanes, steps, 65);
      auto saved = [&](SimdPath path) {
        SpectrumEstimator estimator(config, lanes, path);
        for (std::size_t done = 0, n = 1; done < steps; done += n, n = n * 7 % 9973 + 1)
          estimator.push(data.data() + done * lanes, std::min(n, steps - done));
        std::string all;
        for (int l = 0; l < lanes; ++l) all += estimator.accumulator(l).save();
        return all;
      };
      const std::string scalar = saved(SimdPath::scalar);
      for (SimdPath path : available_simd_paths())
        EXPECT_EQ(saved(path), scalar) << to_string(path) << ", " << lanes << " lanes";
    }
  }
}

TEST(Estimator, SegmentTransformMatchesTheDefinitionOfTheDft) {
  // |X_k|^2 of every lane against X_k = sum_n w_n x_{(start + n) mod L} e^{-2 pi i k n/L}
  // summed in long double, on every path, lanes padded around each width, the segment
  // wrapped around its ring. A wrong twiddle or index is an O(1) error, rounding ~1e-15
  // of sqrt(L sum (w x)^2).
  constexpr int L = estimator_detail::kSegmentLength;
  const auto& tables = estimator_detail::fourier_tables();
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.1, 1.0);
  std::vector<double> window(L);
  for (double& w : window) w = uniform(rng);
  const std::size_t start = 37;
  for (SimdPath path : available_simd_paths()) {
    const estimator_detail::StreamKernels kernels = estimator_detail::stream_kernels(path);
    const int width = lane_width(path);
    for (int lanes : {1, width + 1, 2 * width}) {
      const std::ptrdiff_t stride = (lanes + width - 1) / width * width;
      std::vector<double> ring(L * stride, 0.0), work(L * stride), power((L / 2 + 1) * stride);
      for (int n = 0; n < L; ++n)
        for (int l = 0; l < lanes; ++l) ring[n * stride + l] = normal(rng) + (l == 0 ? std::cos(0.7 * n) : 0.0);
      kernels.segment_power(tables, window.data(), ring.data(), start, 0, L / 2, work.data(), power.data(), stride);
      for (int l = 0; l < lanes; ++l) {
        std::vector<long double> segment(L);
        long double energy = 0;
        for (int n = 0; n < L; ++n) {
          segment[n] = static_cast<long double>(window[n]) * ring[((start + n) % L) * stride + l];
          energy += segment[n] * segment[n];
        }
        const double tolerance = 1e-13 * std::sqrt(static_cast<double>(L * energy));
        double worst = 0;
        for (int k = 0; k <= L / 2; ++k) {
          long double re = 0, im = 0;
          for (int n = 0; n < L; ++n) {
            const long double angle = -2.0L * std::numbers::pi_v<long double> * ((static_cast<long>(k) * n) % L) / L;
            re += segment[n] * std::cos(angle);
            im += segment[n] * std::sin(angle);
          }
          const double exact = static_cast<double>(std::sqrt(re * re + im * im));
          worst = std::max(worst, std::abs(std::sqrt(power[k * stride + l]) - exact));
        }
        EXPECT_LT(worst, tolerance) << to_string(path) << ", lane " << l << " of " << lanes;
      }
    }
  }
}

TEST(Estimator, HalfBandPowerMatchesTheDefinition) {
  // |H(theta)|^2 with H = sum_n h_n e^{-i n theta} over the taps, summed in long double
  // with a cosine per tap, across the pass band, the transition and the stop band (where
  // H is ~1e-7, so a wrong tap or recurrence step is far beyond the 1e-14 of rounding).
  const std::vector<double> taps = estimator_detail::half_band_taps();
  const int K = (static_cast<int>(taps.size()) - 1) / 2;
  for (int i = 0; i <= 4000; ++i) {
    const double theta = std::numbers::pi * i / 4000;
    long double amplitude = 0;
    for (int n = -K; n <= K; ++n) amplitude += taps[K + n] * std::cos(static_cast<long double>(n) * theta);
    const double exact = static_cast<double>(amplitude * amplitude);
    EXPECT_NEAR(std::sqrt(estimator_detail::half_band_power(taps, theta)), std::sqrt(exact), 1e-14)
        << "theta = " << theta;
  }
}

TEST(Estimator, ConcurrentEstimatorsOnTwoThreadsMatchSequentialBitwise) {
  const auto a = ar1_data(2, 200000, 70), b = ar1_data(2, 200000, 80);
  auto run = [](const std::vector<double>& data, std::string& out) {
    SpectrumEstimator estimator(kSmallConfig, 2);
    estimator.push(data.data(), data.size() / 2);
    out = estimator.merged().save();
  };
  std::string seq_a, seq_b, par_a, par_b;
  run(a, seq_a);
  run(b, seq_b);
  std::thread first(run, std::cref(a), std::ref(par_a));
  std::thread second(run, std::cref(b), std::ref(par_b));
  first.join();
  second.join();
  EXPECT_EQ(seq_a, par_a);
  EXPECT_EQ(seq_b, par_b);
}

TEST(Estimator, SaveLoadRoundTripIsBitwise) {
  const auto data = ar1_data(2, 200000, 90);
  SpectrumEstimator estimator(kSmallConfig, 2);
  estimator.push(data.data(), 200000);
  const std::string bytes = estimator.merged().save();
  const SpectrumAccumulator loaded = SpectrumAccumulator::load(bytes);
  EXPECT_EQ(loaded.save(), bytes);
  const auto original = estimator.merged().spectrum(), again = loaded.spectrum();
  ASSERT_EQ(original.size(), again.size());
  for (std::size_t k = 0; k < original.size(); ++k) {
    EXPECT_EQ(original[k].C, again[k].C);
    EXPECT_EQ(original[k].standard_error, again[k].standard_error);
  }
}

// The message of the InputError `action` throws, or "" if it throws none.
std::string input_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Estimator, RefusesMismatchedMergeAndForeignFiles) {
  const auto data = ar1_data(1, 50000, 95);
  SpectrumEstimator a(kSmallConfig, 1);
  EstimatorConfig other = kSmallConfig;
  other.dt = 2e-3;
  other.omega_max = 1000;
  SpectrumEstimator b(other, 1);
  a.push(data.data(), 50000);
  b.push(data.data(), 50000);
  SpectrumAccumulator merged = a.merged();
  const std::string mismatch = input_error([&] { merged.merge(b.merged()); });
  EXPECT_NE(mismatch.find("cannot merge"), std::string::npos) << mismatch;
  EXPECT_EQ(mismatch.find('\n'), std::string::npos);

  std::string bytes = a.merged().save();
  std::string future = bytes;
  future[8] = 2;  // the version field follows the 8-byte magic
  EXPECT_NE(input_error([&] { SpectrumAccumulator::load(future); }).find("version 2"), std::string::npos);
  EXPECT_NE(input_error([&] { SpectrumAccumulator::load(bytes.substr(0, bytes.size() - 3)); }).find("truncated"),
            std::string::npos);
  EXPECT_NE(input_error([&] { SpectrumAccumulator::load("not a spectrum"); }), "");
  EXPECT_NE(input_error([&] { SpectrumAccumulator::load(bytes + "x"); }), "");
  EXPECT_NE(input_error([] { SpectrumEstimator({0.0, 0, 0, 8, SampleKind::value}, 1); }), "");
  EXPECT_NE(input_error([] { SpectrumEstimator({1e-3, 0, 3000.0, 8, SampleKind::value}, 1); }), "");
}

TEST(Estimator, MemoryDoesNotGrowWithTheStream) {
  // After the first push has sized everything, further pushes allocate nothing, and the
  // saved accumulator has the same size whatever the stream's length.
  const auto data = ar1_data(4, 100000, 99);
  SpectrumEstimator estimator(kSmallConfig, 4);
  estimator.push(data.data(), 100000);
  const std::size_t short_size = estimator.merged().save().size();
  const std::size_t before = g_allocations.load();
  for (int repeat = 0; repeat < 10; ++repeat) estimator.push(data.data(), 100000);
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_EQ(estimator.merged().save().size(), short_size);
}

void expect_standard_normal(const std::vector<double>& z, const char* what) {
  const double M = static_cast<double>(z.size());
  auto bound_above = [&](double p) { return M * p + 4 * std::sqrt(M * p * (1 - p)); };
  int beyond2 = 0, beyond3 = 0, within1 = 0;
  double sum_squares = 0;
  for (double v : z) {
    beyond2 += std::abs(v) > 2;
    beyond3 += std::abs(v) > 3;
    within1 += std::abs(v) <= 1;
    sum_squares += v * v;
  }
  std::printf("%s: %zu points, |z|<=1 %.1f%%, |z|<=2 %.1f%%, |z|>3 %.2f%%, mean z^2 %.3f\n", what, z.size(),
              100 * within1 / M, 100 * (1 - beyond2 / M), 100 * beyond3 / M, sum_squares / M);
  EXPECT_LE(beyond2, bound_above(0.0455)) << what;
  EXPECT_LE(beyond3, bound_above(0.0027)) << what;
  // Error bars too wide would show as too many |z| <= 1 and a small mean z^2.
  EXPECT_NEAR(within1, M * 0.683, 4 * std::sqrt(M * 0.683 * 0.317)) << what;
  EXPECT_NEAR(sum_squares / M, 1.0, 4 * std::sqrt(2 / M)) << what;
}

TEST(Estimator, ZScoresAreStandardNormal) {
  // AR(1) over many seeds, including the lowest points with only 12-30 segments.
  // z = (C - exact)/standard_error, for both the centre values against C(omega) and
  // the bin averages against the exact C averaged over the same FFT bins.
  const double dt = 1e-3, pole = 0.99;
  const EstimatorConfig config{dt, 2.0, 1500.0, 8, SampleKind::value};
  const auto layout = estimator_detail::Layout::make(config);
  auto exact = [&](double w) { return AutoRegressive::spectrum(pole, w, dt); };
  std::vector<double> z_centre, z_average;
  for (std::uint64_t seed = 0; seed < 12; ++seed) {
    SpectrumEstimator estimator(config, 2);
    std::vector<AutoRegressive> lanes;
    for (int l = 0; l < 2; ++l) lanes.emplace_back(1000 + 10 * seed + l, pole);
    feed(estimator, lanes, 500000);
    const SpectrumAccumulator all = estimator.merged();
    for (const SpectrumPoint& p : all.spectrum(PointValue::centre))
      z_centre.push_back((p.C - exact(p.omega)) / p.standard_error);
    for (const SpectrumPoint& p : all.spectrum(PointValue::bin_average)) {
      for (const auto& point : layout->points) {
        if (point.omega != p.omega) continue;
        double sum = 0;
        for (int j = point.first_bin; j < point.first_bin + point.bin_count; ++j)
          sum += exact(layout->bin_omega(point.band, j));
        z_average.push_back((p.C - sum / point.bin_count) / p.standard_error);
      }
    }
  }
  ASSERT_GE(z_centre.size(), 200u);
  expect_standard_normal(z_centre, "centre");
  expect_standard_normal(z_average, "bin average");
}

}  // namespace
}  // namespace slidespec
