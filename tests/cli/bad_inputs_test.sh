#!/usr/bin/env bash
# Table-driven refusals: every line below is a bad input. Each must exit 2 with one line on
# stderr naming the problem, before any work (within seconds), leaving the working
# directory exactly as it was (every file's bytes, no new file, no temporary).
source "$(dirname "$0")/common.sh"

# Inputs a user has lying around: a parameter file, a measured record, a table, a state.
cd "$work" || exit 1
echo '{"alpha": 0.5}' > p.json
"$bin" synth --duration 5 --sample-interval 0.01 --out rec > /dev/null 2>&1 || fail "synth fixture"
mv rec.csv rec.tsv
"$bin" theory --out table > /dev/null 2>&1 || fail "theory fixture"
"$bin" run --omega-min 100 --omega-max 1000 --realizations-range 0:8 --save-state part.state --out part \
  --no-plot --quiet || fail "state fixture"
rm -f part.tsv part.json
mkdir adir
cp p.json q.tsv
cp p.json sw.png
cp part.state part2.tsv
cp part.state stale.state
printf '1\n10\n' > om.tsv
# Inputs named as some command's outputs would be: figures in every format, sweep sub-runs,
# paper outputs, links to an input.
for f in fig.pdf fig.svg swp.pdf 'sw_alpha=0.6.json' 'sw_alpha=0.6.state' an.svg syn.csv; do cp p.json "$f"; done
cp part.state pt3.svg
cp rec.tsv an.svg
cp table.tsv tab.svg
mkdir d6 && cp rec.tsv d6/fig6.tsv && cp rec.tsv d6/fig6_record.csv
ln -s p.json link.json
ln p.json hard.tsv
# Parameter files that are not strict JSON, or endless.
printf '{"alpha": 0.5, "alpha": 0.7}' > dup.json
printf '{"alpha": 0.5} trailing' > trail.json
printf '{"parameters": {"alpha": 0.5}, "alpha": 0.7}' > outer.json
head -c 1100000 /dev/zero | tr '\0' ' ' > big.json
# Records whose columns cannot be told apart, whose times no double holds, or with a NUL
# inside a quoted field.
awk 'BEGIN { print "t,t,x"; for (k = 0; k < 200; ++k) print k * 0.01 "," k * 0.01 "," k * 1e-6 }' > twot.csv
awk 'BEGIN { print "t,x,x"; for (k = 0; k < 200; ++k) print k * 0.01 "," k * 1e-6 "," k * 2e-6 }' > twox.csv
awk 'BEGIN { print "t,x"; for (k = 0; k < 200; ++k) print k "e300," k * 1e-6 }' > huge_t.csv
awk 'BEGIN { print "x"; for (k = 0; k < 200; ++k) print k * 1e-6 }' > untimed.csv
awk 'BEGIN { print "t (s),time (s)"; for (k = 0; k < 200; ++k) print k * 0.01 "," k * 0.01 }' > two_clocks.csv
printf 't,x\n0,1\n0.01,"2\0003"\n0.02,4\n' > nul.csv
awk 'BEGIN { print "t,x"; for (k = 0; k < 200; ++k) print k * 0.01 "," (k == 5 ? "1.0004e30" : k * 1e-6) }' > big30.csv
long=$(printf 'n%.0s' $(seq 1 300))
odd=$(printf 'odd\xff')

snapshot() { find . -print0 | sort -z | xargs -0 stat -c '%n %s %a' ; find . -type f -print0 | sort -z | xargs -0 sha256sum; }

