// The one run-time choice of an instruction-set path. The compiled paths come from
// simd/paths.inc, generated from SLIDESPEC_SIMD_PATHS (src/CMakeLists.txt); this file
// itself is compiled for the baseline CPU and only reads the paths' tables (data) until
// the CPU is known to run them.
#include <xsimd/xsimd.hpp>

#include "simd/path_table.hpp"
#include "slidespec/parameters.hpp"

namespace slidespec::simd {

#define SLIDESPEC_SIMD_PATH(name, cpu_runs) extern const PathTable name##_path;
#include "simd/paths.inc"
#undef SLIDESPEC_SIMD_PATH

namespace {

struct CompiledPath {
  const PathTable* table;
  const char* name;
  bool cpu_runs;
};

// Narrowest first, as listed.
const std::vector<CompiledPath>& compiled_paths() {
  static const std::vector<CompiledPath> paths = [] {
    const auto cpu = xsimd::available_architectures();
    (void)cpu;
#define SLIDESPEC_SIMD_PATH(name, cpu_runs) {&name##_path, #name, static_cast<bool>(cpu_runs)},
    return std::vector<CompiledPath>{
#include "simd/paths.inc"
    };
#undef SLIDESPEC_SIMD_PATH
  }();
  return paths;
}

const CompiledPath* find(SimdPath path) {
  for (const CompiledPath& p : compiled_paths())
    if (p.table->path == path) return &p;
  return nullptr;
}

}  // namespace

const PathTable& path_table(SimdPath path) {
  const SimdPath resolved = resolve_simd_path(path);
  return *find(resolved)->table;
}

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
    if (name == p.name) return p.table->path;
    names += std::string(p.name) + ", ";
  }
  throw InputError("--simd: '" + name + "' is not one of " + names + "auto");
}

std::string simd_path_names() {
  std::string names;
  for (const simd::CompiledPath& p : simd::compiled_paths()) names += std::string(p.name) + "|";
  return names + "auto";
}

std::vector<SimdPath> available_simd_paths() {
  std::vector<SimdPath> paths;
  for (const simd::CompiledPath& p : simd::compiled_paths())
    if (p.cpu_runs) paths.push_back(p.table->path);
  return paths;
}

SimdPath resolve_simd_path(SimdPath requested) {
  const auto paths = available_simd_paths();
  if (requested == SimdPath::automatic) return paths.back();
  if (std::find(paths.begin(), paths.end(), requested) == paths.end())
    throw InputError(std::string("--simd: this CPU cannot run the ") + to_string(requested) + " path");
  return requested;
}

int lane_width(SimdPath path) { return simd::path_table(path).width; }

}  // namespace slidespec
