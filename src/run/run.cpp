#include "slidespec/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "run/session.hpp"
#include "slidespec/estimator.hpp"
#include "slidespec/stepper.hpp"
#include "slidespec/theory.hpp"
#include "stepper/kernel.hpp"

namespace slidespec {

using namespace run_detail;

namespace {
// The highest omega a time step serves: omega dt <= 0.3 keeps the aliases of even the
// Brownian omega^-2 part of C_x below 0.5% (docs/numerics.md).
constexpr double kOmegaDtMax = 0.3;
// Renewals inside a step are exact however many (docs/numerics.md §2), and more per step
// fill more lanes per renewal pass; but a step's renewals are its work, so the steps of a
// band far below v/a are capped at this many renewals per realization.
constexpr double kRenewalsPerStepMax = 16;
// Each realization of a sub-band spans this many of the segments serving its lowest point.
// Two: a precision-driven run's first round (64 realizations) then lands near the default
// 5% at a sub-band's lowest points instead of far below it (six gave 1-2% there, three
// times the work, most of a run's time in its lowest sub-band), and every point still gets
// whole segments from every realization.
constexpr double kSegmentsPerRealization = 2;
// A realization holds at least this many renewals (of all its contacts together), up to
// kMostLengthening times its two segments. Where it holds a few, its periodogram at the
// sub-band's points is the energy of those few jumps, weighted by where they fall in the
// windows (a jump near an edge counts little); the spread of their number and places is
// most of the scatter between realizations, and the scatter per unit of work falls as
// realizations lengthen. Measured at the reference's top sub-band (1e4..1e5 rad/s, 1.5
// renewals in two segments; equal work, 8 seeds): 1.23% with two segments, 0.72% with six,
// 0.53% with twenty (15 renewals), 0.69% with sixty, whose fewer realizations leave the
// regression on the forcing control variate less to work with.
constexpr double kRenewalsPerRealization = 15;
constexpr double kMostLengthening = 10;
// Precision-driven runs stop growing at kMaxRealizationsPerBand (session.hpp) or 2e9
// realization-steps per sub-band (about a minute on two cores; a block coasting near the
// stall counts its extra renewals too, validate.cpp), whichever comes first, and
// report the precision they reached. Where the random forces stall the block the spectrum
// collapses and its scatter can keep any precision out of reach (kMaxStepsPerBand,
// session.hpp).
// Batches per process in one chunk: the unit of checkpoints, of the work shared between
// processes and of what an interrupt can lose. It changes no number (every sum runs over
// the batches in realization order), only how often the session can be saved.
constexpr std::uint64_t kChunkBatches = 32;

struct Interrupted {};
// A realization's block ran away: the stepper made its increments NaN (stepper/kernel.hpp).
struct RanAway {};

/// Whether no value is NaN or inf: x * 0 is 0 for a finite x and NaN otherwise, summed in
/// four independent chains so the check costs a fraction of a cycle per value.
bool all_finite(const double* data, std::size_t count) {
  double sum[4] = {0, 0, 0, 0};
  std::size_t k = 0;
  for (; k + 4 <= count; k += 4)
    for (int j = 0; j < 4; ++j) sum[j] += data[k + j] * 0.0;
  for (; k < count; ++k) sum[0] += data[k] * 0.0;
  return sum[0] + sum[1] + sum[2] + sum[3] == 0;
}

}  // namespace

EstimatorConfig run_detail::estimator_config(const SubBand& band, int points_per_decade) {
  EstimatorConfig config;
  config.dt = band.dt;
  config.omega_min = band.omega_low;
  config.omega_max = band.omega_high;
  config.points_per_decade = points_per_decade;
  config.input = SampleKind::increment;
  return config;
}

namespace {

// Below this many realizations the scatter between them is too coarse for the control
// variate; the estimator's own (segment-scatter) error bars are used instead.
constexpr std::uint64_t kMinimumForControl = 8;

}  // namespace

std::uint64_t run_detail::first_round_realizations(const Parameters& p, const RunRequest& request,
                                                   const SubBand& band) {
  if (request.realizations > 0) return request.realizations;
  const double reach = kInitialRoundReach / request.precision;
  const double renewals = renewals_per_second(p) * band.duration;
  const double wanted = std::max(static_cast<double>(kInitialRealizations) * reach * reach,
                                 renewals > 0 ? kFirstRoundRenewals / renewals : 0.0);
  const double batches = std::ceil(std::min(wanted, static_cast<double>(kInitialRealizations)) / kBatchRealizations);
  const std::uint64_t first = std::max(kFewestFirstRound, static_cast<std::uint64_t>(batches) * kBatchRealizations);
  if (!(renewals > 0) || static_cast<double>(first) * renewals >= kLeastBandRenewals) return first;
  // Beyond any sub-band's cap, which validate_request refuses before work.
  const double least = std::min(std::ceil(kLeastBandRenewals / renewals / kBatchRealizations), 0x1p52);
  return static_cast<std::uint64_t>(least) * kBatchRealizations;
}

namespace {

/// The frequency a sub-band's time step must serve: its top point, and for a block held
/// by a spring at least omega_s. Below omega_s C_x stops rising (docs/model.md §9), so what
/// lies above the step's Nyquist frequency is not negligible against the band as an
/// omega^-2 spectrum's is: a step set by a band far below omega_s (or by the renewals)
/// would alias the spectrum near omega_s into it (2% at 0.01 rad/s for omega_s = 1 rad/s
/// and a 2.7 s step). At omega_s dt <= 0.3 the aliases come from beyond 20 omega_s, where
/// C_x has fallen by 1e-5.
double step_frequency(const Parameters& p, const SubBand& band) {
  return p.drive == Drive::spring ? std::max(band.omega_high, landmarks(p).omega_s) : band.omega_high;
}

/// The relative excess of a realization's forcing over what the model prescribes:
/// sum (f_new - f_old)^2 over its renewals against 2 s2 per renewal mark passed, x/a per
/// contact (exactly its expectation: marks and forces are drawn independently of x).
double forcing_control(const Parameters& p, const RealizationSummary& r) {
  const double distance = p.v * r.duration + r.xi_end;
  const double expected = expected_jump_energy(p, distance);
  return expected > 0 ? r.jump_energy / expected - 1 : 0.0;
}

/// A sub-band's estimate, point by point: what spectrum() gives, with the estimator used
/// and its variance over the plain mean's.
struct BandEstimate {
  std::vector<SpectrumPoint> points;
  std::vector<const char*> estimator;
  std::vector<double> variance_ratio;
};

/// The shadow's expected mean periodogram per point (before the smoothing correction), by
/// omega: the first-order theory through the estimator, exactly (docs/run.md, "The shadow").
std::map<double, double> shadow_expectation(const Parameters& p, const SpectrumAccumulator& merged) {
  std::map<double, double> out;
  const LumpedTheory theory(p);
  for (const SpectrumPoint& e : merged.expected(std::cref(theory), PointValue::window_smoothed)) out[e.omega] = e.C;
  return out;
}

/// The intercept of a least-squares regression of x on the controls, at the controls'
/// known means (zero), with its variance: the control-variate estimate of E[x].
struct Regression {
  double estimate = 0, variance = INFINITY;
};
Regression regress(const std::vector<double>& x, const std::vector<const std::vector<double>*>& controls) {
  const std::size_t n = x.size(), m = controls.size();
  if (n < m + 4) return {};
  const double count = static_cast<double>(n);
  double x_mean = 0;
  for (double v : x) x_mean += v / count;
  std::vector<double> mean(m, 0.0);
  for (std::size_t j = 0; j < m; ++j)
    for (double v : *controls[j]) mean[j] += v / count;
  // Centered sums: S (controls x controls), s (controls x x), and x's own.
  double S[2][2] = {{0, 0}, {0, 0}}, sx[2] = {0, 0}, sxx = 0;
  for (std::size_t r = 0; r < n; ++r) {
    const double dx = x[r] - x_mean;
    sxx += dx * dx;
    for (std::size_t j = 0; j < m; ++j) {
      const double dj = (*controls[j])[r] - mean[j];
      sx[j] += dj * dx;
      for (std::size_t k = 0; k < m; ++k) S[j][k] += dj * ((*controls[k])[r] - mean[k]);
    }
  }
  double inverse[2][2] = {{0, 0}, {0, 0}};
  if (m == 1) {
    if (!(S[0][0] > 0)) return {};
    inverse[0][0] = 1 / S[0][0];
  } else {
    const double det = S[0][0] * S[1][1] - S[0][1] * S[1][0];
    if (!(det > 0)) return {};
    inverse[0][0] = S[1][1] / det, inverse[1][1] = S[0][0] / det;
    inverse[0][1] = inverse[1][0] = -S[0][1] / det;
  }
  double slope[2] = {0, 0};
  for (std::size_t j = 0; j < m; ++j)
    for (std::size_t k = 0; k < m; ++k) slope[j] += inverse[j][k] * sx[k];
  double residual = sxx, leverage = 0, estimate = x_mean;
  for (std::size_t j = 0; j < m; ++j) {
    residual -= slope[j] * sx[j];
    estimate -= slope[j] * mean[j];
    for (std::size_t k = 0; k < m; ++k) leverage += mean[j] * inverse[j][k] * mean[k];
  }
  // The scatter about the regression, unbiased; the estimate's error over the error bar
  // it gives then follows Student's t with `dof` degrees of freedom, whose mean square is
  // dof / (dof - 2): the bar carries that factor, so that z^2 averages 1 also for the few
  // realizations of a coarse target's first round (1.07 for 32 realizations).
  const double dof = count - static_cast<double>(m) - 1;
  const double sigma2 = std::max(residual, 0.0) / dof;
  return {estimate, sigma2 * (1 / count + leverage) * dof / (dof - 2)};
}

/// The band's spectrum. Above v/a every point of a band is driven by the same renewals,
/// so their realized number and sizes move all points together; that common part is
/// removed with the exactly known mean of the forcing as a control variate (regression
/// over realizations), which leaves unbiased, nearly independent errors. Each
/// realization's linear shadow (docs/run.md) is a second control, whose mean is the
/// first-order theory through the estimator: where it follows the block closely it
/// removes most of the scatter; where a regression on it does not lower the estimated
/// variance, the forcing alone serves. The error bars come from the scatter between
/// independent realizations about the regression.
BandEstimate band_spectrum(const BandTotals& totals, const SpectrumAccumulator& merged,
                           const std::map<double, double>& shadow_mean_expected) {
  BandEstimate out;
  out.points = merged.spectrum();
  out.estimator.assign(out.points.size(), "plain");
  out.variance_ratio.assign(out.points.size(), 1.0);
  std::vector<const std::vector<double>*> own_mean, shadow_mean;
  std::vector<double> control;
  const std::size_t point_count = merged.point_sums().size();
  bool shadows = true;
  for (const BatchRecord& batch : totals.batches)
    for (std::size_t r = 0; r < batch.control.size(); ++r) {
      if (batch.own_mean[r].size() != point_count ||
          (!batch.shadow_mean.empty() && batch.shadow_mean[r].size() != point_count))
        throw InputError("run state: a batch record does not match its sub-band's points");
      own_mean.push_back(&batch.own_mean[r]);
      control.push_back(batch.control[r]);
      if (batch.shadow_mean.empty())
        shadows = false;
      else
        shadow_mean.push_back(&batch.shadow_mean[r]);
    }
  const std::size_t R = control.size();
  if (R < kMinimumForControl) return out;
  const auto sums = merged.point_sums();
  std::vector<double> x(R), shadow(R);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    SpectrumPoint& point = out.points[i];
    std::size_t k = 0;
    while (k < sums.size() && sums[k].omega != point.omega) ++k;
    if (k == sums.size() || sums[k].segments == 0 || sums[k].sum <= 0) continue;
    // spectrum() corrects the raw mean for the window's smoothing: keep that factor.
    const double smoothing = point.C / (sums[k].sum / static_cast<double>(sums[k].segments));
    for (std::size_t r = 0; r < R; ++r) x[r] = (*own_mean[r])[k];
    double x_mean = 0, sxx = 0;
    for (double v : x) x_mean += v / static_cast<double>(R);
    for (double v : x) sxx += (v - x_mean) * (v - x_mean);
    const double plain = sxx / static_cast<double>(R - 1) / static_cast<double>(R);
    Regression best = regress(x, {&control});
    out.estimator[i] = "forcing";
    const auto expected = shadow_mean_expected.find(point.omega);
    if (shadows && expected != shadow_mean_expected.end()) {
      for (std::size_t r = 0; r < R; ++r) shadow[r] = (*shadow_mean[r])[k] - expected->second;
      const Regression both = regress(x, {&shadow, &control});
      if (both.variance < best.variance) best = both, out.estimator[i] = "shadow";
    }
    if (!std::isfinite(best.variance)) continue;
    point.C = smoothing * best.estimate;
    point.standard_error = smoothing * std::sqrt(best.variance);
    out.variance_ratio[i] = plain > 0 ? best.variance / plain : 1.0;
  }
  return out;
}

/// A realization's mean periodogram per point, before the smoothing correction.
std::vector<double> own_means(const SpectrumAccumulator& own) {
  std::vector<double> mean;
  for (const auto& point : own.point_sums())
    mean.push_back(point.segments > 0 ? point.sum / static_cast<double>(point.segments) : 0.0);
  return mean;
}

/// Runs realizations [first, first + count) of one sub-band, in batches from `first`, and
/// returns the completed prefix of its batches in realization order (all of them unless
/// `stop` was set).
std::vector<BatchRecord> run_batches_of(const Parameters& p, const SubBand& band, const StepperConfig& stepper_config,
                                        const RunRequest& request, std::uint64_t first, std::uint64_t count,
                                        std::int64_t steps, const std::atomic<bool>* stop,
                                        const std::function<void(double)>& chunk_progress, bool& ran_away) {
  const EstimatorConfig config = estimator_config(band, request.points_per_decade);
  std::map<std::size_t, BatchRecord> records;
  std::map<std::uint64_t, std::shared_ptr<SpectrumEstimator>> estimators, shadows;  // by first realization
  std::atomic<std::int64_t> lane_steps_done{0};
  const double warm_steps = band.warm_up > 0 ? std::ceil(band.warm_up / band.warm_up_dt) : 0.0;
  const double lane_steps_planned = static_cast<double>(count) * (static_cast<double>(steps) + warm_steps);
  StepperConfig stoppable = stepper_config;
  stoppable.stop = stop;  // heard inside a realization too, its warm-up included
  stoppable.warm_up_progress = [&](std::int64_t lane_steps) {
    const auto done = lane_steps_done += lane_steps;
    if (chunk_progress) chunk_progress(static_cast<double>(done) / lane_steps_planned);
  };
  try {
    run_batches(
        p, stoppable, first, count, steps, request.threads, kBatchRealizations,
        [&](std::uint64_t batch_first, int batch_count) -> BatchSinks {
          auto estimator = std::make_shared<SpectrumEstimator>(config, batch_count, request.simd);
          estimators[batch_first] = estimator;
          BatchSinks sinks;
          sinks.block = [&, estimator, batch_count](const double* data, std::size_t n) {
            if (stop && stop->load(std::memory_order_relaxed)) throw Interrupted{};
            if (!all_finite(data, n * static_cast<std::size_t>(batch_count))) throw RanAway{};
            estimator->push(data, n);
            const auto done = lane_steps_done += static_cast<std::int64_t>(n) * batch_count;
            if (chunk_progress) chunk_progress(static_cast<double>(done) / lane_steps_planned);
          };
          if (stepper_config.shadow) {
            auto shadow = std::make_shared<SpectrumEstimator>(config, batch_count, request.simd);
            shadows[batch_first] = shadow;
            sinks.shadow = [shadow](const double* data, std::size_t n) { shadow->push(data, n); };
          }
          return sinks;
        },
        [&](std::size_t batch, std::vector<RealizationSummary> summaries) {
          const std::uint64_t batch_first = first + batch * kBatchRealizations;
          const auto& estimator = estimators.at(batch_first);
          BatchRecord record;
          for (int lane = 0; lane < estimator->lanes(); ++lane) {
            const SpectrumAccumulator own = estimator->accumulator(lane);
            record.spectrum.merge(own);
            record.own_mean.push_back(own_means(own));
          }
          for (const RealizationSummary& r : summaries) {
            record.control.push_back(forcing_control(p, r));
            record.speed.push_back(p.v + r.xi_end / r.duration);
          }
          if (const auto shadow = shadows.find(batch_first); shadow != shadows.end()) {
            for (int lane = 0; lane < shadow->second->lanes(); ++lane)
              record.shadow_mean.push_back(own_means(shadow->second->accumulator(lane)));
            shadows.erase(shadow);
          }
          records[batch] = std::move(record);
          estimators.erase(batch_first);
        });
  } catch (const Interrupted&) {
  } catch (const StepperStopped&) {
  } catch (const RanAway&) {
    ran_away = true;
  }
  std::vector<BatchRecord> prefix;
  for (std::size_t batch = 0; records.count(batch) != 0; ++batch) prefix.push_back(std::move(records[batch]));
  return prefix;
}

// A stationary run slides at v on average in every sub-band, short by the second-order
// eps^2/2 (0.3% for the reference case, at most 4.5% where eps <= 0.3); a stalled block
// loses most of it (84% for the stall example, docs/model.md). Half of v, beyond five
// standard errors, lies far from both.
constexpr double kStalledSpeedDeficit = 0.5;
constexpr double kSpeedStandardErrors = 5;
// Under a spring the mean speed is v once the block holds its stationary lag. A realization
// starts at the first-order lag d0; the stationary lag differs from it by the second-order
// shift of the mean friction, about eps^2/2 (F_drive - F_kin), over k_drive, a displacement
// the block makes once, early, and which its mean speed carries as that over the duration.
// Allowed: four times that (forces that cannot stall the block only), and else the
// rounding of summed increments.
constexpr double kSpringSpeedRoundoff = 1e-9;
constexpr double kSpringLagShifts = 4;
// Where the forces can stall the block the spring's stretch wanders over its whole range,
// (F_drive - F_kin + the random forces' reach) / k_drive, which the load point takes up in
// tau = range / v: the lowest sub-band's realizations must span this many tau to sample
// that wandering, and every sub-band's mean speed may carry twice the range over its duration.
constexpr double kSpringRelaxations = 20;
constexpr double kSpringRanges = 2;
// Renewals per contact a realization must span before its sliding can vouch for a
// parameter set whose forces can stall the block.
constexpr double kStallRenewalsToJudge = 100;
// Neighbouring sub-bands of one stationary process join smoothly: their estimates over
// theory differ by their errors only (a few per cent). Stalls make them disagree by 5 to
// 50 times (docs/model.md §8); a factor of two beyond five standard errors is a break.
constexpr double kBandBreakFactor = 2;

/// The chance that a sliding realization of `duration` still averages below v/2, bounded
/// with Hoeffding's inequality: its speed falls short of v by (sum of its contacts' forces,
/// averaged over the realization) / (F_drive - F_kin), a sum of independent bounded draws,
/// about v duration / (2 a) of them per contact (docs/model.md §8).
/// The largest sum of the touching contacts' random forces [N]: each f_j lies in
/// [-alpha f_kin / 2, alpha f_kin / 2).
double random_force_reach(const Parameters& p) {
  double reach = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) reach += static_cast<double>(p.blocks(l)) * p.level(l).alpha * p.friction_per_miniblock() / 2;
  return reach;
}

