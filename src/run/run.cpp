#include "slidespec/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "slidespec/estimator.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {

namespace {

// Realizations per stepper batch. Fixed, so the work a batch does is the same whatever the
// SIMD width or thread count (and a multiple of every lane width).
constexpr int kBatchRealizations = 8;
// The highest omega a time step serves: omega dt <= 0.3 keeps the aliases of even the
// Brownian omega^-2 part of C_x below 0.5% (docs/numerics.md).
constexpr double kOmegaDtMax = 0.3;
// Renewals take effect at the next step; lambda dt <= 0.1 keeps that below 0.1% of S_f.
constexpr double kRenewalDtMax = 0.1;
// Each realization of a sub-band spans this many of the segments serving its lowest point.
constexpr double kSegmentsPerRealization = 6;
// The first round of a precision-driven run: fixed, not scaled by the thread count, so
// that every later round (chosen from the results so far) is the same on any machine;
// large enough that the error bars from the scatter between realizations are themselves
// good to ~13%.
constexpr std::uint64_t kInitialRealizations = 32;
// Precision-driven runs stop growing here and report the precision they reached: 65536
// realizations, or 2e9 realization-steps per sub-band (about a minute on two cores),
// whichever comes first. Where the random forces stall the block the spectrum collapses
// and its scatter can keep any precision out of reach.
constexpr std::uint64_t kMaxRealizationsPerBand = std::uint64_t{1} << 16;
constexpr double kMaxStepsPerBand = 2e9;

struct Interrupted {};

EstimatorConfig estimator_config(const SubBand& band, int points_per_decade) {
  EstimatorConfig config;
  config.dt = band.dt;
  config.omega_min = band.omega_low;
  config.omega_max = band.omega_high;
  config.points_per_decade = points_per_decade;
  config.input = SampleKind::increment;
  return config;
}

/// What one sub-band has accumulated, merged in realization order.
struct BandTotals {
  SpectrumAccumulator spectrum;
  // Per realization: its own mean periodogram at each output point, and its control.
  std::vector<std::vector<double>> own_mean;
  std::vector<double> control;
  double speed_sum = 0, speed_sum2 = 0;
  std::uint64_t realizations = 0;
  double miniblock_steps = 0;
};

// Below this many realizations the scatter between them is too coarse for the control
// variate; the estimator's own (segment-scatter) error bars are used instead.
constexpr std::uint64_t kMinimumForControl = 8;

/// The relative excess of a realization's forcing over what the model prescribes:
/// sum (f_new - f_old)^2 over its renewals against 2 s2 per renewal mark passed, x/a per
/// contact (exactly its expectation: marks and forces are drawn independently of x).
double forcing_control(const Parameters& p, const RealizationSummary& r) {
  const double distance = p.v * r.duration + r.xi_end;
  const double expected = expected_jump_energy(p, distance);
  return expected > 0 ? r.jump_energy / expected - 1 : 0.0;
}

/// The band's spectrum. Above v/a every point of a band is driven by the same renewals,
/// so their realized number and sizes move all points together; that common part is
/// removed with the exactly known mean of the forcing as a control variate (regression
/// over realizations), which leaves unbiased, nearly independent errors. The error bars
/// come from the scatter between independent realizations about the regression.
std::vector<SpectrumPoint> band_spectrum(const BandTotals& totals) {
  std::vector<SpectrumPoint> points = totals.spectrum.spectrum();
  const std::size_t R = totals.own_mean.size();
  if (R < kMinimumForControl) return points;
  const auto sums = totals.spectrum.point_sums();
  double y_mean = 0;
  for (double y : totals.control) y_mean += y / static_cast<double>(R);
  double syy = 0;
  for (double y : totals.control) syy += (y - y_mean) * (y - y_mean);
  for (SpectrumPoint& point : points) {
    std::size_t k = 0;
    while (k < sums.size() && sums[k].omega != point.omega) ++k;
    if (k == sums.size() || sums[k].segments == 0 || sums[k].sum <= 0) continue;
    // spectrum() corrects the raw mean for the window's smoothing: keep that factor.
    const double smoothing = point.C / (sums[k].sum / static_cast<double>(sums[k].segments));
    double x_mean = 0;
    for (std::size_t r = 0; r < R; ++r) x_mean += totals.own_mean[r][k] / static_cast<double>(R);
    double sxy = 0;
    for (std::size_t r = 0; r < R; ++r) sxy += (totals.own_mean[r][k] - x_mean) * (totals.control[r] - y_mean);
    const double slope = syy > 0 ? sxy / syy : 0.0;
    double residual = 0;
    for (std::size_t r = 0; r < R; ++r) {
      const double e = totals.own_mean[r][k] - x_mean - slope * (totals.control[r] - y_mean);
      residual += e * e;
    }
    const double n = static_cast<double>(R);
    const double variance = residual / (n - 2) * (1 / n + (syy > 0 ? y_mean * y_mean / syy : 0.0));
    point.C = smoothing * (x_mean - slope * y_mean);
    point.standard_error = smoothing * std::sqrt(variance);
  }
  return points;
}

/// Runs realizations [first, first + count) of one sub-band and adds them to `totals` in
/// realization order. Returns false if interrupted (the completed prefix is still added).
bool run_round(const Parameters& p, const SubBand& band, const StepperConfig& stepper_config,
               const RunRequest& request, std::uint64_t first, std::uint64_t count,
               std::int64_t steps, BandTotals& totals, const std::atomic<bool>* stop,
               const std::function<void(double)>& round_progress) {
  const EstimatorConfig config = estimator_config(band, request.points_per_decade);
  std::map<std::size_t, std::vector<SpectrumAccumulator>> accumulators;  // by batch
  std::map<std::size_t, std::vector<RealizationSummary>> summaries;
  std::atomic<std::int64_t> lane_steps_done{0};
  const double lane_steps_planned = static_cast<double>(count) * static_cast<double>(steps);
  std::map<std::uint64_t, std::shared_ptr<SpectrumEstimator>> estimators;  // by first realization

  bool interrupted = false;
  try {
    run_batches(
        p, stepper_config, first, count, steps, request.threads, kBatchRealizations,
        [&](std::uint64_t batch_first, int batch_count) -> IncrementSink {
          auto estimator = std::make_shared<SpectrumEstimator>(config, batch_count);
          estimators[batch_first] = estimator;
          return [&, estimator, batch_count](const double* data, std::size_t n) {
            if (stop && stop->load(std::memory_order_relaxed)) throw Interrupted{};
            estimator->push(data, n);
            const auto done = lane_steps_done += static_cast<std::int64_t>(n) * batch_count;
            if (round_progress) round_progress(static_cast<double>(done) / lane_steps_planned);
          };
        },
        [&](std::size_t batch, std::vector<RealizationSummary> s) {
          const std::uint64_t batch_first = first + batch * kBatchRealizations;
          const auto& estimator = estimators.at(batch_first);
          std::vector<SpectrumAccumulator> lanes;
          for (int lane = 0; lane < estimator->lanes(); ++lane) lanes.push_back(estimator->accumulator(lane));
          accumulators[batch] = std::move(lanes);
          summaries[batch] = std::move(s);
          estimators.erase(batch_first);
        });
  } catch (const Interrupted&) {
    interrupted = true;
  }
  // Merge the completed prefix of batches in realization order: the same sums, in the
  // same order, whatever thread finished which batch first.
  for (std::size_t batch = 0; accumulators.count(batch) != 0; ++batch) {
    for (const SpectrumAccumulator& lane : accumulators[batch]) {
      totals.spectrum.merge(lane);
      std::vector<double> own;
      for (const auto& point : lane.point_sums())
        own.push_back(point.segments > 0 ? point.sum / static_cast<double>(point.segments) : 0.0);
      totals.own_mean.push_back(std::move(own));
    }
    for (const RealizationSummary& r : summaries[batch]) {
      totals.control.push_back(forcing_control(p, r));
      const double speed = p.v + r.xi_end / r.duration;
      totals.speed_sum += speed;
      totals.speed_sum2 += speed * speed;
      ++totals.realizations;
      totals.miniblock_steps += static_cast<double>(p.N) * static_cast<double>(steps);
    }
  }
  return !interrupted;
}

double worst_relative_error(const std::vector<SpectrumPoint>& points, std::size_t expected_points) {
  if (points.size() < expected_points) return INFINITY;
  double worst = 0;
  for (const SpectrumPoint& point : points)
    worst = std::max(worst, point.C > 0 ? point.standard_error / point.C : INFINITY);
  return worst;
}

}  // namespace

