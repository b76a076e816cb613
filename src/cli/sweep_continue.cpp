#include "cli/sweep_continue.hpp"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

bool exists(const std::string& path) {
  std::error_code ignored;
  return std::filesystem::exists(path, ignored);
}

/// A JSON value as a message shows it: a word without its quotes, a number as typed (10, not 10.0).
std::string shown_value(const nlohmann::ordered_json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.is_number_float() ? util::format_number(value.get<double>()) : value.dump();
}

/// The first key of two flat objects whose values differ, named by `name`: "KEY: A there,
/// B here"; "" when they agree.
template <class Name>
std::string first_difference(const nlohmann::ordered_json& there, const nlohmann::ordered_json& here, Name name) {
  std::vector<std::string> keys;
  for (const auto* object : {&here, &there})
    for (const auto& item : object->items())
      if (std::find(keys.begin(), keys.end(), item.key()) == keys.end()) keys.push_back(item.key());
  for (const std::string& key : keys) {
    const bool in_there = there.contains(key), in_here = here.contains(key);
    if (in_there && in_here && there.at(key) == here.at(key)) continue;
    return name(key) + ": " + (in_there ? shown_value(there.at(key)) : "(none)") + " there, " +
           (in_here ? shown_value(here.at(key)) : "(none)") + " here";
  }
  return "";
}

std::string parameter_name(const std::string& key) { return "parameter " + key; }

/// A request field as the command line spells its option.
std::string request_option(const std::string& key) {
  return worded("{" + (key == "points_per_decade" ? std::string("points") : key) + "}", FrontEnd::command_line);
}

/// The grid as it is typed: "alpha=0.5,1 N=10,20".
std::string grid_text(const nlohmann::ordered_json& sweep) {
  std::string text;
  for (const auto& axis : sweep.items()) {
    if (!text.empty()) text += ' ';
    text += axis.key();
    char separator = '=';
    for (const nlohmann::ordered_json& value : axis.value()) {
      text += separator;
      text += shown_value(value);
      separator = ',';
    }
  }
  return text;
}

/// The first difference between two records, "" when they describe one sweep.
std::string record_difference(const nlohmann::ordered_json& there, const nlohmann::ordered_json& here) {
  if (there.at("sweep") != here.at("sweep"))
    return "the grid: " + grid_text(there.at("sweep")) + " there, " + grid_text(here.at("sweep")) + " here";
  if (there.at("case") != here.at("case"))
    return "--case: " + shown_value(there.at("case")) + " there, " + shown_value(here.at("case")) + " here";
  if (std::string differs = first_difference(there.at("request"), here.at("request"), request_option); !differs.empty())
    return differs;
  const nlohmann::ordered_json &runs_there = there.at("runs"), &runs_here = here.at("runs");
  if (runs_there.size() != runs_here.size())
    return "its runs: " + std::to_string(runs_there.size()) + " there, " + std::to_string(runs_here.size()) + " here";
  for (std::size_t k = 0; k < runs_here.size(); ++k) {
    const std::string differs =
        first_difference(runs_there[k].at("parameters"), runs_here[k].at("parameters"), parameter_name);
    if (!differs.empty()) return "run " + shown_value(runs_here[k].at("values")) + ": " + differs;
  }
  return "";
}

/// The first difference between a run's JSON and the run this sweep would make there.
std::string run_difference(const nlohmann::ordered_json& doc, const Parameters& p, const RunRequest& request,
                           const std::string& label) {
  if (std::string differs = first_difference(doc.at("parameters"), io::parameters_json(p), parameter_name);
      !differs.empty())
    return differs;
  if (std::string differs = first_difference(doc.at("request"), io::request_json(request), request_option);
      !differs.empty())
    return differs;
  if (doc.at("label") != label) return "label: " + shown_value(doc.at("label")) + " there, " + label + " here";
  return "";
}

