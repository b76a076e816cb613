#include "slidespec/many_records.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "slidespec/input_error.hpp"

namespace slidespec {

namespace {

/// What the report analysed, in the segment kinds' words, and its first and last time [s].
void analysed_stretch(const AnalysisReport& report, bool windowed, RecordRow& row) {
  const Record& record = report.record;
  row.start = record.start_time;
  row.end = report.end_time();
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

RecordRow record_row(const std::string& file, const AnalysisReport& report, bool windowed) {
  RecordRow row;
  row.file = file;
  analysed_stretch(report, windowed, row);
  const RecordSpectrum& s = report.spectrum;
  row.v = s.sliding.v;
  row.v_error = s.sliding.v_error;
  if (s.has_usable_band()) row.usable_low = s.usable_low, row.usable_high = s.usable_high;
  if (report.slope) {
    row.slope = report.slope->slope;
    row.slope_error = report.slope->slope_error;
  } else if (report.power_law) {
    row.slope = report.power_law->slope;
    row.slope_error = report.power_law->slope_error;
  }
  if (report.alpha) row.alpha = report.alpha->alpha, row.alpha_error = report.alpha->alpha_error;
  row.ok = report.ok();
  if (!row.ok) row.reason = report.failure();
  return row;
}

RecordRow refused_row(const std::string& file, const std::string& reason) {
  RecordRow row;
  row.file = file;
  row.reason = reason;
  return row;
}

void refuse_unreadable_record(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw InputError(path + ": a directory, not a record");
  if (!std::filesystem::exists(path, error)) throw InputError(path + ": no such file");
  if (access(path.c_str(), R_OK) != 0) throw InputError(path + ": not readable");
}

RecordOfMany analyze_one_of_many(const std::string& path, const RecordFormat& format, const AnalysisPlan& plan) {
  try {
    refuse_unreadable_record(path);
    AnalysisReport report = analyze(read_record_file(path, format), plan);
    RecordRow row = record_row(path, report, format.window.has_value());
    return {std::move(row), std::move(report)};
  } catch (const InputError& e) {
    return {refused_row(path, e.what()), std::nullopt};
  }
}

}  // namespace slidespec
