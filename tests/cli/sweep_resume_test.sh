#!/usr/bin/env bash
# An interrupted sweep continues: `sweep ... --resume` takes its finished runs from their
# outputs, its cut run from its state, runs the rest, and writes the combined table, JSON
# and figure bitwise as the uninterrupted sweep does, whether the signal landed in its first,
# a middle or its last run, between two runs, or in the continuation itself. Continuing
# another sweep, or nothing, is refused before any work.
source "$(dirname "$0")/common.sh"
cd "$work" || exit 1

# Three runs of 0.3, 0.4 and 0.6 s on two idle cores (more when busy): a signal sent 0.05 s
# after a run starts lands inside it.
grid="alpha=0.5,0.7,1"
options="--omega-min 10 --omega-max 1000 --precision 0.003 --seed 3"
mkdir whole
(cd whole && "$bin" sweep $grid $options --out sw --quiet) || fail "the uninterrupted sweep"

# same_as_whole DIR NAME [--figure]: every output of the sweep in DIR is the uninterrupted
# one's, bit for bit; a run's JSON but for how it ran (its wall time, throughput, threads).
same_as_whole() {
  local dir=$1 name=$2
  for file in sw.tsv sw.json sw_alpha=0.5.tsv sw_alpha=0.7.tsv sw_alpha=1.tsv; do
    cmp -s "$dir/$file" "whole/$file" || fail "$name: $file differs from the uninterrupted sweep's"
  done
  for a in 0.5 0.7 1; do
    cmp -s <(grep -v '"wall_seconds"\|"throughput_\|"threads"' "$dir/sw_alpha=$a.json") \
      <(grep -v '"wall_seconds"\|"throughput_\|"threads"' "whole/sw_alpha=$a.json") \
      || fail "$name: sw_alpha=$a.json differs from the uninterrupted sweep's"
  done
  if [ "${3:-}" = --figure ]; then cmp -s "$dir/sw.png" whole/sw.png || fail "$name: sw.png differs"; fi
  for left in "$dir"/*.state "$dir"/sw.sweep "$dir"/*.lock; do [ -e "$left" ] && fail "$name: left $left"; done
}

# cut_in RUN SIGNAL DIR [ARGS...]: starts the sweep in DIR and sends SIGNAL 0.05 s after run RUN
# of 3 starts ("sweep RUN/3" on stderr); its exit status in $status, its stderr in DIR/err.
cut_in() {
  local run=$1 signal=$2 dir=$3
  shift 3
  mkdir -p "$dir"
  (cd "$dir" && exec "$bin" sweep $grid $options --out sw --no-plot "$@" 2> err) &
  local pid=$!
  for _ in $(seq 600); do grep -q "sweep $run/3" "$dir/err" 2> /dev/null && break; sleep 0.02; done
  sleep 0.05
  kill -s "$signal" $pid
  wait $pid
  status=$?
}

# --- Cut in the first run: nothing finished, the cut run continues from its state.
cut_in 1 INT first
[ $status -eq 130 ] || fail "cut in the first run: exit status $status, expected 130"
[ -s "first/sw_alpha=0.5.state" ] || fail "cut in the first run: no state of it: $(cat first/err)"
[ -s first/sw.sweep ] || fail "cut in the first run: no sw.sweep"
(cd first && "$bin" sweep $grid $options --out sw --resume 2> err)
status=$?
[ $status -eq 0 ] || fail "the sweep cut in its first run, continued: exit status $status: $(cat first/err)"
grep -q "sweep 1/3: alpha=0.5: continued from sw_alpha=0.5.state" first/err || fail "first: no word of the continued run"
same_as_whole first "cut in the first run" --figure

# --- Cut in the middle, continued on one thread (the same numbers whatever the threads).
cut_in 2 INT middle
[ $status -eq 130 ] || fail "cut in the middle: exit status $status, expected 130"
[ -s "middle/sw_alpha=0.7.state" ] || fail "cut in the middle: no state of run 2"
before=$(stat -c %i "middle/sw_alpha=0.5.json")
(cd middle && "$bin" sweep $grid $options --out sw --no-plot --resume --threads 1 2> err)
status=$?
[ $status -eq 0 ] || fail "the sweep cut in the middle, continued: exit status $status: $(cat middle/err)"
grep -q "1 of 3 runs reused from their outputs, 1 continued from their state, 1 to run" middle/err \
  || fail "middle: no account of what is reused: $(cat middle/err)"
grep -q "sweep 1/3: alpha=0.5: reused sw_alpha=0.5.tsv" middle/err || fail "middle: the reused run is not named"
[ "$(stat -c %i "middle/sw_alpha=0.5.json")" = "$before" ] || fail "middle: the finished run was written again"
grep -q '"threads": 1' "middle/sw_alpha=1.json" || fail "middle: --threads 1 not used"
same_as_whole middle "cut in the middle"

# --- Cut in the last run by SIGTERM.
cut_in 3 TERM last
[ $status -eq 143 ] || fail "cut in the last run: exit status $status, expected 143"
(cd last && "$bin" sweep $grid $options --out sw --no-plot --resume 2> err) \
  || fail "the sweep cut in its last run, continued: $(cat last/err)"
grep -q "2 of 3 runs reused" last/err || fail "last: the two finished runs were not reused: $(cat last/err)"
same_as_whole last "cut in the last run"

# --- Cut between two runs (held there by SLIDESPEC_SWEEP_STALL): the next run has not begun.
mkdir between
(cd between && SLIDESPEC_SWEEP_STALL=$work/between/stalled exec "$bin" sweep $grid $options --out sw --no-plot \
  2> err) &
pid=$!
for _ in $(seq 600); do [ -s between/stalled ] && break; sleep 0.05; done
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "cut between runs: exit status $status, expected 130"
ls between/sw_alpha=0.7.* > /dev/null 2>&1 && fail "cut between runs: run 2 began: $(ls between/sw_alpha=0.7.*)"
[ -s between/sw_alpha=0.5.tsv ] || fail "cut between runs: run 1 was not written"
(cd between && "$bin" sweep $grid $options --out sw --no-plot --resume 2> err) \
  || fail "the sweep cut between runs, continued: $(cat between/err)"
same_as_whole between "cut between runs"

# --- Cut while the combined figure is drawn (a plotter that never finishes): all runs are
# done, but not the sweep; the continuation reuses every run and draws the figure.
mkdir figure
printf '#!/bin/sh\necho $$ > "%s/plotter.pid"\nexec sleep 60\n' "$work/figure" > figure/slow_plotter
chmod +x figure/slow_plotter
(cd figure && SLIDESPEC_PYTHON=$work/figure/slow_plotter exec "$bin" sweep $grid $options --out sw 2> err) &
pid=$!
# The plotter starts with the sweep; the figure is drawn once the last run is written.
for _ in $(seq 600); do grep -q "wrote sw_alpha=1.tsv" figure/err 2> /dev/null && break; sleep 0.05; done
sleep 0.2
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "cut while the figure is drawn: exit status $status, expected 130: $(cat figure/err)"
[ -e figure/sw.png ] && fail "cut while the figure is drawn: a figure was written"
(cd figure && "$bin" sweep $grid $options --out sw --resume 2> err) || fail "cut in the figure, continued: $(cat figure/err)"
grep -q "3 of 3 runs reused" figure/err || fail "cut in the figure: the runs were not all reused: $(cat figure/err)"
same_as_whole figure "cut while the figure is drawn" --figure

# --- The continuation cut in its turn keeps what it finished, and continues again.
cut_in 2 INT twice
(cd twice && exec "$bin" sweep $grid $options --out sw --no-plot --resume 2> err) &
pid=$!
for _ in $(seq 600); do grep -q "sweep 3/3" twice/err && break; sleep 0.02; done
sleep 0.05
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "a continuation cut again: exit status $status, expected 130"
cmp -s twice/sw_alpha=0.7.tsv whole/sw_alpha=0.7.tsv || fail "a continuation cut again: its finished run is not kept"
[ -s twice/sw.sweep ] && [ -s "twice/sw_alpha=1.state" ] || fail "a continuation cut again: record or state gone"
(cd twice && "$bin" sweep $grid $options --out sw --no-plot --resume 2> err) \
  || fail "the twice-cut sweep, continued: $(cat twice/err)"
grep -q "2 of 3 runs reused from their outputs, 1 continued" twice/err || fail "twice: $(cat twice/err)"
same_as_whole twice "cut twice"

# --- Refusals, before any work and touching nothing: another sweep than the one cut,
# nothing to continue, a fresh sweep over a cut one, a finished run's outputs of another run.
cut_in 2 INT refused
cd refused || exit 1
rm -f err
snapshot=$(sha256sum *)
refused() {  # NAME WORD ARGS...
  local name=$1 word=$2
  shift 2
  expect_refused "$name" "$word" sweep "$@"
  [ "$(sha256sum *)" = "$snapshot" ] || fail "$name: files changed"
}
refused "other values" "sw.sweep holds another sweep (the grid: alpha=0.5,0.7,1 there, alpha=0.5,0.7,2 here" alpha=0.5,0.7,2 $options --out sw --resume
refused "another case" "sw.sweep holds another sweep (--case: reference there, weak-noise here)" $grid $options --case weak-noise --out sw --resume
refused "another seed" "sw.sweep holds another sweep (--seed: 3 there, 4 here)" $grid ${options% --seed 3} --seed 4 --out sw --resume
refused "another precision" "sw.sweep holds another sweep (--precision: 0.003 there, 0.01 here)" $grid --omega-min 10 --omega-max 1000 --precision 0.01 \
  --seed 3 --out sw --resume
refused "another band" "sw.sweep holds another sweep (--omega-min: 10 there, 20 here)" $grid --omega-min 20 \
  --omega-max 1000 --precision 0.003 --seed 3 --out sw --resume
refused "another parameter" "sw.sweep holds another sweep (run alpha=0.5: parameter N: 30 there, 12 here)" $grid $options --set N=12 --out sw --resume
refused "nothing to continue" "nothing to continue: no other.sweep" $grid $options --out other --resume
refused "a fresh sweep over a cut one" "sw.sweep holds a sweep not yet written whole" $grid $options --out sw
# A finished run's outputs replaced by those of another seed: refused, naming the run.
mkdir ../elsewhere
(cd ../elsewhere && "$bin" run --set alpha=0.5 ${options% --seed 3} --seed 4 --out "sw_alpha=0.5" --no-plot --quiet)
cp "../elsewhere/sw_alpha=0.5.tsv" "../elsewhere/sw_alpha=0.5.json" .
snapshot=$(sha256sum *)
refused "a run's outputs of another seed" "run alpha=0.5: sw_alpha=0.5.json is of another run (--seed: 4 there, 3 here)" \
  $grid $options --out sw --resume
# Outputs of this run that do not agree (a table changed since) are not reused: run again.
cp "../whole/sw_alpha=0.5.tsv" "../whole/sw_alpha=0.5.json" .
sed -i 's/^# seed = 3/# seed = 3 /' "sw_alpha=0.5.tsv"
"$bin" sweep $grid $options --out sw --no-plot --resume 2> err || fail "a changed table: $(cat err)"
grep -q "alpha=0.5: run again: its table and JSON do not agree" err || fail "a changed table was not run again: $(cat err)"
cd .. || exit 1
same_as_whole refused "a changed table run again"

[ $failures -eq 0 ] && echo "sweep --resume: cut in the first, a middle and the last run, between runs and twice:" \
  "bitwise the uninterrupted sweep; other sweeps and nothing refused"
exit $((failures > 0))
