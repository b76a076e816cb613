#include "io/table_reader.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "util/numbers.hpp"

namespace slidespec::io {

namespace {

std::vector<std::string> tab_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string field; std::getline(in, field, '\t');) fields.push_back(field);
  return fields;
}

}  // namespace

std::optional<std::string> Table::value(const std::string& key) const {
  for (auto line = metadata.rbegin(); line != metadata.rend(); ++line)
    if (line->first == key) return line->second;
  return std::nullopt;
}

std::optional<double> Table::number(const std::string& key) const {
  const std::optional<std::string> text = value(key);
  return text ? util::parse_number(*text) : std::nullopt;
}

const std::vector<double>& Table::column(const std::string& name) const {
  static const std::vector<double> none;
  const auto found = columns.find(name);
  return found == columns.end() ? none : found->second;
}

Table read_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  Table table;
  std::vector<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("#", 0) == 0) {
      const auto equals = line.find(" = ");
      if (equals != std::string::npos && names.empty()) {
        std::string key = line.substr(1, equals - 1);
        key.erase(0, key.find_first_not_of(' '));
        table.metadata.emplace_back(key, line.substr(equals + 3, line.find("  #", equals) - equals - 3));
      } else if (line.find('\t') != std::string::npos) {
        names = tab_fields(line.substr(line.find_first_not_of("# ")));
      }
      continue;
    }
    const std::vector<std::string> fields = tab_fields(line);
    if (fields.empty()) continue;
    if (names.empty() || !util::parse_number(fields[0])) {
      names = fields;
      continue;
    }
    for (std::size_t k = 0; k < names.size() && k < fields.size(); ++k)
      table.columns[names[k]].push_back(util::parse_number(fields[k]).value_or(NAN));
  }
  return table;
}

}  // namespace slidespec::io
