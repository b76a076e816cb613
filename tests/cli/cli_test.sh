#!/usr/bin/env bash
# End-to-end checks of the command line: exit codes, one-line errors, files untouched.
source "$(dirname "$0")/common.sh"

out="--out $work/out"
expect_refused drive-below-friction F_drive theory $out --set F_drive=4
expect_refused no-miniblocks "parameter N" theory $out --set N=0
expect_refused negative-mass "parameter m" theory $out --set m=-1
expect_refused negative-spring k0 theory $out --set k0=-5
expect_refused zero-renewal-distance "parameter a" theory $out --set a=0
expect_refused negative-alpha alpha theory $out --set alpha=-1
expect_refused not-finite M theory $out --set M=inf
expect_refused unknown-key wobble theory $out --set wobble=1
expect_refused unknown-case slow theory $out --case slow
expect_refused malformed-override KEY=VALUE theory $out --set N30
expect_refused both-v-and-eta1 eta1 theory $out --set v=1e-3 --set eta1=1e7
expect_refused short-ring ring theory $out --set chain=ring --set N=2
expect_refused bad-omega-range omega theory $out --omega-min 10 --omega-max 1
expect_refused missing-directory "does not exist" theory --out "$work/nowhere/x"
expect_refused unknown-option "--bogus" theory --bogus
expect_refused level-mass "parameter m_2" theory $out --set levels=2 --set m_2=0
expect_refused level-below-lowest "parameter N_3" theory $out --set levels=2 --set N_3=4
expect_refused touching-level "parameter touching" theory $out --case hierarchical --set touching=3
expect_refused second-order-periodic "eps 0.25" theory $out --order 2 --set renewal=periodic --set alpha=4
expect_refused bad-order "order" theory $out --order 3
expect_refused stepper-levels "levels" run --out $work/levels4 --set levels=4 --work-budget 1e15 --no-plot --quiet

# A good run writes the table atomically and leaves no temporary file behind.
"$bin" theory --out "$work/ref" > /dev/null 2>&1 || fail "theory --out failed"
[ -f "$work/ref.tsv" ] || fail "theory --out wrote no PREFIX.tsv"
grep -q "^# beyond first order .*mean speed V = 0.000498[0-9]* m/s" "$work/ref.tsv" ||
  fail "theory: no long-time motion line (reference: V = 0.99721 v)"
"$bin" theory --order 2 --points 1 --omega-max 1 | grep -q "^# omega	C_x	C_eq1	C_x2$" ||
  fail "theory --order 2: no C_x2 column"
# C_x2 is the theory that theory_kind names: beyond the series' limit the quasi-static one,
# as a run's theory2 column holds it.
"$bin" theory --order 2 --set N=3 --set alpha=1.273 --omega 1 > "$work/qs.tsv" || fail "theory --order 2 at eps 0.3"
grep -q "^# theory_kind = quasi_static" "$work/qs.tsv" && grep -q "C_x2 \[m^2 s\] the quasi-static spectrum" "$work/qs.tsv" \
  || fail "theory --order 2 beyond the series' limit does not print the quasi-static spectrum it names"
grep -q "^# omega	C_x	C_eq1$" "$work/ref.tsv" || fail "theory table has no header line"
[ "$(grep -vc '^#' "$work/ref.tsv")" -eq 49 ] || fail "theory table does not have 49 rows"
ls "$work" | grep -q tmp && fail "a temporary file was left behind"
"$bin" cases | grep -q "^concrete-fit" || fail "cases does not list concrete-fit"

# The parameter file route gives the same as --set.
echo '{"alpha": 0.4, "chain": "ring"}' > "$work/p.json"
"$bin" theory --params "$work/p.json" > "$work/a.tsv" && "$bin" theory --set alpha=0.4 --set chain=ring > "$work/b.tsv" \
  && cmp -s "$work/a.tsv" "$work/b.tsv" || fail "--params differs from --set"

# slidespec run: refusals happen before any work and touch nothing.
expect_refused run-drive-below-friction F_drive run $out --set F_drive=1
expect_refused run-bad-precision precision run $out --precision 2
expect_refused run-bad-band omega run $out --omega-min 0
expect_refused run-bad-simd simd run $out --simd neon
expect_refused run-duration-and-precision "cannot be given together" run $out --duration 10 --precision 0.1
expect_refused run-missing-directory "does not exist" run --out "$work/nowhere/x"
expect_refused plot-missing-file "missing.tsv" plot "$work/missing.tsv" -o "$work/out.png"
expect_refused paper-unknown-figure fig9 paper fig9 --out-dir "$work"