# SLIDESPEC_TEST_SAMPLE=K (the sanitizer build, where each start costs seconds) tries the
# first line of every class (each '#' heading) and every K-th line after it: every class
# stays covered.
sample=${SLIDESPEC_TEST_SAMPLE:-1}
tried=0 in_class=0
# NAME | WORD the message must contain | ARGS (shell words)
while IFS='|' read -r name word args; do
  [ -z "$name" ] && continue
  [ "${name:0:1}" = "#" ] && { in_class=0; continue; }
  in_class=$((in_class + 1))
  [ $(((in_class - 1) % sample)) -eq 0 ] || continue
  tried=$((tried + 1))
  before=$(snapshot)
  eval "set -- $args"
  timeout 20 "$bin" "$@" > stdout.log 2> stderr.log
  status=$?
  message=$(cat stderr.log)
  rm -f stdout.log stderr.log
  [ $status -eq 124 ] && { fail "$name: still running after 20 s (a hang or work where a refusal belongs)"; continue; }
  [ $status -eq 2 ] || fail "$name: exit status $status, expected 2: $message"
  [ "$(printf '%s\n' "$message" | wc -l)" -eq 1 ] && [ -n "$message" ] || fail "$name: not a one-line message: $message"
  printf '%s' "$message" | grep -qF -- "$word" || fail "$name: message does not name '$word': $message"
  [ "$before" = "$(snapshot)" ] || fail "$name: the directory changed"
