// The text forms of results: TSV tables with '#' metadata lines, and JSON.
#pragma once

#include <string>

#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec::io {

/// Fixed-width scientific notation, 10 significant digits.
std::string format_number(double x);

/// '#' lines: version, case, every parameter, and the landmarks of the theory.
std::string metadata_lines(const Parameters& p, const std::string& case_name);

/// The run's table: metadata, the run's own facts, a header, one row per point.
std::string run_table(const Parameters& p, const std::string& case_name, const RunRequest& request,
                      const RunResult& result);

/// The same as JSON, plus wall time, throughput, SIMD path and threads.
std::string run_json(const Parameters& p, const std::string& case_name, const RunRequest& request,
                     const RunResult& result);

}  // namespace slidespec::io
