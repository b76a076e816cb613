// What the command line says about an argument it does not know: the subcommand or
// option the user probably meant.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace slidespec::cli {

/// After a failed parse of argv: "unknown command 'theroy'; did you mean 'theory'?" or
/// "run: unknown option '--omega-mni'; did you mean '--omega-min'?" for the first word
/// that is neither a subcommand nor an option of the chosen one; empty when every word
/// is known (then CLI11's own message is the better one).
std::string unknown_argument(const CLI::App& app, int argc, const char* const* argv);

}  // namespace slidespec::cli
