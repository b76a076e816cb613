// Records as labs write them: irregular sample times, a rate that changes inside the record,
// velocity steps (units and force channels: channels_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <complex>
#include <numbers>
#include <random>
#include <tuple>

#include "analysis/report.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"

namespace slidespec {
namespace {

constexpr double kDt = 0.136;      // [s], the sepiolite record's median interval
constexpr double kJitter = 0.2;    // sample times k dt + U(-0.2, 0.2) dt: intervals 0.6..1.4 dt
constexpr int kFine = 20;          // the process lives on a grid 20 times finer
constexpr double kTau = 10 * kDt;  // correlation time of each of two cascaded relaxations
// The mean sliding v t: between samples a slider moves more than it fluctuates (the process's
// rms is ~1400 here), a ramp that linear interpolation carries exactly and a nearest-sample
// pick turns into a sawtooth of v times the time error.
constexpr double kSlide = 2000 / kDt;

/// v t plus a smooth process (two cascaded first-order relaxations, C ~ omega^-4 above 1/tau)
/// on the fine grid, read at irregular times by the nearest fine point (an error of dt/40).
struct IrregularRecord {
  std::vector<double> time, x;
};

IrregularRecord irregular(std::size_t samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> e;
  std::uniform_real_distribution<double> offset(-kJitter, kJitter);
  const double h = kDt / kFine, phi = std::exp(-h / kTau);
  std::vector<double> fine((samples + 2) * kFine);
  double y = 0, z = 0;
  for (int burn = 0; burn < 200 * kFine; ++burn) y = phi * y + e(rng), z = phi * z + y;
  for (double& f : fine) y = phi * y + e(rng), z = phi * z + y, f = z;
  IrregularRecord r;
  for (std::size_t k = 0; k < samples; ++k) {
    const double t = (double(k) + 1 + offset(rng)) * kDt;
    r.time.push_back(t);
    r.x.push_back(kSlide * t + fine[std::size_t(std::lround(t / h))]);
  }
  return r;
}

/// The fine process's spectrum folded onto the record's band (docs/model.md §3, unit
/// innovations): the 20 aliases of omega that the fine band holds once each.
double irregular_spectrum(double omega) {
  const double h = kDt / kFine, phi = std::exp(-h / kTau);
  double sum = 0;
  for (int m = -kFine / 2; m < kFine / 2; ++m) {
    const double w = omega + 2 * std::numbers::pi * m / kDt;
    sum += h / (2 * std::numbers::pi) / std::pow(std::norm(1.0 - phi * std::polar(1.0, -w * h)), 2);
  }
  return sum;
}

TEST(Resampling, IrregularRecordIsInterpolatedAndWithinItsErrorBarsBelowTheCut) {
  int inside = 0, points = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const IrregularRecord r = irregular(3900, seed);
    const Record record = record_from_samples(r.time, r.x, {});
    ASSERT_TRUE(record.resampled);
    ASSERT_FALSE(record.notes.empty());
    EXPECT_NE(record.notes.front().find("linear interpolation"), std::string::npos) << record.notes.front();
    EXPECT_NEAR(record.dt, kDt, 0.01 * kDt);
    AnalysisRequest request;
    const RecordSpectrum s = analyze_record(record, request);
    EXPECT_TRUE(s.top_set_by_interpolation);
    EXPECT_LE(s.points.back().omega, record.interpolation_cut);
    // The mean sliding v t removed by analyze is a line; its spectrum is below the lowest point.
    const std::vector<double> truth = expected_points(s, irregular_spectrum);
    for (std::size_t k = 0; k < s.points.size(); ++k, ++points)
      inside += truth[k] >= s.points[k].lower && truth[k] <= s.points[k].upper ? 1 : 0;
  }
  EXPECT_GE(double(inside) / points, 0.85) << inside << " of " << points;
}

TEST(Resampling, GapsAreRefusedNamingTheOptionAndJitterCanBeRefused) {
  std::vector<double> t, x;
  for (int k = 0; k < 200; ++k) t.push_back(k < 100 ? k : k + 2), x.push_back(0);
  try {
    record_from_samples(t, x, {});
    FAIL() << "a gap of 3 intervals was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(worded(e.what(), FrontEnd::command_line).find("--resample median"), std::string::npos) << e.what();
    EXPECT_NE(worded(e.what(), FrontEnd::command_line).find("gap"), std::string::npos) << e.what();
  }
  RecordFormat median;
  median.resample = Resampling::median;
  EXPECT_TRUE(record_from_samples(t, x, median).resampled);
  const IrregularRecord r = irregular(500, 1);
  RecordFormat off;
  off.resample = Resampling::off;
  EXPECT_THROW(record_from_samples(r.time, r.x, off), InputError);
  RecordFormat loose;
  loose.resample = Resampling::off;
  loose.time_tolerance = 0.49;
  const Record accepted = record_from_samples(r.time, r.x, loose);
  EXPECT_FALSE(accepted.resampled);
  ASSERT_FALSE(accepted.notes.empty());
  EXPECT_NE(accepted.notes.front().find("treated as uniform"), std::string::npos);
}

/// Follows every option a refusal of `format` suggests (--time-tolerance X, --window A:B,
/// --resample median): each must be accepted. Returns the refusal's message.
std::string follow_the_advice(const std::vector<double>& t, const std::vector<double>& x, const RecordFormat& format) {
  std::string message;
  try {
    record_from_samples(t, x, format);
    ADD_FAILURE() << "accepted";
    return message;
  } catch (const InputError& e) {
    message = worded(e.what(), FrontEnd::command_line);
  }
  if (const auto at = message.find("--time-tolerance "); at != std::string::npos) {
    RecordFormat loose = format;
    loose.time_tolerance = std::stod(message.substr(at + 17));
    EXPECT_NO_THROW(record_from_samples(t, x, loose)) << message;
  }
  if (const auto at = message.find("--window "); at != std::string::npos) {
    std::size_t used = 0;
    RecordFormat window = format;
    const double t0 = std::stod(message.substr(at + 9), &used);
    window.window = {{t0, std::stod(message.substr(at + 9 + used + 1))}};
    EXPECT_NO_THROW(record_from_samples(t, x, window)) << message;
  }
  EXPECT_NE(message.find("--resample median"), std::string::npos) << message;
  RecordFormat median = format;
  median.resample = Resampling::median;
  EXPECT_NO_THROW(record_from_samples(t, x, median)) << message;
  return message;
}

TEST(Resampling, ARefusalSuggestsOnlyWhatWouldBeAccepted) {
  // An 11 s gap in a record every second: a tolerance of 11 would be refused; the stretch
  // before it, or interpolation, is accepted.
  std::vector<double> t, x;
  for (int k = 0; k < 3000; ++k) t.push_back(k + (k >= 1700 ? 11 : 0)), x.push_back(1e-6 * t.back());
  std::string message = follow_the_advice(t, x, {});
  EXPECT_EQ(message.find("--time-tolerance"), std::string::npos) << message;
  EXPECT_NE(message.find("--window 0:1699"), std::string::npos) << message;
  // Intervals of 0.4..1.6 s: a tolerance of 0.61 would be refused.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> interval(0.4, 1.6);
  t = {0};
  for (int k = 1; k < 3000; ++k) t.push_back(t.back() + interval(rng));
  message = follow_the_advice(t, x, {});
  EXPECT_EQ(message.find("--time-tolerance"), std::string::npos) << message;
  // Intervals of 0.8..1.2 s, refused with --resample off: a tolerance of 0.21 is accepted.
  std::uniform_real_distribution<double> small(0.8, 1.2);
  t = {0};
  for (int k = 1; k < 3000; ++k) t.push_back(t.back() + small(rng));
  RecordFormat off;
  off.resample = Resampling::off;
  message = follow_the_advice(t, x, off);
  EXPECT_NE(message.find("--time-tolerance 0.2"), std::string::npos) << message;
  // A tolerance the reader cannot take is refused naming the option.
  RecordFormat wide;
  wide.time_tolerance = 0.61;
  try {
    record_from_samples(t, x, wide);
    ADD_FAILURE() << "a time tolerance of 0.61 was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(worded(e.what(), FrontEnd::command_line).rfind("--time-tolerance:", 0), 0u) << e.what();
  }
}

/// A record at 0.1 s (`coarse` samples at 3 um/s), then at 0.01 s (`fine` samples at 10 um/s),
/// as the basalt record; plus a random walk of `walk` [m] a sample.
std::pair<std::vector<double>, std::vector<double>> two_rates(int coarse = 600, int fine = 3000, double walk = 0) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0, 1);
  std::vector<double> t{0}, x{0};
  for (int k = 1; k < coarse + fine; ++k) {
    const double interval = k < coarse ? 0.1 : 0.01, speed = k < coarse ? 3e-6 : 1e-5;
    t.push_back(t.back() + interval);
    x.push_back(x.back() + speed * interval + walk * noise(rng));
  }
  return {t, x};
}

