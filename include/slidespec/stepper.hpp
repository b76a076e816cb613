// The batch stepper: many independent realizations of the model, one per SIMD lane,
// advanced by the exact discretization of the model's linear part with the renewal of
// the random forces fused into the same loop. See docs/numerics.md for why it is exact.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "slidespec/parameters.hpp"
#include "slidespec/simd.hpp"

namespace slidespec {

struct StepperConfig {
  double dt = 1e-5;          ///< time step [s]; the discretization is exact for any dt
  std::uint64_t seed = 1;    ///< keys the random numbers
  std::uint64_t stream = 0;  ///< independent sub-run index (e.g. one per frequency band)
  SimdPath simd = SimdPath::automatic;
  /// Simulated before the first step, outside every output [s]: a realization starts with
  /// its forces' stationary law in sliding distance, and reaches the law in time, which a
  /// spectrum assumes, only after the block has slid a few renewal distances (docs/run.md).
  double warm_up = 0;
  /// The warm-up's own time step [s] (0: dt). Exact at any step, so a coarse one costs
  /// about the warm-up's renewals, not its duration over dt.
  double warm_up_dt = 0;
  /// Also runs each realization's linear shadow (docs/run.md): the same draws and dynamics,
  /// each force renewed when the nominal place v t, not the block, passes its mark. Its
  /// spectrum is exactly the first-order theory's, and it follows the block closely.
  bool shadow = false;
  /// Heard between pieces of the steps, the warm-up's included, each piece short enough to
  /// end well within a second however many renewals its steps hold: once set, the stepper
  /// throws StepperStopped. Pieces change no number (a lane's steps are the same sequence).
  const std::atomic<bool>* stop = nullptr;
  /// Told the realization-steps (steps x realizations) of each piece of the warm-up as it
  /// ends, on the stepping thread: near the stall one warm-up can take minutes, which a
  /// progress line should show.
  std::function<void(std::int64_t)> warm_up_progress;
};

/// What a stepper throws when its config's stop is set.
struct StepperStopped {};

/// What one realization did, for diagnostics and tests.
struct RealizationSummary {
  std::uint64_t realization = 0;
  double duration = 0;         ///< simulated time after the warm-up [s]
  double xi_end = 0;           ///< xi's change since the warm-up [m]; mean speed = v + xi_end / duration
  double mean_offset = 0;      ///< time average of the miniblocks' mean offset from u_bar [m]
  std::uint64_t renewals = 0;  ///< renewals of all miniblocks together (after the warm-up)
  double jump_energy = 0;      ///< sum over renewals of (f_new - f_old)^2 [N^2]
  /// Renewal passes of the realization's lane group: renewals / (passes x the path's
  /// width), summed over realizations, is the renewal passes' lane utilization.
  std::uint64_t renewal_passes = 0;
  std::uint64_t shadow_renewals = 0;  ///< the shadow's renewals after the warm-up (with a shadow)
};

/// Receives the increments xi_{n+1} - xi_n of every realization of a batch, chunk by
/// chunk: data[step * realizations + k] for realization first + k.
using IncrementSink = std::function<void(const double* data, std::size_t steps)>;

/// A batch of consecutive realizations [first, first + count), advanced together.
/// Realization r follows the same trajectory whatever the batch, lane width or thread.
class Stepper {
 public:
  Stepper(const Parameters& params, const StepperConfig& config, std::uint64_t first_realization, int count);
  ~Stepper();
  Stepper(Stepper&&) noexcept;
  Stepper& operator=(Stepper&&) noexcept;

  int count() const;
  SimdPath simd_path() const;
  /// Steps taken so far.
  std::int64_t steps_done() const;

  /// Advances every realization by `steps`, handing the increments to `sink` (may be empty),
  /// and with StepperConfig::shadow its shadow's to `shadow_sink`.
  void advance(std::int64_t steps, const IncrementSink& sink = {}, const IncrementSink& shadow_sink = {});

  std::vector<RealizationSummary> summaries() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// The threads a run uses when asked for `threads`: every core for 0 (the one default).
int resolve_threads(int threads);

/// A batch's sinks: the block's increments, and its shadow's (with StepperConfig::shadow).
struct BatchSinks {
  BatchSinks(IncrementSink block_sink = {}, IncrementSink shadow_sink = {})  // NOLINT: a plain sink converts
      : block(std::move(block_sink)), shadow(std::move(shadow_sink)) {}
  IncrementSink block, shadow;
};

/// Runs `realizations` realizations from `first` for `steps` steps each on `threads`
/// threads (0 = all cores), in batches of `batch_size`. `make_sink(first, count)` gives
/// each batch its sinks; `done(batch_index, summaries)` is called as batches finish, in
/// any order: combine their results by batch index to stay independent of scheduling.
void run_batches(const Parameters& params, const StepperConfig& config, std::uint64_t first, std::uint64_t realizations,
                 std::int64_t steps, int threads, int batch_size,
                 const std::function<BatchSinks(std::uint64_t first, int count)>& make_sink,
                 const std::function<void(std::size_t batch, std::vector<RealizationSummary>)>& done);

}  // namespace slidespec