double slow_sliding_chance(const Parameters& p, double duration) {
  const double resistance = random_force_reach(p);
  double range_squared = 0, longest_a = 0;
  for (int l = 1; l <= p.levels; ++l) {
    if (!p.touches(l)) continue;
    const double contacts = static_cast<double>(p.blocks(l));
    const double range = p.level(l).alpha * p.friction_per_miniblock();  // f_j in [-range/2, range/2)
    range_squared += contacts * range * range;
    longest_a = std::max(longest_a, p.level(l).a);
  }
  const double drive_excess = p.F_drive - p.F_kin;
  if (resistance <= kStalledSpeedDeficit * drive_excess) return 0;  // frozen forces cannot slow it that much
  const double draws = std::max(1.0, p.v * duration / (2 * longest_a));
  const double deficit = kStalledSpeedDeficit * drive_excess;
  return std::min(1.0, std::exp(-2 * deficit * deficit * draws / range_squared));
}

/// The range over which a spring's stretch wanders where the forces can stall the block,
/// (F_drive - F_kin + the random forces' reach) / k_drive [m]; 0 where they cannot.
double spring_stretch_range(const Parameters& p) {
  if (p.drive != Drive::spring || !landmarks(p).forces_can_stall) return 0;
  return (p.F_drive - p.F_kin + random_force_reach(p)) / p.k_drive;
}

