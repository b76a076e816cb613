// The segment finder on records made here of known holds, steps, loading and strokes, and the
// spectrum of their steady sliding against the noise put in.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "slidespec/analysis.hpp"

namespace slidespec {
namespace {

constexpr double kDt = 0.01;        // [s]
constexpr double kWalk = 2e-9;      // random walk step per sample [m]
constexpr double kWhiteRms = 2e-8;  // white sensor noise [m]

/// The noise put into every record: a random walk of step kWalk plus white noise of rms kWhiteRms,
/// whose spectrum (docs/model.md §3) sampled every kDt is exact.
double exact_noise(double omega) {
  const double s = 2 * std::sin(omega * kDt / 2);
  return (kWalk * kWalk / (s * s) + kWhiteRms * kWhiteRms) * kDt / (2 * std::numbers::pi);
}

/// x = the load point's path (speed `speed(t)` integrated) + the noise, every kDt up to `duration`.
template <class Speed>
Record make_record(double duration, Speed speed, std::uint64_t seed, std::vector<double>* force = nullptr,
                   const std::function<double(double)>& force_of_time = {}) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0, 1);
  std::vector<double> t, x;
  double path = 0, walk = 0;
  for (int k = 0; k * kDt < duration; ++k) {
    const double time = k * kDt;
    path += speed(time) * kDt;
    walk += kWalk * gauss(rng);
    t.push_back(time), x.push_back(path + walk + kWhiteRms * gauss(rng));
    if (force) force->push_back(force_of_time(time) + 0.01 * gauss(rng));
  }
  if (!force) return record_from_samples(t, x, {});
  RecordFormat format;
  format.observable = Observable::force;
  format.force_column = "F";
  return record_from_columns({"t", "x", "F [N]"}, {t, x, *force}, format);
}

/// The share of a spectrum's points whose bar holds the exact noise spectrum (through its bins).
double coverage(const RecordSpectrum& s) {
  const std::vector<double> exact = expected_points(s, exact_noise);
  int inside = 0;
  for (std::size_t k = 0; k < s.points.size(); ++k)
    inside += s.points[k].lower <= exact[k] && exact[k] <= s.points[k].upper ? 1 : 0;
  return double(inside) / double(s.points.size());
}

/// The segments of `kind` overlapping [start, end].
std::vector<SteadySegment> overlapping(const std::vector<SteadySegment>& segments, SegmentKind kind, double start,
                                       double end) {
  std::vector<SteadySegment> found;
  for (const SteadySegment& s : segments)
    if (s.kind == kind && s.end > start && s.start < end) found.push_back(s);
  return found;
}

// Slide-hold-slide and velocity steps: 10 um/s, a 2 s hold, 10 um/s, a step to 30 um/s, a 10 s
// hold, then 3 um/s for the longest stretch.
double shs_speed(double t) {
  if (t < 100) return 10e-6;
  if (t < 102) return 0;
  if (t < 200) return 10e-6;
  if (t < 300) return 30e-6;
  if (t < 310) return 0;
  return 3e-6;
}

TEST(Segments, EveryHoldAndStepOfASlideHoldSlideRecordIsFound) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Record record = make_record(600, shs_speed, seed);
    const std::vector<SteadySegment> segments = steady_segments(record);
    // Every stretch labelled, end to end.
    ASSERT_FALSE(segments.empty());
    EXPECT_NEAR(segments.front().start, 0, 1e-9);
    EXPECT_NEAR(segments.back().end, record.start_time + double(record.samples() - 1) * kDt, 1e-9);
    for (std::size_t k = 1; k < segments.size(); ++k)
      EXPECT_NEAR(segments[k].start, segments[k - 1].end + kDt, 1e-6) << seed;
    for (const auto& [start, end] : {std::pair{100.0, 102.0}, std::pair{300.0, 310.0}}) {
      const auto holds = overlapping(segments, SegmentKind::hold, start, end);
      ASSERT_EQ(holds.size(), 1u) << "seed " << seed << ": the hold " << start << ".." << end;
      EXPECT_GT(holds[0].end - holds[0].start, 0.4 * (end - start)) << seed;
      EXPECT_NEAR(holds[0].start, start, 1.5) << seed;
    }
    // The step from 10 to 30 um/s: two sliding stretches at their speeds, split near 200 s.
    const auto before = overlapping(segments, SegmentKind::sliding, 150, 160);
    const auto after = overlapping(segments, SegmentKind::sliding, 250, 260);
    ASSERT_EQ(before.size(), 1u);
    ASSERT_EQ(after.size(), 1u);
    EXPECT_NEAR(before[0].mean_speed, 10e-6, 0.1e-6);
    EXPECT_NEAR(after[0].mean_speed, 30e-6, 0.1e-6);
    EXPECT_NEAR(before[0].end, 200, 2);
    EXPECT_NEAR(after[0].start, 200, 2);
    EXPECT_EQ(overlapping(segments, SegmentKind::sliding, 100.5, 101.5).size(), 0u);
    EXPECT_EQ(overlapping(segments, SegmentKind::sliding, 301, 309).size(), 0u);

    // The default analysis takes the longest sliding stretch, 3 um/s after 310 s, and its
    // spectrum is the noise put in.
    std::vector<std::string> notes;
    const Record steady = longest_steady(record, segments, notes);
    EXPECT_NEAR(steady.start_time, 310, 2);
    ASSERT_FALSE(notes.empty());
    EXPECT_NE(notes.back().find("2 hold(s)"), std::string::npos) << notes.back();
    const RecordSpectrum s = analyze_record(steady, {});
    EXPECT_NEAR(s.sliding.v, 3e-6, 0.05e-6);
    EXPECT_GE(coverage(s), 0.85) << seed;
  }
}

