// The one run-time choice of an instruction-set path: the compiled paths (simd/paths.inc,
// generated from SLIDESPEC_SIMD_PATHS in src/CMakeLists.txt), which of them this CPU runs,
// and their widths. It knows no kernel: the stepper and the estimator look theirs up for
// the path chosen here (stepper::path_kernels, estimator_detail::stream_kernels).
#include <xsimd/xsimd.hpp>

#include "slidespec/simd.hpp"
#include "slidespec/input_error.hpp"

namespace slidespec::simd {

namespace {

struct CompiledPath {
  SimdPath path;
  const char* name;
  bool cpu_runs;
  int width;  // lanes a kernel call advances together
};

// Narrowest first, as listed.
const std::vector<CompiledPath>& compiled_paths() {
  static const std::vector<CompiledPath> paths = [] {
    const auto cpu = xsimd::available_architectures();
    (void)cpu;
#define SLIDESPEC_SIMD_PATH(name, cpu_runs, width) {SimdPath::name, #name, static_cast<bool>(cpu_runs), width},
    return std::vector<CompiledPath>{
#include "simd/paths.inc"
    };
#undef SLIDESPEC_SIMD_PATH
  }();
  return paths;
}

const CompiledPath* find(SimdPath path) {
  for (const CompiledPath& p : compiled_paths())
    if (p.path == path) return &p;
  return nullptr;
}

}  // namespace

}  // namespace slidespec::simd

namespace slidespec {

const char* to_string(SimdPath path) {
  if (path == SimdPath::automatic) return "auto";
  const simd::CompiledPath* p = simd::find(path);
  return p ? p->name : "?";
}

SimdPath parse_simd_path(const std::string& name) {
  if (name == "auto") return SimdPath::automatic;
  std::string names;
  for (const simd::CompiledPath& p : simd::compiled_paths()) {
    if (name == p.name) return p.path;
    names += std::string(p.name) + ", ";
  }
  throw InputError("{simd}: '" + name + "' is not one of " + names + "auto");
}

std::string simd_path_names() {
  std::string names;
  for (const simd::CompiledPath& p : simd::compiled_paths()) names += std::string(p.name) + "|";
  return names + "auto";
}

std::vector<SimdPath> available_simd_paths() {
  std::vector<SimdPath> paths;
  for (const simd::CompiledPath& p : simd::compiled_paths())
    if (p.cpu_runs) paths.push_back(p.path);
  return paths;
}

SimdPath resolve_simd_path(SimdPath requested) {
  const auto paths = available_simd_paths();
  if (requested == SimdPath::automatic) return paths.back();
  if (std::find(paths.begin(), paths.end(), requested) == paths.end())
    throw InputError(std::string("{simd}: this CPU cannot run the ") + to_string(requested) + " path");
  return requested;
}

int lane_width(SimdPath path) { return simd::find(resolve_simd_path(path))->width; }

}  // namespace slidespec
