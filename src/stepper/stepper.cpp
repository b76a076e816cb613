#include "slidespec/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

#include "model/linear_structure.hpp"
#include "model/exact_step.hpp"
#include "stepper/kernel.hpp"
#include "stepper/renewal.hpp"

namespace slidespec {

namespace {
// Checked before the renewal state is built, which holds at most three input classes.
stepper::GroupKernel compiled_kernel(SimdPath path, const model::ExactStep& step, const Parameters& p) {
  const stepper::GroupKernel kernel = stepper::path_kernels(path).group_kernel(step.dimension, step.inputs);
  if (kernel == nullptr)
    throw InputError("parameters levels, touching: the stepper is compiled for up to 3 levels (got " +
                     std::to_string(p.levels) + ")");
  return kernel;
}

/// The fastest advance per step against v dt that the forces can drive: every random force
/// and the drive pushing one way against the drag (F_drive - F_kin at v).
double fastest_advance(const Parameters& p) {
  double range = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) range += static_cast<double>(p.blocks(l)) * p.level(l).alpha * p.friction_per_miniblock();
  return 1 + (std::fabs(p.F_drive) + range) / std::fabs(p.F_drive - p.F_kin);
}
}  // namespace

/// One path through the marks: the block's own (crossing_weight 1), or its linear shadow,
/// which renews each force when the nominal place v t passes the mark (weight 0) but
/// otherwise draws the same renewals and follows the same dynamics.
struct PathState {
  PathState(stepper::RenewalState r, double weight) : renewal(std::move(r)), crossing_weight(weight) {}
  stepper::RenewalState renewal;
  double crossing_weight;
  std::vector<double> z, xi, offset_sum, increments, compact;
};

struct Stepper::Impl {
  Impl(const Parameters& p, const StepperConfig& c, std::uint64_t first_realization, int n)
      : params(p),
        config(c),
        path(resolve_simd_path(c.simd)),
        width(lane_width(path)),
        first(first_realization),
        count(n),
        padded((n + width - 1) / width * width),
        lumped(model::lumped_tree_structure(p)),
        step(model::exact_step(lumped, c.dt, {p.drive == Drive::spring, p.renewal_rate()})),
        kernel(compiled_kernel(path, step, p)) {
    if (!(c.dt > 0) || !std::isfinite(c.dt)) throw InputError("time step dt must be > 0");
    if (n < 1) throw InputError("a batch needs at least one realization");
    // A chunk of increments of about 256 KiB: big enough to amortize the kernel call,
    // small enough to stay in L2 while the sink reads it.
    chunk_steps = std::max<std::int64_t>(64, 32768 / padded);
    // Each start draws every contact's force and mark: a tenth of a second or more with a
    // million contacts, so the stop is heard between them too.
    hear_stop();
    paths.push_back(start_path(1.0));
    hear_stop();
    if (c.shadow) paths.push_back(start_path(0.0));
    if (c.warm_up > 0) warm_up();
  }

  void hear_stop() const {
    if (config.stop && config.stop->load(std::memory_order_relaxed)) throw StepperStopped{};
  }

  /// A path at the start: fresh forces, marks ahead, and z in equilibrium with the forces
  /// (docs/model.md §1: steady sliding), computed in plain scalar code so that every SIMD
  /// path starts from the same bits.
  PathState start_path(double crossing_weight) const {
    PathState s(stepper::RenewalState(lumped.contacts, lumped.class_of_contact, params.renewal, config.seed,
                                      config.stream, first, padded),
                crossing_weight);
    s.z.assign(static_cast<size_t>(step.dimension) * padded, 0.0);
    s.xi.assign(padded, 0.0);
    s.offset_sum.assign(padded, 0.0);
    for (int lane = 0; lane < padded; ++lane)
      for (int r = 0; r < step.dimension; ++r) {
        double value = 0.0;
        for (int k = 0; k < step.inputs; ++k)
          value += step.initial_response[r * step.inputs + k] * s.renewal.input_force(k, lane);
        s.z[static_cast<size_t>(r) * padded + lane] = value;
      }
    s.increments.assign(static_cast<size_t>(chunk_steps) * padded, 0.0);
    if (padded != count) s.compact.assign(static_cast<size_t>(chunk_steps) * count, 0.0);
    return s;
  }

