#!/usr/bin/env bash
# analyze of many records (issue "Lab records II", item 8) and synth's drive programs, end to
# end: one table of all records, a bad record reported while the rest go on, the exit status,
# an interrupt that keeps the records finished, and refusals before any work.
source "$(dirname "$0")/common.sh"

synth_fast() { "$bin" synth --case fast --set alpha=0.4 --sample-interval 0.01 --resolution 0 --sensor-noise 0 "$@"; }
mkdir -p "$work/g" "$work/other"
synth_fast --duration 200 --out "$work/g/plain" 2> /dev/null || fail "synth of a plain record failed"
synth_fast --strokes 8 --stroke-length 50mm --dwell 1 --out "$work/g/strokes" 2> "$work/synth.err" \
  || fail "synth --strokes failed: $(cat "$work/synth.err")"
# 8 strokes of 10 s and 7 dwells of 1 s: 87 s at 0.01 s, the last sample at 87 s.
[ "$(grep -vc '^#' "$work/g/strokes.csv")" -eq 8702 ] || fail "synth --strokes: expected a header and 8701 samples"
grep -q "^# strokes = 8 of 50mm (dwell 1 s)$" "$work/g/strokes.csv" || fail "synth --strokes: the record does not say its strokes"
synth_fast --program 1:100,0:2,3:100 --out "$work/g/steps" 2> /dev/null || fail "synth --program failed"
grep -q "^# program (speed / v : seconds) = 1:100 0:2 3:100$" "$work/g/steps.csv" || fail "synth --program: not in the record"
printf 't,x\n0,1\n0.001,abc\n' > "$work/g/bad.csv"
# A rig's program: the load point and the force written, the force standing through the hold.
rig="--set drive=spring --set k_drive=1e8 --set alpha=0.004 --set F_kin=14700 --set F_drive=14800 --load-point"
"$bin" synth $rig --program 1:10,0:2,3:10 --sample-interval 0.02 --out "$work/rig" 2> /dev/null \
  || fail "synth --load-point --program failed"
grep -q "^t (s),x (um),F (N)$" "$work/rig.csv" || fail "synth --load-point --program: no force column"
grep -q "^# note: .*in a hold .* the force stands" "$work/rig.csv" || fail "synth --load-point --program: no note of the hold"
[ "$(awk -F, '!/^#/ && $1 >= 10 && $1 <= 12 {print $3}' "$work/rig.csv" | sort -u | wc -l)" -eq 1 ] \
  || fail "synth --load-point --program: the force moves in the hold"

# Three records and a bad one: each analysed into its own outputs, the bad one reported in one
# line naming it, the table listing all four, exit status 3 (one is not ok).
"$bin" analyze "$work/g/plain.csv" "$work/g/strokes.csv" "$work/g/bad.csv" "$work/g/steps.csv" --no-plot \
  --fit-slope 8 30 --out "$work/many" > "$work/stdout" 2> "$work/many.err"
status=$?
[ $status -eq 3 ] || fail "analyze of four records, one bad, exited $status, expected 3: $(cat "$work/many.err")"
for stem in plain strokes steps; do
  for ext in tsv json; do [ -s "$work/many_$stem.$ext" ] || fail "analyze of many wrote no many_$stem.$ext"; done
done
ls "$work" | grep -q "^many_bad" && fail "a refused record has outputs"
[ "$(grep -c "^slidespec: error: $work/g/bad.csv: .*line 3" "$work/many.err")" -eq 1 ] \
  || fail "the bad record is not reported in one line naming it: $(cat "$work/many.err")"
for k in 1 2 3 4; do grep -q "^slidespec: analyze $k/4: " "$work/many.err" || fail "no progress line $k/4"; done
table="$work/many.tsv"
[ "$(grep -vc '^#' "$table")" -eq 5 ] || fail "the combined table holds no header and four rows: $(cat "$table")"
grep -q "^file	outputs	segment	start	end	v	v_err	usable_low	usable_high	slope	slope_err	alpha	alpha_err	strokes	ok	reason$" "$table" \
  || fail "the combined table's columns"