TEST(Resampling, ARateChangeIsReportedAndTheLongestPartOrTheWindowAnalyzed) {
  const auto [t, x] = two_rates();
  const Record longest = record_from_samples(t, x, {});
  ASSERT_EQ(longest.parts.size(), 2u);
  EXPECT_NEAR(longest.parts[0].interval, 0.1, 1e-9);
  EXPECT_NEAR(longest.parts[1].interval, 0.01, 1e-9);
  EXPECT_NEAR(longest.dt, 0.1, 1e-9);  // 60 s at 0.1 s against 30 s at 0.01 s
  EXPECT_NE(longest.notes.front().find("longest part in time"), std::string::npos) << longest.notes.front();
  EXPECT_NE(longest.notes.front().find("holds the most samples (3000)"), std::string::npos) << longest.notes.front();
  RecordFormat after;
  after.window = {{61, 89}};
  const Record part = record_from_samples(t, x, after);
  EXPECT_NEAR(part.dt, 0.01, 1e-9);
  EXPECT_NEAR(part.start_time, 61, 1e-9);
  RecordFormat across;
  across.window = {{30, 80}};
  EXPECT_THROW(record_from_samples(t, x, across), InputError);
}

// Resampled, a record's band stops where interpolation filters the coarsest input interval of
// the stretch analysed: acos(0.85) / 0.1 s = 5.5 rad/s in the 0.1 s part, not the 55 rad/s of
// the 0.01 s median, which would give points beyond the 0.1 s samples' own Nyquist.
TEST(Resampling, TheCutFollowsTheCoarsestIntervalOfTheStretchAnalysed) {
  const double coarse_cut = std::acos(0.85) / 0.1, fine_cut = std::acos(0.85) / 0.01;
  const auto [t, x] = two_rates(600, 3000, 1e-8);
  RecordFormat median;
  median.resample = Resampling::median;
  const Record whole = record_from_samples(t, x, median);
  ASSERT_NEAR(whole.dt, 0.01, 1e-9);
  EXPECT_NEAR(whole.interpolation_interval, 0.1, 1e-9);
  EXPECT_NEAR(whole.interpolation_cut, coarse_cut, 1e-6);
  ASSERT_FALSE(whole.notes.empty());
  EXPECT_NE(whole.notes.back().find("input interval 0.1 s"), std::string::npos) << whole.notes.back();
  const RecordSpectrum s = analyze_record(whole, {});
  EXPECT_TRUE(s.top_set_by_interpolation);
  EXPECT_LE(s.points.back().omega, coarse_cut);
  // A stretch of the resampled record, and a --window as read: the parts each overlaps.
  for (const auto& [start, end, cut] :
       {std::tuple{10.0, 50.0, coarse_cut}, std::tuple{50.0, 70.0, coarse_cut}, std::tuple{61.0, 89.0, fine_cut}}) {
    EXPECT_NEAR(record_window(whole, start, end).interpolation_cut, cut, 1e-6) << start << ".." << end;
    RecordFormat window = median;
    window.window = {{start, end}};
    EXPECT_NEAR(record_from_samples(t, x, window).interpolation_cut, cut, 1e-6) << start << ".." << end;
  }
  // The longest steady segment in the finer part: its own cut, said in a note.
  const auto [later_t, later_x] = two_rates(300, 6000, 1e-8);
  const Record later = record_from_samples(later_t, later_x, median);
  EXPECT_NEAR(later.interpolation_cut, coarse_cut, 1e-6);
  std::vector<std::string> notes;
  const Record segment = longest_steady(later, steady_segments(later), notes);
  EXPECT_GT(segment.start_time, 29.9);  // the 0.1 s part ends at 29.9 s
  EXPECT_NEAR(segment.interpolation_cut, fine_cut, 1e-6);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.back().find("input interval 0.01 s"), std::string::npos) << notes.back();
}

