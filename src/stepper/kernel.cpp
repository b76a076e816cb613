#include "stepper/kernel.hpp"

#include "simd/path_table.hpp"

namespace slidespec::stepper {

#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) extern const PathKernels name##_kernels;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH

const PathKernels& path_kernels(SimdPath path) {
  static constexpr simd::PathEntry<PathKernels> kernels[] = {
#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) {SimdPath::name, &name##_kernels},
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH
  };
  return simd::table_for(kernels, path);
}

}  // namespace slidespec::stepper
