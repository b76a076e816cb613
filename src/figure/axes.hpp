// Where a value lands on a panel, and which values carry ticks: logarithmic axes for the
// spectrum (decades), a linear one for the residuals.
#pragma once

#include <string>
#include <vector>

namespace slidespec::figure {

/// A rectangle on the page, in points from the top left corner.
struct Box {
  double left = 0, top = 0, width = 0, height = 0;
  double right() const { return left + width; }
  double bottom() const { return top + height; }
};

/// One axis: the range of values it shows and the span of the page it takes.
/// Logarithmic axes hold their range as log10 of the values.
struct Scale {
  double low = 0, high = 1;   ///< the range shown (log10 of values on a log axis)
  double start = 0, end = 1;  ///< where low and high land on the page [pt]
  bool logarithmic = false;

  /// The page coordinate of `value` (a value, not its log); NaN for a value <= 0 on a log axis.
  double at(double value) const;
  /// The scale over [low, high] widened by `margin` of its span at each end.
  static Scale around(double low, double high, bool logarithmic, double margin = 0.05);
};

/// A tick: its value, and its label as text markup (empty for a minor tick).
struct Tick {
  double value;
  std::string label;
};

/// Decades carrying labels ("10^{-8}"), every `step` decades so that at most `most` fit,
/// and minor ticks at 2..9 times each decade (a step of one over at most ten decades) or
/// at the decades left unlabelled.
std::vector<Tick> log_ticks(const Scale& scale, int most, std::vector<double>& minor);

/// Round values (1, 2, 2.5 or 5 times a power of ten apart), at most `most`, labelled
/// with the decimals their spacing needs.
std::vector<Tick> linear_ticks(const Scale& scale, int most);

}  // namespace slidespec::figure
