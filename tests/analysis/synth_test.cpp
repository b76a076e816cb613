// synth's drive programs: a reciprocating record and a slide-hold-slide record with velocity
// steps, made by the stepper, found by the segment finder, and their steady sliding's spectrum
// against the model's exact theory at each stretch's speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {
namespace {

// The fast case at alpha = 0.4: its slider's own wander over a block of 0.32 s is below a
// tenth of the slowest speed, so a 2 s hold is blocks of zero speed (at alpha = 1 and the
// reference speed it would take blocks of 8 s to tell a hold).
Parameters slider(double v = 5e-3) {
  return ParameterBuilder("fast").set("alpha", "0.4").set("v", std::to_string(v)).build();
}

SensorRequest exact_sensor(std::vector<DriveStretch> program, std::uint64_t seed) {
  SensorRequest sensor;
  sensor.sample_interval = 0.01;
  sensor.resolution = 0;
  sensor.sensor_noise = 0;
  sensor.seed = seed;
  sensor.program = std::move(program);
  return sensor;
}

// Up to a fifth of Nyquist: the omega^-4 spectrum aliased from beyond Nyquist adds < 2e-4.
constexpr double kOmegaMax = 63;
// Points enough that a share of 85% inside the bars is a test (at 95% expected).
constexpr int kPointsPerDecade = 16;

/// How a spectrum's points hold `p`'s exact (first-order) theory through the estimator's bins:
/// how many bars hold it, and the sum of squares of (C - exact) / standard error.
struct Tally {
  int points = 0, inside = 0;
  double squares = 0;
  void add(const RecordSpectrum& s, const Parameters& p) {
    const LumpedTheory theory(p);
    const std::vector<double> exact = expected_points(s, [&](double omega) { return theory(omega); });
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      inside += s.points[k].lower <= exact[k] && exact[k] <= s.points[k].upper ? 1 : 0;
      squares += std::pow((s.points[k].C_x - exact[k]) / s.points[k].standard_error, 2);
      ++points;
    }
  }
  double share() const { return double(inside) / points; }
  double rms() const { return std::sqrt(squares / points); }
};

TEST(Synth, AStrokeProgramAlternatesWithItsDwells) {
  const std::vector<DriveStretch> program = stroke_program(4, 0.02, 5e-3, 1.5);
  ASSERT_EQ(program.size(), 7u);
  for (std::size_t k = 0; k < program.size(); ++k) {
    const double expected_factor = k % 2 == 1 ? 0 : (k % 4 == 0 ? 1 : -1);
    EXPECT_EQ(program[k].speed_factor, expected_factor) << k;
    EXPECT_NEAR(program[k].duration, k % 2 == 1 ? 1.5 : 4, 1e-12) << k;
  }
  EXPECT_EQ(stroke_program(3, 0.02, 5e-3, 0).size(), 3u);
  for (const auto& [strokes, length, dwell, id] :
       {std::tuple{0.0, 0.02, 0.0, "{strokes}"}, std::tuple{2.5, 0.02, 0.0, "{strokes}"},
        std::tuple{2.0, -0.02, 0.0, "{stroke_length}"}, std::tuple{2.0, 0.02, -1.0, "{dwell}"}}) {
    try {
      stroke_program(strokes, length, 5e-3, dwell);
      ADD_FAILURE() << id << " not refused";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(id, 0), 0u) << e.what();
    }
  }
}

// The load point's path, exactly: with an exact sensor, x at a stroke's end is the stroke's
// length plus xi, and in a dwell x stands still.
TEST(Synth, TheRecordFollowsTheProgram) {
  const Parameters p = slider();
  const Record record = synthesize_record(p, exact_sensor(stroke_program(4, 0.02, p.v, 1), 5));
  ASSERT_EQ(record.samples(), std::size_t(std::llround((4 * 4 + 3 * 1) / 0.01)) + 1);
  const auto x = [&](double t) { return record.displacement[std::size_t(std::llround(t / 0.01))]; };
  // Stroke ends at 4, 9, 14 s (out to 0.02 m, back to 0, out again); xi's wander is some 100 um.
  EXPECT_NEAR(x(4), 0.02, 1e-3);
  EXPECT_NEAR(x(9), 0, 1e-3);
  EXPECT_NEAR(x(14), 0.02, 1e-3);
  for (const double dwell_start : {4.0, 9.0, 14.0})
    for (double t = dwell_start; t <= dwell_start + 1 + 1e-9; t += 0.01) EXPECT_EQ(x(t), x(dwell_start)) << t;
  EXPECT_GT(std::fabs(x(5.5) - x(5)), 1e-3);  // the next stroke moves
}

