#include "util/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace slidespec::util {

namespace {

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/// Optimal string alignment distance: insertions, deletions, substitutions and swaps of
/// neighbours ("theroy" is one edit from "theory").
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

}  // namespace

std::string closest_name(const std::string& word, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_distance = 0, best_gap = 0;
  for (const std::string& name : known) {
    // Case slips cost nothing; a prefix ("--omega" for "--omega-min") is a near miss.
    std::size_t distance = edit_distance(lower(word), lower(name));
    if (word.size() >= 3 && name.size() > word.size() && name.compare(0, word.size(), word) == 0) distance = 1;
    // Between near misses alike, the name closest in length: "--omeg" is "--omega", not
    // "--omega-min", of which it is a prefix too.
    const std::size_t gap = name.size() > word.size() ? name.size() - word.size() : word.size() - name.size();
    if (best.empty() || distance < best_distance || (distance == best_distance && gap < best_gap))
      best = name, best_distance = distance, best_gap = gap;
  }
  // Up to a third of the longer name wrong, at least one edit, at most three.
  const std::size_t allowed = std::clamp<std::size_t>(std::max(word.size(), best.size()) / 3, 1, 3);
  return !best.empty() && best_distance <= allowed && best != word ? best : "";
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& known) {
  const std::string best = closest_name(word, known);
  return best.empty() ? "" : "; did you mean '" + best + "'?";
}

}  // namespace slidespec::util
