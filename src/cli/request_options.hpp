// The request options every simulating command shares (run, sweep, paper): the band, the
// target, the seed and the execution, declared once on each command that has them.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "cli/command.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

/// The request a simulating command's options fill. Help defaults come from RunRequest's
/// own defaults.
struct RequestOptions {
  RunRequest request;
  std::string simd = "auto";

  /// The band, the target, the seed and the execution: every simulating command has them.
  void add_to(CLI::App& command);
  /// The output grid's density and a fixed count of realizations (run, sweep).
  void add_sampling_to(CLI::App& command);
  /// The request with its SIMD path checked on this CPU and its default thread count.
  RunRequest resolved(const Context& context) const;
};

}  // namespace slidespec::cli