row() { grep "^$work/g/$1.csv	" "$table"; }
row plain | cut -f3,15 | grep -q "^whole	1$" || fail "plain: not a whole record, ok: $(row plain)"
row strokes | cut -f3,14,15 | grep -q "^strokes	8	1$" || fail "strokes: not its 8 strokes, ok: $(row strokes)"
row steps | cut -f3 | grep -q "^sliding$" || fail "steps: not its longest sliding stretch: $(row steps)"
row steps | awk -F'\t' '{exit !($6 > 0.0145 && $6 < 0.0155 && $4 > 100)}' || fail "steps: not the 3x stretch: $(row steps)"
row bad | cut -f2,3,15 | grep -q "^-	-	0$" || fail "bad: not marked refused: $(row bad)"
row bad | cut -f16 | grep -q "line 3" || fail "bad: no reason: $(row bad)"
grep -q '"named": 4' "$work/many.json" || fail "the combined JSON"
[ "$(grep -c '"ok": true' "$work/many.json")" -eq 3 ] || fail "the combined JSON's ok"

# A directory and a missing file among the records: each reported, the rest go on.
"$bin" analyze "$work/g/plain.csv" "$work/g" "$work/g/none.csv" --no-plot --out "$work/odd" 2> "$work/odd.err"
status=$?
[ $status -eq 3 ] || fail "analyze with a directory and a missing file among the records exited $status, expected 3"
grep -q "^slidespec: error: $work/g: a directory, not a record$" "$work/odd.err" || fail "a directory: $(cat "$work/odd.err")"
grep -q "^slidespec: error: $work/g/none.csv: no such file$" "$work/odd.err" || fail "a missing file: $(cat "$work/odd.err")"
[ "$(grep -vc '^#' "$work/odd.tsv")" -eq 4 ] || fail "the table of a directory and a missing file"

# A quoted glob: the shell leaves it, analyze expands it; all records good, exit 0; the
# figures too.
rm "$work/g/bad.csv"
"$bin" analyze "$work/g/*.csv" --out "$work/glob" 2> "$work/glob.err"
status=$?
[ $status -eq 0 ] || fail "analyze of a glob exited $status: $(cat "$work/glob.err")"
[ "$(grep -vc '^#' "$work/glob.tsv")" -eq 4 ] || fail "the glob's table holds no header and three rows"
for stem in plain strokes steps; do [ -s "$work/glob_$stem.png" ] || fail "no figure glob_$stem.png"; done

# Refused before any work: a pattern matching nothing, two records of one name, standard input
# among many, --segments of many, synth's drive options that cannot go together.
out="--out $work/out"
expect_refused glob-of-nothing "matches no file" analyze "$work/g/*.nothing" $out
cp "$work/g/plain.csv" "$work/other/plain.csv"
expect_refused same-stem "would both write" analyze "$work/g/plain.csv" "$work/other/plain.csv" $out
expect_refused stdin-among-many "standard input" analyze - "$work/g/plain.csv" $out
expect_refused segments-of-many "segments" analyze --segments "$work/g/plain.csv" "$work/g/steps.csv" $out
expect_refused strokes-without-length "stroke-length" synth --strokes 4 $out
expect_refused strokes-and-duration "duration" synth --strokes 4 --stroke-length 1mm --duration 10 $out
expect_refused dwell-without-strokes "strokes" synth --dwell 1 $out
expect_refused half-strokes "strokes" synth --strokes 2.5 --stroke-length 1mm $out
expect_refused bad-program "program" synth --program 1:100,0 $out
expect_refused program-and-strokes "program" synth --program 1:10 --strokes 2 --stroke-length 1mm $out
expect_refused rig-stalling-speed "program" synth $rig --program 1:10,0.1:10 --sample-interval 0.02 $out
expect_refused load-point-without-spring "load-point" synth --load-point --program 1:10 $out

# An interrupt between records keeps those finished and lists them in the combined table.
mkdir -p "$work/slow"
for k in 1 2 3 4 5 6 7 8; do synth_fast --duration 2000 --seed $k --out "$work/slow/r$k" 2> /dev/null; done
start_in_background analyze "$work/slow/"r*.csv --no-plot --out "$work/cut"
interrupt_once_written "$work/cut_r1.json"
[ $status -eq 130 ] || fail "an interrupted analyze of many exited $status, expected 130"
[ -s "$work/cut.tsv" ] || fail "an interrupt left no combined table"
rows=$(grep -vc '^#' "$work/cut.tsv")
[ "$rows" -ge 2 ] && [ "$rows" -le 8 ] || fail "the interrupted table holds $rows lines, expected a header and 1..7 rows"
for f in $(grep -v '^#' "$work/cut.tsv" | tail -n +2 | cut -f2); do
  [ -s "$f.tsv" ] || fail "a record listed as finished has no $f.tsv"
done
ls -a "$work" | grep -q "tmp" && fail "a temporary file was left behind"

[ $failures -eq 0 ] && echo "analyze of many records, synth's programs: all passed"
exit $((failures > 0))
