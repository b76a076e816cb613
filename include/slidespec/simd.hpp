// Instruction-set paths. Every path gives bitwise the same numbers; they differ only in
// speed. The stepper and the estimator take one, the widest this CPU has by default.
#pragma once

#include <string>
#include <vector>

namespace slidespec {

/// The paths compiled into slidespec, narrowest first. The values are stored in run
/// state files: append, never renumber.
enum class SimdPath { automatic, scalar, sse2, avx2, avx512 };

const char* to_string(SimdPath path);
/// Parses scalar|sse2|avx2|avx512|auto; throws InputError.
SimdPath parse_simd_path(const std::string& name);
/// The paths this CPU can run, narrowest first (scalar is always there).
std::vector<SimdPath> available_simd_paths();
/// `automatic` becomes the widest available path; an unavailable path is an InputError.
SimdPath resolve_simd_path(SimdPath requested);
/// Realizations (lanes) a path advances together.
int lane_width(SimdPath path);

}  // namespace slidespec
