#!/usr/bin/env bash
# The library as another CMake project uses it (examples/): installs a built tree into a
# scratch prefix with `cmake --install`, configures examples/ against that prefix alone
# (find_package(slidespec)), builds it and runs it. Usage: tools/check_example.sh [BUILD_DIR]
# (default build, as tools/setup.sh leaves it).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f "$build/CMakeCache.txt" ] || { echo "check_example: $build is not a configured build" >&2; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

cmake --install "$build" --prefix "$scratch/prefix" > /dev/null
# Only the scratch prefix: a slidespec installed elsewhere on the machine must not be found.
cmake -S examples -B "$scratch/example" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$scratch/prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF > /dev/null
cmake --build "$scratch/example" -j1 > /dev/null
"$scratch/example/spectrum" > "$scratch/out.tsv"
# Seven theory rows (1 .. 1e3 rad/s, two a decade), then at least one point of the run.
rows=$(grep -vc '^#' "$scratch/out.tsv")
echo "check_example: examples/ built against $(basename "$scratch")/prefix and ran: $rows rows" >&2
[ "$rows" -gt 7 ]
