// A spectrum run: from a parameter set and a band to the simulated C_x(omega) with error
// bars, beside the exact theory. This is what `slidespec run` does, as a library call.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "slidespec/parameters.hpp"
#include "slidespec/stepper.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {

struct RunRequest {
  double omega_min = 0.1;  ///< lowest output omega [rad/s]
  double omega_max = 1e5;  ///< highest output omega [rad/s]
  int points_per_decade = 8;
  double precision = 0.05;         ///< target standard error / C_x at every point
  double duration = 0;             ///< > 0: fixed simulated time per realization of the lowest sub-band [s]
  std::uint64_t realizations = 0;  ///< > 0: fixed number of realizations per sub-band
  /// With `realizations` > 0: this run is the part [first_realization, first_realization +
  /// realizations) of a larger run (a multiple of 8, so parts share its batches).
  std::uint64_t first_realization = 0;
  /// A part of a larger run (--realizations-range): its finished state is what merge
  /// joins, so finishing it (a resume included) keeps PREFIX.state. Changes no number.
  bool part = false;
  std::uint64_t seed = 1;
  /// Each realization's linear shadow as a control variate (docs/run.md, "The shadow"):
  /// the same expectation, a smaller error for the same work; false: the forcing alone.
  bool control_variate = true;
  int threads = 0;  ///< 0 = all cores
  SimdPath simd = SimdPath::automatic;
  /// Most work the run may plan up front, in realization-steps (a step of a model with more
  /// than 100 blocks counts blocks/100 times); 0 = kDefaultWorkBudget. Changes no number.
  double work_budget = 0;
};

/// About an hour on two cores: a plan beyond it is refused unless the budget is raised.
constexpr double kDefaultWorkBudget = 1e11;

/// One sub-run: a stretch of the band simulated with its own time step.
struct SubBand {
  double omega_low = 0, omega_high = 0;  ///< output points it serves [rad/s]
  double dt = 0;                         ///< its time step [s]
  double duration = 0;                   ///< simulated time per realization [s]
  /// Simulated before each realization at the coarse `warm_up_dt`, outside its outputs [s]:
  /// long enough that the realization starts in the stationary state in time (docs/run.md).
  double warm_up = 0;
  double warm_up_dt = 0;  ///< [s]
  /// Whether its realizations run their linear shadow as a control variate: where the
  /// shadow's renewals stay close in time to the block's against the segments (docs/run.md).
  bool shadow = false;
  std::uint64_t realizations = 0;  ///< realizations completed
  int rounds = 0;                  ///< rounds of realizations run
};

/// The FFT bins a point averages: `count` frequencies from `first` to `last` [rad/s],
/// `spacing` apart. The mean of any C(omega) over them is what the point estimates.
struct BinRange {
  double first = 0, last = 0, spacing = 0;
  int count = 0;
  std::vector<double> omegas() const;  ///< the bin frequencies themselves [rad/s]
};

/// The continuous-time exact theory (exact_spectrum, the full structure) averaged over the
/// bins: what a point's C_x estimates [m^2 s].
double bin_average(const Parameters& params, const BinRange& bins);

struct RunPoint {
  double omega;            ///< [rad/s]
  double C_x;              ///< estimate [m^2 s]
  double standard_error;   ///< [m^2 s]
  double theory;           ///< continuous-time exact theory averaged over `bins`, window-smoothed
                           ///< as the estimate is (for a smooth C_x: bin_average) [m^2 s]
  double theory_at_omega;  ///< exact theory at omega [m^2 s]
  double n_avg;            ///< periodogram values averaged
  double bandwidth;        ///< resolution bandwidth [rad/s]
  BinRange bins;           ///< the FFT bins the estimate averages
  /// The second-order theory (docs/model.md §7) averaged as `theory` is [m^2 s]; NaN where
  /// it does not apply (RunResult::theory2_note says why).
  double theory2 = std::numeric_limits<double>::quiet_NaN();
  /// Which estimate this is: "shadow" (the regression on the shadow and the forcing),
  /// "forcing" (on the forcing alone, where the shadow did not pay or was off), or "plain"
  /// (too few realizations for a regression).
  std::string estimator = "plain";
  /// The estimate's variance over the plain mean's from the same realizations: the factor
  /// on the realizations the point needs.
  double variance_ratio = 1;
  /// The best theory that holds at this point (best_theory_at; RunResult::theory_kind is
  /// the band's): `theory2` where second_order or quasi_static, `theory` where first_order.
  TheoryKind theory_kind = TheoryKind::none;
};

