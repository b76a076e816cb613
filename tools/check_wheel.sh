#!/usr/bin/env bash
# The pip path end to end (docs/python.md, "Getting it"), as CI runs it: clones the
# repository's committed HEAD into a scratch directory, builds the wheel there with pip
# (offline, no build isolation, no compiler cache: what a fresh machine sees), installs it
# into a fresh venv (--system-site-packages: Debian's numpy and matplotlib), checks the module
# against the `slidespec` command the wheel puts on PATH, `python -m slidespec` and the build's
# executable bit for bit, draws a run's table with the wheel's plotting tool, and uninstalls,
# leaving the venv as it was. Usage: tools/check_wheel.sh [EXECUTABLE]
# (EXECUTABLE: a further slidespec to agree with; default build/slidespec when it exists)
set -euo pipefail
cd "$(dirname "$0")/.."
reference=${1:-$PWD/build/slidespec}
[ -x "$reference" ] || reference=""
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
started=$SECONDS

git clone -q "$PWD" "$scratch/src"
/usr/bin/python3 -m venv --system-site-packages "$scratch/venv"
venv=$scratch/venv
find "$venv" -not -name '*.pyc' -not -name __pycache__ | sort > "$scratch/before"

building=$SECONDS
(cd "$scratch/src" && CCACHE_DISABLE=1 "$venv/bin/pip" wheel -q --no-cache-dir --no-build-isolation --no-deps \
  --no-index -w "$scratch/wheels" .)
built=$SECONDS
# Gone, so that the executable can only find the plotting tool the wheel carries.
rm -rf "$scratch/src"
wheel=$(echo "$scratch"/wheels/slidespec-*.whl)
[ -f "$wheel" ] || { echo "check_wheel: pip wheel made no wheel" >&2; exit 1; }
echo "check_wheel: $(basename "$wheel"), $(du -k "$wheel" | cut -f1) kB, built in $((built - building)) s" >&2

# --no-index without --no-deps: the declared dependencies must be met by what is installed.
"$venv/bin/pip" install -q --no-cache-dir --no-index "$wheel"
[ -x "$venv/bin/slidespec" ] || { echo "check_wheel: no slidespec on the venv's PATH" >&2; exit 1; }
(cd "$scratch" && PATH="$venv/bin:$PATH" "$venv/bin/python" - "$venv" "$reference" <<'PYTHON'
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import slidespec as ss

venv, reference = Path(sys.argv[1]), sys.argv[2]
assert Path(ss.__file__).resolve().is_relative_to(venv.resolve()), f"imported {ss.__file__}, not the venv's"

commands = {"slidespec on PATH": ["slidespec"], "python -m slidespec": [sys.executable, "-m", "slidespec"]}
if reference:
    commands["the build's executable"] = [reference]
overrides = {"alpha": 0.4, "N": 12}
sets = [arg for key, value in overrides.items() for arg in ("--set", f"{key}={value}")]
p = ss.Parameters("reference", **overrides)
omega = ss.omegas(1, 1e3, 8)
theory = ss.theory(p, omega)
run = ss.run(p, omega_min=1, omega_max=1e3, precision=0.08, seed=3, threads=1)
assert run.complete and len(run) == 25


def same_bits(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


for name, command in commands.items():
    version = subprocess.run([*command, "--version"], capture_output=True, text=True, check=True).stdout
    assert ss.__version__ in version, (name, version)
    printed = subprocess.run([*command, "theory", "--case", "reference", *sets, "--omega-min", "1",
                              "--omega-max", "1e3"], capture_output=True, text=True, check=True).stdout
    rows = [line.split("\t") for line in printed.splitlines() if line and not line.startswith("#")]
    assert same_bits([float(r[0]) for r in rows], omega), name
    assert same_bits([float(r[1]) for r in rows], theory), name
    # Two threads against the module's one: the numbers do not depend on it. The run draws
    # its figure itself (cairo); `plot` draws it with the plotting tool the wheel carries.
    out = Path(name.replace(" ", "_").replace("'", ""))
    subprocess.run([*command, "run", "--case", "reference", *sets, "--omega-min", "1", "--omega-max", "1e3",
                    "--precision", "0.08", "--seed", "3", "--threads", "2", "--out", str(out), "--quiet"],
                   check=True, env=dict(os.environ, SLIDESPEC_TOOLS=""))
    points = json.loads(out.with_suffix(".json").read_text())["points"]
    for column in ("omega", "C_x", "stderr", "theory"):
        assert same_bits(getattr(run, column), [q[column] for q in points]), (name, column)
    assert out.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    drawn = out.with_name(out.name + "_matplotlib.png")
    subprocess.run([*command, "plot", str(out.with_suffix(".tsv")), "-o", str(drawn)], check=True,
                   env=dict(os.environ, SLIDESPEC_TOOLS=""))
    assert drawn.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    print(f"check_wheel: {name} agrees with the module bit for bit, and drew its figure", file=sys.stderr)
PYTHON
)

"$venv/bin/pip" uninstall -q -y slidespec
find "$venv" -not -name '*.pyc' -not -name __pycache__ | sort > "$scratch/after"
if ! diff "$scratch/before" "$scratch/after" >&2; then
  echo "check_wheel: the uninstall left the files above (> added, < removed)" >&2
  exit 1
fi
echo "check_wheel: installed, agreed and uninstalled cleanly in $((SECONDS - started)) s" >&2