/// The warm-up (docs/run.md, "Warm-up"). A realization starts with its forces in their
/// stationary law in sliding distance; in time a resisting configuration lasts longer, so
/// the block slides faster at first than in the stationary state, by about eps^2/2 of v, an
/// excess that decays as exp(-t / tau) (tools/transient_decay.cpp, 2e5 realizations a case):
/// tau = (1 + 2.5 eps^2) a/v for poisson marks (measured 1.05-1.11 a/v at eps 0.2-0.25, 1.21 at
/// 0.33, 1.37 at 0.39 next to the stall), half that for periodic ones (0.58, 0.59, 0.66); under
/// a spring the lag's relaxation, 1.5/omega_s + 2 a/v (measured 6.7 a/v at omega_s = 0.3 v/a,
/// 13-15 at 0.1). The warm-up lasts tau ln(eps^2 / kWarmUpResidual): what is left of the
/// excess is under kWarmUpResidual of v, ten times below the finest precision a run reaches.
constexpr double kWarmUpResidual = 1e-4;

struct WarmUp {
  double duration = 0, dt = 0;  // [s]
};

/// The warm-up of every realization of a run whose lowest sub-band's realizations last
/// `longest` [s]. Its step is the coarsest the run's lowest sub-band could take (at most 16
/// renewals per step; under a spring 0.3/omega_s, so that a step still follows the spring),
/// so that it costs about its renewals.
WarmUp warm_up_for(const Parameters& p, double longest) {
  const Landmarks l = landmarks(p);
  double slowest_renewal = 0;
  for (int level = 1; level <= p.levels; ++level)
    if (p.touches(level)) slowest_renewal = std::max(slowest_renewal, p.level(level).a / p.v);
  // Where the forces can stall the block there is no stationary state under a constant force
  // (check_stationarity says so) and the decay was measured only up to the stall boundary,
  // eps^2 = 2/(3 N): the warm-up stays the boundary's (at most 24 a/v).
  const double eps2 = std::min(l.coupling_eps * l.coupling_eps, 2 / (3.0 * static_cast<double>(p.touching_blocks())));
  double decay = (1 + 2.5 * eps2) * slowest_renewal * (p.renewal == Renewal::periodic ? 0.5 : 1.0);
  WarmUp warm;
  warm.dt = kRenewalsPerStepMax / renewals_per_second(p);
  if (p.drive == Drive::spring) {
    // Where the forces can stall the block, the stretch wanders over its whole range, which
    // the load point takes up in range / v. A spring slower than the run's longest
    // realizations fails the relaxation check anyway (check_stationarity): no warm-up
    // beyond those realizations' length.
    const double lag = l.forces_can_stall ? spring_stretch_range(p) / p.v : 1.5 / l.omega_s + 2 * slowest_renewal;
    decay = std::max(decay, std::min(lag, longest));
    warm.dt = std::min(warm.dt, kOmegaDtMax / l.omega_s);
  }
  warm.duration = decay * std::max(1.0, std::log(eps2 / kWarmUpResidual));
  return warm;
}

