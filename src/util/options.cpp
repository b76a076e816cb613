#include "slidespec/options.hpp"

#include <array>
#include <cctype>
#include <iterator>

namespace slidespec {

namespace {

constexpr std::array kOptions = {
#define SLIDESPEC_OPTION(id, flag, keyword, value, python_value, unit, doc) \
  OptionInfo{#id, flag, keyword, value, python_value, unit, doc},
#include "slidespec/options.def"
};

bool is_word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

const OptionInfo* by_id(const std::string& id) {
  for (const OptionInfo& info : kOptions)
    if (id == info.id) return &info;
  return nullptr;
}

const OptionInfo* by_flag(const std::string& flag) {
  for (const OptionInfo& info : kOptions)
    if (flag == info.flag) return &info;
  return nullptr;
}

/// Every "{id}" of a known option as its flag.
std::string with_flags(const std::string& message) {
  std::string out;
  std::size_t at = 0;
  while (at < message.size()) {
    const std::size_t open = message.find('{', at);
    std::size_t close = open == std::string::npos ? open : open + 1;
    while (close < message.size() && is_word_char(message[close])) ++close;
    const OptionInfo* known =
        close < message.size() && message[close] == '}' ? by_id(message.substr(open + 1, close - open - 1)) : nullptr;
    if (!known) {
      out += message.substr(at, open == std::string::npos ? open : open + 1 - at);
      at = open == std::string::npos ? message.size() : open + 1;
      continue;
    }
    out += message.substr(at, open - at) + known->flag;
    at = close + 1;
  }
  return out;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t found = text.find(from); found != std::string::npos; found = text.find(from, found + to.size()))
    text.replace(found, from.size(), to);
}

/// Flags in `text` as Python's keywords: "--omega-max" as omega_max, "--window T0:T1" as
/// window=(T0, T1), "--set k_drive=K" as k_drive=K; a flag Python lacks left as it is.
std::string with_keywords(std::string text) {
  for (const OptionInfo& info : kOptions)
    if (*info.value)
      replace_all(text, std::string(info.flag) + " " + info.value, std::string(info.keyword) + info.python_value);
  std::string out;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t dashes = text.find("--", at);
    if (dashes == std::string::npos) {
      out += text.substr(at);
      break;
    }
    const bool starts_word = dashes == 0 || !std::isalnum(static_cast<unsigned char>(text[dashes - 1]));
    std::size_t end = dashes + 2;
    while (end < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[end])) ||
            (text[end] == '-' && end + 1 < text.size() && std::isalpha(static_cast<unsigned char>(text[end + 1])))))
      ++end;
    const OptionInfo* known = starts_word ? by_flag(text.substr(dashes, end - dashes)) : nullptr;
    out += text.substr(at, dashes - at);
    if (!known || !*known->keyword) {
      out += text.substr(dashes, end - dashes);
    } else if (std::string(known->id) == "set" && end + 1 < text.size() && text[end] == ' ' &&
               text.find('=', end) < text.find_first_of(" ,;)", end + 1)) {
      ++end;  // "--set k_drive=K" reads as the keyword "k_drive=K"
    } else {
      out += known->keyword;
    }
    at = end;
  }
  return out;
}

}  // namespace

const OptionInfo& option_info(Option option) { return kOptions.at(static_cast<std::size_t>(option)); }

std::string named(Option option) { return std::string("{") + option_info(option).id + "}"; }

std::string worded(const std::string& message, FrontEnd reader) {
  const std::string flags = with_flags(message);
  return reader == FrontEnd::command_line ? flags : with_keywords(flags);
}

}  // namespace slidespec
