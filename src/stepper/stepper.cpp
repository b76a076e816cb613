#include "slidespec/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

#include "model/linear_structure.hpp"
#include "stepper/exact_step.hpp"
#include "stepper/kernel.hpp"
#include "stepper/renewal.hpp"

namespace slidespec {

namespace {
// Checked before the renewal state is built, which holds at most three input classes.
stepper::GroupKernel compiled_kernel(SimdPath path, const stepper::ExactStep& step, const Parameters& p) {
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
        step(stepper::exact_step(lumped, c.dt, {p.drive == Drive::spring, p.renewal_rate()})),
        kernel(compiled_kernel(path, step, p)),
        renewal(model::tree_structure(p).contacts, lumped.class_of_contact, p.renewal, c.seed, c.stream,
                first_realization, padded) {
    if (!(c.dt > 0) || !std::isfinite(c.dt)) throw InputError("time step dt must be > 0");
    if (n < 1) throw InputError("a batch needs at least one realization");
    z.assign(static_cast<size_t>(step.dimension) * padded, 0.0);
    xi.assign(padded, 0.0);
    offset_sum.assign(padded, 0.0);
    // Start in equilibrium with the initial forces (docs/model.md §1: steady sliding),
    // computed in plain scalar code so that every path starts from the same bits.
    for (int lane = 0; lane < padded; ++lane)
      for (int r = 0; r < step.dimension; ++r) {
        double value = 0.0;
        for (int k = 0; k < step.inputs; ++k)
          value += step.initial_response[r * step.inputs + k] * renewal.input_force(k, lane);
        z[static_cast<size_t>(r) * padded + lane] = value;
      }
    // A chunk of increments of about 256 KiB: big enough to amortize the kernel call,
    // small enough to stay in L2 while the sink reads it.
    chunk_steps = std::max<std::int64_t>(64, 32768 / padded);
    increments.assign(static_cast<size_t>(chunk_steps) * padded, 0.0);
    if (padded != count) compact.assign(static_cast<size_t>(chunk_steps) * count, 0.0);
    if (c.warm_up > 0) warm_up();
  }

  /// Runs the kernel of `exact` for `total` steps after `done` of them, from the load's
  /// position `origin`, handing each chunk's increments to `chunk_done`.
  template <class ChunkDone>
  void run_kernel(const stepper::ExactStep& exact, double origin, std::int64_t done, std::int64_t total,
                  const ChunkDone& chunk_done) {
    stepper::KernelArgs args{};
    args.step = &exact;
    args.steady_origin = origin;
    args.advance_per_step = params.v * exact.dt;
    args.runaway_increment = stepper::kRunawayAdvances * fastest_advance(params) * args.advance_per_step;
    args.stride = padded;
    args.z = z.data();
    args.xi = xi.data();
    args.offset_sum = offset_sum.data();
    args.renewal = &renewal.lanes_view();
    args.increments = increments.data();
    while (total > 0) {
      const std::int64_t chunk = std::min(total, chunk_steps);
      args.first_step = done;
      args.steps = chunk;
      args.lane0 = 0;
      args.lanes = padded;
      kernel(args);
      chunk_done(chunk);
      done += chunk;
      total -= chunk;
    }
  }

  /// The warm-up at its own step; then the realization starts where it left the block, and
  /// its summaries count from there. A lane that ran away in the warm-up (its xi NaN)
  /// gets a NaN state, so that every increment it hands on says so.
  void warm_up() {
    const double warm_dt = config.warm_up_dt > 0 ? config.warm_up_dt : config.dt;
    const stepper::ExactStep coarse =
        warm_dt == config.dt
            ? step
            : stepper::exact_step(lumped, warm_dt, {params.drive == Drive::spring, params.renewal_rate()});
    const auto warm_steps = static_cast<std::int64_t>(std::ceil(config.warm_up / warm_dt));
    run_kernel(coarse, 0.0, 0, warm_steps, [](std::int64_t) {});
    // The kernel's own expression for v t at the warm-up's end, so the load continues there.
    steady_origin = params.v * warm_dt * static_cast<double>(warm_steps);
    for (int lane = 0; lane < padded; ++lane) {
      if (!std::isfinite(xi[lane]))
        for (int r = 0; r < step.dimension; ++r) z[static_cast<size_t>(r) * padded + lane] = NAN;
      xi_at_start.push_back(xi[lane]);
    }
    std::fill(offset_sum.begin(), offset_sum.end(), 0.0);
    renewal.reset_counters();
  }

  Parameters params;
  StepperConfig config;
  SimdPath path;
  int width;
  std::uint64_t first;
  int count, padded;
  model::LumpedStructure lumped;
  stepper::ExactStep step;
  stepper::GroupKernel kernel;
  stepper::RenewalState renewal;
  std::vector<double> z, xi, offset_sum, increments, compact;
  std::vector<double> xi_at_start;  // [lane], after a warm-up
  double steady_origin = 0;         // v t where the warm-up ended [m]
  std::int64_t chunk_steps = 0;
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

void Stepper::advance(std::int64_t steps, const IncrementSink& sink) {
  Impl& s = *impl_;
  s.run_kernel(s.step, s.steady_origin, s.steps_done, steps, [&](std::int64_t chunk) {
    if (sink) {
      if (s.padded == s.count) {
        sink(s.increments.data(), static_cast<std::size_t>(chunk));
      } else {
        for (std::int64_t t = 0; t < chunk; ++t)
          std::copy_n(s.increments.data() + t * s.padded, s.count, s.compact.data() + t * s.count);
        sink(s.compact.data(), static_cast<std::size_t>(chunk));
      }
    }
    s.steps_done += chunk;
  });
}

std::vector<RealizationSummary> Stepper::summaries() const {
  const Impl& s = *impl_;
  std::vector<RealizationSummary> out(s.count);
  for (int k = 0; k < s.count; ++k) {
    out[k].realization = s.first + static_cast<std::uint64_t>(k);
    out[k].duration = static_cast<double>(s.steps_done) * s.config.dt;
    out[k].xi_end = s.xi_at_start.empty() ? s.xi[k] : s.xi[k] - s.xi_at_start[k];
    out[k].mean_offset = s.steps_done > 0 ? s.offset_sum[k] / static_cast<double>(s.steps_done) : 0.0;
    out[k].renewals = s.renewal.renewals(k);
    out[k].jump_energy = s.renewal.jump_energy(k);
    out[k].renewal_passes = s.renewal.passes(k);
  }
  return out;
}

int resolve_threads(int threads) {
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void run_batches(const Parameters& params, const StepperConfig& config, std::uint64_t first, std::uint64_t realizations,
                 std::int64_t steps, int threads, int batch_size,
                 const std::function<IncrementSink(std::uint64_t first, int count)>& make_sink,
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
        IncrementSink sink;
        {
          std::lock_guard<std::mutex> lock(callbacks);
          if (make_sink) sink = make_sink(batch_first, count);
        }
        stepper.advance(steps, sink);
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
