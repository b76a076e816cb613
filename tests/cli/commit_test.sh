#!/usr/bin/env bash
# Commit, then forget: a finished run survives whatever happens while its outputs are
# written. A figure that cannot be drawn (out of memory), or slidespec itself killed
# (SIGKILL) while drawing, leaves the run's state; the command slidespec prints then writes outputs identical to an
# undisturbed run's. A second writer on the same output prefix is refused while the first
# holds it.
source "$(dirname "$0")/common.sh"
cd "$work" || exit 1

# A run to a precision (a fixed-count run is a part of a run, whose resumed state stays for merge).
band="--omega-min 100 --omega-max 1000 --precision 0.2 --seed 3"
"$bin" run $band --out reference --quiet || fail "the undisturbed run failed"

same_as_reference() {  # PREFIX: its table is the undisturbed run's, its JSON and figure there
  cmp -s "$1.tsv" reference.tsv || fail "$2: $1.tsv differs from the undisturbed run's table"
  [ -s "$1.json" ] && [ -s "$1.png" ] || fail "$2: $1.json or $1.png missing"
}

# 1. The figure cannot be drawn: a 24000-pixel-square PNG (2.3 GB) beyond the memory
# allowed. No output of the set appears, the state stays, exit status 1, and the printed
# command finishes the job.
# Under AddressSanitizer (whose shadow memory needs more address space than the limit
# leaves) the allocator's own limit refuses the same allocation.
if [ "${SLIDESPEC_SANITIZED:-OFF}" = ON ]; then
  ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}allocator_may_return_null=1:max_allocation_size_mb=1500" \
    "$bin" run $band --out killed --quiet --dpi 2400 --size 10x10 2> err
else
  (ulimit -v 1500000 && exec "$bin" run $band --out killed --quiet --dpi 2400 --size 10x10) 2> err
fi
status=$?
[ $status -eq 1 ] || fail "figure out of memory: exit status $status, expected 1: $(cat err)"
grep -q "killed.png not drawn" err || fail "figure out of memory: no message naming the figure: $(cat err)"
[ -s killed.state ] || fail "figure out of memory: the finished run's state is gone"
ls killed.tsv killed.json killed.png > /dev/null 2>&1 && fail "figure out of memory: a part of the output set appeared"
finish=$(sed -n 's/.*write its outputs with: slidespec //p' err)
[ -n "$finish" ] || fail "figure out of memory: no command to finish the job: $(cat err)"
"$bin" $finish --quiet || fail "figure out of memory: '$finish' failed"
same_as_reference killed "figure out of memory"
[ -e killed.state ] && fail "figure out of memory: the state stayed after the outputs were written"

# 2. slidespec itself killed (SIGKILL) while it draws: the state is already on disk. The
# figure stalls there (SLIDESPEC_FIGURE_STALL), so the kill lands while it draws.
export SLIDESPEC_FIGURE_STALL=$work/plotting
start_in_background run $band --out cut --quiet
unset SLIDESPEC_FIGURE_STALL
for _ in $(seq 400); do [ -s plotting ] && break; sleep 0.05; done
[ -s plotting ] || fail "SIGKILL: the figure never started"
# 3. Meanwhile a second writer on the same prefix is refused, and changes nothing.
"$bin" run $band --out cut --quiet 2> err2
status=$?
[ $status -eq 2 ] || fail "second writer: exit status $status, expected 2"
grep -q "another slidespec is writing" err2 || fail "second writer: no clear message: $(cat err2)"
kill -9 "$pid"
wait "$pid" 2> /dev/null
[ -s cut.state ] || fail "SIGKILL while drawing: the finished run's state is gone"
"$bin" run --resume cut --quiet || fail "SIGKILL while drawing: the resume failed"
same_as_reference cut "SIGKILL while drawing"
[ -e cut.state ] || [ -e cut.lock ] && fail "SIGKILL while drawing: state or lock left after the resume"

[ $failures -eq 0 ] && echo "commit: a figure out of memory, a SIGKILL while drawing and a second writer lost no run"
exit $((failures > 0))
