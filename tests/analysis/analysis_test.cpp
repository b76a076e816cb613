// The measured-data path on a record slidespec makes itself: the reference case at
// alpha = 0.4 (the paper's Fig. 6 fit), read by a 1 kHz sensor of 0.5 um resolution, written
// as CSV and analysed back. Tolerances are 3 standard errors of the quantity checked.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {
namespace {

constexpr double kResolution = 0.5e-6;    // the paper's sensor [m]
constexpr double kSensorNoise = 0.25e-6;  // q/2: dithers the quantizer (docs/analysis.md)
constexpr double kTolerance = 3;          // standard errors

Parameters concrete_fit() { return ParameterBuilder("reference").set("alpha", "0.4").build(); }

/// The record once per test binary: 1000 s at 1 kHz, through CSV in um and back.
const Record& sensor_record() {
  static const Record record = [] {
    SensorRequest sensor;
    sensor.sample_interval = 1e-3;
    sensor.duration = 1000;
    sensor.resolution = kResolution;
    sensor.sensor_noise = kSensorNoise;
    sensor.seed = 1;
    std::istringstream csv(record_csv(synthesize_record(concrete_fit(), sensor), LengthUnit::um, "synthetic"));
    RecordFormat format;
    format.unit = LengthUnit::um;
    return read_record(csv, "synthetic.csv", format);
  }();
  return record;
}

const RecordSpectrum& sensor_spectrum() {
  static const RecordSpectrum spectrum = [] {
    AnalysisRequest request;
    request.resolution = kResolution;
    request.sensor_noise = kSensorNoise;
    return analyze_record(sensor_record(), request);
  }();
  return spectrum;
}

/// The omega^-4 band of the model (5 v/a to omega_c/3) where the data are usable.
std::pair<double, double> omega4_band() {
  const Landmarks l = landmarks(concrete_fit());
  return {std::max(5 * l.renewal_rate, sensor_spectrum().usable_low),
          std::min(l.omega_c / 3, sensor_spectrum().usable_high)};
}

TEST(SensorRecord, CsvRoundTripKeepsSamplingAndReadings) {
  const Record& r = sensor_record();
  EXPECT_EQ(r.displacement.size(), 1000001u);
  EXPECT_NEAR(r.dt, 1e-3, 1e-12);
  for (std::size_t n = 0; n < r.displacement.size(); n += 9973) {
    const double steps = r.displacement[n] / kResolution;
    EXPECT_NEAR(steps, std::round(steps), 1e-6) << "reading " << n << " is not a whole number of steps";
  }
}

TEST(SensorRecord, MeanSpeedIsTheCasesWithinItsError) {
  const SlidingFit& fit = sensor_spectrum().sliding;
  ASSERT_GT(fit.v_error, 0);
  EXPECT_NEAR(fit.v, concrete_fit().v, kTolerance * fit.v_error);
  // The error of v comes from diffusion, 2 D / T for the mean speed over T; blocks see it.
  const double diffusive = std::sqrt(2 * landmarks(concrete_fit()).diffusion / sensor_spectrum().duration);
  EXPECT_GT(fit.v_error, diffusive / 3);
  EXPECT_LT(fit.v_error, diffusive * 3);
}

TEST(SensorRecord, FloorIsWhereQuantizationAndSensorNoisePutIt) {
  const RecordSpectrum& s = sensor_spectrum();
  const double white = (kResolution * kResolution / 12 + kSensorNoise * kSensorNoise) * s.dt / (2 * std::numbers::pi);
  const std::vector<double> model = model_spectrum(s, concrete_fit());
  // Points where the motion is below a thousandth of the floor measure the floor alone.
  double sum = 0, weight = 0;
  int points = 0;
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const AnalysisPoint& p = s.points[k];
    EXPECT_NEAR(p.noise_floor, white, 1e-4 * white);  // the smoothing correction's residue
    if (model[k] > 1e-3 * p.noise_floor) continue;
    const double w = std::pow(p.noise_floor / p.standard_error, 2);
    sum += w * p.C_x / p.noise_floor;
    weight += w;
    ++points;
  }
  ASSERT_GE(points, 5);
  EXPECT_NEAR(sum / weight, 1.0, kTolerance / std::sqrt(weight)) << points << " floor points";
  EXPECT_TRUE(s.usable_high_set_by_floor);
  EXPECT_GT(s.top_to_floor, 0.5);
  EXPECT_FALSE(s.floor_above_spectrum);
  EXPECT_FALSE(s.readings_off_grid);  // read through CSV in um, still whole steps of q
}

