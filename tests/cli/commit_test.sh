#!/usr/bin/env bash
# Commit, then forget: a finished run survives whatever happens while its outputs are
# written. A plotter that dies, or slidespec itself killed (SIGKILL) while drawing, leaves
# the run's state; the command slidespec prints then writes outputs identical to an
# undisturbed run's. A second writer on the same output prefix is refused while the first
# holds it.
source "$(dirname "$0")/common.sh"
cd "$work" || exit 1

# A run to a precision (a fixed-count run is a part of a run, whose resumed state stays for merge).
band="--omega-min 100 --omega-max 1000 --precision 0.2 --seed 3"
"$bin" run $band --out reference --quiet || fail "the undisturbed run failed"

# A plotter that is killed (by the OOM killer, say) as it draws.
cat > dying_plotter.sh << 'EOF'
#!/bin/sh
kill -9 $$
EOF
# A plotter that draws slowly: once handed its work (it starts with the run and reads its
# arguments at the run's end), it says so (its pid) and waits: as the sleep itself (exec),
# so that killing that pid leaves nothing holding the test's output open for a minute.
cat > slow_plotter.sh << 'EOF'
#!/bin/sh
cat > /dev/null
echo $$ > plotting
exec sleep 60
EOF
chmod +x dying_plotter.sh slow_plotter.sh

same_as_reference() {  # PREFIX: its table is the undisturbed run's, its JSON and figure there
  cmp -s "$1.tsv" reference.tsv || fail "$2: $1.tsv differs from the undisturbed run's table"
  [ -s "$1.json" ] && [ -s "$1.png" ] || fail "$2: $1.json or $1.png missing"
}

# 1. The plotter dies: no output of the set appears, the state stays, exit status 1, and
# the printed command finishes the job.
SLIDESPEC_PYTHON=$work/dying_plotter.sh "$bin" run $band --out killed --quiet 2> err
status=$?
[ $status -eq 1 ] || fail "killed plotter: exit status $status, expected 1: $(cat err)"
[ -s killed.state ] || fail "killed plotter: the finished run's state is gone"
ls killed.tsv killed.json killed.png > /dev/null 2>&1 && fail "killed plotter: a part of the output set appeared"
finish=$(sed -n 's/.*write its outputs with: slidespec //p' err)
[ -n "$finish" ] || fail "killed plotter: no command to finish the job: $(cat err)"
"$bin" $finish --quiet || fail "killed plotter: '$finish' failed"
same_as_reference killed "killed plotter"
[ -e killed.state ] && fail "killed plotter: the state stayed after the outputs were written"

# 2. slidespec itself killed (SIGKILL) while it draws: the state is already on disk.
export SLIDESPEC_PYTHON=$work/slow_plotter.sh
start_in_background run $band --out cut --quiet
unset SLIDESPEC_PYTHON
for _ in $(seq 400); do [ -s plotting ] && break; sleep 0.05; done
[ -s plotting ] || fail "SIGKILL: the slow plotter never started"
# 3. Meanwhile a second writer on the same prefix is refused, and changes nothing.
"$bin" run $band --out cut --quiet 2> err2
status=$?
[ $status -eq 2 ] || fail "second writer: exit status $status, expected 2"
grep -q "another slidespec is writing" err2 || fail "second writer: no clear message: $(cat err2)"
kill -9 "$pid"
wait "$pid" 2> /dev/null
kill "$(cat plotting)" 2> /dev/null
[ -s cut.state ] || fail "SIGKILL while drawing: the finished run's state is gone"
"$bin" run --resume cut --quiet || fail "SIGKILL while drawing: the resume failed"
same_as_reference cut "SIGKILL while drawing"
[ -e cut.state ] || [ -e cut.lock ] && fail "SIGKILL while drawing: state or lock left after the resume"

[ $failures -eq 0 ] && echo "commit: a killed plotter, a SIGKILL while drawing and a second writer lost no run"
exit $((failures > 0))
