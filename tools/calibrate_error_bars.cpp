// Measures whether a precision-driven run's error bars are what they claim, and what the run
// costs: runs one case over many seeds and compares every point with the theory that holds
// there (theory2 where it can be computed, else the first order), per sub-band:
// the mean z = (C_x - theory) / stderr (0 without bias) and mean z^2 (1 for honest bars), the share within two standard
// errors (95% for normal errors) and beyond three (0.27%), the mean realizations and the mean lane-steps (realization
// steps, the shadow's counted again, warm-ups left out) a seed needed.
//
//   slidespec_calibrate [--case NAME] [--set KEY=VALUE ...] [--precision P] [--seeds S]
//                       [--omega-min W] [--omega-max W] [--control-variate shadow|off]
//
// Where the first order is far from the truth (eps large) theory2 is the reference, and its
// own error (third order) shows as z^2 above 1 in every sub-band alike.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "slidespec/input_error.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace {

using namespace slidespec;

struct Tally {
  double z = 0, z2 = 0, realizations = 0, lane_steps = 0;
  int points = 0, within_two = 0, beyond_three = 0;

  void add_point(double zi) {
    z += zi, z2 += zi * zi, ++points, within_two += std::fabs(zi) <= 2, beyond_three += std::fabs(zi) > 3;
  }
  void print(const char* label, int seeds) const {
    std::printf("%-24s %9.1f %12.4g %7.3f %7.3f %7.1f%% %7.2f%% %6d\n", label, realizations / seeds, lane_steps / seeds,
                points > 0 ? z / points : NAN, points > 0 ? z2 / points : NAN,
                points > 0 ? 100.0 * within_two / points : NAN, points > 0 ? 100.0 * beyond_three / points : NAN,
                points);
  }
};

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string case_name = "reference";
    std::vector<std::string> sets;
    RunRequest request;
    int seeds = 30;
    for (int i = 1; i + 1 < argc; i += 2) {
      const std::string key = argv[i], value = argv[i + 1];
      if (key == "--case")
        case_name = value;
      else if (key == "--set")
        sets.push_back(value);
      else if (key == "--precision")
        request.precision = std::stod(value);
      else if (key == "--seeds")
        seeds = std::stoi(value);
      else if (key == "--omega-min")
        request.omega_min = std::stod(value);
      else if (key == "--omega-max")
        request.omega_max = std::stod(value);
      else if (key == "--control-variate")
        request.control_variate = value == "shadow";
      else
        throw InputError("unknown option " + key);
    }
    if (argc % 2 == 0) throw InputError(std::string("option ") + argv[argc - 1] + " needs a value");
    const Parameters p = build_case(case_name, sets);

    std::vector<Tally> bands;
    Tally all;
    double wall = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
      request.seed = static_cast<std::uint64_t>(seed);
      const auto start = std::chrono::steady_clock::now();
      const RunResult result = run_spectrum(p, request);
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!result.complete || !result.stationary)
        std::fprintf(stderr, "seed %d: %s\n", seed, result.stationary ? "incomplete" : result.stationarity.c_str());
      bands.resize(result.sub_bands.size());
      for (std::size_t b = 0; b < result.sub_bands.size(); ++b) {
        const SubBand& band = result.sub_bands[b];
        const double steps = std::ceil(band.duration / band.dt) * static_cast<double>(band.realizations);
        bands[b].realizations += static_cast<double>(band.realizations);
        bands[b].lane_steps += steps * (band.shadow ? 2 : 1);
        all.realizations += static_cast<double>(band.realizations);
        all.lane_steps += steps * (band.shadow ? 2 : 1);
      }
      for (const RunPoint& point : result.points) {
        const double theory = std::isfinite(point.theory2) ? point.theory2 : point.theory;
        const double z = (point.C_x - theory) / point.standard_error;
        all.add_point(z);
        for (std::size_t b = 0; b < result.sub_bands.size(); ++b)
          if (point.omega >= result.sub_bands[b].omega_low * (1 - 1e-12) &&
              point.omega <= result.sub_bands[b].omega_high * (1 + 1e-12))
            bands[b].add_point(z);
      }
    }
    std::printf("%-24s %9s %12s %7s %7s %8s %8s %6s\n", "sub-band [rad/s]", "realiz.", "lane-steps", "mean z", "z^2",
                "|z|<=2", "|z|>3", "points");
    const RunResult plan = [&] {
      RunRequest fixed = request;
      fixed.realizations = 8;
      RunSession session(p, fixed);
      return session.result();
    }();
    for (std::size_t b = 0; b < bands.size(); ++b) {
      char label[64];
      std::snprintf(label, sizeof label, "%.3g..%.3g", plan.sub_bands[b].omega_low, plan.sub_bands[b].omega_high);
      bands[b].print(label, seeds);
    }
    all.print("all", seeds);
    std::printf("wall per seed %.3f s\n", wall / seeds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "slidespec_calibrate: %s\n", e.what());
    return 2;
  }
}
