#include "cli/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "io/tables.hpp"
#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

bool integer_key(const std::string& key) {
  const ParameterInfo* info = find_parameter(key);
  return info && info->kind == "count";
}

double parse_value(const std::string& text, const std::string& word) {
  const std::optional<double> value = util::parse_number(text);
  if (!value) throw InputError("sweep: '" + text + "' in '" + word + "' is not a number");
  return *value;
}

/// A grid value as text: 12 significant digits drop the rounding of FIRST + k STEP
/// (0.30000000000000004 is 0.3), then the shortest form.
std::string grid_value(double value, bool integer) {
  if (integer) return std::to_string(std::llround(value));
  char text[32];
  std::snprintf(text, sizeof text, "%.12g", value);
  return util::format_number(std::stod(text));
}

std::vector<std::string> range_values(const std::string& key, const std::string& range, const std::string& spacing,
                                      const std::string& count_text, const std::string& word) {
  const bool integer = integer_key(key);
  std::vector<double> values;
  if (const auto dots = range.find(".."); dots != std::string::npos) {
    if (spacing.empty())
      throw InputError("sweep: '" + word + "': say how many values, e.g. " + key + "=" + range + " log 5");
    const double first = parse_value(range.substr(0, dots), word), last = parse_value(range.substr(dots + 2), word);
    const double count = parse_value(count_text, word);
    if (count < 2 || count != std::floor(count) || count > 1000)
      throw InputError("sweep: '" + word + "': the number of values must be a whole number from 2 to 1000");
    if (spacing == "log" && !(first > 0 && last > 0))
      throw InputError("sweep: '" + word + "': a log range needs positive ends");
    for (int k = 0; k < static_cast<int>(count); ++k) {
      const double t = k / (count - 1);
      values.push_back(spacing == "log" ? first * std::pow(last / first, t) : first + (last - first) * t);
    }
  } else {
    const auto colon = range.find(':'), second = range.find(':', colon + 1);
    const double first = parse_value(range.substr(0, colon), word);
    const double last = parse_value(range.substr(colon + 1, second - colon - 1), word);
    const double step = parse_value(range.substr(second + 1), word);
    if (!(step > 0) || last < first)
      throw InputError("sweep: '" + word + "': FIRST:LAST:STEP needs STEP > 0 and LAST >= FIRST");
    const double count = std::floor((last - first) / step + 1e-9) + 1;
    if (count > 1000) throw InputError("sweep: '" + word + "' gives more than 1000 values");
    for (int k = 0; k < static_cast<int>(count); ++k) values.push_back(first + k * step);
  }
  // Values that round to one (N=10..12 log 5: 10, 10, 11, 11, 12) would run twice and
  // write once: refused, as the same value given twice in a list is.
  std::vector<std::string> texts;
  for (double value : values) texts.push_back(grid_value(value, integer));
  for (std::size_t k = 1; k < texts.size(); ++k)
    if (std::find(texts.begin(), texts.begin() + std::ptrdiff_t(k), texts[k]) != texts.begin() + std::ptrdiff_t(k)) {
      std::string all;
      for (const std::string& text : texts) all += (all.empty() ? "" : ", ") + text;
      throw InputError("sweep: '" + word + "' gives the value " + texts[k] + " more than once (" + all + ")" +
                       (integer ? ": " + key + " is a whole number" : "") + "; give fewer values");
    }
  return texts;
}

}  // namespace