/// The shadow (docs/run.md, "The shadow") renews a force when v t passes its mark, the block
/// when v t + xi does: their renewals drift apart by xi/v, diffusively, over the warm-up and
/// the realization. A periodogram follows the renewals' places in the segments' windows, so
/// the shadow tracks the block where that drift is small against a segment. Measured on the
/// reference at 1% (realizations needed with the shadow over without): 0.26 and 0.23 at
/// drift / segment 0.02 and 0.08, 0.86 at 0.5, 0.96 at 5, against about twice the work per
/// realization: the shadow runs up to a fifth of a segment.
constexpr double kShadowDriftPerSegment = 0.2;
/// A precision-driven run's first round (64 realizations) reaches about 5% at a sub-band's
/// lowest points without the shadow; at coarser targets it would only double that round's work.
constexpr double kPlainFirstRoundPrecision = 0.05;

/// The time the shadow's renewals drift from the block's over `duration` [s]: the spread of
/// xi/v, sqrt(2 D duration)/v under a constant force; under a spring at most the stationary
/// spread of the lag, sqrt(D/omega_s)/v (D of the same contacts under a constant force).
double shadow_drift(const Parameters& p, double duration) {
  Parameters force = p;
  force.drive = Drive::force;
  const double diffusion = landmarks(force).diffusion;
  double spread2 = 2 * diffusion * duration;
  if (p.drive == Drive::spring) spread2 = std::min(spread2, diffusion / landmarks(p).omega_s);
  return std::sqrt(spread2) / p.v;
}

