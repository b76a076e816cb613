// Run requests checked before any work: the same refusals for the command line and the
// library (and so the Python bindings).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "estimator/design.hpp"
#include "run/session.hpp"
#include "slidespec/theory.hpp"
#include "util/numbers.hpp"

namespace slidespec {

double run_detail::renewals_per_second(const Parameters& p) {
  double rate = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) rate += static_cast<double>(p.blocks(l)) * p.renewal_rate(l);
  return rate;
}

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
constexpr double kFastestPlausibleRenewal = 1e-9;  // [s]

std::string text(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

// A renewal inside a step costs about six steps: a step serving the plan's 16 renewals runs
// about a hundred times slower than one serving none (reference case, one thread, 8e5
// against 8e7 realization-steps per second).
constexpr double kRenewalWork = 6;
// The plan's time steps hold the renewals of sliding at up to this many times v. A block
// whose forces cannot stall it stays within 1 + eps/sqrt(2) < 1.6 of v with its forces
// frozen, so only near the stall can a block pass marks faster than its plan foresaw.
constexpr double kPlannedSpeedRatio = 2;

/// The spread of the touching contacts' sum of random forces [N].
double random_force_spread(const Parameters& p) {
  double variance = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) variance += static_cast<double>(p.blocks(l)) * p.random_force_variance(l);
  return std::sqrt(variance);
}

/// The spread of the speed a constant force's block slides at [m/s]: the speed its forces'
/// equilibrium sets, v (1 + F / (F_drive - F_kin)) for a sum F of the random forces. A drag
/// (F_drive - F_kin)/v too weak to move the block within a realization leaves it at the
/// equilibrium of the forces it started with (F_drive = 5.000001 N: 132 m/s; measured at
/// 100..1000 rad/s, 32 to 164 m/s and -85 within the first second, unchanged after 12 s).
/// A spring holds the block near its load point instead.
double speed_spread(const Parameters& p) {
  if (p.drive != Drive::force) return 0;
  return p.v * random_force_spread(p) / (p.F_drive - p.F_kin);
}

/// The mean speed at which the block passes marks [m/s]: that of a Gaussian speed v +-
/// speed_spread where forward, as backwards it passes none. 52.6 m/s for F_drive =
/// 5.000001 N (measured: 47 m/s, 4.4e7 renewals in 21 s over 8 realizations). Where the
/// drag is strong enough to follow the forces (F_drive = 5.01 N: 11 v) this is an upper
/// bound: a block soon draws resisting forces, stalls and creeps back passing no mark.
double forward_speed(const Parameters& p) {
  const double spread = speed_spread(p);
  if (!(spread > 0)) return p.v;
  const double z = p.v / spread;
  return p.v * 0.5 * std::erfc(-z / std::sqrt(2.0)) + spread * std::exp(-0.5 * z * z) / std::sqrt(2 * std::numbers::pi);
}

double block_weight(const Parameters& p) {
  double blocks = 0;
  for (int level = 1; level <= p.levels; ++level) blocks += static_cast<double>(p.blocks(level));
  return std::max(1.0, blocks / 100);
}

}  // namespace