std::vector<SweepAxis> parse_sweep(const std::vector<std::string>& arguments) {
  // A quoted grid ("N=10..30 lin 2") is the same words as the unquoted one.
  std::vector<std::string> words;
  for (const std::string& argument : arguments) {
    std::istringstream split(argument);
    for (std::string word; split >> word;) words.push_back(word);
  }
  std::vector<SweepAxis> axes;
  for (std::size_t k = 0; k < words.size(); ++k) {
    const std::string& word = words[k];
    const auto equals = word.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == word.size())
      throw InputError("sweep: expected KEY=V1,V2,..., KEY=FIRST:LAST:STEP or KEY=FIRST..LAST log|lin K, got '" + word +
                       "'");
    SweepAxis axis{word.substr(0, equals), {}};
    for (const SweepAxis& other : axes)
      if (other.key == axis.key) throw InputError("sweep: key " + axis.key + " given twice");
    const std::string list = word.substr(equals + 1);
    const bool dotted = list.find("..") != std::string::npos;
    if (dotted || std::count(list.begin(), list.end(), ':') == 2) {
      std::string spacing, count;
      if (dotted && k + 2 < words.size() && (words[k + 1] == "log" || words[k + 1] == "lin")) {
        spacing = words[k + 1];
        count = words[k + 2];
        k += 2;
      }
      axis.values = range_values(axis.key, list, spacing, count, word);
    } else {
      std::stringstream values(list);
      for (std::string value; std::getline(values, value, ',');) {
        if (value.empty()) throw InputError("sweep: an empty value in '" + word + "'");
        axis.values.push_back(value);
      }
      if (list.back() == ',') throw InputError("sweep: an empty value in '" + word + "'");
      // The same value twice (0.5 and 0.50) would run twice, and its outputs once.
      std::map<double, std::string> numbers;
      std::set<std::string> words_seen;
      for (const std::string& value : axis.values) {
        const std::optional<double> number = util::parse_number(value);
        const auto [seen, fresh] = number ? numbers.emplace(*number, value) : std::pair{numbers.end(), true};
        if (!fresh || !words_seen.insert(value).second) {
          const std::string first = fresh ? value : seen->second;
          throw InputError("sweep: '" + word + "' gives the value " + first + " twice" +
                           (first == value ? "" : " (also as " + value + ")") + "; give each value once");
        }
      }
    }
    axes.push_back(axis);
  }
  if (axes.empty()) throw InputError("sweep: no KEY=VALUES given");
  std::size_t runs = 1;
  for (const SweepAxis& axis : axes) runs *= axis.values.size();
  if (runs > 10000) throw InputError("sweep: the grid has " + std::to_string(runs) + " runs (at most 10000)");
  return axes;
}

std::vector<std::vector<std::pair<std::string, std::string>>> sweep_grid(const std::vector<SweepAxis>& axes) {
  std::vector<std::vector<std::pair<std::string, std::string>>> grid = {{}};
  for (const SweepAxis& axis : axes) {
    std::vector<std::vector<std::pair<std::string, std::string>>> next;
    for (const auto& partial : grid)
      for (const std::string& value : axis.values) {
        next.push_back(partial);
        next.back().emplace_back(axis.key, value);
      }
    grid = std::move(next);
  }
  return grid;
}

std::vector<double> sub_band_work(const Parameters& p, const RunRequest& request) {
  double blocks = 1;
  for (int l = 1; l <= p.levels; ++l) blocks += static_cast<double>(p.blocks(l));
  std::vector<double> work;
  for (const SubBand& band : plan_sub_bands(p, request))
    work.push_back((band.duration / band.dt + band.warm_up / band.warm_up_dt) * blocks);
  return work;
}

double planned_work(const Parameters& p, const RunRequest& request) {
  double work = 0;
  for (double w : sub_band_work(p, request)) work += w;
  return std::max(work, 1.0);
}

double weighted_fraction(double fraction, const std::vector<double>& band_work) {
  double total = 0;
  for (double w : band_work) total += w;
  if (band_work.empty() || !(total > 0)) return fraction;
  const double position = std::clamp(fraction, 0.0, 1.0) * static_cast<double>(band_work.size());
  const std::size_t band = std::min(band_work.size() - 1, static_cast<std::size_t>(position));
  double before = 0;
  for (std::size_t b = 0; b < band; ++b) before += band_work[b];
  return (before + (position - static_cast<double>(band)) * band_work[band]) / total;
}