std::vector<SubBand> plan_sub_bands(const Parameters& p, const RunRequest& request) {
  const std::vector<double> omegas =
      log_spaced_omegas(request.omega_min, request.omega_max, request.points_per_decade);
  if (!(request.precision > 0) || !(request.precision < 1))
    throw InputError("--precision: must be between 0 and 1 (a relative standard error)");
  if (request.duration < 0 || !std::isfinite(request.duration))
    throw InputError("--duration: must be a positive number of seconds");

  // About one decade per sub-band; a short remainder joins the sub-band below it.
  const std::size_t per_band = static_cast<std::size_t>(request.points_per_decade);
  std::vector<std::pair<std::size_t, std::size_t>> groups;  // [first, last] point index
  for (std::size_t first = 0; first < omegas.size(); first += per_band)
    groups.emplace_back(first, std::min(first + per_band, omegas.size()) - 1);
  if (groups.size() > 1 && groups.back().second - groups.back().first + 1 < per_band / 2) {
    groups[groups.size() - 2].second = groups.back().second;
    groups.pop_back();
  }

  std::vector<SubBand> bands;
  for (const auto& [first, last] : groups) {
    SubBand band;
    band.omega_low = omegas[first];
    band.omega_high = omegas[last];
    band.dt = std::min(kOmegaDtMax / band.omega_high, kRenewalDtMax / p.renewal_rate());
    const double segment = SpectrumEstimator(estimator_config(band, request.points_per_decade), 1)
                               .segment_duration(band.omega_low);
    band.duration = request.duration > 0
                        ? request.duration * omegas.front() / band.omega_low
                        : kSegmentsPerRealization * segment;
    // At least the segments a point needs, whatever the user's fixed duration.
    band.duration = std::max(band.duration, 1.5 * segment);
    bands.push_back(band);
  }
  return bands;
}

