// The stepper's kernel, written once (kernel.inc) and compiled per instruction-set path
// inside that path's namespace (stepper/path.cpp.in), which defines Batch, width, load,
// store, broadcast and any_passed (simd/primitives.inc). Each path exports its kernels
// through its PathKernels; path_kernels() picks them at run time.
#pragma once

#include <cstddef>
#include <cstdint>

#include "slidespec/simd.hpp"
#include "model/exact_step.hpp"
#include "stepper/renewal.hpp"

namespace slidespec::stepper {

/// A step that moves the block this many times its fastest plausible advance has run away
/// (the fastest: v dt times 1 + (|F_drive| + the random forces' range) / (F_drive - F_kin),
/// every force pushing one way against the drag). The kernel turns such a lane's
/// increments into NaN.
inline constexpr double kRunawayAdvances = 1e4;

/// One call advances the lanes [lane0, lane0 + lanes) of a batch by `steps`.
struct KernelArgs {
  const model::ExactStep* step;
  double steady_origin;      // v t at step 0 [m]: where a warm-up left the load
  double advance_per_step;   // v dt [m]: the steady sliding over one step
  double runaway_increment;  // [m]: a step's xi increment beyond this has run away
  double crossing_weight;    // 1: the block's x = v t + xi crosses the marks; 0: v t does (the shadow)
  std::int64_t first_step;   // steps already taken, so x = steady_origin + v dt (first_step + s) + xi
  std::int64_t steps;
  int lane0;
  int lanes;              // a multiple of the path's width
  int stride;             // lanes in the batch (padded to the width): z is [component][stride]
  double* z;              // the exact step's state, component-major
  double* xi;             // [stride]
  double* offset_sum;     // [stride]: sum over steps of the miniblocks' mean offset
  RenewalLanes* renewal;  // lanes laid out like z
  double* increments;     // [steps][stride]
};

using GroupKernel = void (*)(const KernelArgs&);

/// One path's kernels.
struct PathKernels {
  /// The kernel for a state of `dimension` components and `inputs` input classes, or
  /// nullptr if it was not compiled for that shape.
  GroupKernel (*group_kernel)(int dimension, int inputs);
  /// The renewal draws of `lanes` lanes (a multiple of the width) for given counter words:
  /// the generator's four words and -log of the uniform made of the last two.
  void (*draw_lanes)(const std::uint32_t (&key)[2], const std::uint64_t* const (&counter)[4], int lanes,
                     std::uint64_t* const (&words)[4], double* exponential);
};

/// The kernels of resolve_simd_path(path); throws InputError for a path this CPU cannot run.
const PathKernels& path_kernels(SimdPath path);

}  // namespace slidespec::stepper