// A resolution coarser than the sensor's: its steps are not whole multiples of it, and a
// floor far above the spectrum is said to be so.
TEST(SensorRecord, AResolutionTheReadingsDoNotFollowIsSaid) {
  AnalysisRequest request;
  request.resolution = 1.3 * kResolution;
  EXPECT_TRUE(analyze_record(sensor_record(), request).readings_off_grid);
  request.resolution = 1e6 * kResolution;
  const RecordSpectrum s = analyze_record(sensor_record(), request);
  EXPECT_TRUE(s.floor_above_spectrum);
  EXPECT_FALSE(s.usable_high > s.usable_low);
}

TEST(SensorRecord, SlopeIsMinusFourInTheOmega4Band) {
  const auto [low, high] = omega4_band();
  const SlopeFit fit = fit_slope(sensor_spectrum(), low, high);
  ASSERT_GE(fit.points, 5);
  // The same fit on the model seen through the estimator (plus the floor): the exact model
  // is omega^-4 only asymptotically, so this says how far -4 is from the target at all.
  RecordSpectrum model = sensor_spectrum();
  const std::vector<double> values = model_spectrum(model, concrete_fit());
  for (std::size_t k = 0; k < values.size(); ++k) model.points[k].C_x = values[k] + model.points[k].noise_floor;
  const double model_slope = fit_slope(model, low, high).slope;
  EXPECT_NEAR(model_slope, -4, fit.slope_error / 2) << "the model's own slope in the band";
  EXPECT_NEAR(fit.slope, -4, kTolerance * fit.slope_error);
  EXPECT_NEAR(fit.force_slope(), 0, kTolerance * fit.slope_error);
  EXPECT_LT(fit.slope_error, 0.1) << "the record is too short to tell -4 from -4.75";
}

TEST(SensorRecord, AlphaIsRecoveredWithinItsError) {
  const auto [low, high] = omega4_band();
  Parameters unit = concrete_fit();
  unit.alpha = 1;  // the fit must not depend on the case's own alpha
  const AlphaFit fit = fit_alpha(sensor_spectrum(), unit, low, high);
  ASSERT_GE(fit.points, 5);
  EXPECT_NEAR(fit.alpha, 0.4, kTolerance * fit.alpha_error);
  EXPECT_LT(fit.alpha_error, 0.02);
  EXPECT_LT(fit.chi2_per_dof, 4);
}

// Few contacts and strong noise (N = 6, alpha = 1.2: eps = 0.2). In the omega^-4 band the
// spectrum sits 1/(1 + eps^2/2) below the first order (docs/model.md §7), so a first-order fit
// finds alpha / sqrt(1 + eps^2/2), 1% low; the second-order fit finds alpha. A record of
// 2e4 s at 100 Hz (exact sensor) gives alpha to 0.16%, so the bias is 6 standard errors.
TEST(AlphaFit, TheSecondOrderFitRemovesTheFirstOrdersBias) {
  const Parameters p = ParameterBuilder("reference").set("N", "6").set("alpha", "1.2").build();
  const double eps = landmarks(p).coupling_eps;
  ASSERT_NEAR(eps, 0.2, 1e-9);
  SensorRequest sensor;
  sensor.sample_interval = 0.01;
  sensor.duration = 2e4;
  sensor.resolution = 0;
  sensor.sensor_noise = 0;
  sensor.seed = 3;
  const RecordSpectrum spectrum = analyze_record(synthesize_record(p, sensor), AnalysisRequest{});
  const auto [low, high] = default_alpha_band(spectrum, p);
  const AlphaFit first = fit_alpha(spectrum, p, low, high, ModelOrder::first);
  const AlphaFit second = fit_alpha(spectrum, p, low, high, ModelOrder::best);
  EXPECT_EQ(first.theory_order, 1);
  EXPECT_EQ(second.theory_order, 2);
  ASSERT_LT(second.alpha_error, 0.003);
  EXPECT_NEAR(second.alpha, 1.2, kTolerance * second.alpha_error);
  EXPECT_NEAR(first.alpha, 1.2 / std::sqrt(1 + eps * eps / 2), kTolerance * first.alpha_error);
  EXPECT_GT(1.2 - first.alpha, kTolerance * first.alpha_error);
  EXPECT_LT(second.chi2_per_dof, 4);
}

