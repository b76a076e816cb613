#include "util/numbers.hpp"

#include <charconv>
#include <cstdio>
#include <cfloat>
#include <cmath>
#include <cstdlib>

namespace slidespec::util {

std::string format_number(double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  return std::string(text, end);
}

std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

std::optional<double> parse_number(const std::string& text) {
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

/// Whether all of `text` is [+-]digits[.digits][(e|E)[+-]digits], a digit in the mantissa.
bool is_decimal_spelling(const std::string& text) {
  std::size_t k = 0, digits = 0;
  auto skip_digits = [&] {
    const std::size_t start = k;
    while (k < text.size() && is_digit(text[k])) ++k;
    return k - start;
  };
  if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
  digits += skip_digits();
  if (k < text.size() && text[k] == '.') ++k, digits += skip_digits();
  if (digits == 0) return false;
  if (k < text.size() && (text[k] == 'e' || text[k] == 'E')) {
    ++k;
    if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
    if (skip_digits() == 0) return false;
  }
  return k == text.size();
}

}  // namespace

std::optional<double> parse_decimal(const std::string& text, std::string& problem) {
  const std::string quoted = "'" + text + "'";
  if (!is_decimal_spelling(text)) {
    std::string word =
        text.substr(text.find_first_not_of("+-") == std::string::npos ? 0 : text.find_first_not_of("+-"));
    for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (word == "inf" || word == "infinity" || word == "nan")
      problem = quoted + " is not a finite number";
    else if (word.rfind("0x", 0) == 0)
      problem = quoted + " is not a decimal number (hexadecimal is not read)";
    else
      problem = quoted + " is not a number";
    return std::nullopt;
  }
  const double value = std::strtod(text.c_str(), nullptr);
  if (!std::isfinite(value)) {
    problem = quoted + " is not a finite number (beyond 1.8e308)";
    return std::nullopt;
  }
  if (value != 0 && std::fabs(value) < DBL_MIN) {
    problem = quoted + " is below the smallest normal double (2.2e-308)";
    return std::nullopt;
  }
  // strtod rounds a tiny value such as 1e-400 to 0: it is not the 0 typed.
  if (value == 0 && text.find_first_of("123456789") < text.find_first_of("eE")) {
    problem = quoted + " is below the smallest normal double (2.2e-308)";
    return std::nullopt;
  }
  return value;
}

}  // namespace slidespec::util
