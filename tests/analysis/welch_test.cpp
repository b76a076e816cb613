// The short-record estimator on processes whose spectra are known exactly (docs/model.md §3
// normalisation): white noise, a random walk (omega^-2), an AR(1) process (the sampled
// Lorentzian of an Ornstein-Uhlenbeck process) and an AR(2) oscillator (a mass on a spring
// driven by white noise). The exact spectra are written here from the recursions, not taken
// from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>
#include <numbers>
#include <random>

#include "slidespec/analysis.hpp"

namespace slidespec {
namespace {

constexpr double kDt = 0.1;  // [s], the rock-friction records' rate

struct Process {
  const char* name;
  std::function<std::vector<double>(std::size_t, std::mt19937_64&)> sample;
  std::function<double(double)> spectrum;  // exact, two-sided, [unit^2 s]
};

/// x_n = a1 x_{n-1} + a2 x_{n-2} + e_n with unit e, after a burn-in that forgets the start.
std::vector<double> autoregressive(std::size_t n, double a1, double a2, std::mt19937_64& rng) {
  std::normal_distribution<double> e;
  const std::size_t burn = 5000;
  std::vector<double> x(n + burn, 0.0);
  for (std::size_t i = 2; i < x.size(); ++i) x[i] = a1 * x[i - 1] + a2 * x[i - 2] + e(rng);
  return {x.begin() + burn, x.end()};
}

double ar_spectrum(double omega, double a1, double a2) {
  const std::complex<double> z = std::polar(1.0, -omega * kDt);
  return kDt / (2 * std::numbers::pi * std::norm(1.0 - a1 * z - a2 * z * z));
}

/// x integrated `times` times: its spectrum divided by |1 - e^{-i omega dt}|^2 per sum.
std::vector<double> cumulative(std::vector<double> x, int times) {
  for (int t = 0; t < times; ++t)
    for (std::size_t i = 1; i < x.size(); ++i) x[i] += x[i - 1];
  return x;
}
double integrated(double omega, int times) { return std::pow(4 * std::pow(std::sin(omega * kDt / 2), 2), -times); }

// AR(2) with poles at radius 0.97 and angle 0.3 rad: a resonance at 3 rad/s, Q ~ 10.
constexpr double kSpringA1 = 2 * 0.97 * 0.955336489125606, kSpringA2 = -0.97 * 0.97;

const std::vector<Process>& processes() {
  static const std::vector<Process> list = {
      {"white", [](std::size_t n, std::mt19937_64& rng) { return autoregressive(n, 0, 0, rng); },
       [](double) { return kDt / (2 * std::numbers::pi); }},
      {"random walk", [](std::size_t n, std::mt19937_64& rng) { return cumulative(autoregressive(n, 0, 0, rng), 1); },
       [](double w) { return kDt / (2 * std::numbers::pi) * integrated(w, 1); }},
      {"AR(1) Lorentzian", [](std::size_t n, std::mt19937_64& rng) { return autoregressive(n, 0.95, 0, rng); },
       [](double w) { return ar_spectrum(w, 0.95, 0); }},
      {"AR(2) spring", [](std::size_t n, std::mt19937_64& rng) { return autoregressive(n, kSpringA1, kSpringA2, rng); },
       [](double w) { return ar_spectrum(w, kSpringA1, kSpringA2); }},
  };
  return list;
}

struct Coverage {
  int inside = 0, points = 0;
  double share() const { return double(inside) / points; }
};

Coverage coverage(const WelchSpectrum& s, const std::function<double(double)>& exact, bool skip_leaky = false) {
  Coverage c;
  const std::vector<double> truth = welch_expected(s, exact);
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    if (skip_leaky && s.points[k].leaky) continue;
    ++c.points;
    c.inside += truth[k] >= s.points[k].lower && truth[k] <= s.points[k].upper ? 1 : 0;
  }
  return c;
}

#ifdef SLIDESPEC_LONG_WELCH
// Long records (label "long"): a day at 100 Hz holds 1e7 samples.
constexpr std::size_t kRecordLengths[] = {1000000, 10000000};
#else
constexpr std::size_t kRecordLengths[] = {1000, 3900, 10000, 100000};
#endif

TEST(Welch, EachProcessIsWithinItsErrorBarsAtEveryLength) {
  for (const Process& process : processes())
    for (const std::size_t n : kRecordLengths) {
      Coverage total;
      for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        std::mt19937_64 rng(seed);
        const WelchSpectrum s = welch_spectrum(process.sample(n, rng), kDt, {});
        const Coverage c = coverage(s, process.spectrum);
        total.inside += c.inside, total.points += c.points;
      }
      EXPECT_GE(total.share(), 0.85) << process.name << ", " << n << " samples: " << total.inside << " of "
                                     << total.points << " points with the truth inside their error bars";
    }
}

