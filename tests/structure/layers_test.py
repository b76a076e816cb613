#!/usr/bin/env python3
"""No include runs from a lower layer to a higher one (README.md, "Layout"):
util < model < simd < stepper, estimator < theory < run < io < analysis < figure < cli, python.

A file's layer is its folder under src/ (or, for include/slidespec/NAME.hpp, the layer of
what it declares); every quoted #include must name a file of the same or a lower layer.
Usage: layers_test.py SOURCE_DIR. Exit status 1 naming every arrow that runs upward."""

import pathlib
import re
import sys

ORDER = [("util",), ("model",), ("simd",), ("stepper", "estimator"), ("theory",), ("run",), ("io",),
         ("analysis",), ("figure",), ("cli", "python")]
RANK = {room: rank for rank, rooms in enumerate(ORDER) for room in rooms}
# Public headers: the layer of the code that implements them.
PUBLIC = {"input_error": "util", "parameters": "model", "simd": "simd", "stepper": "stepper",
          "estimator": "estimator", "theory": "theory", "run": "run", "analysis": "analysis"}


def layer(path):
    parts = pathlib.PurePosixPath(path).parts
    if parts[0] == "slidespec":
        return PUBLIC[pathlib.PurePosixPath(parts[1]).stem]
    return parts[0]


def main(root):
    root = pathlib.Path(root)
    files = [(f, f.relative_to(root / "src").as_posix()) for f in (root / "src").rglob("*") if f.is_file()]
    files += [(f, "slidespec/" + f.name) for f in (root / "include" / "slidespec").iterdir()]
    files += [(f, "python/" + f.name) for f in (root / "python").glob("*.cpp")]
    upward, arrows = [], 0
    for file, name in files:
        if file.suffix not in (".cpp", ".hpp", ".inc", ".in", ".def"):
            continue
        here = layer(name)
        for target in re.findall(r'^#include "([^"]+)"', file.read_text(), re.MULTILINE):
            arrows += 1
            there = layer(target)
            if RANK[there] > RANK[here]:
                upward.append(f"{name} ({here}) includes {target} ({there})")
    for line in upward:
        print("upward:", line)
    print(f"{arrows} includes in {len(files)} files, {len(upward)} upward")
    return 1 if upward else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
