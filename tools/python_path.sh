#!/usr/bin/env bash
# Points /usr/bin/python3 at one checkout's built module: a one-line slidespec.pth in SITE
# naming BUILD_PYTHON (tools/setup.sh calls it). A slidespec.pth naming another checkout's
# build that still exists is left as it is, so the system interpreter does not follow
# whichever clone ran setup last (nor break once a temporary clone is deleted); one naming
# a build that is gone is replaced. SLIDESPEC_PTH=replace points it here regardless.
# Usage: tools/python_path.sh BUILD_PYTHON SITE
set -euo pipefail
line=$1
site=$2
pth="$site/slidespec.pth"
current=$(cat "$pth" 2> /dev/null || true)
[ "$current" = "$line" ] && exit 0
if [ -n "$current" ] && [ -d "$current/slidespec" ] && [ "${SLIDESPEC_PTH:-}" != replace ]; then
  echo "setup: /usr/bin/python3 keeps importing slidespec from $current (via $pth), another checkout;" \
    "SLIDESPEC_PTH=replace tools/setup.sh points it at $line" >&2
  exit 0
fi
mkdir -p "$site"
# Written beside it and renamed: a reader never sees a half-written file.
temporary=$(mktemp "$pth.XXXXXX")
echo "$line" > "$temporary"
chmod 644 "$temporary"
mv "$temporary" "$pth"
echo "setup: /usr/bin/python3 imports slidespec from $line (via $pth)" >&2