TEST(Segments, AVelocityStepAndAHoldSplitTheRecord) {
  // 0.2 um/s for 400 s, a hold of 200 s, 2 um/s for 600 s, every 0.1 s, with 0.1 um noise.
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0, 0.1e-6);
  std::vector<double> t, x;
  double position = 0;
  for (int k = 0; k < 12000; ++k) {
    const double time = 0.1 * k;
    position += (time < 400 ? 0.2e-6 : time < 600 ? 0 : 2e-6) * 0.1;
    t.push_back(time), x.push_back(position + noise(rng));
  }
  std::vector<SteadySegment> segments;  // the steady ones, without the steps' transitions
  for (const SteadySegment& s : steady_segments(record_from_samples(t, x, {})))
    if (s.kind != SegmentKind::step) segments.push_back(s);
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_NEAR(segments[0].mean_speed, 0.2e-6, 0.02e-6);
  EXPECT_TRUE(segments[1].hold);
  EXPECT_NEAR(segments[2].mean_speed, 2e-6, 0.02e-6);
  const double block = 1200.0 / 48;  // boundaries within two blocks of the steps
  EXPECT_NEAR(segments[0].end, 400, 2 * block);
  EXPECT_NEAR(segments[2].start, 600, 2 * block);
}

TEST(Segments, ADriftlessRandomWalkIsOneSegment) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> step(0, 1e-7);
  std::vector<double> t, x;
  double position = 0;
  for (int k = 0; k < 3900; ++k) t.push_back(0.1 * k), x.push_back(position += step(rng));
  EXPECT_EQ(steady_segments(record_from_samples(t, x, {})).size(), 1u);
}

