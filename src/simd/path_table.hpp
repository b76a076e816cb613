// A module's kernels, compiled once per instruction-set path, looked up for a path this
// CPU runs. Each module (stepper, estimator) lists its per-path tables in the order of
// simd/paths.inc and asks here; the choice of the path is resolve_simd_path's.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include "slidespec/simd.hpp"

namespace slidespec::simd {

template <class Table>
struct PathEntry {
  SimdPath path;
  const Table* table;
};

/// The table of `path` (automatic: the widest path this CPU runs). InputError when this
/// CPU cannot run the path (from resolve_simd_path).
template <class Table, std::size_t N>
const Table& table_for(const PathEntry<Table> (&entries)[N], SimdPath path) {
  const SimdPath resolved = resolve_simd_path(path);
  for (const PathEntry<Table>& entry : entries)
    if (entry.path == resolved) return *entry.table;
  throw std::logic_error(std::string("no kernels were compiled for the ") + to_string(resolved) + " path");
}

}  // namespace slidespec::simd
