// Run requests checked before any work: the same refusals for the command line and the
// library (and so the Python bindings).
#include <cmath>
#include <limits>
#include <sstream>

#include "estimator/design.hpp"
#include "run/session.hpp"

namespace slidespec {

using namespace run_detail;

namespace {

// The finest precision worth planning: the lowest point of a sub-band averages about a
// dozen periodograms per realization, so kMaxRealizationsPerBand realizations reach about
// 1/sqrt(12 * 65536) ~ 1e-3 and no finer.
constexpr double kFinestPrecision = 1e-3;
constexpr int kMostThreads = 4096;
constexpr int kMostRunPointsPerDecade = 100;
// Step counts stay exact in a double and far from the int64 range.
constexpr double kMostSteps = 1e15;
// A time step below this fraction of the renewal time a/v moves the block by less than
// the rounding of its position: the stepped process would no longer be the model's.
constexpr double kFinestStepOfRenewalTime = 1e-12;

std::string text(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

double block_weight(const Parameters& p) {
  double blocks = 0;
  for (int level = 1; level <= p.levels; ++level) blocks += static_cast<double>(p.blocks(level));
  return std::max(1.0, blocks / 100);
}

}  // namespace

namespace run_detail {

void check_request_fields(const RunRequest& r) {
  // A sub-band's 512-sample segments resolve 1/512 of their band: finer points than this
  // fall between FFT bins, get none, and could never reach a precision.
  if (r.points_per_decade < 1 || r.points_per_decade > kMostRunPointsPerDecade)
    throw InputError("--points: a run has 1 to " + std::to_string(kMostRunPointsPerDecade) +
                     " points per decade (got " + std::to_string(r.points_per_decade) +
                     "; finer points fall between the FFT bins)");
  if (!std::isfinite(r.omega_min) || !(r.omega_min > 0))
    throw InputError("--omega-min: must be a finite positive frequency (got " + text(r.omega_min) + ")");
  if (!std::isfinite(r.omega_max) || !(r.omega_max > r.omega_min))
    throw InputError("--omega-max: must be finite and above --omega-min (got " + text(r.omega_max) + ")");
  if (!(r.precision > 0) || !(r.precision < 1))
    throw InputError("--precision: must be between 0 and 1 (a relative standard error)");
  if (r.duration == 0 && r.realizations == 0 && r.precision < kFinestPrecision)
    throw InputError("--precision: " + text(r.precision) + " is finer than the " + text(kFinestPrecision) +
                     " a sub-band can reach within its " + std::to_string(kMaxRealizationsPerBand) +
                     " realizations; use --precision " + text(kFinestPrecision) + " or more");
  if (r.duration < 0 || !std::isfinite(r.duration))
    throw InputError("--duration: must be a finite positive number of seconds (got " + text(r.duration) + ")");
  if (r.threads < 0 || r.threads > kMostThreads)
    throw InputError("--threads: must be 0 (all cores) to " + std::to_string(kMostThreads) + " (got " +
                     std::to_string(r.threads) + ")");
  if (!(r.work_budget >= 0) || !std::isfinite(r.work_budget))
    throw InputError("--work-budget: must be a finite positive number of realization-steps");
  if (r.realizations > (std::uint64_t{1} << 52) || r.first_realization > (std::uint64_t{1} << 52))
    throw InputError("--realizations: " + std::to_string(r.realizations) + " is not a plannable count");
}

void check_plan(const Parameters& p, const std::vector<SubBand>& plan) {
  const double renewal_time = 1 / p.renewal_rate();
  for (const SubBand& band : plan) {
    const std::string where = "sub-band " + text(band.omega_low) + ".." + text(band.omega_high) + " rad/s";
    if (!std::isnormal(band.dt) || !(band.dt >= kFinestStepOfRenewalTime * renewal_time))
      throw InputError("--omega-max: " + where + " needs a time step of " + text(band.dt) + " s, below " +
                       text(kFinestStepOfRenewalTime) + " of the renewal time a/v = " + text(renewal_time) +
                       " s (the block's position would not resolve it)");
    const double steps = band.duration / band.dt;
    const double warm_steps = band.warm_up > 0 ? band.warm_up / band.warm_up_dt : 0.0;
    if (!std::isfinite(warm_steps) || warm_steps > kMostSteps)
      throw InputError("parameters: " + where + " plans " + text(warm_steps) +
                       " warm-up steps per realization (at most " + text(kMostSteps) +
                       "): the renewals or the spring are too slow against the band");
    if (!std::isfinite(steps) || steps > kMostSteps)
      throw InputError((band.omega_low == plan.front().omega_low ? "--omega-min/--duration: " : "--omega-max: ") +
                       where + " plans " + text(steps) + " time steps per realization (at most " + text(kMostSteps) +
                       ")");
  }
}

}  // namespace run_detail

namespace {

double first_round_work(const Parameters& p, const RunRequest& r, const std::vector<SubBand>& plan) {
  double steps = 0;
  for (const SubBand& band : plan)
    steps +=
        static_cast<double>(first_round_realizations(p, r, band)) *
        (std::ceil(band.duration / band.dt) + (band.warm_up > 0 ? std::ceil(band.warm_up / band.warm_up_dt) : 0.0));
  return steps * block_weight(p);
}

// A duration is rounded up to whole time steps: far below this.
constexpr double kDurationRoundingSlack = 1.01;

/// `x` rounded up to three significant digits: a least value a message names is then itself enough.
std::string text_up(double x) {
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2);
  return text(std::ceil(x / unit) * unit);
}

/// The plan lengthens a fixed duration to the segments its lowest point needs: a run that
/// would simulate more than was asked is refused, naming the least it can be.
void check_duration_not_raised(const RunRequest& r, const std::vector<SubBand>& plan) {
  if (!(r.duration > 0) || plan.empty() || plan.front().duration <= kDurationRoundingSlack * r.duration) return;
  throw InputError("--duration: " + text(r.duration) + " s is shorter than the " + text_up(plan.front().duration) +
                   " s the lowest point (omega = " + text(r.omega_min) +
                   " rad/s) needs; ask for at least that, or raise --omega-min");
}

/// A fixed count of realizations too small for every point's error bar: each point needs
/// kMinimumSegments segments of its band from all realizations together (the scatter
/// between them).
void check_realizations_give_segments(const RunRequest& r, const std::vector<SubBand>& plan) {
  if (r.realizations == 0 || r.part) return;
  std::uint64_t fewest = 0;
  const SubBand* where = nullptr;
  for (const SubBand& band : plan) {
    const auto steps = static_cast<std::uint64_t>(std::ceil(band.duration / band.dt));
    const std::uint64_t per_realization =
        SpectrumEstimator(estimator_config(band, r.points_per_decade), 1).segments_after(steps, band.omega_low);
    const std::uint64_t needed = per_realization == 0
                                     ? std::numeric_limits<std::uint64_t>::max()
                                     : (estimator_detail::kMinimumSegments + per_realization - 1) / per_realization;
    if (needed > fewest) fewest = needed, where = &band;
  }
  if (r.realizations >= fewest) return;
  throw InputError("--realizations " + std::to_string(r.realizations) + ": too few for the lowest point of sub-band " +
                   text(where->omega_low) + ".." + text(where->omega_high) + " rad/s, whose error bar needs " +
                   std::to_string(estimator_detail::kMinimumSegments) +
                   " segments (the scatter between them); give at least " + std::to_string(fewest) +
                   (r.duration > 0 ? ", or a longer --duration" : ""));
}

}  // namespace

double planned_first_round_work(const Parameters& p, const RunRequest& r) {
  const std::vector<SubBand> plan = plan_sub_bands(p, r);
  check_plan(p, plan);
  return first_round_work(p, r, plan);
}

void validate_request(const Parameters& p, const RunRequest& r) {
  check_request_fields(r);
  if (!(expected_jump_energy(p, p.a) > 0))
    throw InputError(
        "alpha: 0 gives no random force, so C_x is zero at every omega and there is "
        "nothing to simulate");
  // One plan for every check, its step counts known finite before any is counted.
  const std::vector<SubBand> plan = plan_sub_bands(p, r);
  check_plan(p, plan);
  check_duration_not_raised(r, plan);
  check_realizations_give_segments(r, plan);
  const double work = first_round_work(p, r, plan);
  const double budget = r.work_budget > 0 ? r.work_budget : kDefaultWorkBudget;
  if (work > budget) {
    // Name the option that drives the work: the realization count, else the band's bottom.
    const std::string option = r.realizations > 0 ? "--realizations" : r.duration > 0 ? "--duration" : "--omega-min";
    const double weight = block_weight(p);
    const std::string blocks =
        weight > 1 ? " (its " + text(100 * weight) + " blocks count " + text(weight) + " per step)" : "";
    throw InputError(option + ": the run plans " + text(work) + " realization-steps" + blocks +
                     " before its first result, over the work budget of " + text(budget) +
                     (r.work_budget > 0 ? "" : " (the default: about an hour on two cores)") + "; change " + option +
                     " or raise --work-budget");
  }
}

}  // namespace slidespec
