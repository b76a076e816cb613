#include "stepper/kernel.hpp"

#include <stdexcept>

namespace slidespec::stepper {

#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) extern const PathKernels name##_kernels;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH

const PathKernels& path_kernels(SimdPath path) {
  const SimdPath resolved = resolve_simd_path(path);
#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) \
  if (resolved == SimdPath::name) return name##_kernels;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH
  throw std::logic_error("stepper: no kernels for a compiled path");
}

}  // namespace slidespec::stepper