RunResult run_spectrum(const Parameters& p, const RunRequest& request, const ProgressCallback& progress,
                       const std::atomic<bool>* stop) {
  const auto start = std::chrono::steady_clock::now();
  RunResult result;
  result.sub_bands = plan_sub_bands(p, request);
  result.simd_path = resolve_simd_path(request.simd);
  result.threads = request.threads > 0 ? request.threads
                                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t band_count = result.sub_bands.size();
  const std::uint64_t initial_realizations =
      request.realizations > 0 ? request.realizations
                               : kInitialRealizations;

  std::vector<BandTotals> totals(band_count);
  bool interrupted = false;
  for (std::size_t b = 0; b < band_count && !interrupted; ++b) {
    SubBand& band = result.sub_bands[b];
    StepperConfig stepper_config;
    stepper_config.dt = band.dt;
    stepper_config.seed = request.seed;
    stepper_config.stream = b;  // sub-bands are independent simulations
    stepper_config.simd = result.simd_path;
    const auto steps = static_cast<std::int64_t>(std::ceil(band.duration / band.dt));
    band.duration = static_cast<double>(steps) * band.dt;
    const std::size_t expected_points =
        log_spaced_omegas(band.omega_low, band.omega_high * (1 + 1e-12), request.points_per_decade).size();

    const std::uint64_t most_realizations = std::max<std::uint64_t>(
        kInitialRealizations,
        std::min<std::uint64_t>(kMaxRealizationsPerBand,
                                static_cast<std::uint64_t>(kMaxStepsPerBand / static_cast<double>(steps))));
    std::uint64_t round_size = initial_realizations;
    for (;;) {
      const double band_fraction = static_cast<double>(b) / band_count;
      auto round_progress = [&](double f) {
        if (progress)
          progress(band_fraction + f / band_count,
                   "sub-band " + std::to_string(b + 1) + "/" + std::to_string(band_count) + ", round " +
                       std::to_string(band.rounds + 1));
      };
      const bool finished = run_round(p, band, stepper_config, request, band.realizations, round_size,
                                      steps, totals[b], stop, round_progress);
      band.realizations = totals[b].realizations;
      ++band.rounds;
      if (!finished) {
        interrupted = true;
        break;
      }
      if (request.realizations > 0) break;
      const double worst = worst_relative_error(band_spectrum(totals[b]), expected_points);
      if (worst <= request.precision || band.realizations >= most_realizations) break;
      // Standard errors fall as 1/sqrt(realizations): plan the total with a 30% margin, so
      // that a run stops because it planned enough, not because its error estimate happened
      // to dip below the target (which would bias the reported error bars low). At most
      // eight times more per round, so a noisy early estimate cannot run away.
      const double factor = std::isfinite(worst) ? 1.3 * (worst / request.precision) * (worst / request.precision) : 8.0;
      const auto wanted = static_cast<std::uint64_t>(std::ceil(static_cast<double>(band.realizations) *
                                                               std::min(factor, 8.0)));
      round_size = std::max<std::uint64_t>(wanted - band.realizations, kBatchRealizations);
      round_size = (round_size + kBatchRealizations - 1) / kBatchRealizations * kBatchRealizations;
      round_size = std::min(round_size, most_realizations - band.realizations);
    }
  }

  // Points, with the theory of the simulated (time-stepped) process seen through the
  // estimator: averaged over each point's bins and smoothed by the window exactly as the
  // estimate is. The continuous-time C_x at omega is reported beside it.
  const LumpedTheory theory(p);
  for (std::size_t b = 0; b < band_count; ++b) {
    const std::vector<SpectrumPoint> estimated = band_spectrum(totals[b]);
    const std::vector<SpectrumPoint> expected =
        totals[b].spectrum.expected(SampledTheory(p, result.sub_bands[b].dt));
    for (std::size_t k = 0; k < estimated.size(); ++k) {
      const SpectrumPoint& e = estimated[k];
      result.points.push_back(
          {e.omega, e.C, e.standard_error, expected[k].C, theory(e.omega), e.n_avg, e.bandwidth});
    }
    result.simulated_time += static_cast<double>(totals[b].realizations) * result.sub_bands[b].duration;
    result.miniblock_steps += totals[b].miniblock_steps;
  }
  std::sort(result.points.begin(), result.points.end(),
            [](const RunPoint& x, const RunPoint& y) { return x.omega < y.omega; });

  if (!totals.empty() && totals[0].realizations > 0) {
    const double n = static_cast<double>(totals[0].realizations);
    result.mean_speed = totals[0].speed_sum / n;
    const double variance = std::max(0.0, totals[0].speed_sum2 / n - result.mean_speed * result.mean_speed);
    result.mean_speed_error = n > 1 ? std::sqrt(variance / (n - 1)) : INFINITY;
  }
  result.reached_precision = 0;
  for (const RunPoint& point : result.points)
    result.reached_precision = std::max(result.reached_precision, point.standard_error / point.C_x);
  const std::size_t expected_total =
      log_spaced_omegas(request.omega_min, request.omega_max, request.points_per_decade).size();
  result.complete = !interrupted && result.points.size() == expected_total;
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace slidespec