namespace run_detail {

double renewal_excess_work(const Parameters& p, const SubBand& band) {
  const double time = band.warm_up + band.duration;
  const double beyond = forward_speed(p) / p.v - kPlannedSpeedRatio;
  return beyond > 0 ? kRenewalWork * beyond * renewals_per_second(p) * time : 0.0;
}

void check_step(const Parameters& p, const SubBand& band) {
  const double renewal_time = 1 / p.renewal_rate();
  const double finest = kFinestStepOfRenewalTime * renewal_time;
  // The estimator's octaves reach 60 below the step's Nyquist frequency pi/dt: a step that
  // fast renewals drive further below the band's lowest omega leaves it unresolved.
  const double coarsest_band_reach = std::ldexp(std::numbers::pi, -60);
  if (std::isnormal(band.dt) && band.dt >= finest && band.omega_low * band.dt >= coarsest_band_reach) return;
  const Landmarks l = landmarks(p);
  const std::string sub_band = "sub-band " + text(band.omega_low) + ".." + text(band.omega_high) + " rad/s";
  if (std::isnormal(band.dt) && band.dt >= finest) {
    const double factor = coarsest_band_reach / (band.omega_low * band.dt);
    // Renewals faster than a nanosecond are the parameters' doing; slower ones, the band's.
    if (renewal_time < kFastestPlausibleRenewal)
      throw InputError("parameter v: " + text(p.v) + " m/s renews the forces every a/v = " + text(renewal_time) +
                       " s, and the time step " + text(band.dt) + " s that resolves that puts pi/dt more than 60 " +
                       "octaves above " + sub_band + ", beyond the estimator's reach; give v at most " +
                       text(p.v / factor) + " m/s (or a at least " + text(p.a * factor) + " m)");
    throw InputError("{omega_min}: " + sub_band +
                     " lies more than 60 octaves below pi/dt, beyond the estimator's "
                     "reach, for the time step " +
                     text(band.dt) + " s that resolves the renewals (every a/v = " + text(renewal_time) +
                     " s at v = " + text(p.v) + " m/s); raise the sub-band to at least " +
                     text(band.omega_low * factor) + " rad/s, or give v at most " + text(p.v / factor) +
                     " m/s (or a at least " + text(p.a * factor) + " m)");
  }
  const std::string why = " is below " + text(kFinestStepOfRenewalTime) +
                          " of the renewal time a/v = " + text(renewal_time) +
                          " s (the block's position would not resolve it)";
  // Under a spring the step follows omega_s wherever that lies above the band.
  if (p.drive == Drive::spring && l.omega_s > band.omega_high)
    throw InputError("parameter k_drive: " + text(p.k_drive) + " N/m puts omega_s = k_drive v / (F_drive - F_kin) at " +
                     text(l.omega_s) + " rad/s, whose time step 0.3/omega_s = " + text(band.dt) + " s" + why +
                     "; give k_drive at most " + text(p.k_drive * band.dt / finest) +
                     " N/m, or move F_drive further from F_kin");
  // The band sets the step. A renewal distance beyond any contact's (over a kilometre) is the
  // slip; otherwise the band reaches too high above the renewals.
  constexpr double kLongestPlausibleRenewal = 1e3;  // [m]
  if (!(p.a > kLongestPlausibleRenewal))
    throw InputError("{omega_max}: " + sub_band + " needs a time step of " + text(band.dt) + " s, which" + why +
                     "; lower {omega_max}");
  throw InputError("parameter a: " + text(p.a) + " m makes the renewal time a/v = " + text(renewal_time) +
                   " s, more than " + text(1 / kFinestStepOfRenewalTime) + " times the time step " + text(band.dt) +
                   " s of " + sub_band + " (the block's position would not resolve a step); give a at most " +
                   text(p.a * band.dt / finest) + " m (or v at least " + text(p.v * finest / band.dt) + " m/s)");
}

void check_request_fields(const RunRequest& r) {
  // A sub-band's 512-sample segments resolve 1/512 of their band: finer points than this
  // fall between FFT bins, get none, and could never reach a precision.
  if (r.points_per_decade < 1 || r.points_per_decade > kMostRunPointsPerDecade)
    throw InputError("{points}: a run has 1 to " + std::to_string(kMostRunPointsPerDecade) +
                     " points per decade (got " + std::to_string(r.points_per_decade) +
                     "; finer points fall between the FFT bins)");
  if (!std::isfinite(r.omega_min) || !(r.omega_min > 0))
    throw InputError("{omega_min}: must be a finite positive frequency (got " + text(r.omega_min) + ")");
  if (!std::isfinite(r.omega_max) || !(r.omega_max > r.omega_min))
    throw InputError("{omega_max}: must be finite and above {omega_min} (got " + text(r.omega_max) + ")");
  if (!(r.precision > 0) || !(r.precision < 1))
    throw InputError("{precision}: must be between 0 and 1 (a relative standard error)");
  if (r.duration == 0 && r.realizations == 0 && r.precision < kFinestPrecision)
    throw InputError("{precision}: " + text(r.precision) + " is finer than the " + text(kFinestPrecision) +
                     " a sub-band can reach within its " + std::to_string(kMaxRealizationsPerBand) +
                     " realizations; use {precision} " + text(kFinestPrecision) + " or more");
  if (r.duration < 0 || !std::isfinite(r.duration))
    throw InputError("{duration}: must be a finite positive number of seconds (got " + text(r.duration) + ")");
  if (r.threads < 0 || r.threads > kMostThreads)
    throw InputError("{threads}: must be 0 (all cores) to " + std::to_string(kMostThreads) + " (got " +
                     std::to_string(r.threads) + ")");
  if (!(r.work_budget >= 0) || !std::isfinite(r.work_budget))
    throw InputError("{work_budget}: must be a finite positive number of realization-steps");
  if (r.realizations > (std::uint64_t{1} << 52))
    throw InputError("{realizations}: " + std::to_string(r.realizations) + " is not a plannable count");
  if (r.first_realization > (std::uint64_t{1} << 52))
    throw InputError("{realizations_range}: the first realization " + std::to_string(r.first_realization) +
                     " is beyond the 2^52 a run can number");
}

void check_plan(const Parameters& p, const std::vector<SubBand>& plan) {
  for (const SubBand& band : plan) {
    const std::string where = "sub-band " + text(band.omega_low) + ".." + text(band.omega_high) + " rad/s";
    check_step(p, band);
    const double steps = band.duration / band.dt;
    const double warm_steps = band.warm_up > 0 ? band.warm_up / band.warm_up_dt : 0.0;
    if (!std::isfinite(warm_steps) || warm_steps > kMostSteps)
      throw InputError("parameters: " + where + " plans " + text(warm_steps) +
                       " warm-up steps per realization (at most " + text(kMostSteps) +
                       "): the renewals or the spring are too slow against the band");
    if (!std::isfinite(steps) || steps > kMostSteps) {
      const std::string too_many =
          where + " plans " + text(steps) + " time steps per realization (at most " + text(kMostSteps) + ")";
      const double omega_s = p.drive == Drive::spring ? landmarks(p).omega_s : 0.0;
      if (omega_s > band.omega_high)
        throw InputError("parameter k_drive: " + text(p.k_drive) +
                         " N/m puts omega_s = k_drive v / (F_drive - F_kin) at " + text(omega_s) +
                         " rad/s, whose time step 0.3/omega_s = " + text(band.dt) + " s: " + too_many +
                         "; give k_drive at most " + text(p.k_drive * kMostSteps / steps) +
                         " N/m, move F_drive further from F_kin, or raise {omega_min}");
      throw InputError((band.omega_low == plan.front().omega_low ? "{omega_min}/{duration}: " : "{omega_max}: ") +
                       too_many);
    }
  }
}

}  // namespace run_detail

