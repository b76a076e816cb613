// What a run session holds: shared by the run loop (run.cpp) and its saved form
// (session_state.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "util/binary.hpp"
#include "slidespec/estimator.hpp"
#include "slidespec/run.hpp"

namespace slidespec {

namespace run_detail {

// Realizations per stepper batch. Fixed, so the work a batch does is the same whatever the
// SIMD width or thread count (and a multiple of every lane width).
constexpr int kBatchRealizations = 8;

// The first round of a precision-driven run: fixed by the request and the plan alone, not
// scaled by the thread count, so that every later round (chosen from the results so far) is
// the same on any machine. 64 realizations reach about 2.5% at a sub-band's lowest points
// without the shadow; a coarser target needs fewer, (2.5% / precision)^2 times 64, but never
// under 32 realizations of 15 renewals each: where each holds few renewals their periodograms
// are skewed, and their scatter gives error bars short in the tails (docs/run.md, "Rounds").
constexpr std::uint64_t kInitialRealizations = 64;
constexpr std::uint64_t kFewestFirstRound = 32;
constexpr double kFirstRoundRenewals = 32 * 15;
constexpr double kInitialRoundReach = 0.025;
// Above v/a a sub-band's spectrum is the energy of its renewals' jumps: where its
// realizations together pass only a handful, most realizations hold none, the regression
// on the forcing has nothing to work with and their scatter says nothing (a band of
// 1e7..1e8 rad/s on the reference passed about one renewal in 64 realizations and
// reported standard errors of exactly 0). Every sub-band's first round passes this many.
constexpr double kLeastBandRenewals = 64;
/// Renewals of one realization per second of steady sliding: every touching contact's v/a.
double renewals_per_second(const Parameters& params);
/// The first round's realizations of a sub-band of `params` under `request`.
std::uint64_t first_round_realizations(const Parameters& params, const RunRequest& request, const SubBand& band);
// Bump whenever a change alters any number a run produces (stepper, renewal, estimator):
// saved states of other numerics are refused on resume and merge, which are bitwise.
constexpr int kNumericsVersion = 9;
// A precision-driven sub-band stops growing here (see run.cpp).
constexpr std::uint64_t kMaxRealizationsPerBand = std::uint64_t{1} << 16;
// ... or at this many realization-steps (see run.cpp).
constexpr double kMaxStepsPerBand = 2e9;

/// The request's own fields in range (validate.cpp); throws InputError naming the option.
void check_request_fields(const RunRequest& request);
/// Every sub-band's time step and step count finite and representable.
void check_plan(const Parameters& params, const std::vector<SubBand>& plan);
/// A sub-band's time step resolvable against the renewal time, naming what sets it
/// (validate.cpp); checked while planning, before the band's estimator exists.
void check_step(const Parameters& params, const SubBand& band);
/// The work a realization of `band` adds beyond its steps, in realization-steps: renewals
/// of a block that slides faster than its plan foresaw (0 wherever the forces cannot stall it).
double renewal_excess_work(const Parameters& params, const SubBand& band);
/// The estimator of a sub-band's realizations (run.cpp).
EstimatorConfig estimator_config(const SubBand& band, int points_per_decade);

/// One batch of realizations, as the stepper and estimator leave it.
struct BatchRecord {
  SpectrumAccumulator spectrum;                  // its lanes merged in lane order
  std::vector<std::vector<double>> own_mean;     // per realization: its mean periodogram per output point
  std::vector<double> control;                   // per realization: forcing_control
  std::vector<double> speed;                     // per realization: its mean sliding speed [m/s]
  std::vector<std::vector<double>> shadow_mean;  // per realization: its shadow's own_mean (empty without)
};

/// What one sub-band has accumulated: its batches in realization order, from its first.
struct BandTotals {
  std::vector<BatchRecord> batches;
  std::uint64_t realizations = 0;
  std::uint64_t planned = 0;  // realizations through the end of the current round
  int rounds = 0;             // rounds completed
  bool finished = false;

  /// The batches' spectra merged in realization order.
  SpectrumAccumulator merged() const {
    SpectrumAccumulator all;
    for (const BatchRecord& batch : batches) all.merge(batch.spectrum);
    return all;
  }
};

std::uint64_t realizations_in(const std::vector<BatchRecord>& batches);
void put_batch(std::string& bytes, const BatchRecord& batch);
BatchRecord get_batch(util::Reader& in);

/// Why neighbouring sub-bands b and b + 1 of `result` do not join smoothly (their C_x over
/// theory differ by more than a factor of two beyond five standard errors), or "".
std::string band_break(const RunResult& result, std::size_t b);

}  // namespace run_detail

struct RunSession::Impl {
  Parameters params;
  RunRequest request;
  std::string case_name;
  std::vector<SubBand> plan;
  std::vector<std::int64_t> steps;  // per sub-band realization
  std::vector<run_detail::BandTotals> bands;
  double wall_seconds = 0;  // over every advance, including before a resume
  std::string runaway;      // why the run stopped: a realization's block ran away ("" if none)

  Impl(const Parameters& p, const RunRequest& r, std::string name);
};

}  // namespace slidespec
