// The exact theory of a named case and a short simulated run beside it, through the
// public headers alone (include/slidespec): what `slidespec theory` and `slidespec run`
// print, as library calls.
#include <slidespec/parameters.hpp>
#include <slidespec/run.hpp>
#include <slidespec/theory.hpp>

#include <cstdio>
#include <exception>
#include <vector>

int main() {
  try {
    // The reference case with one override, validated as --set N=5 is.
    const slidespec::Parameters p = slidespec::ParameterBuilder("reference").set("N=5").build();

    const std::vector<double> omegas = slidespec::log_spaced_omegas(1, 1e3, 2);
    const std::vector<double> theory = slidespec::exact_spectrum(p, omegas);
    std::printf("# theory: omega [rad/s]\tC_x [m^2 s]\n");
    for (std::size_t k = 0; k < omegas.size(); ++k) std::printf("%g\t%g\n", omegas[k], theory[k]);

    // A fixed count of realizations keeps the run short; the seed makes it repeatable.
    slidespec::RunRequest request;
    request.omega_min = 10;
    request.omega_max = 1e3;
    request.points_per_decade = 2;
    request.realizations = 8;
    request.threads = 1;
    const slidespec::RunResult run = slidespec::run_spectrum(p, request);
    std::printf("# run: omega [rad/s]\tC_x [m^2 s]\tstderr [m^2 s]\ttheory [m^2 s]\n");
    for (const slidespec::RunPoint& point : run.points)
      std::printf("%g\t%g\t%g\t%g\n", point.omega, point.C_x, point.standard_error, point.theory);
    return run.complete && !run.points.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spectrum: %s\n", e.what());
    return 1;
  }
}
