// The words of the analysis's enums (units, observables, estimators): one table per enum
// gives its name, parsing with "did you mean" and the list of known words.
#pragma once

#include <array>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "slidespec/input_error.hpp"
#include "util/numbers.hpp"
#include "util/suggest.hpp"

namespace slidespec::detail {

using util::short_number;

/// KEY of a "KEY=VALUE" override.
inline std::string key_of(const std::string& assignment) { return assignment.substr(0, assignment.find('=')); }

/// Whether `overrides` set `key`: what the user sets is kept over what a record gives.
inline bool sets(const std::vector<std::string>& overrides, const std::string& key) {
  for (const std::string& assignment : overrides)
    if (key_of(assignment) == key) return true;
  return false;
}

/// A word and the value it names; a table may give several words for one value, the first
/// of them its name.
template <class Enum>
using Word = std::pair<const char*, Enum>;

template <class Enum, std::size_t N>
const char* name_of(const std::array<Word<Enum>, N>& words, Enum value) {
  for (const auto& [word, named] : words)
    if (named == value) return word;
  return "?";
}

template <class Enum, std::size_t N>
std::optional<Enum> find_word(const std::array<Word<Enum>, N>& words, const std::string& text) {
  for (const auto& [word, value] : words)
    if (text == word) return value;
  return std::nullopt;
}

/// The value `text` names, or an InputError "OPTION: unknown WHAT 'text'; did you mean ...?
/// (known: ...)" with `extra` at the end of the parenthesis.
template <class Enum, std::size_t N>
Enum parse_word(const std::array<Word<Enum>, N>& words, const std::string& text, const std::string& option,
                const std::string& what, const std::string& extra = "") {
  if (const auto value = find_word(words, text)) return *value;
  std::vector<std::string> known;
  std::string list;
  for (const auto& [word, value] : words) {
    known.emplace_back(word);
    list += (list.empty() ? "" : ", ") + std::string(word);
  }
  throw InputError(option + ": unknown " + what + " '" + text + "'" + util::did_you_mean(text, known) +
                   " (known: " + list + extra + ")");
}

}  // namespace slidespec::detail
