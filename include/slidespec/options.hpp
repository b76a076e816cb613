// The users' options (slidespec/options.def) and the wording of library messages that name
// them: a message writes an option as its id in braces, "{omega_max}", and each front end
// turns that into its own spelling.
#pragma once

#include <string>

namespace slidespec {

enum class Option {
#define SLIDESPEC_OPTION(id, flag, keyword, value, python_value, unit, doc) id,
#include "slidespec/options.def"
};

struct OptionInfo {
  const char* id;
  const char* flag;     ///< the command line's, "--omega-max"
  const char* keyword;  ///< Python's, "omega_max"; "" when Python has none
  const char* value;    ///< the value's form after the flag in a message, "T0:T1", or ""
  const char* python_value;
  const char* unit;  ///< of a bare number, "" for none
  const char* doc;
};

const OptionInfo& option_info(Option option);

/// "{id}", the way a library message names `option`.
std::string named(Option option);

/// Who reads a message.
enum class FrontEnd { command_line, python };

/// `message` with each "{id}" of an option worded for `reader`: as its flag on the command
/// line; in Python as its keyword (a flag and its value's form as the call gives them, and
/// "--set KEY=V" as "KEY=V"), a flag Python does not have left as it is.
std::string worded(const std::string& message, FrontEnd reader);

}  // namespace slidespec