// A rig's record with a program: the load point follows it, each speed's spring force has the
// model's steady friction F_kin + N m eta1 v as its mean, and in a hold (load point and slider
// standing) the force stands at its value when the hold began.
TEST(Synth, ARigsProgramStepsTheFrictionAndAHoldStandsTheForce) {
  const Parameters p =
      ParameterBuilder("fast").set("alpha", "0.4").set("drive", "spring").set("k_drive", "1000").build();
  const std::vector<DriveStretch> program = {{1, 20}, {0, 5}, {3, 20}, {0, 5}, {1, 20}};
  SensorRequest sensor = exact_sensor(program, 1);
  sensor.load_point = true;
  const Record r = synthesize_record(p, sensor);
  ASSERT_EQ(r.samples(), 7001u);
  ASSERT_EQ(r.force.size(), r.samples());
  const auto at = [&](double t) { return std::size_t(std::llround(t / r.dt)); };
  EXPECT_NEAR(r.displacement[at(20)], 20 * p.v, 1e-12);
  EXPECT_NEAR(r.displacement[at(25)], 20 * p.v, 1e-12);
  EXPECT_NEAR(r.displacement[at(45)], 80 * p.v, 1e-12);
  EXPECT_NEAR(r.displacement[at(70)], 100 * p.v, 1e-12);
  for (const double hold : {20.0, 45.0})
    for (std::size_t n = at(hold); n <= at(hold + 5); ++n) ASSERT_EQ(r.force[n], r.force[at(hold)]) << n;
  const auto mean = [&](std::vector<std::pair<double, double>> spans) {
    double sum = 0, count = 0;
    for (const auto& [from, to] : spans)
      for (std::size_t n = at(from) + 1; n <= at(to); ++n) sum += r.force[n], ++count;
    return sum / count;
  };
  const double viscous = p.F_drive - p.F_kin;  // N m eta1 v
  EXPECT_GT(std::fabs(r.force[at(10)] - r.force[at(12)]), 0.0);
  EXPECT_NEAR(mean({{25, 45}}), p.F_kin + 3 * viscous, 1e-9 * p.F_drive);
  // The first sample belongs to the first 1x stretch.
  EXPECT_NEAR((mean({{0, 20}, {50, 70}}) * 4000 + r.force[0]) / 4001, p.F_drive, 1e-9 * p.F_drive);
}

// A speed at which the random forces could stall the slider is not the model's stationary sliding.
TEST(Synth, ARigsProgramSpeedThatCouldStallIsRefused) {
  const Parameters p =
      ParameterBuilder("fast").set("alpha", "0.4").set("drive", "spring").set("k_drive", "1000").build();
  const double stalling = 0.5 * p.alpha * p.F_kin / (p.F_drive - p.F_kin);  // alpha F_kin = 2 f (F_drive - F_kin)
  SensorRequest sensor = exact_sensor({{1, 10}, {0.9 * stalling, 10}}, 1);
  sensor.load_point = true;
  try {
    synthesize_record(p, sensor);
    ADD_FAILURE() << "a stalling speed, " << 0.9 * stalling << " v";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("{program}", 0), 0u) << e.what();
  }
  sensor.program = {{1, 10}, {1.1 * stalling, 10}};
  EXPECT_NO_THROW(synthesize_record(p, sensor));
}

TEST(Synth, AProgramStretchOfNoLengthOrSpeedIsRefused) {
  for (const DriveStretch bad : {DriveStretch{1, 0}, DriveStretch{1, -1}, DriveStretch{std::nan(""), 1}}) {
    try {
      synthesize_record(slider(), exact_sensor({{1, 10}, bad}, 1));
      ADD_FAILURE() << "not refused";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("{program}", 0), 0u) << e.what();
    }
  }
}

