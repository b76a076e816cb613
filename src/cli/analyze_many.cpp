#include "cli/analyze_many.hpp"

#include "io/tables.hpp"

#include <glob.h>

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

std::vector<std::string> record_prefixes(const std::string& out, const std::vector<std::string>& records) {
  std::vector<std::string> prefixes;
  std::map<std::string, std::string> by_prefix;
  for (const std::string& record : records) {
    if (record == "-") throw InputError("analyze: standard input ('-') is one record alone, not one of many");
    prefixes.push_back(out + "_" + std::filesystem::path(record).stem().string());
    const auto [other, fresh] = by_prefix.emplace(prefixes.back(), record);
    std::error_code unknown;
    if (!fresh && std::filesystem::equivalent(other->second, record, unknown))
      throw InputError("analyze: " + record + " is given twice; give each record once");
    if (!fresh)
      throw InputError("analyze: " + other->second + " and " + record + " would both write " + prefixes.back() +
                       ".tsv; give records of different names");
  }
  return prefixes;
}

std::string records_table(const std::vector<ListedRecord>& rows, std::size_t named) {
  std::ostringstream out;
  const auto failed = std::count_if(rows.begin(), rows.end(), [](const ListedRecord& r) { return !r.row.ok; });
  out << "# slidespec " << SLIDESPEC_VERSION << " analyze: " << rows.size() << " of " << named << " records, " << failed
      << " not ok\n"
      << "# columns: file; outputs (its PREFIX.tsv/.json, - when refused); segment analysed (sliding, strokes, "
         "window, whole; - when refused); start, end [s]; v, v_err [m/s]; usable_low, usable_high [rad/s]; slope, "
         "slope_err (--fit-slope, else --fit power-law); alpha, alpha_err (--fit alpha); strokes; ok (1/0); "
         "reason\n"
      << "file\toutputs\tsegment\tstart\tend\tv\tv_err\tusable_low\tusable_high\tslope\tslope_err\talpha\talpha_"
         "err\tstrokes\tok\treason\n";
  for (const auto& [r, prefix] : rows)
    out << cell(r.file) << "\t" << (prefix.empty() ? "-" : cell(prefix)) << "\t"
        << (r.segment.empty() ? "-" : r.segment) << "\t" << number(r.start) << "\t" << number(r.end) << "\t"
        << number(r.v) << "\t" << number(r.v_error) << "\t" << number(r.usable_low) << "\t" << number(r.usable_high)
        << "\t" << number(r.slope) << "\t" << number(r.slope_error) << "\t" << number(r.alpha) << "\t"
        << number(r.alpha_error) << "\t" << r.strokes << "\t" << (r.ok ? 1 : 0) << "\t"
        << cell(worded(r.reason, FrontEnd::command_line)) << "\n";
  return out.str();
}

std::string records_json(const std::vector<ListedRecord>& rows, std::size_t named) {
  nlohmann::ordered_json doc;
  doc["slidespec_version"] = SLIDESPEC_VERSION;
  doc["named"] = named;
  doc["records"] = nlohmann::ordered_json::array();
  for (const auto& [r, prefix] : rows)
    doc["records"].push_back(
        {{"file", r.file},
         {"outputs", prefix.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(prefix)},
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
         {"reason", worded(r.reason, FrontEnd::command_line)}});
  return io::json_file_text(doc);
}

}  // namespace slidespec::cli