TEST(SlopeFit, ExactPowerLawGivesItsExponentAndTheTextbookError) {
  RecordSpectrum s;
  const double relative = 0.05;
  for (int k = 0; k < 9; ++k) {
    const double omega = std::pow(10.0, k / 8.0);
    const double C = 1e-12 * std::pow(omega, -4.75);
    s.points.push_back({omega, C, relative * C, 0, 100, 0.1, false});
  }
  s.usable_low = 1, s.usable_high = 10;
  const SlopeFit fit = fit_slope(s, 1, 10);
  EXPECT_NEAR(fit.slope, -4.75, 1e-12);
  EXPECT_NEAR(fit.amplitude, 1e-12, 1e-24);
  // var(b) = sigma^2 / sum (u - mean u)^2 for equal weights.
  double mean = 0, spread = 0;
  for (const auto& p : s.points) mean += std::log(p.omega) / 9;
  for (const auto& p : s.points) spread += std::pow(std::log(p.omega) - mean, 2);
  EXPECT_NEAR(fit.slope_error, relative / std::sqrt(spread), 1e-12);
  EXPECT_FALSE(fit.reaches_floor);
}

// --- reading: what a lab's files look like, and every way one can be wrong ---

Record read(const std::string& text, RecordFormat format = {}) {
  std::istringstream in(text);
  return read_record(in, "rec.csv", format);
}

