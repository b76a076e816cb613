#include "io/tables.hpp"

#include <fftw3.h>

#include <Eigen/Core>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <variant>
#include <xsimd/config/xsimd_config.hpp>

#include "io/points.hpp"
#include "slidespec/estimator.hpp"
#include "slidespec/input_error.hpp"
#include "slidespec/simd.hpp"
#include "slidespec/theory.hpp"
#include "util/numbers.hpp"

namespace slidespec::io {

std::string run_label(const std::string& case_name, const Parameters& p) {
  const auto base = describe(ParameterBuilder(case_name).build());
  std::string changed;
  for (const auto& [key, value] : describe(p)) {
    if (key == "eta1") continue;  // derived from v (or v from it, then v is listed)
    const auto same = std::find_if(base.begin(), base.end(), [&](const auto& b) { return b.first == key; });
    if (same != base.end() && same->second == value) continue;
    changed += (changed.empty() ? "" : ", ") + key + "=" + value;
  }
  return changed.empty() ? case_name : case_name + " + " + changed;
}

std::string case_of(const std::string& label) { return label.substr(0, label.find(" + ")); }

std::vector<std::pair<std::string, ParameterValue>> parameter_values(const Parameters& p) {
  std::vector<std::pair<std::string, ParameterValue>> values;
  for (const auto& [key, value] : describe(p)) {
    double number = 0;
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
    if (error != std::errc() || end != value.data() + value.size())
      values.emplace_back(key, value);
    else if (value.find_first_of(".eE") == std::string::npos)
      values.emplace_back(key, std::stoll(value));
    else
      values.emplace_back(key, number);
  }
  return values;
}

nlohmann::ordered_json parameters_json(const Parameters& p) {
  nlohmann::ordered_json block = nlohmann::ordered_json::object();
  for (const auto& [key, value] : parameter_values(p))
    std::visit([&block, &key = key](const auto& v) { block[key] = v; }, value);
  return block;
}

std::string json_file_text(const nlohmann::ordered_json& doc) {
  return doc.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

std::string versions() {
  std::ostringstream out;
  out << "slidespec " << SLIDESPEC_VERSION << ", " << fftw_version << ", Eigen " << EIGEN_WORLD_VERSION << "."
      << EIGEN_MAJOR_VERSION << "." << EIGEN_MINOR_VERSION << ", xsimd " << XSIMD_VERSION_MAJOR << "."
      << XSIMD_VERSION_MINOR << "." << XSIMD_VERSION_PATCH << ", g++ " << __VERSION__;
  return out.str();
}

namespace {

/// A landmark's value as the table writes it.
std::string text(double value) { return util::format_number(value); }
std::string text(bool value) { return value ? "true" : "false"; }
std::string text(const std::string& value) { return value; }

}  // namespace

std::string metadata_lines(const Parameters& p, const std::string& case_name) {
  std::ostringstream out;
  out << "# slidespec " << SLIDESPEC_VERSION << "\n# case = " << case_of(case_name) << "\n";
  if (case_of(case_name) != case_name) out << "# label = " << case_name << "\n";
  for (const auto& [key, value] : describe(p)) out << "# " << key << " = " << value << "\n";
  for (const Landmark& mark : shown_landmarks(p, LandmarkOutput::tsv)) {
    out << "# " << mark.row->key << " = ";
    std::visit([&](const auto& value) { out << text(value); }, mark.value);
    out << "  # " << mark.row->doc << (mark.note.empty() ? "" : "; " + mark.note) << "\n";
  }
  return out.str();
}

namespace {

/// The TSV's numeric codes for a point's estimator and theory kind, so that its columns
/// stay numbers.
int estimator_code(const std::string& estimator) { return estimator == "shadow" ? 2 : estimator == "forcing" ? 1 : 0; }
int theory_kind_code(TheoryKind kind) {
  switch (kind) {
    case TheoryKind::first_order:
      return 1;
    case TheoryKind::second_order:
      return 2;
    case TheoryKind::quasi_static:
      return 3;
    case TheoryKind::none:
      break;
  }
  return 0;
}

}  // namespace

std::string run_point_notes() {
  return "omega [rad/s]; C_x [m^2 s] estimate, the mean of C_x over the bin's frequencies;"
         " stderr [m^2 s]; theory [m^2 s] continuous exact first-order theory, its mean over the same bins;"
         " n_avg periodogram values averaged; bandwidth [rad/s]; C_v = omega^2 C_x [m^2/s];"
         " C_F = M^2 omega^4 C_x [N^2 s]; theory_at_omega [m^2 s]; C_eq1 [m^2 s] the paper's Eq. (1);"
         " theory2 [m^2 s] the theory beyond first order that theory_kind names (second order or quasi-static,"
         " docs/model.md §7), its mean over the same bins,"
         " nan where it does not apply; variance_ratio the estimate's variance over the plain mean's of the same"
         " realizations; estimator 2 shadow (regression on the linear shadow and the forcing), 1 forcing (on"
         " the forcing alone), 0 plain (PREFIX.json names them); theory_kind the best theory that holds at"
         " the point, 2 second_order or 3 quasi_static (theory2), 1 first_order (theory), 0 none;"
         " correction = C_x/theory - 1, the measured departure from the first order, and correction_stderr"
         " = stderr/theory its standard error";
}

std::string run_point_spring_notes() {
  return "C_F_spring [N^2 s] the spring's force spectrum k_drive^2 C_x (what a machine's"
         " force sensor records; C_F above is the block's inertial force); C_F_spring_stderr [N^2 s];"
         " C_F_spring_theory [N^2 s] k_drive^2 theory";
}

std::string run_point_header(bool spring_columns) {
  return std::string(
             "omega\tC_x\tstderr\ttheory\tn_avg\tbandwidth\tC_v\tC_F\ttheory_at_omega\tC_eq1\ttheory2"
             "\tvariance_ratio\testimator\ttheory_kind\tcorrection\tcorrection_stderr") +
         (spring_columns ? "\tC_F_spring\tC_F_spring_stderr\tC_F_spring_theory" : "");
}

std::string run_point_row(const Parameters& p, const RunPoint& point, bool spring_columns) {
  std::ostringstream out;
  out << util::format_number(point.omega) << "\t" << util::format_number(point.C_x) << "\t"
      << util::format_number(point.standard_error) << "\t" << util::format_number(point.theory) << "\t"
      << util::format_number(point.n_avg) << "\t" << util::format_number(point.bandwidth) << "\t"
      << util::format_number(velocity_spectrum(point.omega, point.C_x)) << "\t"
      << util::format_number(force_spectrum(point.omega, point.C_x, p.M)) << "\t"
      << util::format_number(point.theory_at_omega) << "\t" << util::format_number(eq1_asymptote(p, point.omega))
      << "\t" << util::format_number(point.theory2) << "\t" << util::format_number(point.variance_ratio) << "\t"
      << estimator_code(point.estimator) << "\t" << theory_kind_code(point.theory_kind) << "\t"
      << util::format_number(point.C_x / point.theory - 1) << "\t"
      << util::format_number(point.standard_error / point.theory);
  if (spring_columns) {
    // A sweep across drives gives its force-driven runs these columns too: no spring, no force.
    const bool spring = p.drive == Drive::spring;
    for (double value : {point.C_x, point.standard_error, point.theory})
      out << "\t" << util::format_number(spring ? spring_force_spectrum(p, value) : NAN);
  }
  return out.str();
}

nlohmann::ordered_json run_point_json(const Parameters& p, const RunPoint& point) {
  nlohmann::ordered_json row =
      point_json(point.omega, "C_x", point.C_x, point.standard_error, point.n_avg, point.bandwidth);
  row["theory"] = point.theory;
  row["theory_at_omega"] = point.theory_at_omega;
  row["bins"] = {{"first", point.bins.first},
                 {"last", point.bins.last},
                 {"spacing", point.bins.spacing},
                 {"count", point.bins.count}};
  row["theory2"] =
      std::isfinite(point.theory2) ? nlohmann::ordered_json(point.theory2) : nlohmann::ordered_json(nullptr);
  row["variance_ratio"] = point.variance_ratio;
  row["estimator"] = point.estimator;
  row["theory_kind"] = theory_kind_name(point.theory_kind);
  row["correction"] = point.C_x / point.theory - 1;
  row["correction_stderr"] = point.standard_error / point.theory;
  if (p.drive == Drive::spring) {
    row["C_F_spring"] = spring_force_spectrum(p, point.C_x);
    row["C_F_spring_stderr"] = spring_force_spectrum(p, point.standard_error);
    row["C_F_spring_theory"] = spring_force_spectrum(p, point.theory);
  }
  return row;
}

std::string run_table(const Parameters& p, const std::string& case_name, const RunRequest& request,
                      const RunResult& result, FrontEnd reader) {
  std::ostringstream out;
  out << metadata_lines(p, case_name);
  std::uint64_t realizations = 0;
  for (const SubBand& band : result.sub_bands) realizations += band.realizations;
  out << "# seed = " << request.seed << "\n"
      << "# control_variate = "
      << (request.control_variate ? "shadow  # each realization's linear shadow as a control variate where it pays"
                                  : "off  # the forcing control variate alone")
      << " (docs/run.md)\n"
      << "# realizations = " << realizations << "  # over all sub-bands\n"
      << "# simulated_time = " << util::format_number(result.simulated_time) << "  # [s], all realizations\n"
      << "# measured_mean_speed = " << util::format_number(result.mean_speed) << "  # [m/s] +- "
      << util::format_number(result.mean_speed_error) << "\n"
      << "# reached_precision = " << util::format_number(result.reached_precision) << "  # largest stderr/C_x"
      << (result.points.empty() ? ", of no point: none was measured" : "") << " ("
      << (request.realizations > 0 ? std::string("a fixed realization count: no target")
          : request.duration > 0   ? std::string("a fixed duration: no target")
                                   : "target " + util::format_number(request.precision))
      << ")\n"
      << "# complete = " << (result.complete ? "true" : "false") << "\n"
      << "# rows = " << result.points.size() << "  # the point rows below, to tell a table cut short\n"
      << "# stationary = " << (result.stationary ? "true" : "false  # " + worded(result.stationarity, reader)) << "\n"
      << "# versions = " << versions() << "\n";
  for (std::size_t b = 0; b < result.sub_bands.size(); ++b) {
    const SubBand& band = result.sub_bands[b];
    out << "# sub_band " << b << ": omega " << util::format_number(band.omega_low) << " .. "
        << util::format_number(band.omega_high) << ", dt = " << util::format_number(band.dt)
        << " s, duration = " << util::format_number(band.duration)
        << " s, warm_up = " << util::format_number(band.warm_up) << " s at dt " << util::format_number(band.warm_up_dt)
        << " s, shadow = " << (band.shadow ? "true" : "false") << ", realizations = " << band.realizations << "\n";
  }
  out << "# columns: " << run_point_notes() << "\n";
  if (!result.theory2_note.empty()) out << "# theory2_note = " << worded(result.theory2_note, reader) << "\n";
  const bool spring = p.drive == Drive::spring;
  if (spring) out << "# columns (drive=spring): " << run_point_spring_notes() << "\n";
  out << "# " << run_point_header(spring) << "\n";
  for (const RunPoint& point : result.points) out << run_point_row(p, point, spring) << "\n";
  return out.str();
}

nlohmann::ordered_json request_json(const RunRequest& request) {
  return {{"omega_min", request.omega_min},
          {"omega_max", request.omega_max},
          {"points_per_decade", request.points_per_decade},
          {"precision", request.precision},
          {"duration", request.duration},
          {"realizations", request.realizations},
          {"seed", request.seed},
          {"control_variate", request.control_variate ? "shadow" : "off"}};
}

std::string run_json(const Parameters& p, const std::string& case_name, const RunRequest& request,
                     const RunResult& result, FrontEnd reader) {
  nlohmann::ordered_json doc;
  doc["slidespec_version"] = SLIDESPEC_VERSION;
  doc["versions"] = versions();
  doc["case"] = case_of(case_name);
  doc["label"] = case_name;
  doc["parameters"] = parameters_json(p);
  doc["landmarks"] = nlohmann::ordered_json::object();
  for (const Landmark& mark : shown_landmarks(p, LandmarkOutput::json))
    std::visit([&](const auto& value) { doc["landmarks"][mark.row->key] = value; }, mark.value);
  doc["request"] = request_json(request);
  doc["complete"] = result.complete;
  doc["stationary"] = result.stationary;
  if (!result.stationary) doc["stationarity"] = worded(result.stationarity, reader);
  doc["reached_precision"] = result.reached_precision;
  if (!result.theory2_note.empty()) doc["theory2_note"] = worded(result.theory2_note, reader);
  doc["theory_kind"] = theory_kind_name(result.theory_kind);
  if (!result.theory_kind_note.empty()) doc["theory_kind_note"] = worded(result.theory_kind_note, reader);
  doc["measured_mean_speed"] = {{"value", result.mean_speed}, {"standard_error", result.mean_speed_error}};
  doc["simulated_time"] = result.simulated_time;
  doc["wall_seconds"] = result.wall_seconds;
  doc["realization_steps"] = result.realization_steps;
  doc["miniblock_steps"] = result.miniblock_steps;
  doc["throughput_miniblock_steps_per_second"] =
      result.wall_seconds > 0 ? result.miniblock_steps / result.wall_seconds : 0.0;
  doc["simd_path"] = to_string(result.simd_path);
  doc["threads"] = result.threads;
  for (const SubBand& band : result.sub_bands)
    doc["sub_bands"].push_back({{"omega_low", band.omega_low},
                                {"omega_high", band.omega_high},
                                {"dt", band.dt},
                                {"duration", band.duration},
                                {"warm_up", band.warm_up},
                                {"warm_up_dt", band.warm_up_dt},
                                {"shadow", band.shadow},
                                {"realizations", band.realizations},
                                {"rounds", band.rounds}});
  for (const RunPoint& point : result.points) doc["points"].push_back(run_point_json(p, point));
  return json_file_text(doc);
}

}  // namespace slidespec::io

namespace slidespec::io {

namespace {

/// A number as run_json wrote it: JSON has no inf or nan, and writes them as null.
double number(const nlohmann::ordered_json& holder, const char* key) {
  const nlohmann::ordered_json& value = holder.at(key);
  return value.is_null() ? std::numeric_limits<double>::quiet_NaN() : value.get<double>();
}

std::string text_or_empty(const nlohmann::ordered_json& holder, const char* key) {
  return holder.contains(key) ? holder.at(key).get<std::string>() : std::string();
}

TheoryKind theory_kind_named(const std::string& name) {
  for (TheoryKind kind : {TheoryKind::second_order, TheoryKind::quasi_static, TheoryKind::first_order})
    if (name == theory_kind_name(kind)) return kind;
  if (name == theory_kind_name(TheoryKind::none)) return TheoryKind::none;
  throw InputError("no theory kind '" + name + "'");
}

/// The numbers run_json writes under `fields`' keys, into their members of `into`.
template <class Holder>
void read_numbers(const nlohmann::ordered_json& from, Holder& into,
                  std::initializer_list<std::pair<const char*, double Holder::*>> fields) {
  for (const auto& [key, member] : fields) into.*member = number(from, key);
}

RunPoint point_from_json(const nlohmann::ordered_json& row) {
  RunPoint point{};
  read_numbers(row, point,
               {{"omega", &RunPoint::omega},
                {"C_x", &RunPoint::C_x},
                {"stderr", &RunPoint::standard_error},
                {"theory", &RunPoint::theory},
                {"theory_at_omega", &RunPoint::theory_at_omega},
                {"n_avg", &RunPoint::n_avg},
                {"bandwidth", &RunPoint::bandwidth},
                {"theory2", &RunPoint::theory2},
                {"variance_ratio", &RunPoint::variance_ratio}});
  const nlohmann::ordered_json& bins = row.at("bins");
  read_numbers(bins, point.bins,
               {{"first", &BinRange::first}, {"last", &BinRange::last}, {"spacing", &BinRange::spacing}});
  point.bins.count = bins.at("count").get<int>();
  point.estimator = row.at("estimator").get<std::string>();
  point.theory_kind = theory_kind_named(row.at("theory_kind").get<std::string>());
  return point;
}

SubBand sub_band_from_json(const nlohmann::ordered_json& entry) {
  SubBand band;
  read_numbers(entry, band,
               {{"omega_low", &SubBand::omega_low},
                {"omega_high", &SubBand::omega_high},
                {"dt", &SubBand::dt},
                {"duration", &SubBand::duration},
                {"warm_up", &SubBand::warm_up},
                {"warm_up_dt", &SubBand::warm_up_dt}});
  band.shadow = entry.at("shadow").get<bool>();
  band.realizations = entry.at("realizations").get<std::uint64_t>();
  band.rounds = entry.at("rounds").get<int>();
  return band;
}

}  // namespace

RunResult run_result_from_json(const nlohmann::ordered_json& doc) {
  try {
    RunResult result;
    result.complete = doc.at("complete").get<bool>();
    result.stationary = doc.at("stationary").get<bool>();
    result.stationarity = text_or_empty(doc, "stationarity");
    result.theory2_note = text_or_empty(doc, "theory2_note");
    result.theory_kind = theory_kind_named(doc.at("theory_kind").get<std::string>());
    result.theory_kind_note = text_or_empty(doc, "theory_kind_note");
    read_numbers(doc, result,
                 {{"reached_precision", &RunResult::reached_precision},
                  {"simulated_time", &RunResult::simulated_time},
                  {"wall_seconds", &RunResult::wall_seconds},
                  {"realization_steps", &RunResult::realization_steps},
                  {"miniblock_steps", &RunResult::miniblock_steps}});
    read_numbers(doc.at("measured_mean_speed"), result,
                 {{"value", &RunResult::mean_speed}, {"standard_error", &RunResult::mean_speed_error}});
    result.simd_path = parse_simd_path(doc.at("simd_path").get<std::string>());
    result.threads = doc.at("threads").get<int>();
    // A run of no sub-band (or no point) writes no array: JSON's null.
    if (doc.contains("sub_bands") && !doc.at("sub_bands").is_null())
      for (const nlohmann::ordered_json& entry : doc.at("sub_bands"))
        result.sub_bands.push_back(sub_band_from_json(entry));
    if (doc.contains("points") && !doc.at("points").is_null())
      for (const nlohmann::ordered_json& row : doc.at("points")) result.points.push_back(point_from_json(row));
    return result;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a run's JSON (") + e.what() + ")");
  }
}

}  // namespace slidespec::io