// A random walk of step s plus white noise of rms w, every dt: C = s^2 dt / (2 pi 4 sin^2(omega
// dt / 2)) + w^2 dt / (2 pi), a slope of -2 where 4 sin^2 ~ (omega dt)^2, written here exactly.
TEST(PowerLawFit, RandomWalkAndFloorAreRecoveredWithinTheirErrors) {
  constexpr double kStep = 1e-7, kWhite = 3e-7, kInterval = 0.1;
  int slope_inside = 0, floor_inside = 0;
  constexpr int kSeeds = 20;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> e;
    std::vector<double> t, x;
    double position = 0;
    for (int k = 0; k < 20000; ++k)
      t.push_back(kInterval * k), x.push_back((position += kStep * e(rng)) + kWhite * e(rng));
    const RecordSpectrum s = analyze_record(record_from_samples(t, x, {}), {});
    // The fit's band: up to a tenth of Nyquist, where the walk is omega^-2 to 1%.
    const PowerLawFit fit = fit_power_law(s, s.points.front().omega, 0.1 * std::numbers::pi / kInterval);
    EXPECT_FALSE(fit.floor_given);
    slope_inside += std::fabs(fit.slope + 2) < 2 * fit.slope_error ? 1 : 0;
    floor_inside += std::fabs(fit.floor - kWhite * kWhite * kInterval / (2 * std::numbers::pi)) < 2 * fit.floor_error;
    EXPECT_NEAR(fit.slope, -2, 0.2);
  }
  EXPECT_GE(slope_inside, kSeeds * 8 / 10);
  EXPECT_GE(floor_inside, kSeeds * 8 / 10);
}

/// A spectrum of points at omega = 1 .. 30 rad/s, each with a 10% error bar.
RecordSpectrum spectrum_of(const std::function<double(double)>& C) {
  RecordSpectrum s;
  for (double omega = 1; omega < 30; omega *= 1.3)
    s.points.push_back({.omega = omega,
                        .C_x = C(omega),
                        .standard_error = 0.1 * C(omega),
                        .noise_floor = 0,
                        .n_avg = 10,
                        .bandwidth = 0.3 * omega,
                        .below_floor = false});
  return s;
}

TEST(PowerLawFit, ASlopeAtTheEdgeOfItsSearchFailsLoudly) {
  // White but for the lowest point, a thousand times higher: no power law drops that fast,
  // so the steepest slope searched fits best and the band bounds nothing.
  const RecordSpectrum cliff = spectrum_of([](double omega) { return omega < 1.1 ? 1e-13 : 1e-16; });
  const PowerLawFit stuck = fit_power_law(cliff, 1, 30);
  EXPECT_LE(stuck.slope, kSteepestPowerLawSlope + 0.01);
  EXPECT_TRUE(stuck.slope_at_search_edge);
  const Verdict verdict = detail::judge_power_law(stuck);
  EXPECT_FALSE(verdict.ok);
  EXPECT_NE(verdict.reason.find("ran to the edge of its search range (-10 .. 2)"), std::string::npos) << verdict.reason;
  // An exact omega^-3 law over a floor is found, and judged a result.
  const RecordSpectrum law = spectrum_of([](double omega) { return 1e-14 * std::pow(omega, -3) + 1e-19; });
  const PowerLawFit found = fit_power_law(law, 1, 30);
  EXPECT_NEAR(found.slope, -3, 1e-3);
  EXPECT_FALSE(found.slope_at_search_edge);
  EXPECT_TRUE(detail::judge_power_law(found).ok) << detail::judge_power_law(found).reason;
}

TEST(PowerLawFit, AnUnboundedSlopeOrParametersNotToldApartFail) {
  PowerLawFit fit;
  fit.dof = 10, fit.chi2_per_dof = 1, fit.slope = -3, fit.slope_error = 0.5;
  for (int i = 0; i < 3; ++i) fit.correlation[i][i] = 1;
  EXPECT_TRUE(detail::judge_power_law(fit).ok);
  fit.slope_error = 8;  // -11 .. 5: the whole range searched
  EXPECT_NE(detail::judge_power_law(fit).reason.find("spans its whole search range"), std::string::npos);
  fit.slope_error = 0.5;
  fit.correlation[0][2] = fit.correlation[2][0] = -0.9999;  // A + floor where the slope is 0
  EXPECT_NE(detail::judge_power_law(fit).reason.find("the amplitude and the floor are not told apart"),
            std::string::npos)
      << detail::judge_power_law(fit).reason;
  fit.correlation[0][2] = fit.correlation[2][0] = std::nan("");
  EXPECT_FALSE(detail::judge_power_law(fit).ok);
}

}  // namespace
}  // namespace slidespec
