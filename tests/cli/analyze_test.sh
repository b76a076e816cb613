#!/usr/bin/env bash
# End-to-end checks of slidespec synth and analyze: files written, refusals with exit
# status 2, one line naming the problem, and no output file touched.
source "$(dirname "$0")/common.sh"

# A short synthetic record (60 s at 1 kHz, a fine sensor so that a band shows) through the whole path.
"$bin" synth --set alpha=0.4 --duration 60 --resolution 1e-8 --sensor-noise 5e-9 --out "$work/rec" 2> "$work/synth.err" || fail "synth failed: $(cat "$work/synth.err")"
[ "$(grep -vc '^#' "$work/rec.csv")" -eq 60002 ] || fail "synth: expected a header and 60001 samples"
grep -q "^t,x$" "$work/rec.csv" || fail "synth: no t,x header"
"$bin" analyze "$work/rec.csv" --units um --resolution 1e-8 --sensor-noise 5e-9 --fit-slope 30 100 \
  --compare-case reference --set alpha=0.4 --fit alpha --fit-band 30 100 --normal-mass 2 --driving-mass 1 \
  --out "$work/an" 2> "$work/an.err" || fail "analyze failed: $(cat "$work/an.err")"
for ext in tsv json png; do [ -s "$work/an.$ext" ] || fail "analyze wrote no .$ext"; done
grep -q "^omega	C_x	stderr	floor	below_floor	n_avg	bandwidth	C_v	fit	theory$" "$work/an.tsv" || fail "analyze table header"
grep -q "^# mu = 5.0*e-01" "$work/an.tsv" || fail "mu = M'/M not reported"
grep -q '"alpha_fit"' "$work/an.json" || fail "no alpha fit in the JSON"
grep -q "alpha = " "$work/an.err" || fail "no alpha in the summary"
ls -a "$work" | grep -q "tmp\|\.plot_spectra" && fail "a temporary file was left behind"

# Bad input: refused before anything is written.
printf 't,x\n0,1\n0.001,abc\n' > "$work/text.csv"
printf 't,x\n0,1\n' > "$work/single.csv"
printf 't,x\n0,1\n0.001,2\n0.0005,3\n' > "$work/backwards.csv"
out="--out $work/out"
expect_refused missing-file "nothing.csv" analyze "$work/nothing.csv" $out
expect_refused text-in-numbers "line 3" analyze "$work/text.csv" $out
expect_refused single-line "line 2" analyze "$work/single.csv" $out
expect_refused backwards-time "line 4" analyze "$work/backwards.csv" $out
expect_refused missing-column "no column 'pos'" analyze "$work/rec.csv" --column pos $out
expect_refused bad-units furlong analyze "$work/rec.csv" --units furlong $out
expect_refused fit-beta "only 'alpha'" analyze "$work/rec.csv" --fit beta --compare-case reference $out
expect_refused fit-without-case "compare-case" analyze "$work/rec.csv" --fit alpha $out
expect_refused unknown-case slow analyze "$work/rec.csv" --compare-case slow $out
expect_refused empty-slope-band "fit-slope" analyze "$work/rec.csv" --units um --fit-slope 1e4 2e4 $out
expect_refused bad-mass "normal-mass" analyze "$work/rec.csv" --normal-mass -1 --driving-mass 1 $out
expect_refused analyze-missing-directory "does not exist" analyze "$work/rec.csv" --out "$work/nowhere/x"
expect_refused synth-bad-interval "sample-interval" synth --sample-interval -1 $out
expect_refused synth-bad-case slow synth --case slow $out
expect_refused synth-missing-directory "does not exist" synth --out "$work/nowhere/x"

[ $failures -eq 0 ] && echo "cli_analyze: all checks passed"
exit $((failures > 0))
