#include "cli/outputs.hpp"

#include <climits>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "util/numbers.hpp"
#include "slidespec/parameters.hpp"

namespace slidespec::cli {

namespace {

namespace fs = std::filesystem;

using File = NamedFile;

// The name with control characters shown as '?', for a one-line message.
std::string printable(std::string name) {
  for (char& c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return name;
}

// The longest name the atomic writer derives from an output: PATH.tmp.XXXXXX.png.
constexpr std::size_t kLongestSuffix = 20;

bool valid_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto lead = static_cast<unsigned char>(s[i]);
    const std::size_t more = lead < 0x80                   ? 0
                             : lead >= 0xc2 && lead < 0xe0 ? 1
                             : lead >= 0xe0 && lead < 0xf0 ? 2
                             : lead >= 0xf0 && lead < 0xf5 ? 3
                                                           : 4;
    if (more == 4 || i + more >= s.size()) return false;
    for (std::size_t k = 1; k <= more; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    i += more + 1;
  }
  return true;
}

void check_name(const File& f) {
  if (!valid_utf8(f.path)) throw InputError(f.option + ": the file name '" + f.path + "' is not valid UTF-8");
  if (f.path.size() + kLongestSuffix >= PATH_MAX)
    throw InputError(f.option + ": the path '" + f.path.substr(0, 40) + "...' is too long");
}

/// Whether `f` is read from standard input when named '-': a record is; a parameter file,
/// an omega file, a state or a table is read twice or by another process, and is not.
bool reads_standard_input(const File& f) { return f.option == "analyze" || f.option == "--record"; }

void check_input(const File& f) {
  if (f.path == "-" && reads_standard_input(f)) return;
  if (f.path == "-") throw InputError(f.option + ": '-' (standard input) is not read here; give the path of a file");
  check_name(f);
  std::error_code error;
  const fs::file_status status = fs::status(f.path, error);
  if (!fs::exists(status)) throw InputError(f.option + ": " + f.path + " does not exist");
  if (fs::is_directory(status)) throw InputError(f.option + ": " + f.path + " is a directory, not a file");
  if (fs::is_character_file(status) || fs::is_block_file(status))
    throw InputError(f.option + ": " + f.path + " is a device, not a file" +
                     (reads_standard_input(f) ? " (use '-' where standard input is meant)" : ""));
  if (::access(f.path.c_str(), R_OK) != 0) throw InputError(f.option + ": " + f.path + " is not readable");
}

void check_output(const File& f) {
  if (f.path.empty()) throw InputError(f.option + ": empty output name");
  check_name(f);
  for (const char c : f.path)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw InputError(f.option + ": the output name '" + printable(f.path) +
                       "' holds a control character (a newline, a tab...); choose another name");
  const std::string name = fs::path(f.path).filename().string();
  const long most =
      ::pathconf(fs::path(f.path).parent_path().empty() ? "." : fs::path(f.path).parent_path().c_str(), _PC_NAME_MAX);
  const std::size_t limit = most > 0 ? static_cast<std::size_t>(most) : 255;
  if (name.size() + kLongestSuffix > limit)
    throw InputError(f.option + ": the file name " + name.substr(0, 40) + "... is longer than the " +
                     std::to_string(limit - kLongestSuffix) + " bytes an output name may have here");
  std::error_code error;
  if (fs::is_directory(f.path, error))
    throw InputError(f.option + ": " + f.path + " is a directory, not a file it could write");
  const fs::path parent = fs::path(f.path).parent_path();
  const std::string directory = parent.empty() ? "." : parent.string();
  if (!fs::is_directory(directory, error))
    throw InputError(f.option + " " + f.path + ": directory " + directory + " does not exist");
  if (::access(directory.c_str(), W_OK) != 0)
    throw InputError(f.option + " " + f.path + ": directory " + directory + " is not writable");
}

// A parameter file is a few hundred bytes; this ends a read of an endless stream.
constexpr std::size_t kMostJsonBytes = std::size_t{1} << 20;

void check_json_input(const File& f) {
  if (f.path == "-")
    throw InputError(f.option + ": '-' (standard input) is not read here; give the path of a JSON file");
  const std::string text = io::read_file(f.path, f.option, kMostJsonBytes);
  std::vector<std::set<std::string>> keys;  // of each object open at this point
  std::string twice;
  auto note_keys = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (event == Event::object_start) keys.emplace_back();
    if (event == Event::object_end && !keys.empty()) keys.pop_back();
    if (event == Event::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second && twice.empty())
      twice = parsed.get<std::string>();
    return true;
  };
  try {
    // Parsed for its syntax and keys only; the readers parse the document again.
    const nlohmann::json document = nlohmann::json::parse(text, note_keys);
    static_cast<void>(document);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(f.option + ": " + f.path + " is not valid JSON (" + e.what() + ")");
  }
  if (!twice.empty()) throw InputError(f.option + ": " + f.path + " gives the key '" + twice + "' twice");
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
  const fs::path x = fs::weakly_canonical(a, error);
  const fs::path y = fs::weakly_canonical(b, error);
  return !error && x == y;
}

}  // namespace

