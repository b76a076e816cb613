// A run's JSON read back: the result it gives writes the same JSON and table again byte for
// byte (what a continued sweep relies on to reuse a finished run), and what JSON cannot hold
// (an inf) shows in the table rather than passing unnoticed.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/tables.hpp"
#include "slidespec/input_error.hpp"
#include "slidespec/run.hpp"

namespace slidespec::io {
namespace {

struct FinishedRun {
  Parameters p = ParameterBuilder("reference").build();
  RunRequest request;
  RunResult result;
  FinishedRun() {
    request.omega_min = 100;
    request.omega_max = 1000;
    request.realizations = 8;
    request.seed = 11;
    result = run_spectrum(p, request);
  }
};

RunResult read_back(const std::string& json_text) {
  return run_result_from_json(nlohmann::ordered_json::parse(json_text));
}

TEST(RunJson, ReadBackWritesTheSameJsonAndTable) {
  const FinishedRun run;
  ASSERT_TRUE(run.result.complete);
  ASSERT_GT(run.result.points.size(), 4u);
  const std::string json_text = run_json(run.p, "reference", run.request, run.result);
  const RunResult again = read_back(json_text);
  EXPECT_EQ(run_json(run.p, "reference", run.request, again), json_text);
  EXPECT_EQ(run_table(run.p, "reference", run.request, again), run_table(run.p, "reference", run.request, run.result));
  for (std::size_t k = 0; k < again.points.size(); ++k) {
    EXPECT_EQ(again.points[k].C_x, run.result.points[k].C_x) << "point " << k;  // bit for bit, not near
    EXPECT_EQ(again.points[k].bins.count, run.result.points[k].bins.count);
  }
}

TEST(RunJson, NotesAndAMissingTheoryComeBack) {
  FinishedRun run;
  run.result.stationary = false;
  run.result.stationarity = "the block stalled: extend {omega_min} down";
  run.result.theory2_note = "two touching levels";
  run.result.points[1].theory2 = std::numeric_limits<double>::quiet_NaN();
  const std::string json_text = run_json(run.p, "reference", run.request, run.result);
  const RunResult again = read_back(json_text);
  EXPECT_FALSE(again.stationary);
  EXPECT_TRUE(std::isnan(again.points[1].theory2));
  EXPECT_EQ(run_json(run.p, "reference", run.request, again), json_text);
  EXPECT_EQ(run_table(run.p, "reference", run.request, again), run_table(run.p, "reference", run.request, run.result));
}

TEST(RunJson, AnInfTheJsonCannotHoldShowsInTheTable) {
  FinishedRun run;
  run.result.points[0].C_x = std::numeric_limits<double>::infinity();
  const std::string json_text = run_json(run.p, "reference", run.request, run.result);
  const RunResult again = read_back(json_text);
  // JSON writes inf as null, read as nan: the JSON agrees, the table does not.
  EXPECT_EQ(run_json(run.p, "reference", run.request, again), json_text);
  EXPECT_NE(run_table(run.p, "reference", run.request, again), run_table(run.p, "reference", run.request, run.result));
}

TEST(RunJson, AFieldMissingIsRefused) {
  const FinishedRun run;
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(run_json(run.p, "reference", run.request, run.result));
  doc["points"][0].erase("variance_ratio");
  EXPECT_THROW(run_result_from_json(doc), InputError);
  EXPECT_THROW(run_result_from_json(nlohmann::ordered_json::parse("{\"complete\": true}")), InputError);
}

}  // namespace
}  // namespace slidespec::io