// A stretch at constant speed, however short, is not a hold; nor is a slow stretch beside a fast one.
TEST(Segments, ASlowStretchIsSlidingNotAHold) {
  const Record record = make_record(
      400, [](double t) { return t < 200 ? 1e-6 : 10e-6; }, 7);
  for (const SteadySegment& s : steady_segments(record)) EXPECT_NE(s.kind, SegmentKind::hold) << s.start;
}

// A noisy sensor (0.6 um every 0.136 s, twice the sepiolite record's) at 0.2 um/s, then 2 um/s: blocks
// short enough for a 2 s hold cannot tell 0.2 um/s from a hold, so they are made longer.
TEST(Segments, ANoisySlowStretchIsSlidingNotAHold) {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> gauss(0, 0.6e-6);
  std::vector<double> t, x;
  double path = 0;
  for (int k = 0; k * 0.136 < 2200; ++k) {
    path += (k * 0.136 < 1200 ? 0.2e-6 : 2e-6) * 0.136;
    t.push_back(k * 0.136), x.push_back(path + gauss(rng));
  }
  const std::vector<SteadySegment> segments = steady_segments(record_from_samples(t, x, {}));
  int sliding = 0;
  for (const SteadySegment& s : segments) {
    EXPECT_NE(s.kind, SegmentKind::hold) << s.start << ".." << s.end;
    sliding += s.kind == SegmentKind::sliding ? 1 : 0;
  }
  EXPECT_EQ(sliding, 2);
}

// Elastic loading: the load point moves from the start, the force rises for 50 s, then settles.
TEST(Segments, TheForceRisingAtTheStartIsLoading) {
  std::vector<double> force;
  const Record record = make_record(
      400, [](double) { return 10e-6; }, 3, &force, [](double t) { return 10 * std::min(t, 50.0) / 50; });
  const std::vector<SteadySegment> segments = steady_segments(record);
  ASSERT_GE(segments.size(), 2u);
  EXPECT_EQ(segments[0].kind, SegmentKind::loading);
  EXPECT_NEAR(segments[0].end, 50, 3);
  EXPECT_EQ(segments[1].kind, SegmentKind::sliding);
  std::vector<std::string> notes;
  EXPECT_GT(longest_steady(record, segments, notes).start_time, 47);
}

// A reciprocating tribometer: a triangular-wave position of 50 strokes of 20 s at 100 um/s.
double stroke_speed(double t) { return std::fmod(t, 40.0) < 20 ? 100e-6 : -100e-6; }

TEST(Strokes, FiftyStrokesAreFoundAndTheirSpectrumIsTheNoise) {
  const Record record = make_record(1000, stroke_speed, 11);
  const std::vector<SteadySegment> segments = steady_segments(record);
  const std::optional<Strokes> strokes = find_strokes(segments, record.dt);
  ASSERT_TRUE(strokes);
  EXPECT_EQ(strokes->middles.size(), 50u);
  EXPECT_NEAR(strokes->speed, 100e-6, 1e-6);
  EXPECT_NEAR(strokes->middle_duration, 16, 1);
  EXPECT_NEAR(strokes->lowest_omega, 4 * std::numbers::pi / strokes->middle_duration, 1e-9);
  // A reversal at a block's edge leaves no block between the strokes to label.
  int reversals = 0, others = 0;
  for (const SteadySegment& s : segments) {
    reversals += s.kind == SegmentKind::reversal ? 1 : 0;
    others += s.kind != SegmentKind::reversal && s.kind != SegmentKind::sliding ? 1 : 0;
  }
  EXPECT_GT(reversals, 10);
  EXPECT_LE(reversals, 49);
  EXPECT_EQ(others, 0);
  std::vector<std::string> notes;
  const RecordSpectrum s = analyze_strokes(record, *strokes, {}, notes);
  ASSERT_TRUE(s.strokes);
  EXPECT_GE(s.welch.segments, 50u);
  EXPECT_NEAR(s.points.front().omega, strokes->lowest_omega, 0.2 * strokes->lowest_omega);
  EXPECT_GE(coverage(s), 0.85);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.back().find("50 strokes"), std::string::npos) << notes.back();
}

