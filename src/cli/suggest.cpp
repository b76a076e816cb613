#include "cli/suggest.hpp"
#include "slidespec/parameters.hpp"

#include <cctype>

#include "util/suggest.hpp"

namespace slidespec::cli {

namespace {

bool is_negative_number(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && (std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.');
}

/// Every spelling of the options of `command` ("--out", "-o").
std::vector<std::string> option_names(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_snames()) names.push_back("-" + name);
  }
  return names;
}

}  // namespace

std::string unknown_argument(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> commands;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    commands.push_back(command->get_name());
  const CLI::App* chosen = nullptr;
  for (int k = 1; k < argc; ++k) {
    std::string word = argv[k];
    if (word == "--") break;
    if (word.size() > 1 && word[0] == '-' && !is_negative_number(word)) {
      word = word.substr(0, word.find('='));
      const CLI::App& scope = chosen ? *chosen : app;
      const std::vector<std::string> known = option_names(scope);
      if (std::find(known.begin(), known.end(), word) != known.end()) continue;
      // A model parameter typed as an option: it goes with --set where the command has one.
      const std::string key = word.substr(word.find_first_not_of('-'));
      const auto& keys = parameter_keys();
      if (std::find(keys.begin(), keys.end(), key) != keys.end() &&
          std::find(known.begin(), known.end(), "--set") != known.end())
        return (chosen ? chosen->get_name() + ": " : std::string()) + "unknown option '" + word + "': " + key +
               " is a model parameter, set it with --set " + key + "=VALUE";
      return (chosen ? chosen->get_name() + ": " : std::string()) + "unknown option '" + word + "'" +
             util::did_you_mean(word, known) + " (see 'slidespec " + (chosen ? chosen->get_name() + " " : "") +
             "--help')";
    }
    if (chosen) continue;  // an option's value or a positional argument
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
      if (command->get_name() == word) chosen = command;
    if (!chosen)
      return "unknown command '" + word + "'" + util::did_you_mean(word, commands) + " (see 'slidespec --help')";
  }
  return "";
}

}  // namespace slidespec::cli
