#!/usr/bin/env bash
# tools/python_path.sh, on a scratch site directory: the first checkout's slidespec.pth
# stays while its build exists, whichever clone runs setup after it; a deleted clone's is
# replaced; SLIDESPEC_PTH=replace re-points it.
set -u
script="$(dirname "$0")/../../tools/python_path.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
mkdir -p "$work/first/python/slidespec" "$work/second/python/slidespec"
site="$work/site"
bash "$script" "$work/first/python" "$site" 2> /dev/null
[ "$(cat "$site/slidespec.pth")" = "$work/first/python" ] || fail "no slidespec.pth written"
[ "$(stat -c %a "$site/slidespec.pth")" = 644 ] || fail "slidespec.pth is not readable by every user"
bash "$script" "$work/second/python" "$site" 2> "$work/err"
[ "$(cat "$site/slidespec.pth")" = "$work/first/python" ] || fail "a second clone re-pointed slidespec.pth"
grep -q "keeps importing slidespec from $work/first/python" "$work/err" || fail "no note: $(cat "$work/err")"
SLIDESPEC_PTH=replace bash "$script" "$work/second/python" "$site" 2> /dev/null
[ "$(cat "$site/slidespec.pth")" = "$work/second/python" ] || fail "SLIDESPEC_PTH=replace did not re-point it"
rm -rf "$work/second"
bash "$script" "$work/first/python" "$site" 2> /dev/null
[ "$(cat "$site/slidespec.pth")" = "$work/first/python" ] || fail "a deleted clone's slidespec.pth stayed"
[ "$(ls "$site")" = slidespec.pth ] || fail "temporaries left in the site directory: $(ls "$site")"
[ $failures -eq 0 ] && echo "python_path: one checkout's slidespec.pth, not the last clone's"
exit $((failures > 0))
