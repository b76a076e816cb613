// analyze(): the session both front ends call. Its refusals name options by id, which each
// front end words; its warnings are data with a kind and a topic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "slidespec/analysis.hpp"
#include "slidespec/many_records.hpp"
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

// A record of many: analysed as analyze() analyses it, its row from the report; refused
// ones (a directory, a missing file, a malformed one) a row saying why, never an exception.
TEST(ManyRecords, EachRecordIsARowAndARefusalIsNoError) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "slidespec_many_records_test";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder / "a_directory");
  const Record record = reference_record(0.5e-6);
  std::ofstream(folder / "good.csv") << record_csv(record, LengthUnit::m, "");
  std::ofstream(folder / "bad.csv") << "t,x\n0,1\n0.001,abc\n";
  AnalysisPlan plan;
  plan.slope_band = std::pair{3.0, 30.0};
  RecordFormat format;

  const RecordOfMany good = analyze_one_of_many((folder / "good.csv").string(), format, plan);
  ASSERT_TRUE(good.report.has_value()) << good.row.reason;
  const AnalysisReport alone = analyze(read_record_file((folder / "good.csv").string(), format), plan);
  EXPECT_EQ(good.row.segment, "whole");
  EXPECT_EQ(good.row.v, alone.spectrum.sliding.v);
  EXPECT_EQ(good.row.slope, alone.slope->slope);
  EXPECT_EQ(good.row.start, alone.record.start_time);
  EXPECT_EQ(good.row.end, alone.record.start_time + double(alone.record.samples() - 1) * alone.record.dt);
  EXPECT_EQ(good.row.ok, alone.ok());
  EXPECT_TRUE(std::isnan(good.row.alpha));

  const std::string directory = (folder / "a_directory").string(), missing = (folder / "missing.csv").string();
  for (const auto& [path, reason] : {std::pair{directory, directory + ": a directory, not a record"},
                                     std::pair{missing, missing + ": no such file"}}) {
    const RecordOfMany refused = analyze_one_of_many(path, format, plan);
    EXPECT_FALSE(refused.report.has_value());
    EXPECT_FALSE(refused.row.ok);
    EXPECT_EQ(refused.row.reason, reason);
    EXPECT_EQ(refused.row.segment, "");
    EXPECT_TRUE(std::isnan(refused.row.v));
  }
  const RecordOfMany bad = analyze_one_of_many((folder / "bad.csv").string(), format, plan);
  EXPECT_FALSE(bad.report.has_value());
  EXPECT_NE(bad.row.reason.find("line 3"), std::string::npos) << bad.row.reason;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace slidespec