/// Why sub-band b is not stationary by its realizations' own speeds, or "".
std::string stalled_realizations(const RunSession::Impl& s, std::size_t b) {
  const double v = s.params.v;
  // Under a spring a realization's speed falls short of v by at most its lag's change over
  // its duration; where the allowed change reaches v/2 a slow realization proves nothing
  // (the relaxation check judges those runs).
  if (kSpringRanges * spring_stretch_range(s.params) / s.plan[b].duration >= kStalledSpeedDeficit * v) return "";
  double n = 0, slow = 0;
  for (const BatchRecord& batch : s.bands[b].batches)
    for (double speed : batch.speed) n += 1, slow += speed < (1 - kStalledSpeedDeficit) * v;
  // A sliding realization that slow is rare (none where the forces cannot hold back half
  // of the drive); more than the bound allows, beyond five binomial deviations, stalled.
  const double chance = slow_sliding_chance(s.params, s.plan[b].duration);
  const double allowed = n * chance + kSpeedStandardErrors * std::sqrt(n * chance);
  if (slow <= allowed) return "";
  char why[300];
  std::snprintf(why, sizeof why,
                "%.0f of sub-band %zu's %.0f realizations slide slower than v/2 = %.3g m/s (a stationary run "
                "allows at most %.0f): some realizations stalled",
                slow, b, n, 0.5 * v, std::floor(allowed));
  return why;
}

/// Marks `result` non-stationary when a sub-band's realizations do not slide at v, some of
/// them stalled, or neighbouring sub-bands do not join (docs/model.md §8).
void check_stationarity(const RunSession::Impl& s, RunResult& result) {
  const double v = s.params.v;
  auto mark = [&](std::string why) {
    result.stationary = false;
    result.stationarity = std::move(why);
  };
  const bool spring = s.params.drive == Drive::spring;
  const Landmarks l = landmarks(s.params);
  // The displacement of the block against the load point a realization may make once.
  double lag_shift = 0;
  char too_short[500] = "";  // the spring's range is not sampled: said once the bands are judged
  if (spring && !l.forces_can_stall)
    lag_shift = kSpringLagShifts * 0.5 * l.coupling_eps * l.coupling_eps * (s.params.F_drive - s.params.F_kin) /
                s.params.k_drive;
  if (spring && l.forces_can_stall && !s.plan.empty()) {
    const double stretch_range = spring_stretch_range(s.params);
    const double relaxation = stretch_range / v;
    if (s.plan[0].duration < kSpringRelaxations * relaxation) {
      std::snprintf(too_short, sizeof too_short,
                    "the forces can stall the block and the spring's stretch wanders over %.3g m, which the load "
                    "point takes up in %.3g s; the lowest sub-band's realizations last %.3g s, under %.0f times "
                    "that: extend the band down ({omega_min} %.2g rad/s or lower), give {duration} %.2g s or "
                    "more, or stiffen the spring",
                    stretch_range, relaxation, s.plan[0].duration, kSpringRelaxations,
                    // A realization spans two segments of its lowest point's octave band:
                    // within a factor 2 of 1/omega_min, so the advice takes that factor.
                    0.5 * s.plan[0].omega_low * s.plan[0].duration / (kSpringRelaxations * relaxation),
                    kSpringRelaxations * relaxation);
    }
    lag_shift = kSpringRanges * stretch_range;
  }
  for (std::size_t b = 0; b < s.bands.size(); ++b) {
    double sum = 0, n = 0;
    for (const BatchRecord& batch : s.bands[b].batches)
      for (double speed : batch.speed) sum += speed, n += 1;
    if (n < 2) continue;
    const double mean = sum / n;
    // About the mean, not sum2/n - mean^2: under a stiff spring the speeds agree to ~1e-8 of
    // v, a spread that the difference of squares rounds to nothing.
    double spread = 0;
    for (const BatchRecord& batch : s.bands[b].batches)
      for (double speed : batch.speed) spread += (speed - mean) * (speed - mean);
    const double error = std::sqrt(spread / n / (n - 1));
    if (std::string why = stalled_realizations(s, b); !why.empty()) return mark(why);
    // Through a spring the mean speed is v exactly (docs/model.md §9): a deviation beyond the
    // realizations' own scatter means they have not reached the stationary state.
    const double allowed =
        spring ? std::max(kSpringSpeedRoundoff * v, lag_shift / s.plan[b].duration) : kStalledSpeedDeficit * v;
    if (std::fabs(mean - v) - kSpeedStandardErrors * error > allowed) {
      char why[400];
      std::snprintf(why, sizeof why,
                    "sub-band %zu slides at %.6g v on average (+- %.2g v), not v = %.3g m/s%s (allowed: %.2g v)", b,
                    mean / v, error / v, v,
                    spring ? ": its realizations end before the spring holds the block at v; extend the band down" : "",
                    allowed / v);
      return mark(why);
    }
  }
  if (too_short[0] != '\0') return mark(too_short);
  for (std::size_t b = 0; b + 1 < result.sub_bands.size(); ++b)
    if (std::string why = band_break(result, b); !why.empty()) return mark(why);
  // Where the forces can stall the block, a stall is absorbing (docs/model.md §8); a
  // realization that has seen only a few renewals per contact cannot have drawn one yet,
  // so its sliding says nothing about whether a stationary state exists.
  // A spring stretches until the block moves again: no stall to wait for (docs/model.md §9).
  if (landmarks(s.params).forces_can_stall && s.params.drive == Drive::force && !s.plan.empty()) {
    double longest = 0;
    for (const SubBand& band : s.plan) longest = std::max(longest, band.duration);
    const double renewal_time = 1 / s.params.renewal_rate();
    if (longest < kStallRenewalsToJudge * renewal_time) {
      char why[300];
      std::snprintf(why, sizeof why,
                    "the random forces can stall the block (alpha F_kin >= 2 (F_drive - F_kin)) and these "
                    "realizations (at most %.3g s) span under %.0f renewal times a/v = %.3g s: too short to tell "
                    "steady sliding from a coming stall; extend the band down",
                    longest, kStallRenewalsToJudge, renewal_time);
      mark(why);
    }
  }
}

double worst_relative_error(const std::vector<SpectrumPoint>& points, std::size_t expected_points) {
  if (points.size() < expected_points) return INFINITY;
  double worst = 0;
  for (const SpectrumPoint& point : points)
    worst = std::max(worst, point.C > 0 ? point.standard_error / point.C : INFINITY);
  return worst;
}

}  // namespace

