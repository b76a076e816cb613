#include "estimator/kernels.hpp"

#include "simd/path_table.hpp"

namespace slidespec::estimator_detail {

#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) extern const StreamKernels name##_stream;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH

const StreamKernels& stream_kernels(SimdPath path) {
  static constexpr simd::PathEntry<StreamKernels> loops[] = {
#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) {SimdPath::name, &name##_stream},
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH
  };
  return simd::table_for(loops, path);
}

}  // namespace slidespec::estimator_detail
