// The text forms of results: TSV tables with '#' metadata lines, and JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec::io {

/// "reference + N=5, alpha=3": the case and the parameters that differ from it (eta1 is
/// derived, so left out); the case alone when none differ.
std::string run_label(const std::string& case_name, const Parameters& p);

/// The case of a run label "reference + N=5, alpha=3" (the label itself when no keys were set).
std::string case_of(const std::string& label);

/// The parameters as a JSON object of numbers (and the words of chain, renewal,
/// touching), in the form --params reads back.
nlohmann::ordered_json parameters_json(const Parameters& p);

/// "slidespec 1.2.0, fftw-3.3.10, Eigen 3.4.0, xsimd 8.1.0, g++ 12.2.0": what built this
/// program, as a run's outputs record it.
std::string versions();

/// drive = spring outside the first-order theory's range: why, in one line.

/// '#' lines: version, case (and label when keys were set), every parameter, and the
/// landmarks of the theory. `case_name` may be a label "CASE + KEY=V, ...".
std::string metadata_lines(const Parameters& p, const std::string& case_name);

/// The run's table: metadata, the run's own facts, a header, one row per point.
std::string run_table(const Parameters& p, const std::string& case_name, const RunRequest& request,
                      const RunResult& result);

/// The same as JSON, plus wall time, throughput, SIMD path and threads.
std::string run_json(const Parameters& p, const std::string& case_name, const RunRequest& request,
                     const RunResult& result);

}  // namespace slidespec::io
