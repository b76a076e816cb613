#include "estimator/kernels.hpp"

#include <stdexcept>

namespace slidespec::estimator_detail {

#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) extern const StreamKernels name##_stream;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH

const StreamKernels& stream_kernels(SimdPath path) {
  const SimdPath resolved = resolve_simd_path(path);
#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) \
  if (resolved == SimdPath::name) return name##_stream;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH
  throw std::logic_error("estimator: no streaming loops for a compiled path");
}

}  // namespace slidespec::estimator_detail
