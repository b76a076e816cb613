// One table per instruction-set path: its lane width and its kernels (the stepper's
// group kernels, the estimator's streaming loops). Each path's translation unit defines
// its table (simd/path.cpp.in); path_table() is the one place that picks a path at run
// time. The paths themselves are listed once, in SLIDESPEC_SIMD_PATHS (src/CMakeLists.txt).
#pragma once

#include "estimator/kernels.hpp"
#include "slidespec/simd.hpp"
#include "stepper/kernel.hpp"

namespace slidespec::simd {

struct PathTable {
  SimdPath path;
  int width;  // lanes a kernel call advances together
  /// The stepper's kernel for a state of `dimension` components and `inputs` input
  /// classes, or nullptr if it was not compiled for that shape.
  stepper::GroupKernel (*group_kernel)(int dimension, int inputs);
  /// The renewal draws of `lanes` lanes (a multiple of width) for given counter words:
  /// the generator's four words and -log of the uniform made of the last two.
  void (*draw_lanes)(const std::uint32_t (&key)[2], const std::uint64_t* const (&counter)[4], int lanes,
                     std::uint64_t* const (&words)[4], double* exponential);
  estimator_detail::StreamKernels stream;
};

/// The table of `path`; `automatic` is the widest path this CPU runs. Throws InputError
/// for a path this CPU cannot run.
const PathTable& path_table(SimdPath path);

}  // namespace slidespec::simd
