// The stepper's kernel, written once and instantiated per instruction set.
//
// kernel_<path>.cpp defines, inside its own namespace, `Batch` (xsimd::batch<double, Arch>
// or plain double for the scalar path) and the four operations below, then includes
// kernel.inc. Separate namespaces keep each path's symbols apart, so the linker can never
// hand the SSE2 path a function compiled for AVX-512.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stepper/exact_step.hpp"
#include "stepper/renewal.hpp"

namespace slidespec::stepper {

/// One call advances the lanes [lane0, lane0 + lanes) of a batch by `steps`.
struct KernelArgs {
  const ExactStep* step;
  double advance_per_step;    // v dt [m]: the steady sliding over one step
  std::int64_t first_step;    // steps already taken, so x = v dt (first_step + s) + xi
  std::int64_t steps;
  int lane0;
  int lanes;                  // a multiple of the path's width
  int stride;                 // lanes in the batch (padded to the width): z is [component][stride]
  double* z;                  // the exact step's state, component-major
  double* xi;                 // [stride]
  double* offset_sum;         // [stride]: sum over steps of the miniblocks' mean offset
  RenewalState* renewal;      // lanes laid out like z
  double* increments;         // [steps][stride]
};

using GroupKernel = void (*)(const KernelArgs&);

/// The kernel for a state of `dimension` components and `inputs` input classes on a
/// path, or nullptr if that path was not compiled for this shape.
GroupKernel scalar_kernel(int dimension, int inputs);
GroupKernel sse2_kernel(int dimension, int inputs);
GroupKernel avx2_kernel(int dimension, int inputs);
GroupKernel avx512_kernel(int dimension, int inputs);

}  // namespace slidespec::stepper
