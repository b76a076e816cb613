// "Did you mean ...?" for a mistyped name among the known ones.
#pragma once

#include <string>
#include <vector>

namespace slidespec::util {

/// The known name closest to `word` by edit distance (a swap of neighbours counts one),
/// when it is close enough to be a typo of it (or differs only in case); else empty.
std::string closest_name(const std::string& word, const std::vector<std::string>& known);

/// "; did you mean 'NAME'?" for the closest known name, or "" when none is close.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& known);

}  // namespace slidespec::util