# A short run writes its three files, marked complete, with a measured mean speed.
"$bin" run --omega-min 100 --omega-max 1000 --precision 0.2 --seed 3 --out "$work/short" 2> "$work/run.err" \
  || fail "short run failed: $(cat "$work/run.err")"
for ext in tsv json png; do [ -s "$work/short.$ext" ] || fail "short run wrote no .$ext"; done
grep -q "^# complete = true" "$work/short.tsv" || fail "short run not marked complete"
grep -q "^# omega	C_x	stderr	theory	n_avg	bandwidth	C_v	C_F" "$work/short.tsv" || fail "run table header"
grep -q '"simd_path"' "$work/short.json" || fail "run JSON has no simd_path"
grep -q "measured_mean_speed" "$work/short.tsv" || fail "run table has no measured mean speed"
ls "$work" | grep -q tmp && fail "a temporary file was left behind by run"

# Same seed, same table, whatever the thread count and SIMD path (metadata aside).
"$bin" run --omega-min 100 --omega-max 1000 --precision 0.2 --seed 3 --threads 1 --simd scalar \
  --out "$work/scalar" --no-plot --quiet || fail "scalar run failed"
diff <(grep -v '^#' "$work/short.tsv") <(grep -v '^#' "$work/scalar.tsv") > /dev/null \
  || fail "scalar 1-thread run differs from the default run"

# An interrupt writes what has accumulated, marked incomplete, and exits 128 + SIGINT.
start_in_background run --omega-min 0.1 --omega-max 1e5 --precision 0.003 --out "$work/cut" --no-plot --quiet
sleep 2
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "interrupted run exited $status, expected 130"
grep -q "^# complete = false" "$work/cut.tsv" 2>/dev/null || fail "interrupted run did not write an incomplete table"

# ... and saves the run, which --resume continues to the numbers of an uninterrupted run.
# Without the shadow: about half a second of rounds to interrupt (the Python test resumes one
# with it), and not minutes in the sanitizer build.
band="--case many-contacts --omega-min 1 --omega-max 1000 --precision 0.01 --control-variate off --seed 5 --no-plot --quiet"
"$bin" run $band --out "$work/whole" || fail "uninterrupted run failed"
start_in_background run $band --checkpoint-every 0.2 --out "$work/cut2"
# Interrupted once its first checkpoint exists: mid-run however fast the build.
for _ in $(seq 600); do [ -e "$work/cut2.state" ] && break; sleep 0.05; done
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "checkpointed run interrupted: exit $status, expected 130 (finished too soon?)"
[ -s "$work/cut2.state" ] || fail "interrupted run saved no state"
expect_refused resume-other-seed "seed" run --resume "$work/cut2" --seed 6 --out "$work/out"
expect_refused resume-missing "does not exist" run --resume "$work/nothing" --out "$work/out"
"$bin" run --resume "$work/cut2" --threads 1 --quiet --no-plot || fail "resume failed"
cmp -s "$work/whole.tsv" "$work/cut2.tsv" || fail "resumed run differs from the uninterrupted run"
[ -e "$work/cut2.state" ] && fail "a finished run left its checkpoint behind"
# A fixed count resumed forgets its state too: only a part (--realizations-range) keeps it.
fixed="--case many-contacts --omega-min 1 --omega-max 1000 --realizations 512 --seed 5 --no-plot --quiet"
start_in_background run $fixed --checkpoint-every 0.2 --out "$work/cut3"
for _ in $(seq 600); do [ -e "$work/cut3.state" ] && break; sleep 0.05; done
kill -INT $pid
wait $pid
[ $? -eq 130 ] || fail "checkpointed fixed-count run not interrupted (finished too soon?)"
"$bin" run --resume "$work/cut3" --quiet --no-plot || fail "resume of a fixed-count run failed"
[ -e "$work/cut3.state" ] && fail "a resumed fixed-count run left its state behind"
"$bin" run $fixed --out "$work/cut3" || fail "a new run on a finished run's prefix was refused"

