"""`python -m slidespec ARGS` and the `slidespec` command a pip install puts on PATH: the
project's executable with ARGS (docs/python.md, "Getting it")."""

import importlib.util
import os
import sys
from pathlib import Path


def executable():
    """The `slidespec` executable: in the wheel beside the package (slidespec/bin), in a build
    tree two levels up (BUILD/python/slidespec -> BUILD/slidespec), installed by cmake
    --install in PREFIX/bin."""
    package = Path(__file__).resolve().parent
    for candidate in (package / "bin" / "slidespec", package.parent.parent / "slidespec",
                      package.parents[3] / "bin" / "slidespec"):
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return str(candidate)
    sys.exit(f"slidespec: no slidespec executable beside the Python module in {package}")


def main():
    # The figures are drawn by this interpreter when it has matplotlib (a venv's or conda's
    # python, where the package was installed), else by the executable's default
    # (/usr/bin/python3). SLIDESPEC_PYTHON set by the user wins.
    if not os.environ.get("SLIDESPEC_PYTHON") and importlib.util.find_spec("matplotlib") is not None:
        os.environ["SLIDESPEC_PYTHON"] = sys.executable
    program = executable()
    os.execv(program, [program, *sys.argv[1:]])


if __name__ == "__main__":
    main()
