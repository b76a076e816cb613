"""The build step behind pyproject.toml: configures and builds the Python module and the
`slidespec` executable with the project's CMake, then lets setuptools pack the package
(docs/python.md, "Getting it"). Nothing is downloaded.

SLIDESPEC_BUILD_DIR  the CMake build directory (default build-pip); one already configured
                     is only built, keeping its options (e.g. build, tools/setup.sh's)
SLIDESPEC_CMAKE_ARGS extra options for a first configure, e.g. -DSLIDESPEC_WERROR=ON
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

root = Path(__file__).resolve().parent
build_dir = root / os.environ.get("SLIDESPEC_BUILD_DIR", "build-pip")


def version():
    text = (root / "CMakeLists.txt").read_text()
    return re.search(r"project\(\s*slidespec\s+VERSION\s+([0-9][0-9.]*)", text).group(1)


def cmake_build():
    if not (build_dir / "CMakeCache.txt").exists():
        # The wheel needs neither the tests nor the benchmarks; the module is built for the
        # interpreter running pip. ccache, when present, makes a rebuild cheap.
        args = ["-DCMAKE_BUILD_TYPE=Release", "-DSLIDESPEC_BUILD_TESTS=OFF", "-DSLIDESPEC_BUILD_BENCHMARKS=OFF",
                "-DSLIDESPEC_BUILD_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja"):
            args += ["-G", "Ninja"]
        if shutil.which("ccache"):
            args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        args += shlex.split(os.environ.get("SLIDESPEC_CMAKE_ARGS", ""))
        subprocess.check_call(["cmake", "-S", str(root), "-B", str(build_dir), *args])
    jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
    subprocess.check_call(["cmake", "--build", str(build_dir), "-j", jobs, "--target", "slidespec", "slidespec_python"])


class BuildWithCMake(build_py):
    """build_py after CMake: the package as CMake lays it out in BUILD/python/slidespec, and in
    a wheel the executable beside it with the plotting tool where the executable looks for it
    (slidespec/bin/slidespec -> slidespec/share/slidespec/plot_*.py, src/cli/plot.cpp).
    An editable install imports BUILD/python directly and runs BUILD/slidespec."""

    def run(self):
        cmake_build()
        super().run()
        if not self.editable_mode:
            package = Path(self.build_lib) / "slidespec"
            (package / "bin").mkdir(parents=True, exist_ok=True)
            (package / "share" / "slidespec").mkdir(parents=True, exist_ok=True)
            shutil.copy2(build_dir / "slidespec", package / "bin" / "slidespec")
            for tool in ("plot_spectra.py", "plot_server.py", "plot_drives.py", "slidespec_tsv.py",
                         "parameter_symbols.tsv"):
                shutil.copy2(root / "tools" / tool, package / "share" / "slidespec" / tool)


# CMake fills the package directory; setuptools' metadata step, before any build, wants it
# to exist.
(build_dir / "python" / "slidespec").mkdir(parents=True, exist_ok=True)


class BinaryDistribution(Distribution):
    """The package holds a compiled module: a wheel for this platform and Python."""

    def has_ext_modules(self):
        return True


setup(
    version=version(),
    packages=["slidespec"],
    package_dir={"": os.path.relpath(build_dir / "python", root)},
    package_data={"slidespec": ["_core*.so"]},
    include_package_data=False,
    cmdclass={"build_py": BuildWithCMake},
    distclass=BinaryDistribution,
    options={"build": {"build_base": str(build_dir / "setuptools")}, "egg_info": {"egg_base": str(build_dir)}},
)