# A run split into parts (a job array) merges bitwise into the whole run.
split="--omega-min 10 --omega-max 1000 --seed 7 --no-plot --quiet"
"$bin" run $split --realizations 40 --out "$work/all" || fail "40-realization run failed"
"$bin" run $split --realizations-range 0:16 --save-state "$work/a.state" --out "$work/a" || fail "part 0:16 failed"
"$bin" run $split --realizations-range 16:24 --save-state "$work/b.state" --out "$work/b" --threads 1 \
  || fail "part 16:24 failed"
"$bin" merge "$work/b.state" "$work/a.state" --out "$work/merged" --quiet --no-plot || fail "merge failed"
cmp -s "$work/all.tsv" "$work/merged.tsv" || fail "merged parts differ from the whole run"
expect_refused merge-overlap overlap merge "$work/a.state" "$work/a.state" --out "$work/out"
"$bin" run --omega-min 10 --omega-max 1000 --seed 8 --no-plot --quiet --realizations-range 16:24 --save-state "$work/c.state" --out "$work/c" \
  || fail "part of another seed failed"
expect_refused merge-other-run "seed" merge "$work/a.state" "$work/c.state" --out "$work/out"
expect_refused merge-not-a-state "not a slidespec run state" merge "$work/all.tsv" --out "$work/out"
"$bin" run --omega-min 100 --omega-max 1000 --precision 0.2 --save-state "$work/prec.state" --out "$work/prec" \
  --quiet --no-plot || fail "precision run with --save-state failed"
expect_refused merge-precision-run "fixed realization range" merge "$work/prec.state" --out "$work/out"
# Resuming a part (as a job array's retried task does) leaves its state where merge reads it.
"$bin" run $split --realizations-range 16:24 --save-state "$work/d.state" --out "$work/d" || fail "part 16:24 failed"
"$bin" run --resume "$work/d" --quiet --no-plot || fail "resume of a part failed"
"$bin" merge "$work/a.state" "$work/d.state" --out "$work/merged2" --quiet --no-plot || fail "merge after a resumed part failed"
cmp -s "$work/all.tsv" "$work/merged2.tsv" || fail "a resumed part merges differently from the whole run"
expect_refused part-kept "a finished part of a run; join it with merge" run $split --realizations-range 16:24 \
  --save-state "$work/d.state" --out "$work/d"
expect_refused merge-first-missing "realizations 0 to 16 are missing" merge "$work/d.state" --out "$work/out"
expect_refused range-without-state "needs --save-state" run $split --realizations-range 0:16 --out "$work/out"
expect_refused range-unaligned "multiple of 8" run $split --realizations-range 4:8 --save-state "$work/e.state" \
  --out "$work/out"

# The best theory that holds, by the measured limits (docs/model.md §7.4): the second order
# in the reference case (eps 0.075), none at poisson eps 0.3 with 2 miniblocks (a warning).
"$bin" theory --case reference --omega-min 1 --omega-max 10 > "$work/kind.tsv" 2> "$work/kind.err" || fail "theory failed"
grep -q '^# theory_kind = second_order  # the best theory that holds here' "$work/kind.tsv" \
  || fail "reference theory table does not name the second order"
[ ! -s "$work/kind.err" ] || fail "warning in the reference case: $(cat "$work/kind.err")"
"$bin" theory --set N=2 --set alpha=1.04 --omega-min 1 --omega-max 10 > "$work/kind.tsv" 2> "$work/kind.err" \
  || fail "theory at eps 0.3 failed"
grep -q '^# theory_kind = none .*eps = 0.3: the second order holds to eps 0.15 for poisson renewal' "$work/kind.tsv" \
  || fail "eps 0.3 table does not say that no theory holds"
grep -q "no theory holds here" "$work/kind.err" || fail "no warning at eps 0.3"
# --quiet leaves out progress and the summary, not a warning.
"$bin" run --set N=2 --set alpha=1.04 --omega-min 1 --omega-max 10 --realizations 8 --quiet --no-plot \
  --out "$work/kindrun" 2> "$work/kind.err"
grep -q "no theory holds here" "$work/kind.err" || fail "--quiet dropped the warning that no theory holds"

# Where no theory holds (stalling forces): a warning, without refusing.
"$bin" run --set N=7 --set F_drive=8 --set F_kin=6 --set a=3e-4 --omega-min 30 --omega-max 300 \
  --precision 0.3 --out "$work/stall" --no-plot 2> "$work/stall.err"
