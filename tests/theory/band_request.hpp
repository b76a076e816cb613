// The request the theory tests simulate: a band at a relative standard error per point,
// four points a decade.
#pragma once

#include <cstdint>

#include "slidespec/run.hpp"

namespace slidespec {

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
