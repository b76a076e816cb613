// The measured-data commands: `slidespec analyze` (a sensor record's spectrum, slope and
// model fit) and `slidespec synth` (a synthetic sensor record to try it on).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>

namespace slidespec::cli {

class AnalysisCommands {
 public:
  /// Adds the subcommands and their options to `app`.
  explicit AnalysisCommands(CLI::App& app);
  /// After parsing: the chosen command's exit status, or nothing when neither was chosen.
  /// Bad input throws InputError (exit status 2) before any file is written.
  std::optional<int> run() const;

  struct Options;

 private:
  std::shared_ptr<Options> options_;
  CLI::App* analyze_;
  CLI::App* synth_;
};

struct FigureStyle;

/// `slidespec paper fig6`: the concrete-fit model fitted (alpha) to a record through
/// analyze, drawn into DIRECTORY/fig6.<format>. Without `record` a synthetic one of the
/// concrete-fit case read by the paper's sensor is written first (DIRECTORY/fig6_record.csv).
/// Returns analyze's exit status (3 when the fit failed).
int paper_fig6(const std::string& record, const std::string& directory, const FigureStyle& figure, bool quiet);

}  // namespace slidespec::cli