status=$?
[ $status -ne 2 ] || fail "stall-region run refused"
grep -q "no theory holds here (theory_kind = none): alpha F_kin >= 2" "$work/stall.err" || fail "no warning in the stall region"
grep -q '^# theory_kind = none .*stall' "$work/stall.tsv" || fail "stall-region table does not say that no theory holds"
# In its 33 s realizations (55 renewal times a/v) some already stall: exit 3.
[ $status -eq 3 ] || fail "partly stalled run exited $status, expected 3"
grep -q "^# stationary = false  # .* realizations slide slower than v/2.*some realizations stalled" "$work/stall.tsv" \
  || fail "partly stalled run not marked as stalled: $(grep '^# stationary' "$work/stall.tsv")"
# Realizations of 3 s cannot vouch for steady sliding where the forces can stall the block:
# not stationary as far as it can tell, exit 3.
"$bin" run --set N=7 --set F_drive=8 --set F_kin=6 --set a=3e-4 --omega-min 1000 --omega-max 10000 \
  --precision 0.3 --out "$work/stall-short" --no-plot --quiet 2> /dev/null
status=$?
[ $status -eq 3 ] || fail "short stall-capable run exited $status, expected 3"
grep -q "^# stationary = false  # the random forces can stall the block.*too short to tell" "$work/stall-short.tsv" \
  || fail "short stall-capable run not marked as unable to tell"

