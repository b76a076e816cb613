// What the theory tests simulate: the reference case at a coupling eps, and a band at a
// relative standard error per point, four points a decade.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec {

/// The reference case with N contacts and poisson renewal at coupling eps.
inline Parameters poisson(int N, double eps) {
  // eps = alpha F_kin / ((F_drive - F_kin) sqrt(6 N)) with F_kin = F_drive - F_kin = 5.
  Parameters p = ParameterBuilder("reference").set("N", std::to_string(N)).build();
  p.alpha = eps * std::sqrt(6.0 * N);
  return p;
}

inline RunRequest band_request(double omega_min, double omega_max, double precision,
                               std::uint64_t seed = RunRequest{}.seed) {
  RunRequest request;
  request.omega_min = omega_min;
  request.omega_max = omega_max;
  request.points_per_decade = 4;
  request.precision = precision;
  request.seed = seed;
  return request;
}

}  // namespace slidespec
