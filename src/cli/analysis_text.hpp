// The command line's words for an analysis: PREFIX.tsv and the summary on standard error.
#pragma once

#include <string>

#include "slidespec/analysis.hpp"

namespace slidespec::cli {

/// What the command line knows of an analysis beyond its report.
struct AnalysisSource {
  std::string file;          ///< the record as named on the command line
  std::string compare_case;  ///< "" when none
};

/// PREFIX.tsv: '#' lines (the compared case's, the record's, each fit's), then a row per point.
std::string analysis_table(const AnalysisSource& source, const AnalysisReport& report);

/// The notes, warnings and failed fits, on standard error: printed even with --quiet, since
/// they change what the files mean.
void print_messages(const AnalysisReport& report);

/// The summary on standard error: the record, the spectrum, its band, each fit.
void print_summary(const AnalysisSource& source, const AnalysisReport& report);

}  // namespace slidespec::cli
