// `slidespec analyze A B C` (or a glob): many records, each analysed as one record is, and
// one table of them all, as sweep has one of its runs.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "slidespec/analysis.hpp"

namespace slidespec::cli {

/// Whether the records named are many: more than one, or a glob pattern (quoted, so the
/// shell left it), which may match any number.
bool many_records(const std::vector<std::string>& arguments);

/// The records named: each argument a file, or a glob pattern (*, ? or [ in a name that is
/// no file) expanded in name order. Throws InputError for a pattern that matches no file.
std::vector<std::string> expand_record_paths(const std::vector<std::string>& arguments);

/// Refuses (InputError naming it) a record that is a directory or not readable: among many
/// records it is reported as they are analysed, not before (check_files sees only the others).
void refuse_unreadable_record(const std::string& path);

/// Each record's output prefix: OUT_STEM (OUT_run1 for run1.csv). Throws InputError for
/// standard input among many, or two records of one stem (their outputs would collide).
std::vector<std::string> record_prefixes(const std::string& out, const std::vector<std::string>& records);

/// One record of many as the combined table lists it.
struct RecordRow {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::string file;    ///< as named or matched
  std::string prefix;  ///< its own outputs, PREFIX.tsv/.json; "" when none were written
  /// What was analysed: sliding (the longest steady stretch), strokes, window, whole (one
  /// steady stretch, the whole record), or the kind of the longest stretch when none slides;
  /// "" when the record was refused.
  std::string segment;
  double start = kNone, end = kNone;               ///< of what was analysed [s, record time]
  double v = kNone, v_error = kNone;               ///< [m/s] (the force channel's trend [N/s])
  double usable_low = kNone, usable_high = kNone;  ///< [rad/s]
  double slope = kNone, slope_error = kNone;       ///< --fit-slope's, else the power law's
  double alpha = kNone, alpha_error = kNone;       ///< --fit alpha's
  std::size_t strokes = 0;                         ///< strokes combined (0: none)
  bool ok = false;
  std::string reason;  ///< why not ok, in the command line's words ("" when ok)
};

/// The row of a record analysed (`windowed`: read through --window).
RecordRow record_row(const std::string& file, const std::string& prefix, const AnalysisReport& report, bool windowed);

/// The row of a record that was not analysed, and why.
RecordRow refused_row(const std::string& file, const std::string& reason);

/// All records in one TSV: '#' lines, a column line, one row per record (text columns:
/// file, segment, reason; a number not found is nan).
std::string records_table(const std::vector<RecordRow>& rows, std::size_t named);
/// The same as JSON: {"records": [...], "named": N} (null for a number not found).
std::string records_json(const std::vector<RecordRow>& rows, std::size_t named);

}  // namespace slidespec::cli