  /// Runs the kernel of `exact` on `s` for `steps` after `done` of them, from the load's
  /// position `origin`, its increments from row `row` of the chunk's.
  void run_kernel(PathState& s, const model::ExactStep& exact, double origin, std::int64_t done, std::int64_t steps,
                  std::int64_t row) {
    stepper::KernelArgs args{};
    args.step = &exact;
    args.steady_origin = origin;
    args.advance_per_step = params.v * exact.dt;
    args.runaway_increment = stepper::kRunawayAdvances * fastest_advance(params) * args.advance_per_step;
    args.crossing_weight = s.crossing_weight;
    args.stride = padded;
    args.z = s.z.data();
    args.xi = s.xi.data();
    args.offset_sum = s.offset_sum.data();
    args.renewal = &s.renewal.lanes_view();
    args.increments = s.increments.data() + row * padded;
    args.first_step = done;
    args.steps = steps;
    args.lane0 = 0;
    args.lanes = padded;
    kernel(args);
  }

  /// run_kernel over `steps` (at most a chunk), in pieces when a stop can be asked for: a
  /// step passes every mark the block reaches, and near the stall the block can coast
  /// thousands of renewal distances in one, so a piece is sized by its own time.
  void run_stoppable(PathState& s, const model::ExactStep& exact, double origin, std::int64_t done,
                     std::int64_t steps) {
    const auto warming = [&](std::int64_t piece) {
      // The shadow's warm-up runs beside the block's: told once.
      if (warming_up && config.warm_up_progress && &s == &paths.front()) config.warm_up_progress(piece * count);
    };
    if (!config.stop) {
      run_kernel(s, exact, origin, done, steps, 0);
      return warming(steps);
    }
    for (std::int64_t row = 0; row < steps;) {
      hear_stop();
      const std::int64_t piece = std::min(steps - row, piece_steps);
      const auto start = std::chrono::steady_clock::now();
      run_kernel(s, exact, origin, done + row, piece, row);
      row += piece;
      warming(piece);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (seconds < 0.25 * kPieceSeconds)
        piece_steps = std::min(2 * piece_steps, chunk_steps);
      else if (seconds > kPieceSeconds)
        piece_steps = std::max<std::int64_t>(1, piece_steps / 2);
    }
  }

  /// Every path's chunks of `steps` steps of `exact` after `done`, in turn, so that each
  /// path's increments of a chunk are ready together.
  template <class ChunkDone>
  void run_paths(const model::ExactStep& exact, double origin, std::int64_t done, std::int64_t steps,
                 const ChunkDone& chunk_done) {
    while (steps > 0) {
      const std::int64_t chunk = std::min(steps, chunk_steps);
      for (PathState& s : paths) run_stoppable(s, exact, origin, done, chunk);
      chunk_done(chunk);
      done += chunk;
      steps -= chunk;
    }
  }

  /// The warm-up at its own step; then the realization starts where it left the block, and
  /// its summaries count from there. A lane that ran away in the warm-up (its xi NaN) gets
  /// a NaN state, so that every increment it hands on says so. The shadow warms up beside
  /// the block from the same start, which is its own stationary law (fresh forces, marks
  /// ahead of v t), so it stays exactly the stationary linear process.
  void warm_up() {
    const double warm_dt = config.warm_up_dt > 0 ? config.warm_up_dt : config.dt;
    const model::ExactStep coarse =
        warm_dt == config.dt
            ? step
            : model::exact_step(lumped, warm_dt, {params.drive == Drive::spring, params.renewal_rate()});
    const auto warm_steps = static_cast<std::int64_t>(std::ceil(config.warm_up / warm_dt));
    warming_up = true;
    run_paths(coarse, 0.0, 0, warm_steps, [](std::int64_t) {});
    warming_up = false;
    // The kernel's own expression for v t at the warm-up's end, so the load continues there.
    steady_origin = params.v * warm_dt * static_cast<double>(warm_steps);
    for (PathState& s : paths) {
      for (int lane = 0; lane < padded; ++lane)
        if (!std::isfinite(s.xi[lane]))
          for (int r = 0; r < step.dimension; ++r) s.z[static_cast<size_t>(r) * padded + lane] = NAN;
      std::fill(s.offset_sum.begin(), s.offset_sum.end(), 0.0);
      s.renewal.reset_counters();
    }
    xi_at_start = paths.front().xi;
  }

  /// Hands a path's chunk to its sink, without the padding lanes.
  void hand_on(PathState& s, std::int64_t chunk, const IncrementSink& sink) const {
    if (!sink) return;
    if (padded == count) return sink(s.increments.data(), static_cast<std::size_t>(chunk));
    for (std::int64_t t = 0; t < chunk; ++t)
      std::copy_n(s.increments.data() + t * padded, count, s.compact.data() + t * count);
    sink(s.compact.data(), static_cast<std::size_t>(chunk));
  }

