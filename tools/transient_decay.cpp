// Measures how a realization's sliding relaxes from its start to the stationary state in
// time, which the spectrum assumes (docs/run.md, "Warm-up"): the mean speed over many
// realizations, in bins of the renewal time a/v, as a deviation from the speed of realizations
// that have already slid for a long time. A realization starts with its forces in their
// stationary law in sliding distance, where every force configuration weighs by the distance
// it lasts; in time a slow configuration lasts longer, so the stationary mean speed lies
// below v (by eps^2/2 to second order) and the start's excess decays as the forces renew.
//
//   slidespec_transient [--case NAME] [--set KEY=VALUE ...] [--realizations R]
//                       [--renewal-times T] [--warm-up W] [--seed S]
//
// Prints, per bin of a/v / 4: t v/a, the mean speed / v - 1 and its standard error, and the
// same for realizations started after a warm-up of W a/v; last, the reference (realizations
// after 40 a/v) and the first bin where the start's excess is within two standard errors of it.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "slidespec/input_error.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/stepper.hpp"
#include "slidespec/theory.hpp"

namespace {

using namespace slidespec;

struct Profile {
  std::vector<double> mean, error;  // per bin: speed / v - 1
};

/// The mean speed per bin over `realizations` realizations of `bins` bins, each `bin_steps`
/// steps of dt, after a warm-up of `warm_up` s.
Profile speed_profile(const Parameters& p, double dt, std::int64_t bin_steps, int bins, std::uint64_t realizations,
                      double warm_up, std::uint64_t seed) {
  StepperConfig config;
  config.dt = dt;
  config.seed = seed;
  config.warm_up = warm_up;
  config.warm_up_dt = dt;
  const int batch = 64;
  const std::size_t batches = (realizations + batch - 1) / batch;
  // Per batch and bin: the sum over its realizations of the bin's speeds, and of their squares.
  std::vector<std::vector<double>> sum(batches, std::vector<double>(static_cast<size_t>(bins), 0.0));
  std::vector<std::vector<double>> sum2 = sum;
  std::vector<std::vector<double>> lane_bin(batches);
  std::vector<std::int64_t> step_of_batch(batches, 0);
  run_batches(p, config, 0, realizations, bin_steps * bins, 0, batch,
              [&](std::uint64_t first, int count) -> IncrementSink {
                const std::size_t b = first / batch;
                lane_bin[b].assign(static_cast<size_t>(count), 0.0);
                return [&, b, count](const double* data, std::size_t steps) {
                  for (std::size_t s = 0; s < steps; ++s) {
                    for (int k = 0; k < count; ++k) lane_bin[b][static_cast<size_t>(k)] += data[s * count + k];
                    if (++step_of_batch[b] % bin_steps == 0) {
                      const auto bin = static_cast<size_t>(step_of_batch[b] / bin_steps - 1);
                      for (double& x : lane_bin[b]) {
                        const double speed = x / (static_cast<double>(bin_steps) * dt) / p.v;  // (dx/dt - v) / v
                        sum[b][bin] += speed, sum2[b][bin] += speed * speed;
                        x = 0;
                      }
                    }
                  }
                };
              },
              {});
  Profile out;
  const auto n = static_cast<double>(realizations);
  for (int bin = 0; bin < bins; ++bin) {
    double s = 0, s2 = 0;
    for (std::size_t b = 0; b < batches; ++b)
      s += sum[b][static_cast<size_t>(bin)], s2 += sum2[b][static_cast<size_t>(bin)];
    const double mean = s / n;
    out.mean.push_back(mean);
    out.error.push_back(std::sqrt(std::max(0.0, s2 / n - mean * mean) / (n - 1)));
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string case_name = "reference";
    std::vector<std::string> sets;
    std::uint64_t realizations = 4096, seed = 1;
    double renewal_times = 8, warm_up = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
      const std::string key = argv[i], value = argv[i + 1];
      if (key == "--case")
        case_name = value;
      else if (key == "--set")
        sets.push_back(value);
      else if (key == "--realizations")
        realizations = std::stoull(value);
      else if (key == "--renewal-times")
        renewal_times = std::stod(value);
      else if (key == "--warm-up")
        warm_up = std::stod(value);
      else if (key == "--seed")
        seed = std::stoull(value);
      else
        throw InputError("unknown option " + key);
    }
    const Parameters p = build_case(case_name, sets);
    const Landmarks l = landmarks(p);
    const double renewal_time = 1 / l.renewal_rate;
    const int bins_per_time = 4, bins = static_cast<int>(std::ceil(renewal_times * bins_per_time));
    const std::int64_t bin_steps = 16;
    const double dt = renewal_time / bins_per_time / static_cast<double>(bin_steps);
    std::printf("# eps %.4g, N %d, renewal %s, a/v %.4g s, %llu realizations, dt %.3g s\n", l.coupling_eps, p.N,
                to_string(p.renewal), renewal_time, static_cast<unsigned long long>(realizations), dt);
    const Profile start = speed_profile(p, dt, bin_steps, bins, realizations, 0, seed);
    const Profile warmed = speed_profile(p, dt, bin_steps, bins, realizations, warm_up * renewal_time, seed + 1);
    const Profile late = speed_profile(p, dt, bin_steps * bins, 1, realizations, 40 * renewal_time, seed + 2);
    const double stationary = late.mean[0], stationary_error = late.error[0];
    std::printf("# stationary: speed/v - 1 = %.5f +- %.5f (realizations after 40 a/v, averaged over %.3g a/v)\n",
                stationary, stationary_error, renewal_times);
    std::printf("# t v/a\tfrom_start\terror\tafter_%.3g_a/v\terror\n", warm_up);
    int settled = -1;
    for (int bin = 0; bin < bins; ++bin) {
      std::printf("%.3f\t%+.5f\t%.5f\t%+.5f\t%.5f\n", (bin + 0.5) / bins_per_time, start.mean[bin], start.error[bin],
                  warmed.mean[bin], warmed.error[bin]);
      if (settled < 0 && std::fabs(start.mean[bin] - stationary) < 2 * std::hypot(start.error[bin], stationary_error))
        settled = bin;
    }
    std::printf("# the start's excess is within 2 standard errors of the stationary speed from t v/a = %.3g\n",
                settled < 0 ? NAN : (settled + 0.5) / bins_per_time);
    // The excess's decay time: a weighted line through log(excess) over the bins where the
    // excess stands 4 standard errors clear of zero.
    double sw = 0, st = 0, sy = 0, stt = 0, sty = 0;
    const double sign = start.mean[0] >= stationary ? 1 : -1;  // a spring's lag may start either side
    for (int bin = 0; bin < bins; ++bin) {
      const double excess = sign * (start.mean[bin] - stationary),
                   error = std::hypot(start.error[bin], stationary_error);
      if (!(excess > 4 * error)) continue;
      const double t = (bin + 0.5) / bins_per_time, y = std::log(excess), w = (excess / error) * (excess / error);
      sw += w, st += w * t, sy += w * y, stt += w * t * t, sty += w * t * y;
    }
    const double slope = (sw * sty - st * sy) / (sw * stt - st * st);
    const double intercept = (sy - slope * st) / sw;
    std::printf(
        "# excess ~ %+.4f exp(-t / (%.3g a/v)); the warmed realizations' mean excess %.2e +- %.1e\n",
        sign * std::exp(intercept), -1 / slope,
        [&] {
          double sum = 0;
          for (double m : warmed.mean) sum += m - stationary;
          return sum / bins;
        }(),
        stationary_error);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "slidespec_transient: %s\n", e.what());
    return 2;
  }
}
