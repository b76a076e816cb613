// A spectrum run: from a parameter set and a band to the simulated C_x(omega) with error
// bars, beside the exact theory. This is what `slidespec run` does, as a library call.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "slidespec/parameters.hpp"
#include "slidespec/stepper.hpp"

namespace slidespec {

struct RunRequest {
  double omega_min = 0.1;          ///< lowest output omega [rad/s]
  double omega_max = 1e5;          ///< highest output omega [rad/s]
  int points_per_decade = 8;
  double precision = 0.05;         ///< target standard error / C_x at every point
  double duration = 0;             ///< > 0: fixed simulated time per realization of the lowest sub-band [s]
  std::uint64_t realizations = 0;  ///< > 0: fixed number of realizations per sub-band
  std::uint64_t seed = 1;
  int threads = 0;                 ///< 0 = all cores
  SimdPath simd = SimdPath::automatic;
};

/// One sub-run: a stretch of the band simulated with its own time step.
struct SubBand {
  double omega_low = 0, omega_high = 0;  ///< output points it serves [rad/s]
  double dt = 0;                         ///< its time step [s]
  double duration = 0;                   ///< simulated time per realization [s]
  std::uint64_t realizations = 0;        ///< realizations completed
  int rounds = 0;                        ///< rounds of realizations run
};

struct RunPoint {
  double omega;            ///< [rad/s]
  double C_x;              ///< estimate [m^2 s]
  double standard_error;   ///< [m^2 s]
  double theory;           ///< exact theory averaged as the estimate averages it [m^2 s]
  double theory_at_omega;  ///< exact theory at omega [m^2 s]
  double n_avg;            ///< periodogram values averaged
  double bandwidth;        ///< resolution bandwidth [rad/s]
};

struct RunResult {
  std::vector<RunPoint> points;
  std::vector<SubBand> sub_bands;
  double mean_speed = 0;            ///< measured, over the lowest sub-band's realizations [m/s]
  double mean_speed_error = 0;      ///< its standard error [m/s]
  double simulated_time = 0;        ///< all realizations of all sub-bands [s]
  double miniblock_steps = 0;       ///< N x realization-steps simulated
  double wall_seconds = 0;
  double reached_precision = 0;     ///< largest standard_error / C_x over the points
  SimdPath simd_path = SimdPath::scalar;
  int threads = 1;
  bool complete = false;            ///< false when interrupted or out of budget
};

/// Progress of a run, for a progress bar: fraction of the planned work and a message.
using ProgressCallback = std::function<void(double fraction, const std::string& what)>;

/// Runs until every point reaches `precision` (or the fixed duration/realizations are
/// spent). Setting `*stop` (e.g. from a signal handler) ends the run early with what has
/// accumulated, `complete = false`. Same seed and request, same numbers, whatever the
/// thread count or SIMD path.
RunResult run_spectrum(const Parameters& params, const RunRequest& request,
                       const ProgressCallback& progress = {}, const std::atomic<bool>* stop = nullptr);

/// The sub-runs a request is split into: about a decade each, with the time step set by
/// the sub-band's top frequency (and the renewal rate), not by the model's stiffness.
std::vector<SubBand> plan_sub_bands(const Parameters& params, const RunRequest& request);

}  // namespace slidespec