struct RunResult {
  std::vector<RunPoint> points;
  std::vector<SubBand> sub_bands;
  double mean_speed = 0;         ///< measured, over the lowest sub-band's realizations [m/s]
  double mean_speed_error = 0;   ///< its standard error [m/s]
  double simulated_time = 0;     ///< all realizations of all sub-bands [s]
  double realization_steps = 0;  ///< time steps simulated, over all realizations
  double miniblock_steps = 0;    ///< blocks below the big block (all levels) x realization-steps
  double wall_seconds = 0;
  double reached_precision = 0;  ///< largest standard_error / C_x over the points
  /// Empty when every point has `theory2`; otherwise why the second-order theory does not
  /// apply (several touching levels, periodic renewal far beyond its validity).
  std::string theory2_note;
  /// The best theory that holds here (docs/model.md §7.4): the run's `theory2` for
  /// second_order, `theory` for first_order; none: neither column describes the run.
  TheoryKind theory_kind = TheoryKind::none;
  std::string theory_kind_note;  ///< why no better theory holds (empty for second_order)
  SimdPath simd_path = SimdPath::scalar;
  int threads = 1;
  bool complete = false;  ///< false when interrupted or out of budget
  /// False when the realizations are not one stationary process (the block stalled: a
  /// sub-band's mean sliding speed far from v); then no spectrum exists (docs/model.md).
  bool stationary = true;
  std::string stationarity;  ///< why not, when not stationary
};

/// Progress of a run, for a progress bar: fraction of the planned work and a message.
/// It is called from the run's worker threads, not the caller's, and often (every block
/// of steps); the run makes the calls one at a time, so the callback needs no lock of its
/// own, but workers wait while it runs: keep it short. The fraction steps back when a
/// sub-band plans another round.
using ProgressCallback = std::function<void(double fraction, const std::string& what)>;

/// How a run is spread over processes (MPI ranks): each runs a share of every chunk of
/// realizations and all end with the same totals, so they make the same decisions. The
/// default is one process.
class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Every process's `mine`, in rank order, on every process.
  virtual std::vector<std::string> all_gather(const std::string& mine) const { return {mine}; }
  /// True on every process when `mine` is true on any.
  virtual bool any(bool mine) const { return mine; }
};

/// A run in progress: everything accumulated so far, kept per batch of realizations in
/// realization order so that the totals are the same sums in the same order however the
/// run was cut (threads, processes, checkpoints, parts). It can be saved whenever no
/// batch is in flight and resumed, and parts of one run can be merged.
class RunSession {
 public:
  RunSession(const Parameters& params, const RunRequest& request, std::string case_name = "");
  ~RunSession();
  RunSession(RunSession&&) noexcept;
  RunSession& operator=(RunSession&&) noexcept;

  struct Control {
    ProgressCallback progress;
    const std::atomic<bool>* stop = nullptr;  ///< set: end at the next batch
    double checkpoint_every = 0;              ///< [s] of wall time; 0 = never
    std::function<void(const RunSession&)> checkpoint;
    const Communicator* communicator = nullptr;  ///< null: this process alone
  };
  /// Runs until every point reaches the precision, the fixed realizations are done or the
  /// budget is spent (returns true), or until stopped (returns false).
  bool advance(const Control& control);

  bool finished() const;
  RunResult result() const;
  /// Threads and SIMD path for the rest of the run (a resumed run may use others: they
  /// change no number).
  void set_execution(int threads, SimdPath simd);
  const Parameters& parameters() const;
  const RunRequest& request() const;
  const std::string& case_name() const;

  /// Versioned binary form; load() throws InputError for another version or a corrupt file.
  std::string save() const;
  static RunSession load(const std::string& bytes);
  /// "" if `params` and `request` describe this run, else the first difference, e.g.
  /// "seed: 1 here, 2 given" (threads and SIMD path do not count: they change no number).
  std::string difference(const Parameters& params, const RunRequest& request) const;
  /// Parts of one run (the same fixed-realization request over disjoint realization
  /// ranges) as the run over all of them: bitwise what one run over the whole range gives.
  /// Throws InputError for parts of other parameters, versions or overlapping ranges.
  static RunSession merge(std::vector<RunSession> parts);

  struct Impl;

 private:
  explicit RunSession(std::unique_ptr<Impl> impl);
  static RunSession load_checked(const std::string& bytes);
  std::unique_ptr<Impl> impl_;
};

/// Runs until every point reaches `precision` (or the fixed duration/realizations are
/// spent). Setting `*stop` (e.g. from a signal handler) ends the run early with what has
/// accumulated, `complete = false`. Same seed and request, same numbers, whatever the
/// thread count or SIMD path.
RunResult run_spectrum(const Parameters& params, const RunRequest& request, const ProgressCallback& progress = {},
                       const std::atomic<bool>* stop = nullptr);

/// Checks a request against its parameters before any work: every field in range, every
/// derived step count and sub-band finite and representable, and the planned work within
/// the budget. Throws InputError naming the option by its id (e.g. "{duration}: ...").
void validate_request(const Parameters& params, const RunRequest& request);

/// The work a request plans before its first result, in the unit of `work_budget`: the
/// first round of every sub-band (all of it for a fixed realization count).
double planned_first_round_work(const Parameters& params, const RunRequest& request);

/// The least a run's saved state takes [bytes]: per sub-band, (points + 2) doubles (its own
/// periodogram means, control and speed) for each realization of its first round (all of
/// them for a fixed realization count). A disk that cannot hold this refuses the run at once.
double least_state_bytes(const Parameters& params, const RunRequest& request);

/// The sub-runs a request is split into: about a decade each, with the time step set by
/// the sub-band's top frequency (and capped so a realization renews at most 16 times per
/// step), not by the model's stiffness.
std::vector<SubBand> plan_sub_bands(const Parameters& params, const RunRequest& request);

}  // namespace slidespec
