// The one exception for bad user input, at the bottom of the library: every layer may
// throw it (a parameter, a request, a damaged file, a name it does not know).
#pragma once

#include <stdexcept>

namespace slidespec {

/// Thrown for any bad user input. The message is one line that names the key
/// (or option) and what is wrong with it; the CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input that is a file the system will not give: missing, unreadable, or a place
/// where outputs cannot be created. The CLI treats it as bad input (status 2); Python
/// raises OSError.
class FileError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace slidespec