void require_whole_numbers(CLI::App& app) {
  // The largest each counting option's type holds: 2^64 - 1 for counts of realizations
  // and seeds, 2^31 - 1 for threads and points per decade.
  auto whole_up_to = [](const std::string& largest) {
    return CLI::Validator(
        [largest](std::string& value) -> std::string {
          if (value.empty() || value.find_first_not_of("0123456789") != std::string::npos)
            return "expected a whole number from 0 to " + largest + ", got '" + value + "'";
          const std::string digits = value.substr(std::min(value.find_first_not_of('0'), value.size() - 1));
          if (digits.size() > largest.size() || (digits.size() == largest.size() && digits > largest))
            return "'" + value + "' is above " + largest + ", the largest allowed";
          return "";
        },
        "WHOLE");
  };
  const std::string most_u64 = std::to_string(std::numeric_limits<std::uint64_t>::max());
  const std::string most_int = std::to_string(std::numeric_limits<int>::max());
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
    for (const char* name : {"--realizations", "--seed"})
      if (CLI::Option* option = command->get_option_no_throw(name)) option->check(whole_up_to(most_u64));
    for (const char* name : {"--threads", "--points"})
      if (CLI::Option* option = command->get_option_no_throw(name)) option->check(whole_up_to(most_int));
  }
}

void require_decimal_numbers(CLI::App& app) {
  const CLI::Validator decimal(
      [](std::string& value) -> std::string {
        const auto first = value.find_first_not_of(" \t");
        value = first == std::string::npos ? "" : value.substr(first, value.find_last_not_of(" \t") - first + 1);
        std::string problem;  // an empty value is refuse_empty_values' to word
        return value.empty() || util::parse_decimal(value, problem) ? "" : problem;
      },
      "");
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
    for (CLI::Option* option : command->get_options()) {
      const std::string type = option->get_type_name();
      if (type == "FLOAT" || type == "INT" || type == "UINT") option->check(decimal);
    }
}

void declare_option_rules(CLI::App& app) {
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
    auto option = [&](const char* name) { return command->get_option_no_throw(name); };
    // No figure is drawn: its format, size and resolution would be ignored.
    if (CLI::Option* no_plot = option("--no-plot"))
      for (const char* name : {"--format", "--size", "--dpi"})
        if (CLI::Option* figure = option(name)) no_plot->excludes(figure);
    // Omegas listed or read from a file replace the log grid and its density.
    for (const char* list : {"--omega", "--omega-file"})
      if (CLI::Option* given = option(list))
        for (const char* grid : {"--omega-min", "--omega-max", "--points"})
          if (CLI::Option* ignored = option(grid)) given->excludes(ignored);
    // A fit's band needs a fit; a compared case's overrides and theory order need the case.
    const std::pair<const char*, const char*> needs[] = {
        {"--fit-band", "--fit"}, {"--set", "--compare-case"}, {"--theory-order", "--compare-case"}};
    if (command->get_name() == "analyze")
      for (const auto& [dependent, needed] : needs)
        if (option(dependent) && option(needed)) option(dependent)->needs(option(needed));
  }
}

void refuse_repeated_keys(const CLI::App& command) {
  // KEY of each KEY=VALUE of --set, and of a sweep's KEY=VALUES.
  std::set<std::string> set_keys;
  if (const CLI::Option* set = command.get_option_no_throw("--set"))
    for (const std::string& assignment : set->results()) {
      const std::string key = assignment.substr(0, assignment.find('='));
      if (!set_keys.insert(key).second)
        throw InputError("--set: " + key + " is given twice (" + key + "=...); give each parameter once");
    }
  if (command.get_name() != "sweep") return;
  if (const CLI::Option* values = command.get_option_no_throw("values"))
    for (const std::string& word : values->results()) {
      const std::string key = word.substr(0, word.find('='));
      if (word.find('=') != std::string::npos && set_keys.count(key) != 0)
        throw InputError("sweep: " + key + " is swept and also given by --set " + key +
                         "=...; the --set value would be ignored: leave it out");
    }
}

void Files::outputs_of(const std::string& prefix, const std::string& option,
                       std::initializer_list<std::string> extensions) {
  if (prefix.empty()) throw InputError(option + ": empty output prefix");
  for (const std::string& extension : extensions) output(prefix + extension, option);
  prefixes.push_back({prefix, option});
}

void refuse_empty_values(const CLI::App& command) {
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0 || option->get_expected_min() == 0) continue;  // not given, or a flag
    for (const std::string& value : option->results())
      if (value.empty()) throw InputError(option->get_name() + ": empty value; give one or leave the option out");
  }
}

void check_files(const Files& files) {
  for (const File& f : files.inputs) check_input(f);
  for (const File& f : files.json_inputs) check_json_input(f);
  for (const File& f : files.outputs) check_output(f);
  std::error_code error;
  for (const File& prefix : files.prefixes)
    if (fs::is_directory(prefix.path, error))
      throw InputError(prefix.option + " " + prefix.path + ": is a directory; give a prefix such as " + prefix.path +
                       "/spectrum");
  for (std::size_t k = 0; k < files.outputs.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (same_file(files.outputs[k].path, files.outputs[j].path))
        throw InputError(files.outputs[k].option + ": the output " + files.outputs[k].path + " is also " +
                         files.outputs[j].option + "'s output " + files.outputs[j].path +
                         ": one would replace the other; choose another name");
  for (const File& out : files.outputs)
    for (const File& in : files.inputs)
      if (in.path != "-" && same_file(out.path, in.path))
        throw InputError(out.option + ": the output " + out.path + " would replace the input " + in.path + " (" +
                         in.option + "); choose another output name");
}

std::string literal_title(const std::string& text) {
  std::string title;
  for (const char c : text) {
    if (c == '$') title += '\\';
    title += c;
  }
  return title;
}

}  // namespace slidespec::cli
