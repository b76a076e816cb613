#!/usr/bin/python3
"""tools/plot_correction.py on a real run: a PNG from its correction columns; a table without
them, or an output that would replace an input, refused with exit 2 and nothing written."""

import os
import subprocess
import sys
import tempfile

TOOL = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "plot_correction.py")
CLI = os.environ["SLIDESPEC"]


def tool(*args):
    return subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)


with tempfile.TemporaryDirectory() as work:
    run = os.path.join(work, "run")
    subprocess.run([CLI, "run", "--omega-min", "0.2", "--omega-max", "2", "--realizations", "16", "--out", run,
                    "--no-plot", "--quiet"], check=True)
    out = os.path.join(work, "c.png")
    done = tool(run + ".tsv", out)
    assert done.returncode == 0, done.stderr
    with open(out, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    theory = os.path.join(work, "theory")
    subprocess.run([CLI, "theory", "--out", theory], check=True, capture_output=True)
    bad = os.path.join(work, "bad.png")
    done = tool(theory + ".tsv", bad)
    assert done.returncode == 2 and "correction" in done.stderr and not os.path.exists(bad), done.stderr
    before = open(run + ".tsv").read()
    done = tool(run + ".tsv", run + ".tsv")
    assert done.returncode == 2 and open(run + ".tsv").read() == before, done.stderr
print("plot_correction: ok")