std::string sweep_table(const std::vector<SweepAxis>& axes, const std::vector<SweepRun>& runs) {
  std::ostringstream out;
  out << "# slidespec " << SLIDESPEC_VERSION << " sweep: " << runs.size() << " runs\n";
  // A word-valued key (chain, renewal, touching) is written as its value's index in the
  // sweep_KEY list, so the table stays numbers (numpy.loadtxt reads it with no options).
  std::vector<bool> words(axes.size(), false);
  for (std::size_t a = 0; a < axes.size(); ++a) {
    for (const std::string& value : axes[a].values) words[a] = words[a] || !util::parse_number(value);
    out << "# sweep_" << axes[a].key << " =";
    for (const std::string& value : axes[a].values) out << " " << value;
    out << (words[a] ? "  # its column holds the index of the value in this list" : "") << "\n";
  }
  for (std::size_t r = 0; r < runs.size(); ++r)
    out << "# run_" << r << " = " << runs[r].label << "  # " << runs[r].table
        << (runs[r].result.complete ? "" : ", incomplete")
        << (runs[r].result.stationary
                ? ""
                : ", NOT STATIONARY: " + worded(runs[r].result.stationarity, FrontEnd::command_line))
        << "\n";
  // One set of columns for every run: the spring's force columns when any run has a spring.
  const bool spring =
      std::any_of(runs.begin(), runs.end(), [](const SweepRun& run) { return run.parameters.drive == Drive::spring; });
  out << "# columns: run (index of the run_ lines); the swept keys; then as in each run's table: "
      << io::run_point_notes() << "\n";
  if (spring)
    out << "# columns (a run with drive=spring; nan in a force-driven run's rows): " << io::run_point_spring_notes()
        << "\n";
  out << "# run";
  for (const SweepAxis& axis : axes) out << "\t" << axis.key;
  out << "\t" << io::run_point_header(spring) << "\n";
  for (std::size_t r = 0; r < runs.size(); ++r)
    for (const RunPoint& point : runs[r].result.points) {
      out << r;
      for (std::size_t a = 0; a < axes.size(); ++a) {
        const std::string& value = runs[r].values[a].second;
        if (words[a])
          out << "\t" << std::find(axes[a].values.begin(), axes[a].values.end(), value) - axes[a].values.begin();
        else
          out << "\t" << value;
      }
      out << "\t" << io::run_point_row(runs[r].parameters, point, spring) << "\n";
    }
  return out.str();
}

std::string sweep_json(const std::vector<SweepAxis>& axes, const std::vector<SweepRun>& runs) {
  nlohmann::ordered_json doc;
  doc["slidespec_version"] = SLIDESPEC_VERSION;
  doc["keys"] = nlohmann::ordered_json::array();
  for (const SweepAxis& axis : axes) doc["keys"].push_back(axis.key);
  doc["runs"] = nlohmann::ordered_json::array();
  for (const SweepRun& run : runs) {
    nlohmann::ordered_json entry;
    for (const auto& [key, value] : run.values) {
      if (const auto number = util::parse_number(value))
        entry["values"][key] = *number;
      else
        entry["values"][key] = value;
    }
    entry["label"] = run.label;
    entry["table"] = run.table;
    entry["complete"] = run.result.complete;
    entry["stationary"] = run.result.stationary;
    if (!run.result.stationary) entry["stationarity"] = worded(run.result.stationarity, FrontEnd::command_line);
    entry["measured_mean_speed"] = {{"value", run.result.mean_speed}, {"standard_error", run.result.mean_speed_error}};
    entry["reached_precision"] = run.result.reached_precision;
    entry["points"] = nlohmann::ordered_json::array();
    for (const RunPoint& point : run.result.points)
      entry["points"].push_back(io::run_point_json(run.parameters, point));
    doc["runs"].push_back(entry);
  }
  return doc.dump(2) + "\n";
}

}  // namespace slidespec::cli
