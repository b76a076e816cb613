// Many records analysed alike, each one a row of a combined table: what `slidespec analyze
// A B C` and Python's ss.analyze_many list (docs/analysis.md, "Many records").
#pragma once

#include <limits>
#include <optional>
#include <string>

#include "slidespec/analysis.hpp"

namespace slidespec {

/// One record of many as the combined table lists it.
struct RecordRow {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::string file;  ///< as named
  /// What was analysed: sliding (the longest steady stretch), strokes, window, whole (one
  /// steady stretch, the whole record), or the kind of the longest stretch when none slides;
  /// "" when the record was refused.
  std::string segment;
  double start = kNone, end = kNone;               ///< of what was analysed [s, record time]
  double v = kNone, v_error = kNone;               ///< [m/s] (the force channel's trend [N/s])
  double usable_low = kNone, usable_high = kNone;  ///< [rad/s]
  double slope = kNone, slope_error = kNone;       ///< the slope fit's, else the power law's
  double alpha = kNone, alpha_error = kNone;       ///< the alpha fit's
  std::size_t strokes = 0;                         ///< strokes combined (0: none)
  bool ok = false;
  /// Why not ok ("" when ok), naming options as "{id}" for the front end to word.
  std::string reason;
};

/// The row of a record analysed (`windowed`: read through a window).
RecordRow record_row(const std::string& file, const AnalysisReport& report, bool windowed);

/// The row of a record that was not analysed, and why.
RecordRow refused_row(const std::string& file, const std::string& reason);

/// Refuses (InputError naming it) a record that is a directory, missing or not readable.
void refuse_unreadable_record(const std::string& path);

/// A record of many: its row, and its analysis unless it was refused.
struct RecordOfMany {
  RecordRow row;
  std::optional<AnalysisReport> report;
};

/// The record at `path` read with `format` and analysed as `plan` asks. A record refused (a
/// directory, unreadable, malformed, too short for the band) is no error here: its row says
/// why, so that the records after it are analysed.
RecordOfMany analyze_one_of_many(const std::string& path, const RecordFormat& format, const AnalysisPlan& plan);

}  // namespace slidespec