namespace {

/// The work of a run's first round, every sub-band's first-round realizations together, in
/// realization-steps, split by what drives it.
struct FirstRoundWork {
  double steps = 0;     // steps and warm-up steps, each counting its blocks (block_weight)
  double renewals = 0;  // renewals beyond those the steps were planned for
  double spring = 0;    // the part of `steps` in sub-bands whose step omega_s sets
};

FirstRoundWork first_round(const Parameters& p, const RunRequest& r, const std::vector<SubBand>& plan) {
  FirstRoundWork work;
  const double omega_s = p.drive == Drive::spring ? landmarks(p).omega_s : 0.0;
  const double weight = block_weight(p);
  for (const SubBand& band : plan) {
    const double realizations = static_cast<double>(first_round_realizations(p, r, band));
    const double steps =
        std::ceil(band.duration / band.dt) + (band.warm_up > 0 ? std::ceil(band.warm_up / band.warm_up_dt) : 0.0);
    work.steps += realizations * steps * weight;
    if (omega_s > band.omega_high) work.spring += realizations * steps * weight;
    work.renewals += realizations * renewal_excess_work(p, band);
  }
  return work;
}

double first_round_work(const Parameters& p, const RunRequest& r, const std::vector<SubBand>& plan) {
  const FirstRoundWork work = first_round(p, r, plan);
  return work.steps + work.renewals;
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
  throw InputError("{duration}: " + text(r.duration) + " s is shorter than the " + text_up(plan.front().duration) +
                   " s the lowest point (omega = " + text(r.omega_min) +
                   " rad/s) needs; ask for at least that, or raise {omega_min}");
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
  throw InputError("{realizations} " + std::to_string(r.realizations) + ": too few for the lowest point of sub-band " +
                   text(where->omega_low) + ".." + text(where->omega_high) + " rad/s, whose error bar needs " +
                   std::to_string(estimator_detail::kMinimumSegments) +
                   " segments (the scatter between them); give at least " + std::to_string(fewest) +
                   (r.duration > 0 ? ", or a longer {duration}" : ""));
}

/// A sub-band whose realizations together pass fewer than kLeastBandRenewals renewals has
/// no error bar (session.hpp): refused with the count that would pass them, or, where that
/// count is beyond what a sub-band may spend, with the band.
void check_band_renewals(const Parameters& p, const RunRequest& r, const std::vector<SubBand>& plan) {
  if (r.part) return;
  for (const SubBand& band : plan) {
    const double each = renewals_per_second(p) * band.duration;
    const double realizations = static_cast<double>(first_round_realizations(p, r, band));
    const double least = std::ceil(kLeastBandRenewals / each);
    const std::string where = "sub-band " + text(band.omega_low) + ".." + text(band.omega_high) +
                              " rad/s: its realizations of " + text(band.duration) + " s each pass about " +
                              text(each) + " renewals (v/a per touching block)";
    if (r.realizations > 0) {
      if (realizations * each >= kLeastBandRenewals) continue;
      throw InputError("{realizations} " + std::to_string(r.realizations) + ": " + where + ", " +
                       text(realizations * each) + " in all, fewer than the " + text(kLeastBandRenewals) +
                       " a sub-band's error bars need; give {realizations} " + text(least) +
                       " or more, or lower {omega_max}");
    }
    // Where the rule raises no count, the work checks below name what drives the work.
    if (least <= static_cast<double>(kInitialRealizations)) continue;
    const double steps =
        std::ceil(band.duration / band.dt) + (band.warm_up > 0 ? std::ceil(band.warm_up / band.warm_up_dt) : 0.0);
    if (realizations <= static_cast<double>(kMaxRealizationsPerBand) && realizations * steps <= kMaxStepsPerBand)
      continue;
    throw InputError("{omega_max}: " + where + "; the " + text(kLeastBandRenewals) +
                     " renewals its error bars need take " + text(realizations) + " realizations (" +
                     text(realizations * steps) + " realization-steps), beyond the " +
                     std::to_string(kMaxRealizationsPerBand) + " realizations or " + text(kMaxStepsPerBand) +
                     " realization-steps a sub-band may spend; lower {omega_max}");
  }
}

/// Why a block near the stall passes far more renewals than its plan foresaw, over the
/// realizations of `band`: the start of a refusal.
std::string coasting(const Parameters& p, const SubBand& band) {
  const double time = band.warm_up + band.duration;
  const double speed = forward_speed(p);
  std::ostringstream drive;
  drive.precision(15);
  drive << p.F_drive;
  return "parameter F_drive: " + drive.str() + " N lies only " + text(p.F_drive - p.F_kin) +
         " N above F_kin, so the random forces (spread " + text(random_force_spread(p)) +
         " N) can drive the block at about " + text(speed) + " m/s (" + text(speed / p.v) +
         " v) forward on average through realizations of " + text(time) + " s, each passing about " +
         text(speed * time * renewals_per_second(p) / p.v) + " renewals: ";
}

/// A precision-driven sub-band whose first round of a coasting block outgrows by itself
/// what a sub-band may spend would stop after it, its precision out of reach: refused,
/// before minutes of work that cannot give what was asked.
void check_coasting_band_can_finish(const Parameters& p, const RunRequest& r, const std::vector<SubBand>& plan) {
  if (r.realizations > 0) return;
  for (const SubBand& band : plan) {
    const double realizations = static_cast<double>(first_round_realizations(p, r, band));
    const double steps = realizations * (std::ceil(band.duration / band.dt) +
                                         (band.warm_up > 0 ? std::ceil(band.warm_up / band.warm_up_dt) : 0.0));
    const double renewals = realizations * renewal_excess_work(p, band);
    if (renewals <= steps || steps + renewals <= kMaxStepsPerBand) continue;
    throw InputError(coasting(p, band) + "sub-band " + text(band.omega_low) + ".." + text(band.omega_high) +
                     " rad/s plans " + text(steps + renewals) + " realization-steps in its first round of " +
                     text(realizations) + " realizations, beyond the " + text(kMaxStepsPerBand) +
                     " a sub-band may spend: it would stop there, its {precision} out of reach; move F_drive "
                     "further from F_kin, raise {omega_min} (shorter realizations) or give {realizations}");
  }
}

}  // namespace