/// What the state at `prefix` holds: this run's, or a refusal naming the difference.
RunLeft state_left(const std::string& state, const std::string& shown, const Parameters& p, const RunRequest& request) {
  std::string differs;
  try {
    differs = RunSession::load(io::read_file(state, "--resume")).difference(p, request);
  } catch (const InputError& e) {
    throw InputError("--resume: run " + shown + ": " + e.what());
  }
  if (!differs.empty())
    throw InputError("--resume: run " + shown + ": " + state + " holds another run (" + differs +
                     "); remove it to run this one there");
  return {RunLeft::From::state, {}, ""};
}

}  // namespace

nlohmann::ordered_json sweep_record(const std::string& case_name, const std::vector<SweepAxis>& axes,
                                    const RunRequest& request, const std::vector<Parameters>& runs) {
  nlohmann::ordered_json record;
  record["slidespec_version"] = SLIDESPEC_VERSION;
  record["what"] = "a sweep not yet written whole: the same slidespec sweep command with --resume continues it";
  record["case"] = case_name;
  record["sweep"] = nlohmann::ordered_json::object();
  for (const SweepAxis& axis : axes) record["sweep"][axis.key] = axis.values;
  record["request"] = io::request_json(request);
  record["runs"] = nlohmann::ordered_json::array();
  const auto grid = sweep_grid(axes);
  for (std::size_t k = 0; k < runs.size(); ++k) {
    std::string values;
    for (const auto& [key, value] : grid[k]) values += (values.empty() ? "" : ", ") + key + "=" + value;
    record["runs"].push_back({{"values", values}, {"parameters", io::parameters_json(runs[k])}});
  }
  return record;
}

void check_sweep_record(const std::string& out, const nlohmann::ordered_json& record) {
  const std::string path = out + ".sweep";
  if (!exists(path))
    throw InputError("--resume: nothing to continue: no " + path +
                     " (a sweep keeps it until its table, JSON and figure are all written)");
  std::string differs;
  try {
    differs = record_difference(nlohmann::ordered_json::parse(io::read_file(path, "--resume")), record);
  } catch (const nlohmann::json::exception&) {
    throw InputError("--resume: " + path + " is not a sweep's record; remove it to start the sweep afresh");
  }
  if (!differs.empty())
    throw InputError("--resume: " + path + " holds another sweep (" + differs +
                     "); give the interrupted sweep's values and options");
}

RunLeft run_left(const std::string& prefix, const std::string& shown, const Parameters& p, const RunRequest& request,
                 const std::string& label) {
  if (exists(prefix + ".state")) return state_left(prefix + ".state", shown, p, request);
  const std::string json_path = prefix + ".json", table_path = prefix + ".tsv";
  if (!exists(json_path)) return {};
  const std::string json_text = io::read_file(json_path, "--resume");
  nlohmann::ordered_json doc;
  std::string differs;
  try {
    doc = nlohmann::ordered_json::parse(json_text);
    differs = run_difference(doc, p, request, label);
  } catch (const nlohmann::json::exception&) {
    throw InputError("--resume: run " + shown + ": " + json_path + " is not a run's JSON; remove it to run it there");
  }
  if (!differs.empty())
    throw InputError("--resume: run " + shown + ": " + json_path + " is of another run (" + differs +
                     "); remove it and its .tsv to run this one there");
  RunResult result;
  try {
    result = io::run_result_from_json(doc);
  } catch (const InputError& e) {
    throw InputError("--resume: run " + shown + ": " + json_path + ": " + e.what());
  }
  if (!result.complete) return {RunLeft::From::nothing, {}, "its outputs are of a cut run whose state is gone"};
  // Both files rewritten from the JSON byte for byte: they are this run's, whole, and the
  // result read back is the one the uninterrupted sweep would combine.
  if (!exists(table_path) || io::run_table(p, label, request, result) != io::read_file(table_path, "--resume") ||
      io::run_json(p, label, request, result) != json_text)
    return {RunLeft::From::nothing, {}, "its table and JSON do not agree (changed since written?)"};
  return {RunLeft::From::outputs, result, ""};
}

}  // namespace slidespec::cli
