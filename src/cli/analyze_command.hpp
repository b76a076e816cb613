// `slidespec analyze` (cli/analyze_command.cpp) as paper fig6 uses it.
#pragma once

#include <string>

namespace slidespec::cli {

struct FigureStyle;

/// `slidespec paper fig6`: the concrete-fit model fitted (alpha) to a record through
/// analyze, drawn into DIRECTORY/fig6.<format>. Without `record` a synthetic one of the
/// concrete-fit case read by the paper's sensor is written first (DIRECTORY/fig6_record.csv).
/// Returns analyze's exit status (3 when the fit failed).
int paper_fig6(const std::string& record, const std::string& directory, const FigureStyle& figure, bool quiet);

}  // namespace slidespec::cli