double planned_first_round_work(const Parameters& p, const RunRequest& r) {
  const std::vector<SubBand> plan = plan_sub_bands(p, r);
  check_plan(p, plan);
  return first_round_work(p, r, plan);
}

double least_state_bytes(const Parameters& p, const RunRequest& r) {
  double bytes = 0;
  for (const SubBand& band : plan_sub_bands(p, r)) {
    const double realizations = static_cast<double>(first_round_realizations(p, r, band));
    const double points = static_cast<double>(
        log_spaced_omegas(band.omega_low, band.omega_high * (1 + 1e-12), r.points_per_decade).size());
    bytes += realizations * (points + 2) * sizeof(double);
  }
  return bytes;
}

namespace {

// A point's error bar sums squared periodograms, of the size of C_x^2.
void check_spectrum_squares(const Parameters& p, const RunRequest& r) {
  constexpr double kLeastSpectrum = util::kSmallestSquarableSpectrum;
  const LumpedTheory C_x(p);
  const double lowest = std::min(C_x(r.omega_min), C_x(r.omega_max));
  if (lowest >= kLeastSpectrum || !std::isfinite(lowest)) return;
  throw InputError("parameters: C_x falls to " + text(lowest) + " m^2 s in {omega_min}..{omega_max} = " +
                   text(r.omega_min) + ".." + text(r.omega_max) + " rad/s, below the " + text(kLeastSpectrum) +
                   " m^2 s whose squares (a point's error bar) a double holds: the random forces (alpha F_kin) "
                   "move the block too little in this band against its masses, springs and damping (M, m, k0, "
                   "eta0, eta1): raise them, bring those nearer the case's, or lower {omega_max}");
}

}  // namespace