done <<TABLE
# outputs that would replace an input
analyze-over-record|rec.tsv|analyze rec.tsv --out rec --no-plot
run-over-params|p.json|run --params p.json --out p --no-plot
theory-over-params|q.tsv|theory --params q.tsv --out q
sweep-over-params|sw.png|sweep alpha=0.5 --params sw.png --out sw
theory-over-omega-file|om.tsv|theory --omega-file om.tsv --out om
run-over-stale-state|stale.state holds a finished part of a run|run --omega-min 1 --omega-max 10 --out stale
run-points-between-bins|--points|run --omega-min 1 --omega-max 10 --points 200
run-no-random-force|alpha|run --omega-min 1 --omega-max 10 --set alpha=0
run-no-friction-no-random-force|parameter F_kin: 0 gives no random force|run --omega-min 1 --omega-max 10 --set F_kin=0
save-state-over-params|p.json|run --params p.json --save-state p.json --out x --no-plot
save-state-over-part-record|rec.tsv|run --resume part --out x --save-state rec.tsv --realizations 8 --params rec.tsv
plot-over-table|table.tsv|plot table.tsv -o table.tsv
plot-over-table-dotted|table.tsv|plot table.tsv -o ./table.tsv
merge-over-part|part2.tsv|merge part2.tsv --out part2
resume-over-record|rec.tsv|analyze rec.tsv --out rec --no-plot --points 4
analyze-over-record-abs|rec.tsv|analyze $work/rec.tsv --out ./rec --no-plot
run-out-state-over-state|part.state|run --out part --params p.json --realizations 8 --resume part
run-pdf-over-params|fig.pdf|run --params fig.pdf --out fig --format pdf
run-svg-over-params|fig.svg|run --params fig.svg --out fig --format svg
sweep-pdf-over-params|swp.pdf|sweep alpha=0.5 --params swp.pdf --out swp --format pdf
sweep-range-run-over-params|sw_alpha=0.6.json|sweep alpha=0.5:0.6:0.1 --params sw_alpha=0.6.json --out sw
sweep-run-state-over-params|sw_alpha=0.6.state|sweep alpha=0.6 --params sw_alpha=0.6.state --out sw
merge-svg-over-part|pt3.svg|merge pt3.svg --out pt3 --format svg
analyze-svg-over-record|an.svg|analyze an.svg --out an --format svg
synth-over-params|syn.csv|synth --params syn.csv --out syn
paper-fig6-over-record|d6/fig6.tsv|paper fig6 --record d6/fig6.tsv --out-dir d6
plot-svg-over-table|tab.svg|plot tab.svg -o tab.svg
symlink-out-over-params|p.json|run --params p.json --out link --no-plot
hardlink-out-over-params|p.json|theory --params p.json --out hard
# empty, control characters, conflicting and ignored options
run-empty-out|--out|run --out '' --no-plot
theory-empty-out|--out|theory --out ''
sweep-empty-out|--out|sweep alpha=1 --out ''
merge-empty-out|--out|merge part.state --out ''
analyze-empty-out|--out|analyze rec.tsv --out ''
synth-empty-out|--out|synth --out ''
paper-empty-dir|--out-dir|paper fig2 --out-dir ''
run-empty-resume|--resume|run --resume ''
run-empty-save-state|--save-state|run --save-state '' --no-plot
theory-empty-omega|--omega|theory --omega ''
theory-omega-left-out|an empty value between commas|theory --omega 1,,2
theory-omega-trailing-comma|an empty value between commas|theory --omega 1,2,
run-empty-params|--params|run --params '' --no-plot
run-newline-out|control character|run --out \$'a\nb' --no-plot
theory-tab-out|control character|theory --out \$'a\tb'
sweep-newline-out|control character|sweep alpha=1 --out \$'s\nw' --no-plot
run-realizations-and-precision|--precision|run --realizations 8 --precision 0.1 --no-plot
sweep-realizations-and-precision|--precision|sweep alpha=1 --realizations 8 --precision 0.1 --no-plot
run-duration-zero|--duration|run --duration 0 --no-plot
run-duration-and-precision|--precision|run --duration 5 --precision 0.1 --no-plot
run-realizations-zero|--realizations|run --realizations 0 --no-plot
run-duration-raised|shorter than|run --duration 1 --no-plot
work-budget-zero|--work-budget|run --work-budget 0 --no-plot
sweep-work-budget-zero|--work-budget|sweep alpha=1 --work-budget 0 --no-plot
analyze-dt-zero|--dt|analyze rec.tsv --dt 0 --no-plot --out x
analyze-dt-subnormal|--dt|analyze rec.tsv --dt 1e-320 --no-plot --out x
run-spectrum-squares-underflow|whose squares|run --omega-min 1 --omega-max 10 --set alpha=1e-80 --no-plot
run-spectrum-squares-underflow-mass|whose squares|run --omega-min 1 --omega-max 10 --set M=1e100 --no-plot
analyze-size-hexadecimal|--size|analyze rec.tsv --out x --size 0x10x5
analyze-size-exponent|--size|analyze rec.tsv --out x --size 1e1x5
# options that would be ignored, repeated or conflicting
run-no-plot-format|--format|run --no-plot --format pdf
analyze-no-plot-size|--size|analyze rec.tsv --out x --no-plot --size 3x3
sweep-no-plot-dpi|--dpi|sweep alpha=1 --no-plot --dpi 300
theory-omega-and-omega-min|--omega|theory --omega 1,2 --omega-min 5
theory-omega-file-and-points|--points|theory --omega-file om.tsv --points 3
paper-fig6-seed|--seed|paper fig6 --seed 3
paper-fig6-precision|--precision|paper fig6 --precision 0.1
sweep-key-also-set|alpha|sweep alpha=0.3,0.6 --set alpha=0.5 --no-plot
set-key-twice|twice|theory --set alpha=0.3 --set alpha=0.6
analyze-fit-band-without-fit|--fit|analyze rec.tsv --out x --no-plot --fit-band 1 10
analyze-set-without-compare|--compare-case|analyze rec.tsv --out x --no-plot --set alpha=1
# a title matplotlib cannot typeset
plot-title-mathtext|--title|plot table.tsv -o x.png --title '\$x^\$'
plot-title-double-subscript|--title|plot table.tsv -o x.png --title '\$a_b_c\$'
# strict, bounded parameter files; devices
params-duplicate-key|twice|run --params dup.json --no-plot
params-trailing-data|not valid JSON|theory --params trail.json
params-too-big|longer than|theory --params big.json
synth-params-duplicate|twice|synth --params dup.json
params-dev-zero|device|theory --params /dev/zero
merge-dev-zero|device|merge /dev/zero
omega-file-dev-zero|device|theory --omega-file /dev/zero
record-dev-zero|device|analyze /dev/zero --no-plot
# counts beyond their type, with the allowed range in the message
seed-20-digits|18446744073709551615|run --seed 99999999999999999999 --no-plot
seed-just-above|18446744073709551615|run --seed 18446744073709551616 --no-plot
threads-above-int|2147483647|run --threads 2147483648 --no-plot
# directories, missing files, unreadable names
params-directory|directory|run --params adir
record-directory|directory|analyze adir
plot-directory|directory|plot adir -o x.png
merge-directory|directory|merge adir
out-directory|directory|run --out adir
theory-out-directory|directory|theory --out adir
params-missing|does not exist|theory --params none.json
record-missing|does not exist|analyze none.tsv
merge-missing|does not exist|merge none.state
resume-missing|does not exist|run --resume none
out-missing-dir|does not exist|run --out nowhere/x --no-plot
synth-missing-dir|does not exist|synth --out nowhere/x
too-long-name|longer|theory --out $long
too-long-run-name|longer|run --out $long --no-plot
non-utf8-out|UTF-8|theory --out $odd
non-utf8-run-out|UTF-8|run --out $odd --no-plot
non-utf8-params|UTF-8|theory --params $odd.json
non-utf8-record|UTF-8|analyze $odd.tsv
# state files that are not states
merge-table|not a slidespec run state|merge table.tsv
merge-params|not a slidespec run state|merge p.json
# parameters out of range or not representable
k0-huge|k0|theory --set k0=1e308
k0-tiny|k0|theory --set k0=1e-308
v-huge|parameter v|theory --set v=1e308
M-huge|parameter M|theory --set M=1e308
M-tiny|parameter M|theory --set M=1e-200
a-huge|parameter a|run --set a=1e300 --no-plot
a-tiny|parameter a|run --set a=1e-300 --no-plot
m-huge|parameter m|theory --set m=1e200
eta0-huge|eta0|theory --set eta0=1e200
k1-huge|k1|theory --set k1=1e200
alpha-huge|alpha|theory --set alpha=1e200
F-drive-huge|F_drive|theory --set F_drive=1e300
F-kin-huge|F_kin|theory --set F_kin=1e300 --set F_drive=2e300
eta1-huge|eta1|theory --set eta1=1e300
eta1-tiny|eta1|theory --set eta1=1e-300
v-zero|parameter v|theory --set v=0
v-negative|parameter v|theory --set v=-1
v-nan|parameter v|theory --set v=nan
M-inf|parameter M|theory --set M=inf
M-text|parameter M|theory --set M=heavy
N-negative|parameter N|theory --set N=-1
N-fraction|parameter N|theory --set N=2.5
N-huge|parameter N|theory --set N=1e12
levels-nine|levels|theory --set levels=9
levels-zero|levels|theory --set levels=0
m2-huge|m_2|theory --set levels=2 --set m_2=1e200
a2-tiny|a_2|theory --set levels=2 --set a_2=1e-200
alpha-negative|alpha|theory --set alpha=-0.5
eta0-negative|eta0|theory --set eta0=-1
F-equal|F_drive|theory --set F_kin=10
renewal-kind|renewal|theory --set renewal=sometimes
chain-kind|chain|theory --set chain=circle
empty-value|parameter M|theory --set M=
no-equals|KEY=VALUE|theory --set M
unknown-case|unknown case|run --case slow --no-plot
unknown-key|unknown parameter|run --set speed=1 --no-plot
sweep-bad-value|parameter alpha|sweep alpha=0.5,huge --no-plot
sweep-huge-value|parameter k0|sweep k0=1e4,1e308 --no-plot
sweep-empty-value|empty value|sweep alpha=0.5,,1 --no-plot
sweep-no-values|KEY=V1|sweep alpha --no-plot
# requests: ranges, counts, work
omega-min-zero|omega|run --omega-min 0 --no-plot
omega-min-negative|omega|run --omega-min -1 --no-plot
omega-max-below-min|omega|run --omega-min 10 --omega-max 1 --no-plot
omega-max-inf|omega|run --omega-max inf --no-plot
omega-min-nan|omega|run --omega-min nan --no-plot
omega-min-tiny|--omega-min|run --omega-min 1e-10 --no-plot
omega-max-huge|--omega-max|run --omega-max 1e300 --no-plot
omega-span-huge|points|theory --omega-min 1e-300 --omega-max 1e300 --points 1000
theory-omega-tiny-max|--omega-max 1 must be finite and above --omega-min 1|theory --omega-min 1 --omega-max 1
theory-omega-below-double|lowest at which C_x and C_eq1 fit|theory --omega 1e-300,1
theory-omega-above-double|the highest at which C_x is above the smallest double|theory --omega 1,1e45
theory-omega-min-below-double|lowest at which C_x and C_eq1 fit|theory --omega-min 1e-100 --omega-max 1e-90
points-zero|points|run --points 0 --no-plot
points-negative|--points|run --points -3 --no-plot
points-huge|points|run --points 100000000 --no-plot
theory-points-huge|points|theory --points 1000000000
theory-points-negative|--points|theory --points -8
precision-zero|precision|run --precision 0 --no-plot
precision-one|precision|run --precision 1 --no-plot
precision-negative|precision|run --precision -0.1 --no-plot
precision-tiny|precision|run --precision 1e-12 --no-plot
precision-nan|precision|run --precision nan --no-plot
duration-huge|--omega-min/--duration|run --duration 1e308 --no-plot
duration-long|--duration|run --duration 1e9 --no-plot
duration-negative|duration|run --duration -5 --no-plot
duration-inf|duration|run --duration inf --no-plot
realizations-negative|--realizations|run --realizations -1 --no-plot
realizations-huge|--realizations|run --realizations 1000000000000 --no-plot
realizations-overflow|--realizations|run --realizations 99999999999999999999999 --no-plot
realizations-fraction|--realizations|run --realizations 2.5 --no-plot
realizations-text|--realizations|run --realizations many --no-plot
realizations-too-few|--realizations 2: too few for the lowest point of sub-band 1..10 rad/s, whose error bar needs 12 segments (the scatter between them); give at least 3|run --realizations 2 --omega-min 1 --omega-max 10 --no-plot
realizations-too-few-duration|give at least 3, or a longer --duration|run --realizations 1 --duration 5000 --omega-min 0.3 --omega-max 100 --no-plot
sweep-realizations-negative|--realizations|sweep alpha=1 --realizations -1 --no-plot
seed-negative|--seed|run --seed -1 --no-plot
seed-fraction|--seed|run --seed 1.5 --no-plot
seed-text|--seed|run --seed abc --no-plot
synth-seed-negative|--seed|synth --seed -1
paper-seed-negative|--seed|paper fig2 --seed -1
threads-negative|--threads|run --threads -3 --no-plot
threads-huge|--threads|run --threads 100000 --no-plot
sweep-threads-negative|--threads|sweep alpha=1 --threads -1 --no-plot
paper-threads-negative|--threads|paper fig2 --threads -2
work-budget-negative|--work-budget|run --work-budget -1 --no-plot
work-budget-small|--work-budget|run --work-budget 1000 --no-plot
range-negative|realizations-range|run --realizations-range -8:8 --save-state part.state --no-plot
range-no-colon|realizations-range|run --realizations-range 8 --save-state part.state --no-plot
range-zero-count|realizations-range|run --realizations-range 0:0 --save-state part.state --no-plot
range-unaligned|multiple of 8|run --realizations-range 3:8 --save-state part.state --no-plot
range-huge|--realizations|run --realizations-range 0:99999999999999 --save-state part.state --no-plot
checkpoint-negative|positive number of seconds (got -1)|run --checkpoint-every -1 --no-plot
checkpoint-word|positive number of seconds (got soon)|run --checkpoint-every soon --no-plot
simd-unknown|simd|run --simd neon --no-plot
resume-other-seed|seed|run --resume part --seed 9 --no-plot
paper-unknown|fig9|paper fig9
paper-precision|precision|paper fig2 --precision 0
analyze-points-huge|points|analyze rec.tsv --points 100000000 --no-plot --out x
analyze-points-negative|--points|analyze rec.tsv --points -1 --no-plot --out x
synth-duration-huge|--duration|synth --duration 1e308
synth-interval-tiny|--sample-interval|synth --sample-interval 1e-300
synth-interval-zero|--sample-interval|synth --sample-interval 0
synth-resolution-unit|unknown unit 'furlong'|synth --resolution 5furlong
synth-noise-negative|--sensor-noise|synth --sensor-noise -1um
synth-k0-huge|k0|synth --set k0=1e308
synth-out-directory|directory|synth --out adir
analyze-dt-negative|--dt|analyze rec.tsv --dt -1 --no-plot --out x
analyze-units|--units|analyze rec.tsv --units km --no-plot --out x
analyze-column|nope|analyze rec.tsv --column nope --no-plot --out x
analyze-resolution|--resolution|analyze rec.tsv --resolution -1 --no-plot --out x
tree-too-big|blocks|run --case hierarchical --set N_2=100000 --no-plot
merge-nothing|parts|merge
plot-nothing|tables|plot -o x.png
unknown-command|wobble|wobble
# columns named alike, times beyond a double's reach, bytes a message must show, a sensor
# that swallows the signal, a sweep range that rounds to one value twice
record-two-time-columns|the header names 2 columns 't'|analyze twot.csv --out x --no-plot
record-two-x-columns|the header names 2 columns 'x'|analyze twox.csv --out x --no-plot
record-two-x-columns-named|the header names 2 columns 'x'|analyze twox.csv --column x --out x --no-plot
record-times-1e300|1e+300 s is beyond 1e+30 s|analyze huge_t.csv --out x --no-plot
synth-forces-can-stall|the random forces can stall the slider|synth --set alpha=100 --duration 10 --out x
record-displacement-in-seconds|column time (s) is in s, a time unit|analyze two_clocks.csv --out x --no-plot
analyze-dt-1e300|--dt: 1e+300 s is beyond|analyze untimed.csv --dt 1e300 --out x --no-plot
record-nul-in-a-quoted-field|nul.csv: line 3: a control byte (0x00) at character 8: not a text record|analyze nul.csv --out x --no-plot
synth-resolution-huge|--resolution: 1e+308 m is no less than the whole distance slid|synth --resolution 1e308
synth-resolution-the-distance|--resolution|synth --duration 5 --resolution 2.5mm
sweep-log-rounds-twice|gives the value 10 more than once (10, 10, 11, 11, 12): N is a whole number|sweep "N=10..12 log 5" --no-plot
sweep-step-rounds-twice|more than once|sweep N=1:3:0.5 --no-plot
unknown-option|--bogus|run --bogus
# numbers a user types are decimal: CLI11 and strtod would read hexadecimal, inf and nan
set-hexadecimal|parameter alpha: '0x10' is not a decimal number|theory --set alpha=0x10
set-hexadecimal-count|parameter N: '0x10' is not a decimal number|theory --set N=0x10
set-infinity-word|parameter alpha: 'infinity' is not a finite number|theory --set alpha=infinity
option-hexadecimal|--omega-min: '0x10' is not a decimal number|run --omega-min 0x10 --no-plot
option-hexadecimal-float|--precision: '0x1p-3' is not a decimal number|run --precision 0x1p-3 --no-plot
option-hexadecimal-whole|--order: '0x1' is not a decimal number|theory --order 0x1
option-inf|--omega-max: 'inf' is not a finite number|theory --omega-max inf
analyze-dt-hexadecimal|--dt: '0x1' is not a decimal number|analyze untimed.csv --dt 0x1 --out x --no-plot
analyze-window-hexadecimal|--window: '0x1:3'|analyze rec.tsv --window 0x1:3 --out x --no-plot
analyze-resample-hexadecimal|--resample: '0x1p-7'|analyze rec.tsv --resample 0x1p-7 --out x --no-plot
# CLI11's own wordings reworded: the option, the count, the missing argument
value-missing|--out: no value after it|run --out
given-twice|--seed: given 2 times; give it once|run --seed 1 --seed 2 --no-plot
too-many-values|--fit-band: takes 2 values, got 3|analyze rec.tsv --fit-band 1 2 3 --fit power-law --out x
too-few-values|--fit-band: takes 2 values, got 1|analyze rec.tsv --fit-band 1 --fit power-law --out x
analyze-no-record|analyze: no file given; give a record to analyze|analyze
sweep-no-values-at-all|sweep: no values given|sweep
not-expected|theory: '2' was not expected|theory --omega-min 1 2
not-a-whole-number|--order: '1.5' is not a whole number|theory --order 1.5
synth-noise-beyond-the-slide|--sensor-noise: 1e+300 m is no less than the whole distance slid|synth --sensor-noise 1e300 --duration 10 --out out
touching-empty|parameter touching: '' is not a list of levels|theory --case hierarchical --set touching= --omega 1
touching-trailing-comma|parameter touching: '1,' is not a list of levels|theory --case hierarchical --set touching=1, --omega 1
touching-twice|parameter touching: '1,1' names a level twice|theory --case hierarchical --set touching=1,1 --omega 1
chain-beyond-the-theory|parameter k1: 1e+19 N/m is 1e+15 times k0, beyond the 1e+09|theory --set k1=1e19 --omega 1
theory-no-friction|parameter F_kin: 0 gives no random force|theory --set F_kin=0 --omega 1,10
synth-samples-asked|--duration / --sample-interval: 1e+09 samples|synth --duration 1000 --sample-interval 1e-6 --out out
analyze-noise-beyond-a-record|--sensor-noise: must be a length from 0 to 1e30 m|analyze rec.tsv --sensor-noise 1e200 --out x --no-plot
analyze-resolution-beyond-a-record|--resolution: must be a length from 0 to 1e30 m|analyze rec.tsv --resolution 1e200 --out x --no-plot
count-beyond-any|parameter N: '1180591620717411303424' is far beyond any count|theory --set N=1180591620717411303424 --omega 1
not-a-number|--omega-min: 'abc' is not a number|run --omega-min abc --no-plot
excludes-worded|--no-plot and --format cannot be given together|run --no-plot --format pdf
requires-worded|--set needs --compare-case|analyze rec.tsv --out x --no-plot --set alpha=1
# messages that named the wrong thing: the nearest option, the column's unit, the value as
# given, the case of a resumed run
suggest-the-nearest-option|did you mean '--omega'?|theory --omeg 5
force-column-in-a-length-unit|force column x (um) is in um, a length unit: it holds a displacement|analyze rec.tsv --observable force --force-column x --out x --no-plot
record-value-just-beyond-1e30|1.0004e+30 m is beyond 1e+30 m|analyze big30.csv --out x --no-plot
resume-another-case|a resumed run takes its case and parameters from its state|run --resume part --case fast --no-plot
resume-state-file-another-case|part.state holds a run of case 'reference'|run --resume part.state --case fast --no-plot
N-beyond-memory|parameter N: the tree would have 1000000000 blocks|run --set N=1e9 --no-plot
a-renewal-time-beyond-the-step|parameter a: 1e+90 m makes the renewal time a/v = 2e+93 s|run --set a=1e90 --omega-min 1 --omega-max 100 --no-plot
stall-beyond-the-theory|parameters F_drive, v: eta1 = (F_drive - F_kin) / (touching mass x v) = 6.66726e-06 1/s|run --set F_drive=5.000000000001 --no-plot
v-beyond-the-theory|v at most 2.08333e+06 m/s|run --set v=1e90 --omega-min 1 --omega-max 100 --no-plot
# values that would read as "not given" and be ignored
params-key-beside-its-block|alpha is given outside its "parameters" block|theory --params outer.json
synth-params-key-beside-its-block|alpha is given outside its "parameters" block|synth --params outer.json
params-standard-input|--params: '-' (standard input) is not read here|run --params - --no-plot
omega-file-standard-input|--omega-file: '-' (standard input) is not read here|theory --omega-file -
params-device-no-dash-hint|--params: /dev/zero is a device, not a file|theory --params /dev/zero
synth-zero-strokes|--strokes: must be a whole number of strokes from 1|synth --strokes 0 --stroke-length 1mm --out x
analyze-slider-mass-zero|--slider-mass: must be a mass > 0|analyze rec.tsv --slider-mass 0 --compare-case rig --machine-stiffness 1e6 --out x --no-plot
analyze-slider-mass-negative|--slider-mass: must be a mass > 0|analyze rec.tsv --slider-mass -1 --out x --no-plot
analyze-slider-mass-nan|--slider-mass|analyze rec.tsv --slider-mass nan --out x --no-plot
TABLE

echo "bad inputs: $tried tried, $failures failed"
[ "$sample" -gt 1 ] || [ "$tried" -ge 100 ] || fail "the table holds fewer than 100 bad inputs"
[ $failures -eq 0 ] && echo "bad inputs: all refused cleanly"
exit $((failures > 0))
