// The joint fit of model parameters on a machine-driven record: synthetic records of a
// spring-driven slider with known alpha and a, read by a sensor with white noise, fitted
// back from wrong starting values. Tolerances are 3 standard errors of the quantity checked.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "analysis/report.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {
namespace {

constexpr double kTolerance = 3;  // standard errors
constexpr double kDt = 0.02;      // [s]: Nyquist 157 rad/s, below omega_c = 548 rad/s
constexpr double kAlpha = 0.5, kA = 1e-3;

// The reference slider pulled through a spring of 1e3 N/m: flat below omega_s = 0.1 rad/s,
// the renewal corner at v/a = 0.5 rad/s, omega^-4 above it (eps 0.037: first order holds).
Parameters machine() {
  return ParameterBuilder("reference")
      .set("drive", "spring")
      .set("k_drive", "1e3")
      .set("alpha", "0.5")
      .set("a", "1e-3")
      .build();
}

/// White sensor noise whose floor meets the model at 40 rad/s: the top of the band is the
/// sensor's, as on a real record.
double sensor_noise() {
  static const double sigma = [] {
    const double level = exact_spectrum(machine(), {40.0}).front();
    return std::sqrt(2 * std::numbers::pi * level / kDt);
  }();
  return sigma;
}

RecordSpectrum record_spectrum(double duration, std::uint64_t seed, bool floor_given = false) {
  SensorRequest sensor;
  sensor.sample_interval = kDt;
  sensor.duration = duration;
  sensor.resolution = 0;
  sensor.sensor_noise = sensor_noise();
  sensor.seed = seed;
  AnalysisRequest request;
  if (floor_given) request.sensor_noise = sensor_noise();
  return analyze_record(synthesize_record(machine(), sensor), request);
}

/// The fit of alpha and a from a start a factor 2 and 3 away.
ModelFit fit(const RecordSpectrum& s) {
  Parameters start = machine();
  start.alpha = 2 * kAlpha;
  start.a = 3 * kA;
  return fit_model(s, start, {"alpha", "a"}, s.points.front().omega, s.points.back().omega);
}

TEST(ModelFit, RecoversAlphaAandTheFloorWithinTheirErrors) {
  const RecordSpectrum s = record_spectrum(2000, 1);
  const ModelFit f = fit(s);
  ASSERT_EQ(f.names, (std::vector<std::string>{"alpha", "a", "floor"}));
  EXPECT_TRUE(f.converged);
  EXPECT_LT(f.chi2_per_dof, 2) << f.dof << " dof";
  EXPECT_NEAR(f.values[0], kAlpha, kTolerance * f.errors[0]);
  EXPECT_NEAR(f.values[1], kA, kTolerance * f.errors[1]);
  const double floor = sensor_noise() * sensor_noise() * kDt / (2 * std::numbers::pi);
  EXPECT_NEAR(f.floor, floor, kTolerance * f.floor_error);
  EXPECT_LT(f.errors[0], 0.05 * kAlpha);
  EXPECT_LT(f.errors[1], 0.2 * kA);
  EXPECT_NEAR(f.amplitude, kAlpha * kAlpha / 30, kTolerance * f.amplitude_error);
  EXPECT_EQ(f.undetermined.find("alpha is not determined"), std::string::npos) << f.undetermined;
  EXPECT_NE(f.undetermined.find("N and alpha are not separated"), std::string::npos) << f.undetermined;
  // Every real parameter but the fitted ones and eta1 (which v gives), the spring's too.
  EXPECT_NE(f.undetermined.find("held at the case's values, not measured by this fit: M, m, k0, k1, eta0, v, "
                                "F_drive, F_kin, k_drive"),
            std::string::npos)
      << f.undetermined;
  for (double r : f.residuals) {
    if (std::isfinite(r)) {
      EXPECT_LT(std::fabs(r), 5);
    }
  }
}

// The errors are the scatter's: (fitted - true) / error over seeds has unit rms for both
// parameters over 24 records of 600 s.
TEST(ModelFit, ErrorsMatchTheScatterOverSeeds) {
  constexpr int kSeeds = 24;
  double sum2 = 0;
  int count = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const ModelFit f = fit(record_spectrum(600, 100 + seed));
    ASSERT_TRUE(f.converged) << "seed " << seed;
    sum2 += std::pow((f.values[0] - kAlpha) / f.errors[0], 2) + std::pow((f.values[1] - kA) / f.errors[1], 2);
    count += 2;
  }
  // Measured: 1.13 (alpha 1.09, a 1.18); a variance twice or half as large gives 0.80 or 1.60.
  const double rms = std::sqrt(sum2 / count);
  EXPECT_GT(rms, 0.85) << "errors too large for the scatter";
  EXPECT_LT(rms, 1.4) << "errors too small for the scatter";
}

TEST(ModelFit, AGivenFloorIsHeldNotFitted) {
  const RecordSpectrum s = record_spectrum(1000, 7, true);
  const ModelFit f = fit(s);
  ASSERT_EQ(f.names, (std::vector<std::string>{"alpha", "a"}));
  EXPECT_TRUE(f.floor_given);
  EXPECT_DOUBLE_EQ(f.floor, s.points.front().noise_floor);
  EXPECT_NEAR(f.values[0], kAlpha, kTolerance * f.errors[0]);
}

