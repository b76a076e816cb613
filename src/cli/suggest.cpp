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

/// The text between `before` and `after` in `what` ("" when either is missing).
std::string between(const std::string& what, const std::string& before, const std::string& after) {
  const auto start = what.find(before);
  if (start == std::string::npos) return "";
  const auto end = what.find(after, start + before.size());
  return end == std::string::npos ? "" : what.substr(start + before.size(), end - start - before.size());
}

/// What a left-out positional argument is, as its command's help would say it briefly.
std::string positional_meaning(const std::string& name) {
  if (name == "file") return "a record to analyze (a CSV or TSV file, or - for standard input)";
  if (name == "values") return "KEY=VALUES to sweep (e.g. alpha=0.1,0.5)";
  if (name == "parts") return "the state files of the parts to merge";
  if (name == "tables") return "the TSV tables to draw";
  return "one";
}

/// The count of values in CLI11's "NAME: At Most N required but received M" and kin.
std::string count_message(const std::string& name, const std::string& what) {
  const std::string expected = between(what, name + ": ", " required but received ");
  const std::string received = what.substr(what.rfind(' ') + 1);
  const std::string count = expected.substr(expected.rfind(' ') + 1);
  if (count == "1" && what.find("At Most") != std::string::npos)
    return name + ": given " + received + " times; give it once";
  return name + ": takes " + count + (count == "1" ? " value" : " values") + ", got " + received;
}

}  // namespace

std::string worded_parse_error(const CLI::App& app, const CLI::ParseError& error) {
  const std::string what = error.what();
  const CLI::App* chosen = nullptr;
  for (const CLI::App* command : app.get_subcommands()) chosen = command;
  const std::string scope = chosen ? chosen->get_name() + ": " : "";
  const std::string help = " (see 'slidespec " + (chosen ? chosen->get_name() + " " : "") + "--help')";
  if (dynamic_cast<const CLI::RequiredError*>(&error) && what.size() > 12 &&
      what.rfind(" is required") == what.size() - 12) {
    const std::string name = what.substr(0, what.size() - 12);
    return scope + "no " + name + " given; give " + positional_meaning(name);
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&error)) {
    const std::string name = what.substr(0, what.find(':'));
    if (what.find(" missing") == what.size() - 8) return name + ": no value after it; give one or leave it out";
    if (what.find(" required but received ") != std::string::npos) return count_message(name, what);
  }
  if (dynamic_cast<const CLI::ExtrasError*>(&error))
    return scope + "'" + what.substr(what.find(": ") + 2) + "' was not expected" + help;
  if (dynamic_cast<const CLI::ExcludesError*>(&error)) {
    const auto split = what.find(" excludes ");
    return what.substr(0, split) + " and " + what.substr(split + 10) + " cannot be given together; leave one out";
  }
  if (dynamic_cast<const CLI::RequiresError*>(&error)) {
    const auto split = what.find(" requires ");
    return what.substr(0, split) + " needs " + what.substr(split + 10) + ", which is not given";
  }
  if (dynamic_cast<const CLI::ConversionError*>(&error) && what.rfind("Could not convert: ", 0) == 0) {
    const std::string name = between(what, "Could not convert: ", " = ");
    const std::string value = what.substr(what.find(" = ") + 3);
    const CLI::Option* option = chosen ? chosen->get_option_no_throw(name) : nullptr;
    const bool whole = option != nullptr && option->get_type_name().find("INT") != std::string::npos;
    return name + ": '" + value + "' is not " + (whole ? "a whole number" : "a number");
  }
  return what;
}

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
      std::string lower_key = key;
      for (char& c : lower_key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (lower_key == "inf" || lower_key == "infinity" || lower_key == "nan") {
        const std::string after = k > 1 && argv[k - 1][0] == '-' ? std::string(argv[k - 1]) + ": " : "";
        return (chosen ? chosen->get_name() + ": " : std::string()) + after + "'" + argv[k] +
               "' is not a finite number";
      }
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