/// Why neighbouring sub-bands b and b + 1 do not join smoothly, or "".
std::string run_detail::band_break(const RunResult& result, std::size_t b) {
  const RunPoint* last = nullptr;   // of sub-band b
  const RunPoint* first = nullptr;  // of sub-band b + 1
  for (const RunPoint& point : result.points) {
    if (point.omega <= result.sub_bands[b].omega_high * (1 + 1e-12)) last = &point;
    if (!first && point.omega >= result.sub_bands[b + 1].omega_low * (1 - 1e-12)) first = &point;
  }
  if (!last || !first || last == first) return "";
  const double below = last->C_x / last->theory, above = first->C_x / first->theory;
  if (!(below > 0) || !(above > 0) || !std::isfinite(below) || !std::isfinite(above)) return "";
  const double error = std::hypot(last->standard_error / last->C_x, first->standard_error / first->C_x);
  if (std::fabs(std::log(above / below)) <= std::log(kBandBreakFactor) + kSpeedStandardErrors * error) return "";
  char why[300];
  std::snprintf(why, sizeof why,
                "sub-bands %zu and %zu do not join: C_x / theory is %.3g at %.4g rad/s and %.3g at %.4g rad/s "
                "(+- %.2g): the realizations of different lengths are not one stationary process",
                b, b + 1, below, last->omega, above, first->omega, error);
  return why;
}

std::vector<SubBand> plan_sub_bands(const Parameters& p, const RunRequest& request) {
  const std::vector<double> omegas = log_spaced_omegas(request.omega_min, request.omega_max, request.points_per_decade);
  check_request_fields(request);

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
    band.dt = std::min(kOmegaDtMax / step_frequency(p, band), kRenewalsPerStepMax / renewals_per_second(p));
    check_step(p, band);
    const double segment =
        SpectrumEstimator(estimator_config(band, request.points_per_decade), 1).segment_duration(band.omega_low);
    band.duration = request.duration > 0 ? request.duration * omegas.front() / band.omega_low
                                         : std::max(kSegmentsPerRealization * segment,
                                                    std::min(kRenewalsPerRealization / renewals_per_second(p),
                                                             kMostLengthening * kSegmentsPerRealization * segment));
    // At least the segments a point needs, whatever the user's fixed duration.
    band.duration = std::max(band.duration, 1.5 * segment);
    bands.push_back(band);
  }
  const WarmUp warm = warm_up_for(p, bands.empty() ? 0.0 : bands.front().duration);
  for (SubBand& band : bands) {
    band.warm_up = warm.duration;
    band.warm_up_dt = std::max(band.dt, warm.dt);
    const double segment =
        SpectrumEstimator(estimator_config(band, request.points_per_decade), 1).segment_duration(band.omega_low);
    band.shadow = request.control_variate &&
                  (request.precision < kPlainFirstRoundPrecision || request.duration > 0 || request.realizations > 0) &&
                  shadow_drift(p, band.warm_up + band.duration) < kShadowDriftPerSegment * segment;
    // A target finer than the first round reaches needs (5% / precision)^2 times its work:
    // without the shadow, longer realizations do that work for less (a quarter as long
    // still lets 64 of them undershoot the target), up to kMostLengthening times two segments.
    if (request.duration == 0 && request.realizations == 0 && !band.shadow &&
        request.precision < kPlainFirstRoundPrecision) {
      const double wanted =
          0.25 * (kPlainFirstRoundPrecision / request.precision) * (kPlainFirstRoundPrecision / request.precision);
      const double longest = kMostLengthening * kSegmentsPerRealization * segment;
      band.duration = std::max(band.duration, std::min(wanted * kSegmentsPerRealization * segment, longest));
    }
  }
  return bands;
}

// ---------------------------------------------------------------------------------------
// The session: sub-bands in order, each in rounds, each round in chunks of batches.

RunSession::Impl::Impl(const Parameters& p, const RunRequest& r, std::string name)
    : params(p), request(r), case_name(std::move(name)), plan(plan_sub_bands(p, r)) {
  if (r.first_realization % kBatchRealizations != 0)
    throw InputError("{realizations_range}: FIRST must be a multiple of " + std::to_string(kBatchRealizations) +
                     " (parts share the batches of the whole run)");
  if (r.first_realization > 0 && r.realizations == 0)
    throw InputError("{realizations_range}: needs a fixed realization count (not {precision})");
  check_plan(p, plan);
  for (SubBand& band : plan) {
    steps.push_back(static_cast<std::int64_t>(std::ceil(band.duration / band.dt)));
    band.duration = static_cast<double>(steps.back()) * band.dt;
  }
  bands.resize(plan.size());
}

RunSession::RunSession(const Parameters& params, const RunRequest& request, std::string case_name)
    : impl_((validate_request(params, request), std::make_unique<Impl>(params, request, std::move(case_name)))) {}