// Above v/a and below omega_c the spectrum is alpha^2 v/a times a shape: alpha and a only as
// alpha^2/a, and the fit says so.
TEST(ModelFit, SaysWhatABandAboveTheRenewalCornerCannotDetermine) {
  const RecordSpectrum s = record_spectrum(1000, 3);
  Parameters start = machine();
  const ModelFit f = fit_model(s, start, {"alpha", "a"}, 5, 30);
  EXPECT_NE(f.undetermined.find("only a combination of alpha and a"), std::string::npos) << f.undetermined;
}

// A singular covariance leaves the errors NaN (or inf): said as such, not as "relative error -nan".
TEST(ModelFit, AnErrorThatIsNotANumberIsSaidToBeASingularCovariance) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double error : {nan, -nan, std::numeric_limits<double>::infinity()}) {
    const std::string said = detail::undetermined_parameter("k0", 2, error);
    EXPECT_EQ(said, "k0 is not determined by the band (singular covariance: the band does not depend on it)");
  }
  EXPECT_EQ(detail::undetermined_parameter("a", 2, 0.99), "");
  EXPECT_EQ(detail::undetermined_parameter("a", 2, 1.5), "a is not determined by the band (relative error 0.75)");
}

TEST(ModelFit, RecordModelDrivesTheCaseAsTheMachineDoes) {
  std::vector<std::string> notes;
  const Parameters p = record_model("reference", {"alpha=0.3"}, 2e-6, 5e7, notes);
  EXPECT_EQ(p.drive, Drive::spring);
  EXPECT_DOUBLE_EQ(p.k_drive, 5e7);
  EXPECT_DOUBLE_EQ(p.v, 2e-6);
  EXPECT_DOUBLE_EQ(p.alpha, 0.3);
  EXPECT_EQ(notes.size(), 2u);
  notes.clear();
  const Parameters kept = record_model("reference", {"v=1e-3", "drive=spring", "k_drive=10"}, 2e-6, 5e7, notes);
  EXPECT_DOUBLE_EQ(kept.v, 1e-3);
  EXPECT_DOUBLE_EQ(kept.k_drive, 10);
  EXPECT_TRUE(notes.empty());
  EXPECT_THROW(parse_fit_parameters("alpha,alfa"), InputError);
  EXPECT_THROW(parse_fit_parameters("alpha,alpha"), InputError);
  EXPECT_EQ(parse_fit_parameters("alpha,a"), (std::vector<std::string>{"alpha", "a"}));
}

// Over the default band, the usable one, a record with none is refused saying so, as the
// alpha fit is, not as a malformed --fit-band.
TEST(ModelFit, NoUsableBandIsSaidAsSuch) {
  SensorRequest sensor;
  sensor.sample_interval = kDt;
  sensor.duration = 200;
  sensor.resolution = 0;
  sensor.sensor_noise = sensor_noise();
  AnalysisRequest request;
  request.sensor_noise = 1e4 * sensor_noise();  // a floor far above the spectrum
  const RecordSpectrum s = analyze_record(synthesize_record(machine(), sensor), request);
  ASSERT_FALSE(s.usable_high > s.usable_low);
  for (const auto& names : {std::vector<std::string>{"alpha"}, std::vector<std::string>{"alpha", "a"}}) {
    try {
      fit_model(s, machine(), names, s.usable_low, s.usable_high);
      ADD_FAILURE() << "a fit over no usable band was made";
    } catch (const InputError& e) {
      const std::string message = worded(e.what(), FrontEnd::command_line);
      EXPECT_NE(message.find("no usable band (the sensor floor exceeds 10% of the spectrum"), std::string::npos)
          << message;
      EXPECT_EQ(message.find("need 0 < LO < HI"), std::string::npos) << message;
    }
  }
  try {
    default_alpha_band(s, machine());
    ADD_FAILURE() << "an alpha band over no usable band";
  } catch (const InputError& e) {
    EXPECT_EQ(worded(e.what(), FrontEnd::command_line).rfind("--fit alpha: no usable band (", 0), 0u) << e.what();
  }
  EXPECT_THROW(fit_model(s, machine(), {"alpha"}, 5, 3), InputError);  // a band given wrongly
}

// A force channel is compared with the spring's force k_drive^2 C_x; a constant force has none.
TEST(ModelFit, AForceIsComparedWithTheSpringsForce) {
  RecordSpectrum s = record_spectrum(200, 5);
  const std::vector<double> displacement = model_spectrum(s, machine());
  s.observable = Observable::force;
  const std::vector<double> force = model_spectrum(s, machine());
  for (std::size_t k = 0; k < force.size(); ++k) EXPECT_DOUBLE_EQ(force[k], 1e6 * displacement[k]);
  EXPECT_THROW(model_spectrum(s, ParameterBuilder("reference").build()), InputError);
}

}  // namespace
}  // namespace slidespec
