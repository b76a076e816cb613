// How `slidespec sweep --resume` continues an interrupted sweep: the record PREFIX.sweep says
// which sweep it was, and each run is taken from its complete outputs, continued from its
// state, or run; the combined set is then written as the uninterrupted sweep writes it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/sweep.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

/// What defines a sweep's numbers: its case, its grid, the request and every run's
/// parameters (threads, SIMD path, figure and budget change no number and are left out).
/// Written to PREFIX.sweep before its first run; removed once its combined set is whole.
nlohmann::ordered_json sweep_record(const std::string& case_name, const std::vector<SweepAxis>& axes,
                                    const RunRequest& request, const std::vector<Parameters>& runs);

/// Refuses (InputError, one line) to continue the sweep at `out` when OUT.sweep is missing
/// (nothing to continue) or holds another sweep than `record`, naming the first difference.
void check_sweep_record(const std::string& out, const nlohmann::ordered_json& record);

/// What an interrupted sweep left of one of its runs.
struct RunLeft {
  enum class From { nothing, state, outputs };
  From from = From::nothing;
  RunResult result;   ///< From::outputs: the run's result, read back from its JSON
  std::string rerun;  ///< why outputs there are not taken (incomplete, not reproduced)
};

/// What is left at `prefix` of the run of `p` and `request` (its outputs label it `label`):
/// its state, else its complete outputs when its JSON rewrites both its files byte for byte.
/// Refuses (InputError naming `shown`, the run) a state or outputs of another run.
RunLeft run_left(const std::string& prefix, const std::string& shown, const Parameters& p, const RunRequest& request,
                 const std::string& label);

}  // namespace slidespec::cli
