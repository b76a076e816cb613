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
/// Parses a compiled path's name or "auto"; throws InputError.
SimdPath parse_simd_path(const std::string& name);
/// The names parse_simd_path takes, from the path table: "scalar|sse2|...|auto".
std::string simd_path_names();
/// The paths this CPU can run, narrowest first (scalar is always there).
std::vector<SimdPath> available_simd_paths();
/// `automatic` becomes the widest available path; an unavailable path is an InputError.
SimdPath resolve_simd_path(SimdPath requested);
/// Realizations (lanes) a path advances together.
int lane_width(SimdPath path);

}  // namespace slidespec
