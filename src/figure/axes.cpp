#include "figure/axes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace slidespec::figure {

namespace {

const char* const kMinus = "\u2212";  // typeset minus: as wide as a digit, unlike '-'
// A tick on the end of an axis (0.6 = 3 x 0.2, give or take a rounding) is on the axis.
constexpr double kRoundOff = 1e-9;

std::string signed_number(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof text, format, std::abs(value));
  return (value < 0 && std::string(text).find_first_not_of("0.") != std::string::npos ? kMinus : "") +
         std::string(text);
}

}  // namespace

double Scale::at(double value) const {
  double position = value;
  if (logarithmic) {
    if (!(value > 0)) return std::numeric_limits<double>::quiet_NaN();
    position = std::log10(value);
  }
  return start + (position - low) / (high - low) * (end - start);
}

Scale Scale::around(double low, double high, bool logarithmic, double margin) {
  Scale scale;
  scale.logarithmic = logarithmic;
  if (logarithmic) {
    low = std::log10(low);
    high = std::log10(high);
  }
  if (!(high > low)) {  // one value: a decade (or one unit) around it
    low -= 0.5;
    high += 0.5;
  }
  const double widen = margin * (high - low);
  scale.low = low - widen;
  scale.high = high + widen;
  return scale;
}

std::vector<Tick> log_ticks(const Scale& scale, int most, std::vector<double>& minor) {
  const int first = static_cast<int>(std::ceil(scale.low - kRoundOff));
  const int last = static_cast<int>(std::floor(scale.high + kRoundOff));
  int step = 1;
  for (const int candidate : {1, 2, 4, 5, 10, 20, 50, 100}) {
    step = candidate;
    const int count = static_cast<int>(std::floor(static_cast<double>(last) / step)) -
                      static_cast<int>(std::ceil(static_cast<double>(first) / step)) + 1;
    if (count <= std::max(most, 2)) break;
  }
  std::vector<Tick> ticks;
  minor.clear();
  for (int decade = first; decade <= last; ++decade) {
    if (decade % step == 0)
      ticks.push_back({std::pow(10.0, decade), "10^{" + signed_number("%.0f", decade) + "}"});
    else
      minor.push_back(std::pow(10.0, decade));
  }
  if (step != 1 || last - first > 10) return ticks;
  // Less than two decades labelled (a range within a decade or so): the multiples of a
  // decade carry labels too, 2 and 5 when there is room for them only, "2×10^{−1}".
  const bool label_multiples = ticks.size() < 2;
  const bool all_multiples = scale.high - scale.low < 0.6;
  for (int decade = first - 1; decade <= last; ++decade)
    for (int k = 2; k <= 9; ++k) {
      const double value = k * std::pow(10.0, decade);
      if (std::log10(value) < scale.low || std::log10(value) > scale.high) continue;
      if (label_multiples && (all_multiples || k == 2 || k == 5))
        ticks.push_back({value, std::to_string(k) + "×10^{" + signed_number("%.0f", decade) + "}"});
      else
        minor.push_back(value);
    }
  std::sort(ticks.begin(), ticks.end(), [](const Tick& a, const Tick& b) { return a.value < b.value; });
  return ticks;
}

std::vector<Tick> linear_ticks(const Scale& scale, int most) {
  struct Spacing {
    double step;
    int decimals;
  };
  const Spacing spacing = [&] {
    for (double power = std::pow(10.0, std::floor(std::log10(scale.high - scale.low)) - 2);; power *= 10)
      for (const double mantissa : {1.0, 2.0, 2.5, 5.0}) {
        const double step = mantissa * power;
        if (std::floor(scale.high / step + kRoundOff) - std::ceil(scale.low / step - kRoundOff) + 1 <=
            std::max(most, 2))
          return Spacing{step, std::max(0, static_cast<int>(-std::floor(std::log10(step) + kRoundOff))) +
                                   (mantissa == 2.5 ? 1 : 0)};
      }
  }();
  const double step = spacing.step;
  char format[16];
  std::snprintf(format, sizeof format, "%%.%df", spacing.decimals);
  std::vector<Tick> ticks;
  for (double k = std::ceil(scale.low / step - kRoundOff); k <= std::floor(scale.high / step + kRoundOff); ++k)
    ticks.push_back({k * step, signed_number(format, k * step)});
  return ticks;
}

}  // namespace slidespec::figure
