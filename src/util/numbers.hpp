// Numbers as text, the one way every table, message and parser writes and reads them.
#pragma once

#include <optional>
#include <string>

namespace slidespec::util {

/// The shortest text that reads back as the same double ("1e-05", "0.5", "548.2").
std::string format_number(double x);
/// To three significant digits ("0.0005", "1.23e+04"), as messages and summaries give a number.
std::string short_number(double x);
/// The finite double `text` spells, all of it ("0.5", "1e-05"), or nothing.
std::optional<double> parse_number(const std::string& text);
/// The finite, normal (or zero) double a user's decimal spelling gives ("0.5", "-2", "+1e-3"),
/// or nothing, with `problem` saying why ("'0x10' is not a decimal number"). strtod and
/// CLI11 would also read hexadecimal, "inf", "nan" and padded text.
std::optional<double> parse_decimal(const std::string& text, std::string& problem);

/// The smallest spectrum value [m^2 s, N^2 s] whose square a double holds with digits to
/// spare: an error bar sums such squares, and below it would read 0.
constexpr double kSmallestSquarableSpectrum = 1e-150;

}  // namespace slidespec::util
