#!/usr/bin/env bash
# Installs the Debian packages slidespec needs (only those missing), then configures and
# builds into build/. Idempotent: with everything in place it only runs an incremental build.
# Also makes the Python module importable by /usr/bin/python3; pip installs it elsewhere
# (docs/python.md).
# Extra CMake options: SLIDESPEC_CMAKE_ARGS="-DSLIDESPEC_BUILD_BENCHMARKS=OFF" tools/setup.sh
# The MPI build (OpenMPI, into build-mpi/, the executable only): SLIDESPEC_MPI=ON tools/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake ninja-build g++ pkg-config git
          libeigen3-dev libxsimd-dev libfftw3-dev librandom123-dev
          libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev zlib1g-dev
          libcairo2-dev fonts-dejavu-core  # run's and merge's figure (src/figure/)
          python3 python3-numpy python3-matplotlib
          python3-dev pybind11-dev python3-tqdm python3-pytest
          python3-venv python3-pip python3-setuptools python3-wheel
          python3-scipy)  # bench/welch_scipy.py: the Welch benchmark's reference
mpi=${SLIDESPEC_MPI:-OFF}
[ "$mpi" = "ON" ] && packages+=(libopenmpi-dev openmpi-bin)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" \
    || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

cmake_args=(-DCMAKE_BUILD_TYPE=Release)
build=build
targets=()
if [ "$mpi" = "ON" ]; then
  build=build-mpi
  cmake_args+=(-DSLIDESPEC_MPI=ON -DSLIDESPEC_BUILD_BENCHMARKS=OFF)
  targets=(--target slidespec)
fi
# CI holds the code to zero warnings.
[ "${CI:-}" = "true" ] && cmake_args+=(-DSLIDESPEC_WERROR=ON)
# shellcheck disable=SC2206
cmake_args+=(${SLIDESPEC_CMAKE_ARGS:-})
if [ ! -f "$build/build.ninja" ]; then
  cmake -S . -B "$build" -G Ninja "${cmake_args[@]}" >&2
else
  cmake -S . -B "$build" "${cmake_args[@]}" > /dev/null
fi
cmake --build "$build" -j"$(nproc)" "${targets[@]}" >&2

# import slidespec for /usr/bin/python3 from any directory: a slidespec.pth naming
# build/python in its site directory (the system's as root, else the user's), so a rebuild
# needs no reinstall; one naming another checkout that still exists stays (docs/python.md).
if [ "$mpi" != "ON" ] && [ -d "$build/python/slidespec" ]; then
  if [ "$(id -u)" -eq 0 ]; then
    site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
  else
    site=$(/usr/bin/python3 -m site --user-site)
  fi
  tools/python_path.sh "$PWD/$build/python" "$site"
fi