void validate_request(const Parameters& p, const RunRequest& r) {
  check_request_fields(r);
  // The stepper sums a level's forces exactly in a double (stepper/renewal.hpp): up to 2^20.
  constexpr long long kMostTouchingBlocks = 1LL << 20;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l) && p.blocks(l) > kMostTouchingBlocks)
      throw InputError("parameter N: level " + std::to_string(l) + " has " + std::to_string(p.blocks(l)) +
                       " blocks touching the substrate, more than the " + std::to_string(kMostTouchingBlocks) +
                       " (2^20) a run can step; the theory (slidespec theory) holds for more");
  // The random forces' size is alpha F_kin: whichever is zero takes them away.
  if (!(expected_jump_energy(p, p.a) > 0))
    throw InputError(std::string(p.F_kin == 0 ? "parameter F_kin: 0 gives" : "alpha: 0 gives") +
                     " no random force (its size is alpha F_kin), so C_x is zero at every omega and there is "
                     "nothing to simulate");
  // One plan for every check, its step counts known finite before any is counted.
  const std::vector<SubBand> plan = plan_sub_bands(p, r);
  check_plan(p, plan);
  check_duration_not_raised(r, plan);
  check_realizations_give_segments(r, plan);
  check_coasting_band_can_finish(p, r, plan);
  check_band_renewals(p, r, plan);
  const FirstRoundWork each = first_round(p, r, plan);
  const double work = each.steps + each.renewals;
  const double budget = r.work_budget > 0 ? r.work_budget : kDefaultWorkBudget;
  if (work <= budget) {
    // Last: a stiff spring or a stalling block, which also shrink C_x, are named first.
    check_spectrum_squares(p, r);
    return;
  }
  const std::string plans = "the run plans " + text(work) + " realization-steps";
  const std::string over = " before its first result, over the work budget of " + text(budget) +
                           (r.work_budget > 0 ? "" : " (the default: about an hour on two cores)");
  const std::string option = r.realizations > 0 ? "{realizations}" : r.duration > 0 ? "{duration}" : "{omega_min}";
  // Name what drives most of the work: a block coasting near the stall, a stiff spring's
  // omega_s, else the option that sets how much is simulated.
  if (each.renewals > each.steps)
    throw InputError(coasting(p, plan.front()) + plans + over +
                     "; move F_drive further from F_kin, raise {omega_min} (shorter realizations) or raise "
                     "{work_budget}");
  if (each.spring > each.steps - each.spring) {
    const Landmarks l = landmarks(p);
    // The spring's share of the work scales with omega_s; the rest stays.
    const double rest = each.steps - each.spring + each.renewals;
    const double most_k = rest < budget ? p.k_drive * (budget - rest) / each.spring : 0.0;
    throw InputError("parameter k_drive: " + text(p.k_drive) + " N/m puts omega_s = k_drive v / (F_drive - F_kin) at " +
                     text(l.omega_s) + " rad/s (F_drive - F_kin = " + text(p.F_drive - p.F_kin) +
                     " N), whose time step 0.3/omega_s = " + text(plan.front().dt) +
                     " s serves every sub-band below it: " + plans + over + "; " +
                     (most_k > 0 ? "give k_drive at most about " + text(most_k) + " N/m, " : "") +
                     "move F_drive further from F_kin, raise " + option + " or raise {work_budget}");
  }
  const double weight = block_weight(p);
  const std::string blocks =
      weight > 1 ? " (its " + text(100 * weight) + " blocks count " + text(weight) + " per step)" : "";
  throw InputError(option + ": " + plans + blocks + over + "; change " + option + " or raise {work_budget}");
}

}  // namespace slidespec