// The strokes' error bars over seeds: the normalised deviations (C - exact) / standard error
// have rms near 1, and the 95.4% bars hold the exact spectrum at about 95% of points.
TEST(Strokes, ErrorBarsAreCalibratedOverSeeds) {
  double sum2 = 0;
  int points = 0, inside = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Record record = make_record(1000, stroke_speed, 100 + seed);
    const std::optional<Strokes> strokes = find_strokes(steady_segments(record), record.dt);
    ASSERT_TRUE(strokes) << seed;
    std::vector<std::string> notes;
    const RecordSpectrum s = analyze_strokes(record, *strokes, {}, notes);
    const std::vector<double> exact = expected_points(s, exact_noise);
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      const AnalysisPoint& p = s.points[k];
      sum2 += std::pow((p.C_x - exact[k]) / p.standard_error, 2);
      inside += p.lower <= exact[k] && exact[k] <= p.upper ? 1 : 0;
      ++points;
    }
  }
  const double rms = std::sqrt(sum2 / points), share = double(inside) / points;
  std::printf("strokes over 20 seeds: %d points, rms of (C - exact) / standard error %.3f, inside the bars %.3f\n",
              points, rms, share);
  EXPECT_GT(rms, 0.85);
  EXPECT_LT(rms, 1.15);
  EXPECT_GT(share, 0.92);
}

// A tribometer dwelling at each reversal: 50 strokes of 20 s at 100 um/s with a hold of `dwell` s
// between strokes (shorter than a block's median can see, or a hold of its own).
double dwelling_speed(double t, double dwell) {
  const double phase = std::fmod(t, 2 * (20 + dwell));
  if (phase < 20) return 100e-6;
  if (phase < 20 + dwell) return 0;
  if (phase < 40 + dwell) return -100e-6;
  return 0;
}

TEST(Strokes, StrokesWithHoldsAtTheirEndsAreFoundAndOnlyTheirSlidingIsAnalysed) {
  for (const double dwell : {0.5, 3.0}) {
    const double period = 20 + dwell;
    const Record record = make_record(
        50 * period - dwell, [&](double t) { return dwelling_speed(t, dwell); }, 21);
    const std::vector<SteadySegment> segments = steady_segments(record);
    const std::optional<Strokes> strokes = find_strokes(segments, record.dt);
    ASSERT_TRUE(strokes) << "dwell " << dwell;
    ASSERT_EQ(strokes->middles.size(), 50u) << "dwell " << dwell;
    EXPECT_NEAR(strokes->speed, 100e-6, 1e-6);
    // Each middle inside its stroke's sliding, 10% of the stroke in from each end; none in a dwell.
    for (std::size_t k = 0; k < 50; ++k) {
      const SteadySegment& middle = strokes->middles[k];
      EXPECT_GE(middle.start, double(k) * period + 1) << "dwell " << dwell << ", stroke " << k;
      EXPECT_LE(middle.end, double(k) * period + 19) << "dwell " << dwell << ", stroke " << k;
      EXPECT_GT(middle.end - middle.start, 12) << "dwell " << dwell << ", stroke " << k;
      EXPECT_NEAR(std::fabs(middle.mean_speed), 100e-6, 2e-6);
    }
    if (dwell >= 2) {
      EXPECT_EQ(std::count_if(segments.begin(), segments.end(),
                              [](const SteadySegment& s) { return s.kind == SegmentKind::hold; }),
                49);
    }
    std::vector<std::string> notes;
    const RecordSpectrum s = analyze_strokes(record, *strokes, {}, notes);
    EXPECT_GE(coverage(s), 0.85) << "dwell " << dwell;
  }
}

// Strokes alone make a record reciprocating: a record with one reversal is two slides.
TEST(Strokes, AFewTurnsAreNoStrokes) {
  const Record record = make_record(
      300, [](double t) { return t < 150 ? 10e-6 : -10e-6; }, 5);
  EXPECT_FALSE(find_strokes(steady_segments(record), record.dt));
}

}  // namespace
}  // namespace slidespec
