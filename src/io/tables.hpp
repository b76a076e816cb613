// The text forms of results: TSV tables with '#' metadata lines, and JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "slidespec/options.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec::io {

/// "reference + N=5, alpha=3": the case and the parameters that differ from it (eta1 is
/// derived, so left out); the case alone when none differ.
std::string run_label(const std::string& case_name, const Parameters& p);

/// The case of a run label "reference + N=5, alpha=3" (the label itself when no keys were set).
std::string case_of(const std::string& label);

/// A parameter's value as PREFIX.json holds it: a whole number, a real, or a word.
using ParameterValue = std::variant<long long, double, std::string>;
/// Every parameter (describe's keys, in its order) with its value so typed: what
/// parameters_json writes, for a front end that builds its own objects.
std::vector<std::pair<std::string, ParameterValue>> parameter_values(const Parameters& p);

/// The parameters as a JSON object of numbers (and the words of chain, renewal,
/// touching), in the form --params reads back.
nlohmann::ordered_json parameters_json(const Parameters& p);

/// "slidespec 1.2.0, fftw-3.3.10, Eigen 3.4.0, xsimd 8.1.0, g++ 12.2.0": what built this
/// program, as a run's outputs record it.
std::string versions();

/// A JSON document as an output file holds it (indented, newline-ended). Text that is not
/// UTF-8 (a Latin-1 header of a record, say) is written with U+FFFD in place of the bytes
/// it cannot hold, rather than failing the whole output set.
std::string json_file_text(const nlohmann::ordered_json& doc);

/// '#' lines: version, case (and label when keys were set), every parameter, and the
/// landmarks of the theory. `case_name` may be a label "CASE + KEY=V, ...".
std::string metadata_lines(const Parameters& p, const std::string& case_name);

/// What each column of a run's point holds, with units: the text of the table's "# columns:"
/// line; and of its spring's force columns (run_point_header's `spring_columns`).
std::string run_point_notes();
std::string run_point_spring_notes();

/// The names of a run point's columns, tab-separated, in run_point_row's order; with
/// `spring_columns` the spring's force spectrum (C_F_spring, its stderr and theory) last.
std::string run_point_header(bool spring_columns);

/// One point's row of a table (no newline). The spring's force columns, when asked for,
/// are nan for a run driven by a force (a sweep across drives has them in every row).
std::string run_point_row(const Parameters& p, const RunPoint& point, bool spring_columns);

/// One point as a run's JSON holds it: point_json's fields, the theories, the estimator, the
/// correction, and under a spring its force spectrum.
nlohmann::ordered_json run_point_json(const Parameters& p, const RunPoint& point);

/// The run's table: metadata, the run's own facts, a header, one row per point. The
/// result's notes name options as `reader` spells them.
std::string run_table(const Parameters& p, const std::string& case_name, const RunRequest& request,
                      const RunResult& result, FrontEnd reader = FrontEnd::command_line);

/// The request as a run's JSON holds it: every field that changes a number (threads, SIMD
/// path and work budget change none).
nlohmann::ordered_json request_json(const RunRequest& request);

/// The same as JSON, plus wall time, throughput, SIMD path and threads.
std::string run_json(const Parameters& p, const std::string& case_name, const RunRequest& request,
                     const RunResult& result, FrontEnd reader = FrontEnd::command_line);

/// A result back from the document run_json wrote (its notes as worded there, a null
/// number as nan): run_json of it gives that document again. Throws InputError when a
/// field is missing or of another type.
RunResult run_result_from_json(const nlohmann::ordered_json& doc);

}  // namespace slidespec::io
