// analyze(): the session both front ends call. Its refusals name options by id, which each
// front end words; its warnings are data with a kind and a topic.
#include <gtest/gtest.h>

#include <algorithm>

#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"

namespace slidespec {
namespace {

Record reference_record(double resolution) {
  SensorRequest sensor;
  sensor.duration = 200;
  sensor.sample_interval = 1e-2;
  sensor.resolution = resolution;
  sensor.sensor_noise = resolution / 2;
  return synthesize_record(ParameterBuilder("reference").build(), sensor);
}

bool has(const std::vector<AnalysisMessage>& messages, AnalysisMessage::Kind kind, const std::string& topic) {
  return std::any_of(messages.begin(), messages.end(),
                     [&](const AnalysisMessage& m) { return m.kind == kind && m.topic == topic; });
}

TEST(Options, EachFrontEndWordsAnOptionItsOwnWay) {
  const std::string message =
      named(Option::omega_max) + ": above Nyquist; give " + named(Option::window) + " T0:T1 or --set k_drive=K";
  EXPECT_EQ(worded(message, FrontEnd::command_line),
            "--omega-max: above Nyquist; give --window T0:T1 or --set k_drive=K");
  EXPECT_EQ(worded(message, FrontEnd::python), "omega_max: above Nyquist; give window=(T0, T1) or k_drive=K");
  EXPECT_EQ(worded("{not_an_option} and {out}", FrontEnd::python), "{not_an_option} and --out");  // Python has no out
}

TEST(Session, AFitThatNeedsACaseIsRefusedBeforeAnyReading) {
  AnalysisPlan plan;
  plan.fit = "alpha";
  try {
    check_plan(plan, 0);
    ADD_FAILURE() << "an alpha fit without a compared case";
  } catch (const InputError& e) {
    EXPECT_EQ(worded(e.what(), FrontEnd::command_line), "--fit alpha needs --compare-case NAME");
    EXPECT_EQ(worded(e.what(), FrontEnd::python), "fit alpha needs compare NAME");
  }
}

TEST(Session, AFloorInTheWrongUnitIsAWarningNotAFailure) {
  AnalysisPlan plan;
  plan.request.resolution = 0.1;  // 0.1 m, where 0.1 um was meant
  const AnalysisReport report = analyze(reference_record(0.5e-6), plan);
  EXPECT_TRUE(report.ok());
  EXPECT_TRUE(has(report.warnings, AnalysisMessage::Kind::warning, "no_usable_band"));
  EXPECT_FALSE(report.spectrum.usable_high > report.spectrum.usable_low);
}

TEST(Session, TheComparedCaseTakesTheRecordsSpeedAndItsFitIsJudged) {
  AnalysisPlan plan;
  plan.request.resolution = 0.5e-6;
  plan.request.sensor_noise = 0.25e-6;
  plan.compare_case = "reference";
  plan.fit = "alpha";
  const AnalysisReport report = analyze(reference_record(0.5e-6), plan);
  ASSERT_TRUE(report.model && report.alpha);
  EXPECT_DOUBLE_EQ(report.model->alpha, report.alpha->alpha);
  EXPECT_EQ(report.model_values.size(), report.spectrum.points.size());
  EXPECT_TRUE(has(report.notes, AnalysisMessage::Kind::note, "model_terms"));  // its v is the record's
  EXPECT_EQ(report.ok(), report.alpha_verdict.ok);
  EXPECT_EQ(has(report.warnings, AnalysisMessage::Kind::failed_fit, "alpha"), !report.alpha_verdict.ok);
}

}  // namespace
}  // namespace slidespec
