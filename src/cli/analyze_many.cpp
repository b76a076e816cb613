#include "cli/analyze_many.hpp"

#include "io/tables.hpp"

#include <glob.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

bool is_pattern(const std::string& argument) {
  std::error_code ignored;
  return argument.find_first_of("*?[") != std::string::npos && !std::filesystem::exists(argument, ignored);
}

/// A table cell: text with no tab or line break to split the row.
std::string cell(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  return text;
}

std::string number(double value) { return std::isfinite(value) ? util::format_number(value) : "nan"; }

nlohmann::ordered_json json_number(double value) {
  return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

/// What the report analysed, in the segment kinds' words, and its first and last time [s].
void analysed_stretch(const AnalysisReport& report, bool windowed, RecordRow& row) {
  const Record& record = report.record;
  row.start = record.start_time;
  row.end = record.start_time + double(record.samples() - 1) * record.dt;
  if (report.spectrum.strokes) {
    row.segment = "strokes";
    row.strokes = report.spectrum.strokes->middles.size();
    row.start = report.spectrum.strokes->middles.front().start;
    row.end = report.spectrum.strokes->middles.back().end;
  } else if (windowed) {
    row.segment = "window";
  } else if (report.segments.size() <= 1) {
    row.segment = "whole";
  } else {
    row.segment = "sliding";
    for (const SteadySegment& s : report.segments)
      if (std::fabs(s.start - row.start) < 0.5 * record.dt) row.segment = to_string(s.kind);
  }
}

}  // namespace

bool many_records(const std::vector<std::string>& arguments) {
  return arguments.size() > 1 || std::any_of(arguments.begin(), arguments.end(), is_pattern);
}

std::vector<std::string> expand_record_paths(const std::vector<std::string>& arguments) {
  std::vector<std::string> paths;
  for (const std::string& argument : arguments) {
    if (!is_pattern(argument)) {
      paths.push_back(argument);
      continue;
    }
    glob_t matches{};
    const int found = glob(argument.c_str(), 0, nullptr, &matches);
    for (std::size_t k = 0; found == 0 && k < matches.gl_pathc; ++k) paths.emplace_back(matches.gl_pathv[k]);
    globfree(&matches);
    if (found != 0) throw InputError("analyze: the pattern '" + argument + "' matches no file");
  }
  return paths;
}

void refuse_unreadable_record(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw InputError(path + ": a directory, not a record");
  if (!std::filesystem::exists(path, error)) throw InputError(path + ": no such file");
  if (access(path.c_str(), R_OK) != 0) throw InputError(path + ": not readable");
}

std::vector<std::string> record_prefixes(const std::string& out, const std::vector<std::string>& records) {
  std::vector<std::string> prefixes;
  std::map<std::string, std::string> by_prefix;
  for (const std::string& record : records) {
    if (record == "-") throw InputError("analyze: standard input ('-') is one record alone, not one of many");
    prefixes.push_back(out + "_" + std::filesystem::path(record).stem().string());
    const auto [other, fresh] = by_prefix.emplace(prefixes.back(), record);
    if (!fresh)
      throw InputError("analyze: " + other->second + " and " + record + " would both write " + prefixes.back() +
                       ".tsv; give records of different names");
  }
  return prefixes;
}

RecordRow record_row(const std::string& file, const std::string& prefix, const AnalysisReport& report, bool windowed) {
  RecordRow row;
  row.file = file;
  row.prefix = prefix;
  analysed_stretch(report, windowed, row);
  const RecordSpectrum& s = report.spectrum;
  row.v = s.sliding.v;
  row.v_error = s.sliding.v_error;
  if (s.usable_high > s.usable_low) row.usable_low = s.usable_low, row.usable_high = s.usable_high;
  if (report.slope) {
    row.slope = report.slope->slope;
    row.slope_error = report.slope->slope_error;
  } else if (report.power_law) {
    row.slope = report.power_law->slope;
    row.slope_error = report.power_law->slope_error;
  }
  if (report.alpha) row.alpha = report.alpha->alpha, row.alpha_error = report.alpha->alpha_error;
  row.ok = report.ok();
  if (!row.ok) row.reason = worded(report.failure(), FrontEnd::command_line);
  return row;
}

RecordRow refused_row(const std::string& file, const std::string& reason) {
  RecordRow row;
  row.file = file;
  row.reason = reason;
  return row;
}

std::string records_table(const std::vector<RecordRow>& rows, std::size_t named) {
  std::ostringstream out;
  const auto failed = std::count_if(rows.begin(), rows.end(), [](const RecordRow& r) { return !r.ok; });
  out << "# slidespec " << SLIDESPEC_VERSION << " analyze: " << rows.size() << " of " << named << " records, " << failed
      << " not ok\n"
      << "# columns: file; outputs (its PREFIX.tsv/.json, - when refused); segment analysed (sliding, strokes, "
         "window, whole; - when refused); start, end [s]; v, v_err [m/s]; usable_low, usable_high [rad/s]; slope, "
         "slope_err (--fit-slope, else --fit power-law); alpha, alpha_err (--fit alpha); strokes; ok (1/0); "
         "reason\n"
      << "file\toutputs\tsegment\tstart\tend\tv\tv_err\tusable_low\tusable_high\tslope\tslope_err\talpha\talpha_"
         "err\tstrokes\tok\treason\n";
  for (const RecordRow& r : rows)
    out << cell(r.file) << "\t" << (r.prefix.empty() ? "-" : cell(r.prefix)) << "\t"
        << (r.segment.empty() ? "-" : r.segment) << "\t" << number(r.start) << "\t" << number(r.end) << "\t"
        << number(r.v) << "\t" << number(r.v_error) << "\t" << number(r.usable_low) << "\t" << number(r.usable_high)
        << "\t" << number(r.slope) << "\t" << number(r.slope_error) << "\t" << number(r.alpha) << "\t"
        << number(r.alpha_error) << "\t" << r.strokes << "\t" << (r.ok ? 1 : 0) << "\t" << cell(r.reason) << "\n";
  return out.str();
}

std::string records_json(const std::vector<RecordRow>& rows, std::size_t named) {
  nlohmann::ordered_json doc;
  doc["slidespec_version"] = SLIDESPEC_VERSION;
  doc["named"] = named;
  doc["records"] = nlohmann::ordered_json::array();
  for (const RecordRow& r : rows)
    doc["records"].push_back(
        {{"file", r.file},
         {"outputs", r.prefix.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.prefix)},
         {"segment", r.segment.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.segment)},
         {"start", json_number(r.start)},
         {"end", json_number(r.end)},
         {"v", json_number(r.v)},
         {"v_err", json_number(r.v_error)},
         {"usable_low", json_number(r.usable_low)},
         {"usable_high", json_number(r.usable_high)},
         {"slope", json_number(r.slope)},
         {"slope_err", json_number(r.slope_error)},
         {"alpha", json_number(r.alpha)},
         {"alpha_err", json_number(r.alpha_error)},
         {"strokes", r.strokes},
         {"ok", r.ok},
         {"reason", r.reason}});
  return io::json_file_text(doc);
}

}  // namespace slidespec::cli
