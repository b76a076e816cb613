// Reading a sensor record: the formats a lab's acquisition software writes, and every
// way such a file can be wrong refused with the line that shows it.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <istream>
#include <sstream>

#include "analysis/sampling.hpp"
#include "util/suggest.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec {

namespace {

std::optional<LengthUnit> length_unit(const std::string& name) {
  if (name == "m") return LengthUnit::m;
  if (name == "mm") return LengthUnit::mm;
  if (name == "um" || name == "\u00b5m" || name == "\u03bcm" || name == "micron" || name == "microns" ||
      name == "micrometre" || name == "micrometres" || name == "micrometer" || name == "micrometers")
    return LengthUnit::um;
  if (name == "nm") return LengthUnit::nm;
  return std::nullopt;
}

/// Seconds in one time unit of a header (t_ms, time (us)), or 0 when not a time unit.
double seconds_per(const std::string& name) {
  if (name == "s") return 1;
  if (name == "ms") return 1e-3;
  if (name == "us" || name == "\u00b5s" || name == "\u03bcs") return 1e-6;
  return 0;
}

}  // namespace

LengthUnit parse_length_unit(const std::string& name, const std::string& option) {
  if (const auto unit = length_unit(name)) return *unit;
  throw InputError(option + ": unknown unit '" + name + "'" +
                   util::did_you_mean(name, {"m", "mm", "um", "nm", "microns"}) +
                   " (lengths: m, mm, um, microns, nm; a force or stress channel is not read as a displacement)");
}

double parse_length(const std::string& text, LengthUnit bare_unit, const std::string& option) {
  double value = 0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  std::string unit_name(stop, end);
  unit_name.erase(0, unit_name.find_first_not_of(' '));
  if (error != std::errc() || stop == begin || !std::isfinite(value) || value < 0)
    throw InputError(option + ": '" + text + "' is not a length >= 0 (e.g. 0.5, in the record's unit, or 0.5um)");
  return value * metres_per(unit_name.empty() ? bare_unit : parse_length_unit(unit_name, option));
}

const char* to_string(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::m:
      return "m";
    case LengthUnit::mm:
      return "mm";
    case LengthUnit::um:
      return "um";
    case LengthUnit::nm:
      return "nm";
  }
  return "?";
}

double metres_per(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::m:
      return 1.0;
    case LengthUnit::mm:
      return 1e-3;
    case LengthUnit::um:
      return 1e-6;
    case LengthUnit::nm:
      return 1e-9;
  }
  return 1.0;
}

namespace {

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") + 1 - first);
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/// True while `field` has a bracket or parenthesis it has not closed.
bool open_bracket(const std::string& field) {
  return std::count(field.begin(), field.end(), '(') > std::count(field.begin(), field.end(), ')') ||
         std::count(field.begin(), field.end(), '[') > std::count(field.begin(), field.end(), ']');
}

/// Fields of one line: split on commas, else tabs or semicolons, else runs of whitespace
/// (where a unit in brackets stays with its name: "x (mm)", "t [s]").
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  for (const char separator : {',', '\t', ';'}) {
    if (line.find(separator) == std::string::npos) continue;
    std::string field;
    std::istringstream stream(line);
    while (std::getline(stream, field, separator)) fields.push_back(trim(field));
    if (!line.empty() && line.back() == separator) fields.emplace_back();
    return fields;
  }
  std::istringstream stream(line);
  for (std::string field; stream >> field;) {
    if (!fields.empty() && (field[0] == '(' || field[0] == '[' || open_bracket(fields.back())))
      fields.back() += " " + field;
    else
      fields.push_back(field);
  }
  return fields;
}

/// The whole field as a finite number, or false. from_chars does not accept a leading '+'.
bool parse_number(const std::string& field, double& value) {
  const char* begin = field.data() + (!field.empty() && field[0] == '+' ? 1 : 0);
  const char* end = field.data() + field.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  return error == std::errc() && stop == end && begin != end && std::isfinite(value);
}

