// Pieces the beyond-first-order theories share: Gauss-Legendre rules and the one touching
// level both are derived for.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "slidespec/input_error.hpp"
#include "slidespec/parameters.hpp"

namespace slidespec::theory_detail {

/// The n-point Gauss-Legendre nodes on [-1, 1] and their weights (summing to 2), by Newton
/// steps on the Legendre recurrence from the usual first guesses.
inline void gauss_legendre_rule(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  nodes.assign(n, 0);
  weights.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double step = p1 / dp;
      z -= step;
      if (std::fabs(step) < 1e-16) break;
    }
    nodes[i] = z;
    weights[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

/// The level that touches the substrate; `theory` names the theory that needs just one.
inline int single_touching_level(const Parameters& p, const std::string& theory) {
  int found = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) {
      if (found != 0) throw InputError("touching: " + theory + " needs one touching level");
      found = l;
    }
  return found;
}

}  // namespace slidespec::theory_detail