TEST(Welch, BandReachesNineTimesTheRecordsLowestFrequencyAndTheBinBelowNyquist) {
  for (const std::size_t n : {1000, 3900, 100000, 1000000}) {
    std::mt19937_64 rng(1);
    const WelchSpectrum s = welch_spectrum(autoregressive(n, 0, 0, rng), kDt, {});
    const double record_omega = 2 * std::numbers::pi / (double(n) * kDt);
    EXPECT_LE(s.points.front().omega, 10 * record_omega) << n;
    EXPECT_GE(s.segments, 8u) << n;
    const double nyquist = std::numbers::pi / kDt;
    EXPECT_GE(s.points.back().omega + s.points.back().bins * s.bin_spacing, nyquist - 2 * s.bin_spacing) << n;
  }
}

// The error bars are what the scatter over independent records says they are.
#ifdef SLIDESPEC_LONG_WELCH
constexpr std::size_t kCalibrationLength = 1000000;
constexpr int kSeeds = 60;
#else
constexpr std::size_t kCalibrationLength = 3900;
constexpr int kSeeds = 300;
#endif

TEST(Welch, ErrorBarsMatchTheScatterOverSeeds) {
  for (const Process& process : processes()) {
    std::vector<double> sum, sum2, error;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      std::mt19937_64 rng(seed);
      const WelchSpectrum s = welch_spectrum(process.sample(kCalibrationLength, rng), kDt, {});
      const std::vector<double> truth = welch_expected(s, process.spectrum);
      sum.resize(s.points.size()), sum2.resize(s.points.size()), error.resize(s.points.size());
      for (std::size_t k = 0; k < s.points.size(); ++k) {
        const double r = s.points[k].C / truth[k];
        sum[k] += r / kSeeds, sum2[k] += r * r / kSeeds;
        error[k] += s.points[k].standard_error / truth[k] / kSeeds;
      }
    }
    // Over all points: the scatter's rms against the error bars' rms (each point's ratio
    // is known to ~4% from 300 seeds, ~9% from 60; the pooled one far better).
    double scatter = 0, claimed = 0;
    for (std::size_t k = 0; k < sum.size(); ++k) {
      scatter += sum2[k] - sum[k] * sum[k];
      claimed += error[k] * error[k];
    }
    EXPECT_NEAR(std::sqrt(scatter / claimed), 1.0, 0.1) << process.name;
  }
}

// omega^-8 above a white floor: prewhitened, the steep part still falls as omega^-6, as fast
// as the Hann side lobes, and leaks; the floor above it does not.
TEST(Welch, LeakageIsFlaggedWhereTheSpectrumIsSteeperThanTheWindow) {
  constexpr double kSteepScale = 1e-6;
  const auto exact = [](double w) {
    return kDt / (2 * std::numbers::pi) * (kSteepScale * kSteepScale * integrated(w, 4) + 1);
  };
  Coverage unflagged;
  int flagged = 0, steep = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<double> x = cumulative(autoregressive(10000, 0, 0, rng), 4);
    const std::vector<double> floor = autoregressive(10000, 0, 0, rng);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = kSteepScale * x[i] + floor[i];
    const WelchSpectrum s = welch_spectrum(x, kDt, {});
    for (const WelchPoint& p : s.points)
      if (kSteepScale * kSteepScale * integrated(p.omega, 4) > 1) ++steep, flagged += p.leaky ? 1 : 0;
    const Coverage c = coverage(s, exact, true);
    unflagged.inside += c.inside, unflagged.points += c.points;
  }
  EXPECT_GT(flagged, steep / 2) << "the omega^-8 part leaks";
  EXPECT_GT(unflagged.points, 50);
  EXPECT_GE(unflagged.share(), 0.85) << unflagged.inside << " of " << unflagged.points;
  for (const Process& process : processes()) {
    std::mt19937_64 rng(1);
    for (const WelchPoint& p : welch_spectrum(process.sample(10000, rng), kDt, {}).points)
      EXPECT_FALSE(p.leaky) << process.name << " at " << p.omega;
  }
}

TEST(Welch, OmegaMinTakesEffectOrIsRefusedWithTheReachableOmega) {
  std::mt19937_64 rng(1);
  const std::vector<double> x = autoregressive(3900, 0, 0, rng);
  WelchRequest request;
  request.omega_min = 0.1;  // below 9 x 2 pi / T = 0.145: longer segments, fewer of them
  const WelchSpectrum s = welch_spectrum(x, kDt, request);
  EXPECT_LE(s.points.front().omega, 0.1 * 1.0001);
  EXPECT_GE(s.segments, 4u);
  request.omega_min = 0.01;
  try {
    welch_spectrum(x, kDt, request);
    FAIL() << "omega_min 0.01 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("reaches down to"), std::string::npos) << e.what();
  }
  request.omega_min = 1;
  const WelchSpectrum above = welch_spectrum(x, kDt, request);
  const double first = double(above.points.front().first_bin) * above.bin_spacing;
  EXPECT_LE(first, 1.0);
  EXPECT_GT(first, 1.0 - above.bin_spacing);
}

}  // namespace
}  // namespace slidespec
