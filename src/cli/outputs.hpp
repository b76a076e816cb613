// The files a command reads and writes, checked by one rule before it starts any work.
#pragma once

#include <CLI/CLI.hpp>
#include <initializer_list>
#include <string>
#include <vector>

namespace slidespec::cli {

/// A file a command reads or writes, and the option that named it (for messages).
struct NamedFile {
  std::string path;
  std::string option;
};

/// Everything a command will read and write, known before it does any work.
struct Files {
  std::vector<NamedFile> inputs;   ///< files it reads ("-" is standard input)
  std::vector<NamedFile> outputs;  ///< every file it may write: all formats, sub-runs, states
  /// Output prefixes it writes under: each is locked (PREFIX.lock) while the command runs.
  std::vector<NamedFile> prefixes;

  /// Of the inputs, the JSON files (parameter files): held to strict JSON and a size cap.
  std::vector<NamedFile> json_inputs;

  void input(const std::string& path, const std::string& option) { inputs.push_back({path, option}); }
  void json_input(const std::string& path, const std::string& option) {
    input(path, option);
    json_inputs.push_back({path, option});
  }
  void output(const std::string& path, const std::string& option) { outputs.push_back({path, option}); }
  /// PREFIX + each extension as outputs, and PREFIX among the locked prefixes.
  void outputs_of(const std::string& prefix, const std::string& option, std::initializer_list<std::string> extensions);
};

/// Counting options (--realizations, --seed, --threads, --points) of every command take
/// plain decimal digits only: "-1" would otherwise wrap to 2^64-1.
void require_whole_numbers(CLI::App& app);

/// Every number option (CLI11's FLOAT and INT) of every command takes a decimal number,
/// padding trimmed: CLI11 would read "0x10" as 16 and "inf" or "nan" as numbers.
void require_decimal_numbers(CLI::App& app);

/// Options that would be ignored are refused at parsing (CLI11 excludes and needs): the
/// figure's --format, --size and --dpi beside --no-plot; theory's grid (--omega-min,
/// --omega-max, --points) beside --omega or --omega-file; analyze's --fit-band without
/// --fit, and --set or --theory-order without --compare-case.
void declare_option_rules(CLI::App& app);

/// A parameter given twice to --set (the first would be ignored), and a swept key also
/// given by --set, are refused.
void refuse_repeated_keys(const CLI::App& command);

/// Every option given an empty value ("--out ''", "--resume ''") is refused: an empty
/// name or number means nothing, and would otherwise read as the option not given.
void refuse_empty_values(const CLI::App& command);

/// The one rule for a command's files, before any work: every input is a readable file
/// (not a directory, not a device); every name is valid UTF-8 without control characters and short
/// enough for the file system; no output is empty, a directory, in a directory that does
/// not exist or is not writable, no output prefix a directory, or the same file as an input (compared by resolved path
/// and by inode); a JSON input is at most 1 MiB of strict JSON (no trailing data, no key
/// twice in an object). Throws InputError naming the file and the option.
void check_files(const Files& files);

/// A file name (or other text not meant as mathtext) as a figure title: each '$' escaped,
/// so that matplotlib draws it as written instead of typesetting between dollar signs.
std::string literal_title(const std::string& text);

}  // namespace slidespec::cli
