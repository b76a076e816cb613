// The spectrum map of docs/model.md §7: for six miniblocks, eps from 0.05 to the stall
// boundary (1/3), the largest deviation of the first- and second-order theory from
// simulated spectra (0.05 .. 50 rad/s, 4 points a decade, about 0.45% a point), as TSV
// on stdout (under a minute). Plot with tools/plot_spectrum_map.py.
#include <cmath>
#include <cstdio>

#include "long_time_simulation.hpp"
#include "slidespec/run.hpp"

using namespace long_time_test;

int main() {
  std::printf("renewal\teps\tdeviation_1\tdeviation_2\tbeyond_1\tbeyond_2\tpoints\tstandard_error\n");
  for (const char* renewal : {"poisson", "periodic"})
    for (double eps : {0.05, 0.1, 0.15, 0.2, 0.25, 0.28, 0.3, 0.32}) {
      const Parameters p = flat(6, eps, renewal);
      RunRequest request;
      request.omega_min = 0.05;
      request.omega_max = 50;
      request.points_per_decade = 4;
      request.precision = 0.008;
      request.seed = 11;
      const RunResult run = run_spectrum(p, request);
      double deviation_1 = 0, deviation_2 = 0, error = 0;
      int beyond_1 = 0, beyond_2 = 0;
      for (const RunPoint& point : run.points) {
        deviation_1 = std::fmax(deviation_1, std::fabs(point.C_x / point.theory - 1));
        deviation_2 = std::fmax(deviation_2, std::fabs(point.C_x / point.theory2 - 1));  // nan where not offered
        beyond_1 += std::fabs(point.C_x - point.theory) > 4 * point.standard_error;
        beyond_2 += std::fabs(point.C_x - point.theory2) > 4 * point.standard_error;
        error += point.standard_error / point.C_x / static_cast<double>(run.points.size());
      }
      if (!std::isfinite(run.points.front().theory2)) deviation_2 = NAN;
      std::printf("%s\t%.4f\t%.5f\t%.5f\t%d\t%d\t%zu\t%.5f\n", renewal, landmarks(p).coupling_eps, deviation_1,
                  deviation_2, beyond_1, std::isfinite(deviation_2) ? beyond_2 : -1, run.points.size(), error);
      std::fflush(stdout);
    }
}
