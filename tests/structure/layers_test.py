#!/usr/bin/env python3
"""No include runs from a lower layer to a higher one (README.md, "Layout"):
util < model < simd < stepper, estimator < theory < run < io < analysis < figure < cli, python.

A file's layer is its folder under src/ (or, for include/slidespec/NAME.hpp, the layer of
what it declares); every quoted #include must name a file of the same or a lower layer.
Besides, a measured record's analysis reaches nothing of a run, not even through the layers
between them (io): what both need, numbers as text, sits in util, below both. And the
theory reaches nothing of the stepper: the exact step both use is the model's mathematics.
Usage: layers_test.py SOURCE_DIR. Exit status 1 naming every arrow that runs upward and
every chain of includes between layers kept apart (APART)."""

import pathlib
import re
import sys

ORDER = [("util",), ("model",), ("simd",), ("stepper", "estimator"), ("theory",), ("run",), ("io",),
         ("analysis",), ("figure",), ("cli", "python")]
RANK = {room: rank for rank, rooms in enumerate(ORDER) for room in rooms}
# Public headers: the layer of the code that implements them.
PUBLIC = {"input_error": "util", "options": "util", "landmarks": "theory", "parameters": "model", "simd": "simd", "stepper": "stepper",
          "estimator": "estimator", "theory": "theory", "run": "run", "analysis": "analysis",
          "many_records": "analysis"}
# Layers one may not reach from the other by any chain of includes, though ranked apart.
APART = [("analysis", "run"), ("theory", "stepper")]


def layer(path):
    parts = pathlib.PurePosixPath(path).parts
    if parts[0] == "slidespec":
        return PUBLIC[pathlib.PurePosixPath(parts[1]).stem]
    return parts[0]


def chain_to(start, includes, unwanted):
    """The first chain of includes from `start` to a file of layer `unwanted`, or None."""
    seen, frontier = {start}, [[start]]
    while frontier:
        path = frontier.pop(0)
        for target in includes.get(path[-1], []):
            if target in seen or target not in includes:  # not ours: a generated file
                continue
            if layer(target) == unwanted:
                return path + [target]
            seen.add(target)
            frontier.append(path + [target])
    return None


def main(root):
    root = pathlib.Path(root)
    # util is the bottom layer: below analysis and run both.
    assert RANK["util"] < RANK["run"] and RANK["util"] < RANK["analysis"]
    files = [(f, f.relative_to(root / "src").as_posix()) for f in (root / "src").rglob("*") if f.is_file()]
    files += [(f, "slidespec/" + f.name) for f in (root / "include" / "slidespec").iterdir()]
    files += [(f, "python/" + f.name) for f in (root / "python").glob("*.cpp")]
    upward, arrows, includes = [], 0, {}
    for file, name in files:
        if file.suffix not in (".cpp", ".hpp", ".inc", ".in", ".def"):
            continue
        here = layer(name)
        includes[name] = re.findall(r'^#include "([^"]+)"', file.read_text(), re.MULTILINE)
        for target in includes[name]:
            arrows += 1
            there = layer(target)
            if RANK[there] > RANK[here]:
                upward.append(f"{name} ({here}) includes {target} ({there})")
    for line in upward:
        print("upward:", line)
    reached = []
    for lower, higher in APART:
        for name in sorted(includes):
            if layer(name) == lower and (chain := chain_to(name, includes, higher)):
                reached.append(f"{lower} reaches {higher}: " + " -> ".join(chain))
    for line in reached:
        print(line)
    print(f"{arrows} includes in {len(files)} files, {len(upward)} upward, "
          f"{len(reached)} between layers kept apart")
    return 1 if upward or reached else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