# A spring-driven block whose forces can stall it: the spring's stretch wanders over
# (F_drive - F_kin + the random forces' reach) / k_drive, which the load point takes
# tau = 2.5e4, 2e4, 1e4 and 1e3 s to take up at 0.4, 0.5, 1 and 10 N/m; the lowest
# realizations (3280 s) do not span 20 tau: not a spectrum (exit 3), the message naming the
# omega_min and the --duration that would do (its realizations slower than v/2 prove nothing
# where the spring's range allows them). At 1e3 N/m (tau = 10 s) they do (exit 0).
spring_short="wanders over .* under 20 times that: extend the band down (--omega-min .* or lower), give --duration"
for case in "1e3 " "0.4 $spring_short" "0.5 $spring_short" "1 $spring_short" "10 $spring_short"; do
  k=${case%% *} why=${case#* }
  "$bin" run --set N=7 --set F_drive=8 --set F_kin=6 --set k1=0 --set drive=spring --set k_drive=$k \
    --omega-min 0.3 --omega-max 3 --realizations 32 --out "$work/spring-stall" --no-plot --quiet 2> /dev/null
  status=$?
  if [ -z "$why" ]; then
    [ $status -eq 0 ] || fail "spring-driven stall case at k_drive $k exited $status, expected 0"
    continue
  fi
  [ $status -eq 3 ] || fail "spring-driven run short of v (k_drive $k) exited $status, expected 3"
  grep -q "^# stationary = false  # .*$why" "$work/spring-stall.tsv" \
    || fail "spring-driven run short of v (k_drive $k) not marked: $why"
done
# A sweep says which of its runs is not a spectrum, in its table and its JSON.
"$bin" sweep k_drive=10,1e3 --set N=7 --set F_drive=8 --set F_kin=6 --set k1=0 --set drive=spring \
  --omega-min 0.3 --omega-max 3 --realizations 32 --out "$work/spring-sweep" --no-plot --quiet 2> /dev/null
[ $? -eq 3 ] || fail "a sweep with a run that is not stationary did not exit 3"
grep -q "^# run_0 = .*NOT STATIONARY: the forces can stall" "$work/spring-sweep.tsv" || fail "sweep table: run 0 not flagged"
grep -q "^# run_1 = .*NOT STATIONARY" "$work/spring-sweep.tsv" && fail "sweep table: run 1 flagged"
/usr/bin/python3 -c "
import json; runs = json.load(open('$work/spring-sweep.json'))['runs']
assert [r['stationary'] for r in runs] == [False, True] and 'stationarity' in runs[0], runs" \
  || fail "sweep JSON: stationary per run"
# A part of two realizations is merge's to judge: alone it is written as it is, merged it is
# a finished run short of points, which says why (exit 3), not that it was interrupted.
"$bin" run --omega-min 10 --omega-max 100 --realizations-range 0:2 --save-state "$work/p2.state" \
  --out "$work/p2" --no-plot --quiet || fail "a part of two realizations: exit $?"
"$bin" merge "$work/p2.state" --out "$work/m2" --no-plot 2> "$work/m2.err"
[ $? -eq 3 ] && grep -q "wrote .*m2.tsv" "$work/m2.err" && grep -q "not stationary (2 of the 9 points got too few segments" "$work/m2.err" \
  || fail "a merge short of points: $(cat "$work/m2.err")"
# Its advice, followed, gives a spectrum (k_drive 10 N/m, as the last refusal above named it).
advised=$(grep -o -- "--omega-min [0-9.e+-]* rad/s or lower" "$work/spring-stall.tsv" | cut -d' ' -f2)
"$bin" run --set N=7 --set F_drive=8 --set F_kin=6 --set k1=0 --set drive=spring --set k_drive=10 \
  --omega-min "$advised" --omega-max 3 --realizations 32 --out "$work/spring-advised" --no-plot --quiet 2> /dev/null \
  || fail "the spring-stall advice, --omega-min $advised, followed: exit $?"

# Where the forces stall the block there is no spectrum: said in the table, the JSON and
# the exit status (3), while every named case is stationary.
"$bin" run --set N=7 --set F_drive=8 --set F_kin=6 --set k1=0 --omega-min 1 --omega-max 1000 --precision 0.1 \
  --out "$work/stalled" --no-plot --quiet 2> /dev/null
status=$?
[ $status -eq 3 ] || fail "stalled run exited $status, expected 3"
grep -q "^# stationary = false" "$work/stalled.tsv" || fail "stalled run not marked stationary = false"
grep -q '"stationary": false' "$work/stalled.json" || fail "stalled run's JSON not marked stationary: false"
grep -q "^# stationary = true" "$work/short.tsv" || fail "a healthy run not marked stationary = true"
# Theory holds at any omega where its numbers fit in a double, and refuses below, naming
# the lowest omega that works (for the reference case C_eq1 = 1.1e-10 / omega^4 leaves a
# double below 2.8e-80 rad/s).
"$bin" theory --omega 1e-300,1 --out "$work/tiny" 2> "$work/tiny.err"
status=$?
[ $status -eq 2 ] || fail "theory below the lowest omega exited $status, expected 2"
grep -q "below 2.81e-80 rad/s" "$work/tiny.err" || fail "theory refusal does not name the lowest omega: $(cat "$work/tiny.err")"
[ ! -e "$work/tiny.tsv" ] || fail "refused theory wrote its table"
"$bin" theory --omega 2.81e-80,1e-14 > "$work/tiny.tsv" || fail "theory at the lowest omega failed"
! grep -qiE "inf|nan" "$work/tiny.tsv" || fail "theory at the lowest omega printed inf or nan"
"$bin" theory --omega 1,10 > /dev/null || fail "theory on ordinary omegas did not exit 0"
# Far above every corner C_x ~ omega^-8 leaves the normal doubles (near 1.5e39 rad/s for the
# reference case): refused, naming the highest omega that works, where C_x is still > 0.
"$bin" theory --omega 1,1e45 > /dev/null 2> "$work/huge-omega.err" && fail "theory at 1e45 rad/s exited 0"
highest=$(sed -n 's/.*above \([0-9.e+]*\) rad\/s, the highest.*/\1/p' "$work/huge-omega.err")
[ -n "$highest" ] || fail "theory refusal does not name the highest omega: $(cat "$work/huge-omega.err")"
"$bin" theory --omega "$highest" | awk '!/^#/ && ($2 ~ /^0$/ || $2 ~ /e-(309|3[1-9][0-9])$/) {bad = 1} END {exit bad}' \
  || fail "theory at the highest omega it names ($highest) printed no normal C_x"

# Running out of memory is a failure while working (1), not bad input (2): a record of
# 9e7 samples under a 400 MB address space (skipped where the binary cannot start under it,
# as a sanitizer build cannot).
if (ulimit -v 400000; "$bin" cases > /dev/null 2>&1); then
  (ulimit -v 400000; "$bin" synth --duration 9e4 --out "$work/huge" 2> "$work/huge.err")
  status=$?
  [ $status -eq 1 ] || fail "out of memory exited $status, expected 1: $(cat "$work/huge.err")"
  grep -q "out of memory" "$work/huge.err" || fail "out of memory not named: $(cat "$work/huge.err")"
  [ ! -e "$work/huge.csv" ] || fail "a run out of memory wrote its record"
fi

[ $failures -eq 0 ] && echo "cli: all checks passed"
exit $((failures > 0))