bool is_number(const std::string& field) {
  double ignored;
  if (parse_number(field, ignored)) return true;
  const std::string word = lower(field);
  return word == "nan" || word == "-nan" || word == "inf" || word == "-inf" || word == "infinity";
}

std::string column_list(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

/// A header name and the unit it carries: "time (s)", "t [ms]", "x_mm", "position [um]";
/// a name that is a length unit alone ("nm") has an empty base.
struct ColumnName {
  std::string base, unit;
};

ColumnName split_unit(const std::string& name) {
  const std::string n = lower(trim(name));
  auto known = [](const std::string& u) { return length_unit(u).has_value() || seconds_per(u) > 0; };
  if (known(n)) return {"", n};
  for (const auto& [open, close] : {std::pair{'(', ')'}, std::pair{'[', ']'}}) {
    const auto start = n.rfind(open);
    if (start != std::string::npos && !n.empty() && n.back() == close) {
      const std::string unit = trim(n.substr(start + 1, n.size() - start - 2));
      if (known(unit)) return {trim(n.substr(0, start)), unit};
    }
  }
  for (const char separator : {'_', '/'}) {
    const auto at = n.rfind(separator);
    if (at != std::string::npos && at > 0 && known(n.substr(at + 1))) return {n.substr(0, at), n.substr(at + 1)};
  }
  return {n, ""};
}

bool is_time_name(const ColumnName& c) {
  return (c.base == "t" || c.base == "time") && (c.unit.empty() || seconds_per(c.unit) > 0);
}

bool is_displacement_name(const ColumnName& c) {
  static const std::vector<std::string> bases = {"x",     "pos",  "position", "displacement", "distance",
                                                 "displ", "disp", "lp_displ", "slip",         "sliding distance"};
  const bool unit_ok = c.unit.empty() || length_unit(c.unit).has_value();
  return unit_ok &&
         (std::find(bases.begin(), bases.end(), c.base) != bases.end() || (c.base.empty() && !c.unit.empty()));
}

/// A header naming a force, a stress or a friction coefficient (Friction, mu, shear_MPa,
/// Normal_stress(MPa), F (N)): never read as a displacement. What it holds, or empty.
std::string force_like(const std::string& name) {
  const std::string n = lower(name);
  for (const char* word :
       {"friction", "stress", "shear", "force", "tau", "sigma", "mpa", "kpa", "(n)", "[n]", "(kn)", "[kn]"})
    if (n.find(word) != std::string::npos) return "a force, stress or friction channel";
  for (const char* unit : {"_n", "_kn", " n", " kn"})
    if (n.size() > std::string(unit).size() && n.ends_with(unit)) return "a force channel";
  if (n == "mu" || n.rfind("mu ", 0) == 0 || n.rfind("mu_", 0) == 0 || n.rfind("mu(", 0) == 0)
    return "a friction coefficient";
  return "";
}

/// "0,001;2,5" or "0,001<TAB>2,5": numbers written with a decimal comma.
bool looks_like_decimal_commas(const std::string& line) {
  if (line.find(';') == std::string::npos && line.find('\t') == std::string::npos) return false;
  for (std::size_t k = 1; k + 1 < line.size(); ++k)
    if (line[k] == ',' && std::isdigit(static_cast<unsigned char>(line[k - 1])) &&
        std::isdigit(static_cast<unsigned char>(line[k + 1])))
      return true;
  return false;
}

class RecordReader {
 public:
  RecordReader(const std::string& source, const RecordFormat& format) : source_(source), format_(format) {}

  Record read(std::istream& in) {
    std::string line;
    for (int line_number = 1; std::getline(in, line); ++line_number) {
      if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
      raw_line_ = line;
      const auto comment = line.find('#');
      if (comment != std::string::npos) line.erase(comment);
      line = trim(line);
      if (line.empty()) continue;
      take_line(split_fields(line), line_number);
    }
    if (names_.empty() || record_.displacement.empty()) throw InputError(source_ + ": no data lines");
    if (record_.displacement.size() < 2)
      throw InputError(source_ + ": line " + std::to_string(last_line_) +
                       ": the only sample; a spectrum needs a record of many samples");
    finish();
    return record_;
  }

  /// Samples given as numbers (t empty: format.dt), checked as lines of a file are.
  Record from_samples(const std::vector<double>& time, const std::vector<double>& x) {
    place_ = "sample";
    names_ = {"t", "x"};
    record_.column = names_[1];
    if (!time.empty() && time.size() != x.size())
      throw InputError(source_ + ": " + std::to_string(time.size()) + " times for " + std::to_string(x.size()) +
                       " samples");
    for (std::size_t k = 0; k < x.size(); ++k) {
      const int sample = static_cast<int>(k);
      if (!std::isfinite(x[k])) fail(sample, "x is not a finite number");
      if (!time.empty()) {
        if (!std::isfinite(time[k])) fail(sample, "t is not a finite number");
        take_time(time[k], sample);
      }
      record_.displacement.push_back(x[k] * metres_per(format_.unit.value_or(LengthUnit::m)));
    }
    if (x.size() < 2)
      throw InputError(source_ + ": a spectrum needs a record of many samples, not " + std::to_string(x.size()));
    finish();
    return record_;
  }

 private:
  [[noreturn]] void fail(int where, const std::string& what) const {
    const std::string hint =
        looks_like_decimal_commas(raw_line_) ? " (decimal commas? write numbers with a point, e.g. sed 's/,/./g')" : "";
    throw InputError(source_ + ": " + place_ + " " + std::to_string(where) + ": " + what + hint);
  }

  void take_line(const std::vector<std::string>& fields, int line_number) {
    if (names_.empty()) {
      const bool header = !std::all_of(fields.begin(), fields.end(), is_number);
      for (std::size_t k = 0; k < fields.size(); ++k) names_.push_back(header ? fields[k] : std::to_string(k + 1));
      choose_columns(line_number);
      if (header) return;
    }
    if (fields.size() != names_.size())
      fail(line_number, std::to_string(fields.size()) + " fields, expected " + std::to_string(names_.size()) + " (" +
                            column_list(names_) + ")");
    const double x = number(fields, x_index_, line_number) * metres_per(record_.unit);
    if (time_index_ >= 0) take_time(number(fields, time_index_, line_number) * seconds_per_time_, line_number);
    record_.displacement.push_back(x);
    last_line_ = line_number;
  }

  double number(const std::vector<std::string>& fields, int index, int line_number) const {
    double value;
    const std::string& field = fields[static_cast<std::size_t>(index)];
    if (parse_number(field, value)) return value;
    const std::string& name = names_[static_cast<std::size_t>(index)];
    if (field.empty()) fail(line_number, "column " + name + " is empty");
    if (is_number(field)) fail(line_number, "column " + name + ": '" + field + "' is not a finite number");
    fail(line_number, "column " + name + ": '" + field + "' is not a number");
  }

  int find_column(const std::string& name, const char* option, int line_number) const {
    const auto found = std::find(names_.begin(), names_.end(), name);
    if (found == names_.end())
      fail(line_number, std::string(option) + ": no column '" + name + "' (columns: " + column_list(names_) + ")");
    return static_cast<int>(found - names_.begin());
  }

  void choose_columns(int line_number) {
    const int count = static_cast<int>(names_.size());
    if (format_.dt <= 0) {
      if (!format_.time_column.empty()) {
        time_index_ = find_column(format_.time_column, "--time-column", line_number);
      } else {
        for (int k = 0; k < count && time_index_ < 0; ++k)
          if (is_time_name(split_unit(names_[k]))) time_index_ = k;
        if (time_index_ < 0 && count == 2 && names_[0] == "1") time_index_ = 0;
        if (time_index_ < 0)
          fail(line_number,
               "no time column (columns: " + column_list(names_) + "); name it with --time-column or give --dt");
      }
    }
    if (format_.dt > 0)
      for (int k = 0; k < count; ++k)
        if (is_time_name(split_unit(names_[k])))
          fail(line_number, "--dt: the record has a time column '" + names_[k] +
                                "'; --dt is for records without one (the time column is read by default)");
    if (!format_.column.empty()) {
      x_index_ = find_column(format_.column, "--column", line_number);
      const std::string holds = force_like(names_[static_cast<std::size_t>(x_index_)]);
      if (!holds.empty())
        fail(line_number, "--column " + format_.column + ": the header names " + holds +
                              ", not a displacement; analyze reads displacements only (give the displacement column)");
    } else {
      for (int k = 0; k < count && x_index_ < 0; ++k)
        if (k != time_index_ && is_displacement_name(split_unit(names_[k])) && force_like(names_[k]).empty())
          x_index_ = k;
      if (x_index_ < 0 && count - (time_index_ >= 0 ? 1 : 0) == 1) {
        x_index_ = time_index_ == 0 ? 1 : 0;
        const std::string holds = force_like(names_[static_cast<std::size_t>(x_index_)]);
        if (!holds.empty())
          fail(line_number, "the only column besides time, '" + names_[static_cast<std::size_t>(x_index_)] +
                                "', names " + holds + ", not a displacement; analyze reads displacements only");
      }
      if (x_index_ < 0)
        fail(line_number, "which column is the displacement? give --column (columns: " + column_list(names_) + ")");
    }
    if (x_index_ == time_index_) fail(line_number, "the displacement column is the time column");
    record_.column = names_[static_cast<std::size_t>(x_index_)];
    if (time_index_ >= 0) {
      const std::string unit = split_unit(names_[static_cast<std::size_t>(time_index_)]).unit;
      if (seconds_per(unit) > 0) seconds_per_time_ = seconds_per(unit);
    }
    const std::string header_unit = split_unit(record_.column).unit;
    if (format_.unit) {
      record_.unit = *format_.unit;
      record_.unit_source = "--units";
    } else if (const auto unit = length_unit(header_unit)) {
      record_.unit = *unit;
      record_.unit_source = "header";
    } else {
      record_.unit = LengthUnit::m;
      record_.unit_source = "default";
    }
  }

  // Uniform sampling is what a spectrum of samples assumes: a missing sample (a gap) or
  // a clock jump would fold into the spectrum silently, so both are refused here.
  void finish() {
    if (times_.empty()) {
      record_.dt = format_.dt;
      detail::apply_window(record_, format_, source_);
      if (format_.resample == Resampling::median || format_.resample == Resampling::interval)
        throw InputError("--resample: the record has no time column (--dt); its samples are uniform");
    } else {
      detail::make_uniform(record_, times_, where_, source_, place_, format_);
    }
  }

  void take_time(double t, int line_number) {
    if (!times_.empty() && !(t > times_.back()))
      fail(line_number,
           "time " + std::to_string(t) + " s does not increase (previous " + std::to_string(times_.back()) + " s)");
    times_.push_back(t);
    where_.push_back(line_number);
  }

  std::string source_;
  std::string place_ = "line";
  RecordFormat format_;
  std::vector<std::string> names_;
  int time_index_ = -1, x_index_ = -1;
  int last_line_ = 0;
  std::vector<double> times_;  // [s], as read
  std::vector<int> where_;     // the line (or sample) of each time
  double seconds_per_time_ = 1;
  std::string raw_line_;
  Record record_;
};

void check_format(const RecordFormat& format) {
  if (format.dt < 0 || !std::isfinite(format.dt)) throw InputError("--dt: must be a positive number of seconds");
  if (!(format.time_tolerance > 0 && format.time_tolerance < 0.5))
    throw InputError("time tolerance must be between 0 and 0.5");
}

}  // namespace

Record read_record(std::istream& in, const std::string& source, const RecordFormat& format) {
  check_format(format);
  return RecordReader(source, format).read(in);
}

Record record_from_samples(const std::vector<double>& time, const std::vector<double>& x, const RecordFormat& format,
                           const std::string& source) {
  check_format(format);
  if (time.empty() && !(format.dt > 0)) throw InputError(source + ": give the sample times or a positive dt");
  return RecordReader(source, format).from_samples(time, x);
}

Record read_record_file(const std::string& path, const RecordFormat& format) {
  if (path == "-") return read_record(std::cin, "stdin", format);
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  return read_record(in, path, format);
}

}  // namespace slidespec
