// The linear shadow (docs/run.md, "The shadow"): the same draws and dynamics as the block,
// each force renewed when the nominal place v t passes its mark. Its spectrum is exactly the
// first-order theory's, so its mean through the estimator is known, and it follows the
// block closely, so as a control variate it removes most of a point's scatter.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <vector>

#include "slidespec/estimator.hpp"
#include "slidespec/run.hpp"
#include "slidespec/stepper.hpp"
#include "slidespec/theory.hpp"

using namespace slidespec;

namespace {

/// The block's and the shadow's spectra over `realizations` realizations of sub-band
/// `band` of `request` as the run plans it (its step, length and warm-up).
struct Spectra {
  SpectrumAccumulator block, shadow;
};
Spectra simulate(const Parameters& p, const SubBand& band, std::uint64_t realizations, std::uint64_t seed) {
  EstimatorConfig estimator;
  estimator.dt = band.dt;
  estimator.omega_min = band.omega_low;
  estimator.omega_max = band.omega_high;
  estimator.input = SampleKind::increment;
  StepperConfig config;
  config.dt = band.dt;
  config.seed = seed;
  config.warm_up = band.warm_up;
  config.warm_up_dt = band.warm_up_dt;
  config.shadow = true;
  std::map<std::uint64_t, std::pair<std::shared_ptr<SpectrumEstimator>, std::shared_ptr<SpectrumEstimator>>> batches;
  std::mutex lock;
  run_batches(p, config, 0, realizations, std::llround(band.duration / band.dt), 0, 8,
              [&](std::uint64_t first, int count) -> BatchSinks {
                auto block = std::make_shared<SpectrumEstimator>(estimator, count);
                auto shadow = std::make_shared<SpectrumEstimator>(estimator, count);
                batches[first] = {block, shadow};
                return {[block](const double* data, std::size_t n) { block->push(data, n); },
                        [shadow](const double* data, std::size_t n) { shadow->push(data, n); }};
              },
              {});
  Spectra out;
  for (const auto& [first, pair] : batches)
    for (int lane = 0; lane < pair.first->lanes(); ++lane) {
      out.block.merge(pair.first->accumulator(lane));
      out.shadow.merge(pair.second->accumulator(lane));
    }
  return out;
}

/// The mean over points of estimate / expected - 1, and the mean relative error.
struct Deviation {
  double mean = 0, error = 0;
};
Deviation deviation(const std::vector<SpectrumPoint>& estimate, const std::vector<SpectrumPoint>& expected) {
  Deviation d;
  const double n = static_cast<double>(estimate.size());
  for (std::size_t k = 0; k < estimate.size(); ++k) {
    d.mean += (estimate[k].C / expected[k].C - 1) / n;
    d.error += estimate[k].standard_error / estimate[k].C / n;
  }
  return d;
}

// N = 4 at eps 0.245: the block's spectrum lies 10% above the first order below v/a (D/D_1)
// and 3% below it far above (the renewal rate's eps^2/2), so a shadow renewed at the block's
// place, or late, shows; the shadow's own sits on the first order within its errors (0.4%).
TEST(Shadow, TheShadowAloneHasTheFirstOrderSpectrum) {
  const Parameters p = ParameterBuilder().set("N=4").set("alpha=1.2").set("a=5e-4").build();
  const LumpedTheory theory(p);
  struct Band {
    double low, high;
    std::uint64_t realizations;
  };
  for (const Band b : {Band{0.2, 0.75, 1024}, Band{100, 750, 3072}}) {
    RunRequest request;
    request.omega_min = b.low;
    request.omega_max = b.high;
    const SubBand band = plan_sub_bands(p, request).front();
    const Spectra spectra = simulate(p, band, b.realizations, 77);
    const auto expected = spectra.shadow.expected(std::cref(theory));
    const Deviation shadow = deviation(spectra.shadow.spectrum(), expected);
    const Deviation block = deviation(spectra.block.spectrum(), expected);
    EXPECT_LE(std::fabs(shadow.mean), 3 * shadow.error)
        << b.low << " rad/s: the shadow's mean deviation " << shadow.mean << " +- " << shadow.error << ", the block's "
        << block.mean;
    EXPECT_LT(shadow.error, 0.006) << b.low << " rad/s";
    // The test can tell a shadow that is the block: the block is many errors away.
    EXPECT_GT(std::fabs(block.mean), 5 * block.error) << b.low << " rad/s: the block's mean deviation";
  }
}

// Below v/a the shadow removes most of the scatter between realizations: the points' variance
// over the plain mean's (measured 0.02-0.12 at the reference's lowest sub-band, 0.1-0.3 to 750
// rad/s); a shadow with draws of its own would be as uncorrelated as another realization.
TEST(Shadow, TheShadowFollowsTheBlockBelowTheTopSubRuns) {
  RunRequest request;
  request.omega_min = 0.1;
  request.omega_max = 750;
  request.realizations = 64;
  request.seed = 5;
  const RunResult result = run_spectrum(ParameterBuilder("reference").build(), request);
  ASSERT_TRUE(result.complete);
  for (const SubBand& band : result.sub_bands) EXPECT_TRUE(band.shadow) << band.omega_low;
  double worst = 0, lowest_band = 0;
  int shadowed = 0;
  for (const RunPoint& point : result.points) {
    worst = std::max(worst, point.variance_ratio);
    if (point.omega < 0.8) lowest_band = std::max(lowest_band, point.variance_ratio);
    shadowed += point.estimator == "shadow";
  }
  EXPECT_LT(lowest_band, 0.25);
  EXPECT_LT(worst, 0.5);
  EXPECT_GE(shadowed, static_cast<int>(result.points.size()) - 2);
}

// The control variate changes the error, not the expectation: the same realizations with it
// and without agree within the plain estimate's errors, and its error bars are the smaller.
TEST(Shadow, TheControlVariateKeepsTheEstimateAndShrinksItsError) {
  const Parameters p = ParameterBuilder("reference").build();
  RunRequest request;
  request.omega_min = 1;
  request.omega_max = 75;
  request.realizations = 64;
  request.seed = 9;
  const RunResult with = run_spectrum(p, request);
  request.control_variate = false;
  const RunResult without = run_spectrum(p, request);
  ASSERT_EQ(with.points.size(), without.points.size());
  for (std::size_t k = 0; k < with.points.size(); ++k) {
    const RunPoint &a = with.points[k], &b = without.points[k];
    EXPECT_LE(std::fabs(a.C_x - b.C_x), 3.5 * b.standard_error) << a.omega;
    EXPECT_LT(a.standard_error, b.standard_error) << a.omega;
    EXPECT_EQ(b.estimator, "forcing") << b.omega;
  }
  for (const SubBand& band : without.sub_bands) EXPECT_FALSE(band.shadow);
}

}  // namespace

