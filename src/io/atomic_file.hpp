// Output files appear whole or not at all.
#pragma once

#include <string>

namespace slidespec::io {

/// Writes `content` to a temporary file beside `path`, flushes it to disk and renames it
/// over `path`, so a reader (or an interrupt) never sees a half-written file.
void write_atomically(const std::string& path, const std::string& content);

/// The whole of a file (a saved run state, say); InputError "WHAT: cannot read PATH".
std::string read_file(const std::string& path, const std::string& what);

/// Throws InputError naming the problem if files PREFIX.* cannot be created: checked
/// before any computation starts, so a bad --out fails in a second, not after an hour.
void check_output_prefix(const std::string& prefix);

}  // namespace slidespec::io
