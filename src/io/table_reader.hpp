// Tables read back: a run's, a theory's, a sweep's or a merge's TSV (tables.hpp), or one laid
// out the same way, for the figures and the theory line drawn beside them.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace slidespec::io {

/// A TSV table as written: '#' metadata, a column line, rows of numbers.
struct Table {
  /// The '#' "KEY = VALUE" lines before the column line, in the file's order, each value
  /// without its trailing "  # ..." comment.
  std::vector<std::pair<std::string, std::string>> metadata;
  /// Each column under the name the column line gives it; a field that is not a number is nan.
  std::map<std::string, std::vector<double>> columns;

  /// The value of KEY (its last line), if the table has one.
  std::optional<std::string> value(const std::string& key) const;
  /// The value of KEY as a number, if it is one.
  std::optional<double> number(const std::string& key) const;
  /// The column of that name; empty when the table has none.
  const std::vector<double>& column(const std::string& name) const;
};

/// Reads the table at `path`. The column line is a '#' line of tab-separated names or a
/// row whose first field is not a number. Throws std::runtime_error when it cannot be read.
Table read_table(const std::string& path);

}  // namespace slidespec::io
