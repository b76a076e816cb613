// The one exception for bad user input, at the bottom of the library: every layer may
// throw it (a parameter, a request, a damaged file, a name it does not know).
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace slidespec {

/// Thrown for any bad user input. The message is one line that names the key
/// (or option) and what is wrong with it; the CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(printable(what)) {}

 private:
  /// `text` with its control bytes written as \xNN: a NUL inside a quoted field would end
  /// the message there, a newline in a file name would break its one line.
  static std::string printable(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
      const auto byte = static_cast<unsigned char>(c);
      if (byte >= 0x20 && byte != 0x7f) {
        out.push_back(c);
        continue;
      }
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned>(byte));
      out += escaped;
    }
    return out;
  }
};

/// Bad input that is a file the system will not give: missing, unreadable, or a place
/// where outputs cannot be created. The CLI treats it as bad input (status 2); Python
/// raises OSError.
class FileError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace slidespec
