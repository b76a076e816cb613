// The files a command reads and writes, checked before it starts any work.
#pragma once

#include <CLI/CLI.hpp>

namespace slidespec::cli {

/// Counting options (--realizations, --seed, --threads, --points) of every command take
/// plain decimal digits only: "-1" would otherwise wrap to 2^64-1.
void require_whole_numbers(CLI::App& app);

/// After parsing: every input of the chosen command is a readable file (not a directory),
/// every file name is valid UTF-8 and short enough for the file system, no output is a
/// directory, and no output would replace an input. Throws InputError naming both files.
void check_files(const CLI::App& app);

}  // namespace slidespec::cli