RunSession::RunSession(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RunSession::~RunSession() = default;
RunSession::RunSession(RunSession&&) noexcept = default;
RunSession& RunSession::operator=(RunSession&&) noexcept = default;

const Parameters& RunSession::parameters() const { return impl_->params; }
const RunRequest& RunSession::request() const { return impl_->request; }
const std::string& RunSession::case_name() const { return impl_->case_name; }

void RunSession::set_execution(int threads, SimdPath simd) {
  impl_->request.threads = threads;
  impl_->request.simd = simd;
}

bool RunSession::finished() const {
  return std::all_of(impl_->bands.begin(), impl_->bands.end(), [](const BandTotals& b) { return b.finished; });
}

namespace {

/// The wall time advance() adds to the session: all of it but its checkpoints.
struct WallClock {
  double& session_seconds;
  const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_checkpoint = start;

  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
  void add() { session_seconds += elapsed(); }
};

/// What a sub-band's rounds need beside its totals.
struct BandWork {
  StepperConfig stepper;
  std::int64_t steps;
  std::size_t expected_points;      // the points its spectrum gives
  std::uint64_t most_realizations;  // where a precision-driven run stops growing
};

BandWork band_work(const RunSession::Impl& s, std::size_t b, SimdPath simd) {
  const SubBand& band = s.plan[b];
  BandWork work;
  work.stepper.dt = band.dt;
  work.stepper.warm_up = band.warm_up;
  work.stepper.warm_up_dt = band.warm_up_dt;
  work.stepper.shadow = band.shadow;
  work.stepper.seed = s.request.seed;
  work.stepper.stream = b;  // sub-bands are independent simulations
  work.stepper.simd = simd;
  work.steps = s.steps[b];
  work.expected_points =
      log_spaced_omegas(band.omega_low, band.omega_high * (1 + 1e-12), s.request.points_per_decade).size();
  work.most_realizations = std::max<std::uint64_t>(
      first_round_realizations(s.params, s.request, band),
      std::min<std::uint64_t>(kMaxRealizationsPerBand,
                              static_cast<std::uint64_t>(kMaxStepsPerBand / (static_cast<double>(work.steps) +
                                                                             renewal_excess_work(s.params, band)))));
  return work;
}

/// After a complete round: true when the band is finished, else the next round planned
/// in totals.planned.
bool plan_next_round(const Parameters& p, BandTotals& totals, const BandWork& work, const RunRequest& request) {
  ++totals.rounds;
  if (request.realizations > 0) return true;
  const SpectrumAccumulator merged = totals.merged();
  const double worst = worst_relative_error(
      band_spectrum(totals, merged, work.stepper.shadow ? shadow_expectation(p, merged) : std::map<double, double>())
          .points,
      work.expected_points);
  if (worst <= request.precision || totals.realizations >= work.most_realizations) return true;
  // Standard errors fall as 1/sqrt(realizations): plan the total with a 30% margin, so
  // that a run stops because it planned enough, not because its error estimate happened
  // to dip below the target (which would bias the reported error bars low). At most
  // eight times more per round, so a noisy early estimate cannot run away.
  const double factor = std::isfinite(worst) ? 1.3 * (worst / request.precision) * (worst / request.precision) : 8.0;
  const auto wanted =
      static_cast<std::uint64_t>(std::ceil(static_cast<double>(totals.realizations) * std::min(factor, 8.0)));
  std::uint64_t round_size = std::max<std::uint64_t>(wanted - totals.realizations, kBatchRealizations);
  round_size = (round_size + kBatchRealizations - 1) / kBatchRealizations * kBatchRealizations;
  round_size = std::min(round_size, work.most_realizations - totals.realizations);
  totals.planned = totals.realizations + round_size;
  return false;
}

std::uint64_t batches_of(std::uint64_t realizations) {
  return (realizations + kBatchRealizations - 1) / kBatchRealizations;
}

/// Runs this process's share of the band's next `chunk` realizations (a contiguous run of
/// its batches) and returns its records, fewer when stopped.
std::vector<BatchRecord> run_chunk(const RunSession::Impl& s, std::size_t b, const BandWork& work, std::uint64_t chunk,
                                   const RunSession::Control& control, const Communicator& comm, bool& ran_away) {
  const BandTotals& totals = s.bands[b];
  const std::uint64_t chunk_batches = batches_of(chunk);
  const std::uint64_t share_first = chunk_batches * comm.rank() / comm.size() * kBatchRealizations;
  const std::uint64_t share_end = std::min(chunk, chunk_batches * (comm.rank() + 1) / comm.size() * kBatchRealizations);
  if (share_end <= share_first) return {};
  std::mutex progress_mutex;
  auto chunk_progress = [&](double f) {
    if (!control.progress) return;
    const double in_band = (static_cast<double>(totals.realizations) + f * static_cast<double>(chunk)) /
                           static_cast<double>(totals.planned);
    const std::lock_guard<std::mutex> lock(progress_mutex);  // one call at a time (run.hpp)
    const auto bands = s.plan.size();
    control.progress((static_cast<double>(b) + in_band) / static_cast<double>(bands),
                     "sub-band " + std::to_string(b + 1) + "/" + std::to_string(bands) + ", round " +
                         std::to_string(totals.rounds + 1));
  };
  const std::uint64_t chunk_first = s.request.first_realization + totals.realizations;
  return run_batches_of(s.params, s.plan[b], work.stepper, s.request, chunk_first + share_first,
                        share_end - share_first, work.steps, comm.size() > 1 ? nullptr : control.stop, chunk_progress,
                        ran_away);
}

/// Every process's records of a chunk, in realization order (the shares are contiguous).
std::vector<BatchRecord> gather_across_ranks(const Communicator& comm, std::vector<BatchRecord> records) {
  if (comm.size() == 1) return records;
  std::string mine;
  for (const BatchRecord& record : records) put_batch(mine, record);
  records.clear();
  for (const std::string& theirs : comm.all_gather(mine)) {
    util::Reader in(theirs, "run state from another process");
    while (!in.at_end()) records.push_back(get_batch(in));
  }
  return records;
}

/// Saves the session when a periodic checkpoint is due; its time is not the run's.
void checkpoint_if_due(const RunSession::Control& control, RunSession& session, WallClock& clock) {
  const auto now = std::chrono::steady_clock::now();
  if (!control.checkpoint || !(control.checkpoint_every > 0) ||
      std::chrono::duration<double>(now - clock.last_checkpoint).count() < control.checkpoint_every)
    return;
  clock.add();
  control.checkpoint(session);
  clock.session_seconds -= clock.elapsed();
  clock.last_checkpoint = now;
}

}  // namespace

bool RunSession::advance(const Control& control) {
  Impl& s = *impl_;
  WallClock clock{s.wall_seconds};
  const Communicator alone;
  const Communicator& comm = control.communicator ? *control.communicator : alone;
  const SimdPath simd = resolve_simd_path(s.request.simd);
  // With periodic checkpoints a chunk is one batch per thread, so a checkpoint comes at
  // most one batch after it is due (the chunk size changes no number).
  const std::uint64_t batches_per_process = control.checkpoint_every > 0 && control.checkpoint
                                                ? static_cast<std::uint64_t>(resolve_threads(s.request.threads))
                                                : kChunkBatches;
  for (std::size_t b = 0; b < s.plan.size(); ++b) {
    BandTotals& totals = s.bands[b];
    const BandWork work = band_work(s, b, simd);
    if (totals.planned == 0) totals.planned = first_round_realizations(s.params, s.request, s.plan[b]);
    while (!totals.finished) {
      if (totals.realizations >= totals.planned) {
        totals.finished = plan_next_round(s.params, totals, work, s.request);
        continue;
      }
      if (comm.any(control.stop && control.stop->load())) {
        clock.add();
        return false;
      }
      const std::uint64_t chunk =
          std::min(totals.planned - totals.realizations, batches_per_process * kBatchRealizations * comm.size());
      bool ran_away = false;
      std::vector<BatchRecord> records =
          gather_across_ranks(comm, run_chunk(s, b, work, chunk, control, comm, ran_away));
      if (comm.any(ran_away)) {
        // No spectrum exists: the run ends here, saying why, with what came before.
        char why[300];
        std::snprintf(why, sizeof why,
                      "a realization of sub-band %zu ran away (its block moved over %.0e times v dt in one step, "
                      "xi growing without bound): the model's linear part is unstable",
                      b, stepper::kRunawayAdvances);
        s.runaway = why;
        clock.add();
        return true;
      }
      const bool whole = records.size() == batches_of(chunk);
      totals.realizations += realizations_in(records);
      for (BatchRecord& record : records) totals.batches.push_back(std::move(record));
      if (!whole) {
        clock.add();
        return false;
      }
      checkpoint_if_due(control, *this, clock);
    }
  }
  clock.add();
  return true;
}

std::vector<double> BinRange::omegas() const {
  std::vector<double> out;
  for (int j = 0; j < count; ++j) out.push_back(first + j * spacing);
  return out;
}

double bin_average(const Parameters& params, const BinRange& bins) {
  const std::vector<double> values = exact_spectrum(params, bins.omegas());
  double sum = 0;
  for (double value : values) sum += value;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

namespace {

/// Sub-band b's points: the estimate, the theory seen through the estimator (averaged over
/// exactly the FFT bins each point averages, and smoothed by the window as the estimate is:
/// for a smooth C_x the plain mean over the bins; a periodic force spectrum's zeros are
/// narrower than a bin) and at the point's omega, `second` likewise where it exists, and
/// the estimator and theory that hold there.
void add_band_points(const RunSession::Impl& s, std::size_t b, const LumpedTheory& theory,
                     const std::function<double(double)>& second, std::vector<RunPoint>& points) {
  const BandTotals& totals = s.bands[b];
  const SpectrumAccumulator merged = totals.merged();
  const BandEstimate band_estimate = band_spectrum(
      totals, merged, s.plan[b].shadow ? shadow_expectation(s.params, merged) : std::map<double, double>());
  const std::vector<SpectrumPoint>& estimated = band_estimate.points;
  const std::vector<SpectrumPoint> expected = merged.expected(std::cref(theory));
  const std::vector<SpectrumPoint> expected2 = second ? merged.expected(second) : std::vector<SpectrumPoint>();
  for (std::size_t k = 0; k < estimated.size(); ++k) {
    const SpectrumPoint& e = estimated[k];
    BinRange bins;
    bins.spacing = e.bin_spacing;
    bins.count = e.bin_count;
    bins.first = e.omega_low + 0.5 * e.bin_spacing;
    bins.last = bins.first + (e.bin_count - 1) * e.bin_spacing;
    points.push_back({e.omega, e.C, e.standard_error, expected[k].C, theory(e.omega), e.n_avg, e.bandwidth, bins});
    if (second) points.back().theory2 = expected2[k].C;
    points.back().estimator = band_estimate.estimator[k];
    points.back().theory_kind = best_theory_at(s.params, e.omega).kind;
    points.back().variance_ratio = band_estimate.variance_ratio[k];
  }
}

/// The mean sliding speed and its standard error, over the lowest sub-band's realizations
/// (its longest).
void measure_mean_speed(const RunSession::Impl& s, RunResult& result) {
  if (s.bands.empty() || s.bands[0].realizations == 0) return;
  double sum = 0;
  for (const BatchRecord& batch : s.bands[0].batches)
    for (double speed : batch.speed) sum += speed;
  const double n = static_cast<double>(s.bands[0].realizations);
  result.mean_speed = sum / n;
  // About the mean: under a stiff spring the speeds agree to ~1e-8 of v, which a
  // difference of squares rounds to nothing.
  double spread = 0;
  for (const BatchRecord& batch : s.bands[0].batches)
    for (double speed : batch.speed) spread += (speed - result.mean_speed) * (speed - result.mean_speed);
  const double variance = spread / n;
  result.mean_speed_error = n > 1 ? std::sqrt(variance / (n - 1)) : INFINITY;
}

}  // namespace

RunResult RunSession::result() const {
  const Impl& s = *impl_;
  RunResult result;
  result.sub_bands = s.plan;
  result.simd_path = resolve_simd_path(s.request.simd);
  result.threads = resolve_threads(s.request.threads);
  // Points, with the continuous-time theory seen through the estimator (add_band_points).
  const LumpedTheory theory(s.params);
  // The second-order theory beside it wherever it can be computed (docs/model.md §7), and
  // which theory holds here (§7.4).
  std::function<double(double)> second;
  try {
    second = theory_beyond_first_order(s.params).C_x;
  } catch (const InputError& e) {
    result.theory2_note = e.what();
  }
  const TheoryChoice holds = best_theory(s.params);
  result.theory_kind = holds.kind;
  result.theory_kind_note = holds.reason;
  for (std::size_t b = 0; b < s.bands.size(); ++b) {
    const BandTotals& totals = s.bands[b];
    SubBand& band = result.sub_bands[b];
    band.realizations = totals.realizations;
    band.rounds = totals.rounds;
    if (totals.batches.empty()) continue;
    add_band_points(s, b, theory, second, result.points);
    result.simulated_time += static_cast<double>(totals.realizations) * band.duration;
    result.realization_steps += static_cast<double>(s.steps[b]) * static_cast<double>(totals.realizations);
  }
  {
    double blocks = 0;
    for (int level = 1; level <= s.params.levels; ++level) blocks += static_cast<double>(s.params.blocks(level));
    result.miniblock_steps = blocks * result.realization_steps;
  }
  std::sort(result.points.begin(), result.points.end(),
            [](const RunPoint& x, const RunPoint& y) { return x.omega < y.omega; });

  measure_mean_speed(s, result);
  check_stationarity(s, result);
  if (!s.runaway.empty()) {
    result.stationary = false;
    result.stationarity = s.runaway;
  }
  result.reached_precision = 0;
  for (const RunPoint& point : result.points)
    result.reached_precision = std::max(result.reached_precision, point.standard_error / point.C_x);
  const std::size_t expected_total =
      log_spaced_omegas(s.request.omega_min, s.request.omega_max, s.request.points_per_decade).size();
  result.complete = finished();
  // Finished without every point: a fixed count too small for some point's error bar
  // (validate_request refuses the counts it can foresee).
  // A part's own points are not its result: merge judges the joined run.
  if (finished() && !s.request.part && result.points.size() < expected_total && result.stationary) {
    result.stationary = false;
    result.stationarity = std::to_string(expected_total - result.points.size()) + " of the " +
                          std::to_string(expected_total) +
                          " points got too few segments for an error bar from these realizations; run more";
  }
  result.wall_seconds = s.wall_seconds;
  return result;
}

RunResult run_spectrum(const Parameters& params, const RunRequest& request, const ProgressCallback& progress,
                       const std::atomic<bool>* stop) {
  RunSession session(params, request);
  RunSession::Control control;
  control.progress = progress;
  control.stop = stop;
  session.advance(control);
  return session.result();
}

}  // namespace slidespec