namespace {

// The error bars with the shadow are honest: over many seeds the deviations from the theory
// that holds (theory2, or theory where only the first order does) are standard normal.
// Measured at 1%, 30 seeds, 0.1..1e5 rad/s (docs/run.md): mean z^2 1.02 / 1.09 / 1.06 / 1.01,
// 95.2% / 94.0% / 95.0% / 96.1% within 2 for reference / weak-noise / many-contacts / a spring.
// The short variant runs 8 seeds of two cases over the sub-runs the shadow serves; the long
// one (SLIDESPEC_LONG_SHADOW, label "long") the 30 seeds of four over the whole band.
struct Calibration {
  const char* name;
  const char* case_name;
  std::vector<const char*> changes;
};
void PrintTo(const Calibration& c, std::ostream* os) { *os << c.name; }

class ShadowCalibration : public ::testing::TestWithParam<Calibration> {};

TEST_P(ShadowCalibration, ErrorBarsAreCalibratedOverSeeds) {
  ParameterBuilder builder(GetParam().case_name);
  for (const char* change : GetParam().changes) builder.set(change);
  const Parameters p = builder.build();
  RunRequest request;
  request.precision = 0.01;
#ifdef SLIDESPEC_LONG_SHADOW
  const int seeds = 30;
  const double most_z2 = 1.1, least_within_two = 0.93;
#else
  const int seeds = 8;
  request.omega_max = 750;
  // 8 x 32 points, of which a sub-band's share each fluctuation: looser bounds, still far
  // from a shadow that biases (z^2 >> 1) or error bars twice too wide (z^2 ~ 0.25).
  const double most_z2 = 1.3, least_within_two = 0.9;
#endif
  double z2 = 0;
  int points = 0, within_two = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    request.seed = static_cast<std::uint64_t>(seed);
    const RunResult result = run_spectrum(p, request);
    ASSERT_TRUE(result.complete && result.stationary) << result.stationarity;
    for (const RunPoint& point : result.points) {
      const double theory = std::isfinite(point.theory2) ? point.theory2 : point.theory;
      const double z = (point.C_x - theory) / point.standard_error;
      z2 += z * z, ++points, within_two += std::fabs(z) <= 2;
    }
  }
  EXPECT_LE(z2 / points, most_z2) << GetParam().name;
  EXPECT_GE(z2 / points, 2 - most_z2) << GetParam().name;
  EXPECT_GE(within_two, least_within_two * points) << GetParam().name;
}

#ifdef SLIDESPEC_LONG_SHADOW
INSTANTIATE_TEST_SUITE_P(
    Cases, ShadowCalibration,
    ::testing::Values(Calibration{"reference", "reference", {}}, Calibration{"weak_noise", "weak-noise", {}},
                      Calibration{"many_contacts", "many-contacts", {}},
                      Calibration{"spring", "reference", {"N=12", "alpha=0.5", "drive=spring", "k_drive=1e4"}}),
    [](const ::testing::TestParamInfo<Calibration>& param) { return std::string(param.param.name); });
#else
INSTANTIATE_TEST_SUITE_P(
    Cases, ShadowCalibration,
    ::testing::Values(Calibration{"reference", "reference", {}},
                      Calibration{"spring", "reference", {"N=12", "alpha=0.5", "drive=spring", "k_drive=1e4"}}),
    [](const ::testing::TestParamInfo<Calibration>& param) { return std::string(param.param.name); });
#endif

}  // namespace

namespace {

// With the shadow a run is still the same numbers whatever the threads and SIMD path.
TEST(Shadow, ARunWithTheShadowIsTheSameOnAnyThreadsAndPath) {
  const Parameters p = ParameterBuilder("reference").build();
  RunRequest request;
  request.omega_min = 0.1;
  request.omega_max = 75;
  request.realizations = 24;
  request.seed = 13;
  request.threads = 1;
  request.simd = SimdPath::scalar;
  const RunResult scalar = run_spectrum(p, request);
  request.threads = 2;
  request.simd = SimdPath::automatic;
  const RunResult simd = run_spectrum(p, request);
  ASSERT_EQ(scalar.points.size(), simd.points.size());
  ASSERT_TRUE(scalar.sub_bands.front().shadow);
  for (std::size_t k = 0; k < scalar.points.size(); ++k) {
    EXPECT_EQ(scalar.points[k].C_x, simd.points[k].C_x) << scalar.points[k].omega;
    EXPECT_EQ(scalar.points[k].standard_error, simd.points[k].standard_error) << scalar.points[k].omega;
  }
}

}  // namespace