/// The one-line error, which must name the line.
std::string refusal(const std::string& text, RecordFormat format = {}) {
  try {
    read(text, format);
  } catch (const InputError& e) {
    const std::string message = worded(e.what(), FrontEnd::command_line);
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return "";
}

TEST(ReadRecord, CommentsHeaderWhitespaceAndUnits) {
  RecordFormat mm;
  mm.unit = LengthUnit::mm;
  const Record r = read("# sensor log\r\n\n  time ; x ; force\r\n0.0; 1.0 ;7\n0.5;1.5;7 # ok\n1.0;2.5;7\n", mm);
  EXPECT_EQ(r.column, "x");
  EXPECT_DOUBLE_EQ(r.dt, 0.5);
  ASSERT_EQ(r.displacement.size(), 3u);
  EXPECT_DOUBLE_EQ(r.displacement[2], 2.5e-3);

  const Record tabs = read("t\tpos\n0\t1\n0.1\t2\n0.2\t4\n");  // the only non-time column
  EXPECT_EQ(tabs.column, "pos");
  RecordFormat fixed;
  fixed.dt = 0.01;
  const Record bare = read("1e-6\n  2e-6\n+3e-6\n", fixed);  // no header, one column
  EXPECT_DOUBLE_EQ(bare.dt, 0.01);
  EXPECT_DOUBLE_EQ(bare.displacement[2], 3e-6);
  const Record pairs = read("0 5\n1 6\n2 7\n");  // no header, two columns: t and x
  EXPECT_DOUBLE_EQ(pairs.dt, 1);
  EXPECT_DOUBLE_EQ(pairs.displacement[1], 6);
}

TEST(ReadRecord, RefusesEachMalformedFileNamingTheLine) {
  RecordFormat wants_x;
  wants_x.column = "x";
  const auto names = [](const std::string& message, const std::string& what) {
    return message.find(what) != std::string::npos;
  };
  EXPECT_PRED2(names, refusal("# log\nt,y\n0,1\n1,2\n", wants_x), "line 2: --column: no column 'x'");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,2\n2,abc\n"), "line 4: column x: 'abc' is not a number");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,1.5e-3mm\n"), "line 3: column x: '1.5e-3mm' is not a number");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,NaN\n"), "line 3: column x: 'NaN' is not a finite number");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,\n"), "line 3: column x is empty");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,2\n0.5,3\n"), "line 4: time");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,2\n1,3\n"), "line 4: time");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,2\n2,3\n4,4\n"), "line 5: sampling is not uniform");
  EXPECT_PRED2(names, refusal("t,x\n0,1\n1,2\n2,3,4\n"), "line 4: 3 fields, expected 2");
  EXPECT_PRED2(names, refusal("t,x\n\n0,1\n"), "line 3: the only sample");
  EXPECT_PRED2(names, refusal("t,x\n"), "no data lines");
  EXPECT_PRED2(names, refusal("a,b,c\n0,1,2\n"), "line 1: no time column");
  // A binary file is named as such, its bytes not echoed back as a header.
  EXPECT_PRED2(names,
               refusal(std::string("\x7f"
                                   "ELF\x02\x01\x00\x00,x\n0,1\n",
                                   14)),
               "line 1: a control byte (0x02) at character 5: not a text record");
  EXPECT_PRED2(names,
               refusal("t,x\n0,1\n1,\x1b"
                       "2\n"),
               "line 3: a control byte (0x1b)");
  // A slow drift of the clock: refused with --resample off, interpolated (and said so) by default.
  std::string drifting = "t,x\n";
  for (int n = 0; n < 200; ++n) drifting += std::to_string(n * (1 + 0.0002 * n)) + ",0\n";
  RecordFormat off;
  off.resample = Resampling::off;
  EXPECT_PRED2(names, refusal(drifting, off), "sampling is not uniform");
  const Record resampled = read(drifting);
  EXPECT_TRUE(resampled.resampled);
  ASSERT_EQ(resampled.notes.size(), 1u);
}

// Numbers handed over by a program (the Python module) pass the checks a file passes.
TEST(ReadRecord, SamplesAsNumbersAreReadAsTheirFileIs) {
  RecordFormat mm;
  mm.unit = LengthUnit::mm;
  const Record file = read("t,x\n0.5,1.0\n1.0,1.5\n1.5,2.5\n", mm);
  const Record numbers = record_from_samples({0.5, 1.0, 1.5}, {1.0, 1.5, 2.5}, mm);
  EXPECT_EQ(numbers.displacement, file.displacement);
  EXPECT_EQ(numbers.dt, file.dt);
  EXPECT_EQ(numbers.start_time, file.start_time);
  RecordFormat fixed;
  fixed.dt = 0.01;
  EXPECT_EQ(record_from_samples({}, {1, 2, 3}, fixed).dt, 0.01);
  const auto refused = [](const std::vector<double>& t, const std::vector<double>& x, const std::string& what) {
    try {
      record_from_samples(t, x, {});
    } catch (const InputError& e) {
      return worded(e.what(), FrontEnd::command_line).find(what) != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(refused({0, 1, 2, 4}, {0, 0, 0, 0}, "record: sample 3: sampling is not uniform"));
  EXPECT_TRUE(refused({0, 1, 1}, {0, 0, 0}, "sample 2: time"));
  EXPECT_TRUE(refused({0, 1, 2}, {0, NAN, 0}, "sample 1: x is not a finite number"));
  EXPECT_TRUE(refused({0, 1}, {0, 1, 2}, "2 times for 3 samples"));
  EXPECT_TRUE(refused({}, {0, 1, 2}, "give the sample times or a positive dt"));
  EXPECT_TRUE(refused({0}, {0}, "many samples"));
}

}  // namespace
}  // namespace slidespec
