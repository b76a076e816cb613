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

/// CLI11's failure `error` in our words, one line naming the option and the problem:
/// "--out: no value after it", "--seed: given 2 times; give it once", "merge: no parts
/// given; give the state files of the parts to merge".
std::string worded_parse_error(const CLI::App& app, const CLI::ParseError& error);

}  // namespace slidespec::cli
