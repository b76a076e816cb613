// Reading a sensor record: the formats a lab's acquisition software writes, and every
// way such a file can be wrong refused with the line that shows it.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <sstream>

#include "slidespec/analysis.hpp"

namespace slidespec {

LengthUnit parse_length_unit(const std::string& name) {
  if (name == "m") return LengthUnit::m;
  if (name == "mm") return LengthUnit::mm;
  if (name == "um") return LengthUnit::um;
  throw InputError("--units: unknown unit '" + name + "' (known: m, mm, um)");
}

const char* to_string(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::m: return "m";
    case LengthUnit::mm: return "mm";
    case LengthUnit::um: return "um";
  }
  return "?";
}

double metres_per(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::m: return 1.0;
    case LengthUnit::mm: return 1e-3;
    case LengthUnit::um: return 1e-6;
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

/// Fields of one line: split on commas, else tabs or semicolons, else runs of whitespace.
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
  for (std::string field; stream >> field;) fields.push_back(field);
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

class RecordReader {
 public:
  RecordReader(const std::string& source, const RecordFormat& format) : source_(source), format_(format) {}

  Record read(std::istream& in) {
    std::string line;
    for (int line_number = 1; std::getline(in, line); ++line_number) {
      const auto comment = line.find('#');
      if (comment != std::string::npos) line.erase(comment);
      line = trim(line);
      if (line.empty()) continue;
      take_line(split_fields(line), line_number);
    }
    if (names_.empty() || record_.displacement.empty())
      throw InputError(source_ + ": no data lines");
    if (record_.displacement.size() < 2)
      throw InputError(source_ + ": line " + std::to_string(last_line_) +
                       ": the only sample; a spectrum needs a record of many samples");
    if (time_index_ >= 0) record_.dt = (last_time_ - record_.start_time) / (record_.displacement.size() - 1);
    else record_.dt = format_.dt;
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
      record_.displacement.push_back(x[k] * metres_per(format_.unit));
    }
    if (x.size() < 2) throw InputError(source_ + ": a spectrum needs a record of many samples, not " +
                                       std::to_string(x.size()));
    record_.dt = time.empty() ? format_.dt : (last_time_ - record_.start_time) / static_cast<double>(x.size() - 1);
    return record_;
  }

 private:
  [[noreturn]] void fail(int where, const std::string& what) const {
    throw InputError(source_ + ": " + place_ + " " + std::to_string(where) + ": " + what);
  }

  void take_line(const std::vector<std::string>& fields, int line_number) {
    if (names_.empty()) {
      const bool header = !std::all_of(fields.begin(), fields.end(), is_number);
      for (std::size_t k = 0; k < fields.size(); ++k)
        names_.push_back(header ? fields[k] : std::to_string(k + 1));
      choose_columns(line_number);
      if (header) return;
    }
    if (fields.size() != names_.size())
      fail(line_number, std::to_string(fields.size()) + " fields, expected " + std::to_string(names_.size()) +
                            " (" + column_list(names_) + ")");
    const double x = number(fields, x_index_, line_number) * metres_per(format_.unit);
    if (time_index_ >= 0) take_time(number(fields, time_index_, line_number), line_number);
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
          if (const std::string n = lower(names_[k]); n == "t" || n == "time") time_index_ = k;
        if (time_index_ < 0 && count == 2 && names_[0] == "1") time_index_ = 0;
        if (time_index_ < 0)
          fail(line_number, "no time column (columns: " + column_list(names_) +
                                "); name it with --time-column or give --dt");
      }
    }
    if (!format_.column.empty()) {
      x_index_ = find_column(format_.column, "--column", line_number);
    } else {
      const auto x = std::find(names_.begin(), names_.end(), "x");
      if (x != names_.end()) x_index_ = static_cast<int>(x - names_.begin());
      else if (count - (time_index_ >= 0 ? 1 : 0) == 1) x_index_ = time_index_ == 0 ? 1 : 0;
      else fail(line_number, "which column is the displacement? give --column (columns: " + column_list(names_) + ")");
    }
    if (x_index_ == time_index_) fail(line_number, "the displacement column is the time column");
    record_.column = names_[static_cast<std::size_t>(x_index_)];
  }

  // Uniform sampling is what a spectrum of samples assumes: a missing sample (a gap) or
  // a clock jump would fold into the spectrum silently, so both are refused here.
  void take_time(double t, int line_number) {
    const std::size_t n = record_.displacement.size();
    if (n == 0) {
      record_.start_time = t;
    } else {
      const double interval = t - last_time_;
      if (interval <= 0)
        fail(line_number, "time " + std::to_string(t) + " s does not increase (previous " +
                              std::to_string(last_time_) + " s)");
      if (n == 1) first_interval_ = interval;
      const double nominal = (t - record_.start_time) / static_cast<double>(n);
      // Both the local interval and the cumulative clock are checked: jitter averages out
      // of the second, a slow drift or a single gap does not.
      if (std::abs(interval - first_interval_) > format_.time_tolerance * first_interval_ ||
          std::abs(nominal - first_interval_) > format_.time_tolerance * first_interval_)
        fail(line_number, "sampling is not uniform: interval " + shortest(interval) + " s where the record began with " +
                              shortest(first_interval_) + " s (a gap or clock jump; tolerance " +
                              shortest(format_.time_tolerance * 100) + "%)");
    }
    last_time_ = t;
  }

  static std::string shortest(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
  }

  std::string source_;
  std::string place_ = "line";
  RecordFormat format_;
  std::vector<std::string> names_;
  int time_index_ = -1, x_index_ = -1;
  int last_line_ = 0;
  double last_time_ = 0, first_interval_ = 0;
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

Record record_from_samples(const std::vector<double>& time, const std::vector<double>& x,
                           const RecordFormat& format, const std::string& source) {
  check_format(format);
  if (time.empty() && !(format.dt > 0)) throw InputError(source + ": give the sample times or a positive dt");
  return RecordReader(source, format).from_samples(time, x);
}

Record read_record_file(const std::string& path, const RecordFormat& format) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  return read_record(in, path, format);
}

}  // namespace slidespec
