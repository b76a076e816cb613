// The least-squares line of a uniformly sampled stretch: the mean sliding of a record and
// the speed of a block of it.
#pragma once

#include <cstddef>
#include <vector>

namespace slidespec::detail {

struct Line {
  double intercept, slope;
};

/// Least-squares line through (i dt, x_i) for i in [first, last).
inline Line fit_line(const std::vector<double>& x, std::size_t first, std::size_t last, double dt) {
  const double count = static_cast<double>(last - first);
  const double t_mean = 0.5 * (count - 1) * dt;
  double x_mean = 0;
  for (std::size_t i = first; i < last; ++i) x_mean += x[i];
  x_mean /= count;
  double sxy = 0, sxx = 0;
  for (std::size_t i = first; i < last; ++i) {
    const double t = static_cast<double>(i - first) * dt - t_mean;
    sxy += t * (x[i] - x_mean);
    sxx += t * t;
  }
  const double slope = sxy / sxx;
  return {x_mean - slope * t_mean, slope};
}

}  // namespace slidespec::detail