// The check: 50 strokes of a synthetic reciprocating record (dwelling 1 s at each
// reversal) are found by the default analysis, and their combined spectrum holds the exact
// theory within its bars at >= 85% of points.
TEST(Synth, FiftyStrokesOfAReciprocatingRecordGiveTheModelsSpectrum) {
  const Parameters p = slider();
  Tally all;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Record record = synthesize_record(p, exact_sensor(stroke_program(50, 0.1, p.v, 1), seed));
    AnalysisPlan plan;
    plan.request.omega_max = kOmegaMax;
    plan.request.points_per_decade = kPointsPerDecade;
    const AnalysisReport report = analyze(record, plan);
    ASSERT_TRUE(report.spectrum.strokes) << seed;
    EXPECT_EQ(report.spectrum.strokes->middles.size(), 50u) << seed;
    EXPECT_NEAR(report.spectrum.strokes->speed, p.v, 0.02 * p.v) << seed;
    Tally one;
    one.add(report.spectrum, p);
    all.add(report.spectrum, p);
    std::printf("50 strokes, seed %d: %d points, the exact theory inside the bars at %.3f\n", int(seed), one.points,
                one.share());
    EXPECT_GE(one.points, 20) << seed;
    // Neighbouring points share bins, so one record's share scatters more than a binomial's.
    EXPECT_GE(one.share(), 0.7) << seed;
  }
  std::printf("50 strokes over 5 seeds: %d points, inside the bars %.3f, rms of (C - exact) / standard error %.3f\n",
              all.points, all.share(), all.rms());
  EXPECT_GE(all.share(), 0.85);
  EXPECT_GT(all.rms(), 0.75);
  EXPECT_LT(all.rms(), 1.3);
}

// The check: slide-hold-slide and velocity steps (1x, a 2 s hold, 1x, 3x, a 10 s hold,
// 0.3x for the longest stretch). The default analysis finds every hold and step, takes the
// 0.3x stretch and its spectrum is the exact theory at that speed.
TEST(Synth, ASlideHoldSlideRecordsHoldsStepsAndLongestStretchAreFound) {
  const Parameters p = slider();
  const std::vector<DriveStretch> program = {{1, 100}, {0, 2}, {1, 100}, {3, 100}, {0, 10}, {0.3, 290}};
  Tally all;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Record record = synthesize_record(p, exact_sensor(program, seed));
    const std::vector<SteadySegment> segments = steady_segments(record);
    const auto within = [&](SegmentKind kind, double start, double end) {
      return std::count_if(segments.begin(), segments.end(),
                           [&](const SteadySegment& s) { return s.kind == kind && s.end > start && s.start < end; });
    };
    EXPECT_EQ(within(SegmentKind::hold, 0, 1e9), 2) << seed;
    EXPECT_EQ(within(SegmentKind::hold, 100, 102), 1) << seed;
    EXPECT_EQ(within(SegmentKind::hold, 302, 312), 1) << seed;
    // The step 1x -> 3x at 202 s: sliding at each speed on either side of it, none across.
    EXPECT_EQ(within(SegmentKind::sliding, 150, 160), 1) << seed;
    EXPECT_EQ(within(SegmentKind::sliding, 250, 260), 1) << seed;
    for (const SteadySegment& s : segments) {
      if (s.kind == SegmentKind::sliding) {
        EXPECT_FALSE(s.start < 200 && s.end > 204) << seed << ": " << s.start;
      }
    }

    AnalysisPlan plan;
    plan.request.omega_max = kOmegaMax;
    plan.request.points_per_decade = kPointsPerDecade;
    const AnalysisReport report = analyze(record, plan);
    EXPECT_NEAR(report.record.start_time, 312, 2) << seed;
    EXPECT_GT(report.record.samples() * record.dt, 280) << seed;
    EXPECT_NEAR(report.spectrum.sliding.v, 0.3 * p.v, 0.02 * p.v) << seed;
    Tally one;
    one.add(report.spectrum, slider(0.3 * p.v));
    all.add(report.spectrum, slider(0.3 * p.v));
    std::printf("slide-hold-slide, seed %d: %d points at 0.3 v, the exact theory inside the bars at %.3f\n", int(seed),
                one.points, one.share());
    EXPECT_GE(one.share(), 0.85) << seed;
  }
  std::printf("slide-hold-slide over 3 seeds: %d points, rms of (C - exact) / standard error %.3f\n", all.points,
              all.rms());
  EXPECT_GT(all.rms(), 0.75);
  EXPECT_LT(all.rms(), 1.3);
}

}  // namespace
}  // namespace slidespec
