# Shared by the command-line tests (sourced): a scratch directory, failure counting, and
# the check every refusal must pass.
set -u
bin=${SLIDESPEC:?set SLIDESPEC to the slidespec executable}
work=$(mktemp -d)
# Only this shell removes it: a forked subshell (a background job not yet exec'ed when a
# signal lands) inherits the trap too.
owner=$BASHPID
# The figure's scratch directories (/tmp/slidespec-plot-*) go to a directory of the test's
# own, where its end finds any a command left behind, ended by a signal or not.
TMPDIR=$(mktemp -d)
export TMPDIR
scratch_left() {
  local left
  left=$(ls -d "$TMPDIR"/slidespec-plot-* 2> /dev/null) || return 1
  echo "FAIL: scratch directories left behind: $left: $(ls -A $left)"
}
trap '[ "$BASHPID" = "$owner" ] && { left=0; scratch_left && left=1; rm -rf "$work" "$TMPDIR"; [ $left -eq 0 ] || exit 1; }' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_refused NAME WORD ARGS...: exit 2, one line on stderr naming WORD, and no output
# file $work/out.* touched.
expect_refused() {
  local name=$1 word=$2; shift 2
  for ext in tsv json png csv state; do echo "sentinel" > "$work/out.$ext"; done
  "$bin" "$@" > "$work/stdout" 2> "$work/stderr"
  local status=$?
  [ $status -eq 2 ] || fail "$name: exit status $status, expected 2"
  [ "$(wc -l < "$work/stderr")" -eq 1 ] || fail "$name: stderr is not one line: $(cat "$work/stderr")"
  grep -q -- "$word" "$work/stderr" || fail "$name: stderr does not name '$word': $(cat "$work/stderr")"
  for ext in tsv json png csv state; do
    [ "$(cat "$work/out.$ext")" = "sentinel" ] || fail "$name: output file out.$ext was touched"
  done
}

# start_in_background ARGS...: runs slidespec in the background, pid in $pid.
start_in_background() {
  ( exec "$bin" "$@" ) &
  pid=$!
}

# interrupt_once_written FILE: waits (a minute at most) for FILE to hold something, then
# interrupts the background command $pid and waits for it; its exit status in $status.
interrupt_once_written() {
  for _ in $(seq 600); do [ -s "$1" ] && break; sleep 0.1; done
  kill -INT "$pid"
  wait "$pid"
  status=$?
}