  Parameters params;
  StepperConfig config;
  SimdPath path;
  int width;
  std::uint64_t first;
  int count, padded;
  model::LumpedStructure lumped;
  model::ExactStep step;
  stepper::GroupKernel kernel;
  std::int64_t chunk_steps = 0;
  // A piece's target time [s], far below the second a stop may take, far above a kernel
  // call's overhead.
  static constexpr double kPieceSeconds = 0.05;
  std::int64_t piece_steps = 1;     // steps per piece, grown or shrunk to take about kPieceSeconds
  bool warming_up = false;          // the steps are the warm-up's (its progress is told)
  std::vector<PathState> paths;     // the block's, then its shadow's if asked for
  std::vector<double> xi_at_start;  // [lane], after a warm-up
  double steady_origin = 0;         // v t where the warm-up ended [m]
  std::int64_t steps_done = 0;
};

Stepper::Stepper(const Parameters& params, const StepperConfig& config, std::uint64_t first_realization, int count)
    : impl_(std::make_unique<Impl>(params, config, first_realization, count)) {}
Stepper::~Stepper() = default;
Stepper::Stepper(Stepper&&) noexcept = default;
Stepper& Stepper::operator=(Stepper&&) noexcept = default;

int Stepper::count() const { return impl_->count; }
SimdPath Stepper::simd_path() const { return impl_->path; }
std::int64_t Stepper::steps_done() const { return impl_->steps_done; }

void Stepper::advance(std::int64_t steps, const IncrementSink& sink, const IncrementSink& shadow_sink) {
  Impl& s = *impl_;
  s.run_paths(s.step, s.steady_origin, s.steps_done, steps, [&](std::int64_t chunk) {
    s.hand_on(s.paths.front(), chunk, sink);
    if (s.paths.size() > 1) s.hand_on(s.paths.back(), chunk, shadow_sink);
    s.steps_done += chunk;
  });
}

std::vector<RealizationSummary> Stepper::summaries() const {
  const Impl& s = *impl_;
  const PathState& block = s.paths.front();
  std::vector<RealizationSummary> out(s.count);
  for (int k = 0; k < s.count; ++k) {
    out[k].realization = s.first + static_cast<std::uint64_t>(k);
    out[k].duration = static_cast<double>(s.steps_done) * s.config.dt;
    out[k].xi_end = s.xi_at_start.empty() ? block.xi[k] : block.xi[k] - s.xi_at_start[k];
    out[k].mean_offset = s.steps_done > 0 ? block.offset_sum[k] / static_cast<double>(s.steps_done) : 0.0;
    out[k].renewals = block.renewal.renewals(k);
    out[k].jump_energy = block.renewal.jump_energy(k);
    out[k].renewal_passes = block.renewal.passes(k);
    if (s.paths.size() > 1) out[k].shadow_renewals = s.paths.back().renewal.renewals(k);
  }
  return out;
}

int resolve_threads(int threads) {
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void run_batches(const Parameters& params, const StepperConfig& config, std::uint64_t first, std::uint64_t realizations,
                 std::int64_t steps, int threads, int batch_size,
                 const std::function<BatchSinks(std::uint64_t first, int count)>& make_sink,
                 const std::function<void(std::size_t, std::vector<RealizationSummary>)>& done) {
  if (batch_size < 1) throw InputError("batch size must be at least 1");
  const std::size_t batches = (realizations + batch_size - 1) / batch_size;
  threads = static_cast<int>(std::min<std::size_t>(resolve_threads(threads), std::max<std::size_t>(batches, 1)));

  std::atomic<std::size_t> next_batch{0};
  std::mutex callbacks;  // make_sink and done need not be thread-safe themselves
  std::exception_ptr failure;
  auto worker = [&] {
    try {
      for (std::size_t b = next_batch++; b < batches; b = next_batch++) {
        const std::uint64_t batch_first = first + b * batch_size;
        const int count = static_cast<int>(std::min<std::uint64_t>(batch_size, first + realizations - batch_first));
        Stepper stepper(params, config, batch_first, count);
        BatchSinks sinks;
        {
          std::lock_guard<std::mutex> lock(callbacks);
          if (make_sink) sinks = make_sink(batch_first, count);
        }
        stepper.advance(steps, sinks.block, sinks.shadow);
        std::lock_guard<std::mutex> lock(callbacks);
        if (done) done(b, stepper.summaries());
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(callbacks);
      if (!failure) failure = std::current_exception();
      next_batch = batches;  // let the others stop early
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace slidespec
