// The stepper's kernel, written once (kernel.inc) and compiled per instruction-set path
// inside that path's namespace (simd/path.cpp.in), which defines Batch, width, load,
// store, broadcast and any_passed (simd/primitives.inc). Each path exports its kernels
// through its table (simd/path_table.hpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "stepper/exact_step.hpp"
#include "stepper/renewal.hpp"

namespace slidespec::stepper {

/// One call advances the lanes [lane0, lane0 + lanes) of a batch by `steps`.
struct KernelArgs {
  const ExactStep* step;
  double advance_per_step;  // v dt [m]: the steady sliding over one step
  std::int64_t first_step;  // steps already taken, so x = v dt (first_step + s) + xi
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

}  // namespace slidespec::stepper
