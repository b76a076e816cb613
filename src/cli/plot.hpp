// Pictures come from tools/plot_spectra.py (matplotlib, Debian's python3-matplotlib).
#pragma once

#include <string>
#include <vector>

namespace slidespec::cli {

/// Runs the plotting tool on spectrum tables and returns its exit status (0 done, 2 bad
/// input, with its own one-line message on stderr; 127 the tool could not be started).
int plot(const std::vector<std::string>& tables, const std::string& png, const std::string& title);

}  // namespace slidespec::cli
