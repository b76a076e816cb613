#!/usr/bin/env bash
# End-to-end checks of slidespec synth and analyze: files written, refusals with exit
# status 2, one line naming the problem, and no output file touched.
source "$(dirname "$0")/common.sh"

# A short synthetic record (60 s at 1 kHz, a fine sensor so that a band shows) through the whole path.
"$bin" synth --set alpha=0.4 --duration 60 --resolution 1e-8 --sensor-noise 5e-9 --out "$work/rec" 2> "$work/synth.err" || fail "synth failed: $(cat "$work/synth.err")"
[ "$(grep -vc '^#' "$work/rec.csv")" -eq 60002 ] || fail "synth: expected a header and 60001 samples"
grep -q "^t (s),x (um)$" "$work/rec.csv" || fail "synth: no t (s),x (um) header"
"$bin" analyze "$work/rec.csv" --units um --resolution 1e-8m --sensor-noise 5e-9m --fit-slope 30 100 \
  --compare-case reference --set alpha=0.4 --fit alpha --fit-band 30 100 --normal-mass 2 --driving-mass 1 \
  --out "$work/an" 2> "$work/an.err" || fail "analyze failed: $(cat "$work/an.err")"
for ext in tsv json png; do [ -s "$work/an.$ext" ] || fail "analyze wrote no .$ext"; done
grep -q "^# omega	C_x	stderr	floor	below_floor	n_avg	bandwidth	C_v	dof	segment	leaky	C_low	C_high	fit	theory$" "$work/an.tsv" || fail "analyze table header"
grep -q "^# mu = 0.5 " "$work/an.tsv" || fail "mu = M'/M not reported"
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
# Values whose squares leave a double would give inf or nan where a spectrum is claimed.
printf 't,x\n0,1\n0.001,1e158\n0.002,3\n' > "$work/huge.csv"
expect_refused huge-values "line 3: 1e+158 m is beyond 1e+30 m" analyze "$work/huge.csv" $out
# Endless streams end, with a message: a stream without newlines at its first long line,
# from a pipe and from a named pipe (a stream of lines ends at the 1 GiB record cap).
timeout 60 bash -c "yes 1 | tr -d '\n' | '$bin' analyze - --out '$work/endless'" 2> "$work/stream.err"
status=$?
[ $status -eq 2 ] || fail "analyze of an endless line through a pipe exited $status, expected 2"
grep -q "line 1: longer than 65536 characters" "$work/stream.err" || fail "no cap named: $(cat "$work/stream.err")"
mkfifo "$work/fifo"
( yes 1 | tr -d '\n' > "$work/fifo" 2> /dev/null & )
timeout 60 "$bin" analyze "$work/fifo" --out "$work/endless" 2> "$work/stream.err"
status=$?
[ $status -eq 2 ] || fail "analyze of an endless named pipe exited $status, expected 2"
grep -q "longer than 65536 characters" "$work/stream.err" || fail "no cap named: $(cat "$work/stream.err")"
# A binary stream ends at its first byte that no text holds.
timeout 60 bash -c "cat /dev/zero | '$bin' analyze - --out '$work/endless'" 2> "$work/stream.err"
status=$?
[ $status -eq 2 ] || fail "analyze of /dev/zero through a pipe exited $status, expected 2"
grep -q "stdin: line 1: a control byte (0x00) at character 1: not a text record" "$work/stream.err" \
  || fail "/dev/zero not named binary: $(cat "$work/stream.err")"
ls "$work" | grep -q "^endless\." && fail "a refused endless read wrote outputs"
expect_refused bad-units furlong analyze "$work/rec.csv" --units furlong $out
expect_refused fit-beta "not a model parameter a fit can vary" analyze "$work/rec.csv" --fit beta --compare-case reference $out
expect_refused fit-without-case "compare-case" analyze "$work/rec.csv" --fit alpha $out
expect_refused unknown-case slow analyze "$work/rec.csv" --compare-case slow $out
expect_refused empty-slope-band "fit-slope" analyze "$work/rec.csv" --units um --fit-slope 1e4 2e4 $out
expect_refused bad-mass "normal-mass" analyze "$work/rec.csv" --normal-mass -1 --driving-mass 1 $out
expect_refused analyze-missing-directory "does not exist" analyze "$work/rec.csv" --out "$work/nowhere/x"
expect_refused synth-bad-interval "sample-interval" synth --sample-interval -1 $out
expect_refused synth-bad-case slow synth --case slow $out
expect_refused synth-missing-directory "does not exist" synth --out "$work/nowhere/x"
expect_refused fit-typo "did you mean 'alpha'" analyze "$work/rec.csv" --fit alhpa --compare-case reference $out
printf 'x (mm)\n0.001\n0.002\n0.003\n' > "$work/short.csv"
expect_refused too-short "too short" analyze "$work/short.csv" --dt 0.001 $out

# synth takes --params as run does, and labels its record as run labels its tables.
echo '{"N": 10, "alpha": 0.5}' > "$work/params.json"
"$bin" synth --params "$work/params.json" --duration 5 --out "$work/labelled" 2> "$work/labelled.err" \
  || fail "synth --params failed: $(cat "$work/labelled.err")"
grep -q "^# label = reference + N=10, alpha=0.5$" "$work/labelled.csv" || fail "synth: no label line for --params"
cp "$work/params.json" "$work/clash.csv"
expect_refused synth-replaces-params "would replace the input" synth --params "$work/clash.csv" --out "$work/clash"

# One column headed "x (mm)" (a unit in brackets stays with its name), sampled every --dt.
{ echo "x (mm)"; awk 'NR > 1 { print $2 }' FS=, "$work/rec.csv" | head -20000 | awk '{ printf "%.9g\n", $1 / 1000 }'; } \
  > "$work/one_column.txt"
"$bin" analyze "$work/one_column.txt" --dt 0.001 --out "$work/one" --no-plot 2> "$work/one.err" \
  || fail "one column headed 'x (mm)' refused: $(cat "$work/one.err")"
grep -q "read in mm (from header)" "$work/one.err" || fail "one column 'x (mm)': unit not read from the header: $(cat "$work/one.err")"

# Units from the header: the same record in mm, headed "time (s),position (mm)", gives the
# same speed; a bare --resolution is in the record's unit, one with a unit is converted.
speed() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['measured_mean_speed']['value'])" "$1"; }
awk -F, '/^#/ {next} $1 ~ /^[0-9-]/ {printf "%s,%.12g\n", $1, $2 / 1000; next} {print "time (s),position (mm)"}' "$work/rec.csv" > "$work/mm.csv"
"$bin" analyze "$work/mm.csv" --resolution 1e-5 --sensor-noise 5e-9m --quiet --no-plot --out "$work/mm" || fail "analyze of a mm record"
v_um=$(speed "$work/an.json"); v_mm=$(speed "$work/mm.json")
/usr/bin/python3 -c "import sys; a, b = map(float, sys.argv[1:]); sys.exit(abs(a - b) > 1e-9 * abs(a) or not 4e-4 < a < 6e-4)" "$v_um" "$v_mm" \
  || fail "units from the header: v = $v_mm m/s from mm, $v_um m/s from um"
grep -q '^# units = mm  # of the displacement column, from header' "$work/mm.tsv" || fail "mm record: unit source not reported"
grep -q '^# resolution = 1e-08' "$work/mm.tsv" || fail "--resolution 1e-5 in a mm record is not 1e-8 m"
for header in "t_s,x_mm" "t [s],x [mm]" "time,mm"; do
  sed "1,/^time/s/^time (s),position (mm)\$/$header/" "$work/mm.csv" > "$work/h.csv"
  "$bin" analyze "$work/h.csv" --quiet --no-plot --out "$work/h" || fail "header '$header' not read"
  [ "$(speed "$work/h.json")" = "$v_mm" ] || fail "header '$header': v = $(speed "$work/h.json"), expected $v_mm"
done
# A byte order mark is ignored; '-' reads standard input; --units gives a unit the header does
# not (and is refused where it contradicts one, below).
{ printf '\xEF\xBB\xBF'; cat "$work/mm.csv"; } | "$bin" analyze - --quiet --no-plot --out "$work/bom" || fail "BOM or stdin"
[ "$(speed "$work/bom.json")" = "$v_mm" ] || fail "stdin with a BOM: another speed"
sed 's/^t (s),x (um)$/t (s),x/' "$work/rec.csv" > "$work/bare.csv"
"$bin" analyze "$work/bare.csv" --units m --no-plot --out "$work/over" 2> "$work/over.err"
grep -q "implausible.*read in m (from --units)" "$work/over.err" || fail "no implausible-speed warning naming the unit: $(cat "$work/over.err")"
# An empty usable band (a resolution given in the wrong unit: 10 mm for 10 um) is warned about
# with its cause when the floor lies above the spectrum everywhere.
"$bin" analyze "$work/mm.csv" --resolution 10 --quiet --no-plot --out "$work/floor" 2> "$work/floor.err"
grep -q "no usable band: the sensor floor lies above the spectrum everywhere.*wrong unit" "$work/floor.err" || fail "empty usable band not explained: $(cat "$work/floor.err")"
grep -q '"floor_above_spectrum": true' "$work/floor.json" || fail "floor above the spectrum: not in the JSON"
grep -q "^# usable_band = none  # " "$work/floor.tsv" || fail "empty usable band: the table says $(grep usable_band "$work/floor.tsv")"
/usr/bin/python3 -c "
import json; b = json.load(open('$work/floor.json'))['usable_band']
assert b['empty'] and b['omega_low'] == b['omega_high'] == 0 and b['top_set_by'].startswith('none'), b" || fail "empty usable band: the JSON does not say none"
printf 't;x\n0;0,001\n0,001;0,002\n' > "$work/comma.csv"
expect_refused decimal-comma "decimal commas" analyze "$work/comma.csv" $out
expect_refused bad-resolution "resolution" analyze "$work/mm.csv" --resolution 1furlong $out
expect_refused units-typo "did you mean 'um'" analyze "$work/mm.csv" --units uum $out

# A failed fit: a random walk (slope -2) against the model's omega^-4 is reported as failed,
# with ok = false in both files and exit status 3, and its alpha not printed as a result.
/usr/bin/python3 -c "
import numpy as np; r = np.random.default_rng(1); n = 200000
x = np.cumsum(r.normal(0, 1e-7, n)) + 5e-4 * np.arange(n) * 1e-3
np.savetxt('$work/walk.csv', np.c_[np.arange(n) * 1e-3, x], delimiter=',', header='t,x', comments='')"
"$bin" analyze "$work/walk.csv" --compare-case reference --fit alpha --fit-band 1 100 --no-plot --out "$work/walk" 2> "$work/walk.err"
status=$?
[ $status -eq 3 ] || fail "failed fit: exit status $status, expected 3"
grep -q "alpha fit FAILED: chi2/dof" "$work/walk.err" || fail "failed fit not reported: $(cat "$work/walk.err")"
grep -q "alpha = " "$work/walk.err" && fail "a failed alpha printed as a result"
grep -q '^  "ok": false' "$work/walk.json" || fail "failed fit: JSON ok is not false"
grep -q '^# alpha_fit_ok = false' "$work/walk.tsv" || fail "failed fit: TSV does not say so"
grep -q '^  "ok": true' "$work/an.json" || fail "a good fit is not ok = true"

# The measured records (tests/data/realdata, MIT, see its README): segments found, both sides
# of each velocity step analyzed with --window alone, the band from ~9 x 2 pi / T up.
data=$(dirname "$0")/../data/realdata
sepiolite=$data/velstep3_TR2_exp013_sepiolite.txt
basalt=$data/velstep4_BRAVA_expb819_basalt.txt
"$bin" analyze "$sepiolite" --segments > "$work/seg3.txt" 2> "$work/seg3.err" || fail "segments of the sepiolite record: $(cat "$work/seg3.err")"
[ "$(grep -c 'sliding$' "$work/seg3.txt")" -eq 2 ] || fail "sepiolite: expected 2 sliding segments: $(cat "$work/seg3.txt")"
grep -q "linear interpolation" "$work/seg3.err" || fail "sepiolite: resampling not said"
"$bin" analyze "$basalt" --segments --resample 0.1 > "$work/seg4.txt" 2>/dev/null || fail "segments of the basalt record"
[ "$(grep -c 'sliding$' "$work/seg4.txt")" -eq 2 ] || fail "basalt: expected 2 sliding segments: $(cat "$work/seg4.txt")"
# Without --resample the basalt record's two sampling rates are listed part by part, each
# with the --window that picks it and its own steady speed.
"$bin" analyze "$basalt" --segments > "$work/seg5.txt" 2>/dev/null || fail "segments of the basalt record by parts"
[ "$(grep -c '^# part [12]: ' "$work/seg5.txt")" -eq 2 ] || fail "basalt: parts not listed: $(cat "$work/seg5.txt")"
# The step comes 2 s into the second part: its first 2 s are the slower sliding.
[ "$(grep 'sliding$' "$work/seg5.txt" | cut -f4 | tr '\n' ' ')" = "3.02e-06 3e-06 1e-05 " ] ||
  fail "basalt: the parts' steady speeds: $(cat "$work/seg5.txt")"

# Records made here: a slide-hold-slide with a velocity step, and a reciprocating record of 50
# strokes; the table and JSON say what each segment is, and how many strokes were averaged.
/usr/bin/python3 - "$work" <<'PY'
import math, random, sys
random.seed(4)
def write(name, speed, duration):
    x = walk = 0.0
    with open(f"{sys.argv[1]}/{name}.csv", "w") as f:
        f.write("t,x_um\n")
        for k in range(int(duration / 0.01)):
            t = k * 0.01
            x += speed(t) * 0.01
            walk += random.gauss(0, 0.002)
            f.write(f"{t:.2f},{x + walk + random.gauss(0, 0.02):.6f}\n")
write("shs", lambda t: 10 if t < 100 else 0 if t < 105 else 30 if t < 200 else 3, 400)
write("strokes", lambda t: 100 if math.fmod(t, 40) < 20 else -100, 1000)
PY
"$bin" analyze "$work/shs.csv" --no-plot --out "$work/shs" 2> "$work/shs.err" || fail "slide-hold-slide: $(cat "$work/shs.err")"
grep -q '^# segment = .* hold ' "$work/shs.tsv" || fail "slide-hold-slide: no hold in the table: $(grep segment "$work/shs.tsv")"
grep -q "analyzing the longest sliding one, 20[0-9.]*:399" "$work/shs.err" || fail "slide-hold-slide: not the 3 um/s stretch: $(cat "$work/shs.err")"
/usr/bin/python3 -c "
import json, sys
kinds = [s['kind'] for s in json.load(open(sys.argv[1]))['segments']]
sys.exit(kinds.count('hold') != 1 or kinds.count('sliding') != 3 or 'step' not in kinds)" "$work/shs.json" ||
  fail "slide-hold-slide: JSON segments $(grep -c kind "$work/shs.json")"
"$bin" analyze "$work/strokes.csv" --no-plot --out "$work/strokes" 2> "$work/strokes.err" || fail "strokes: $(cat "$work/strokes.err")"
grep -q '^# strokes = 50 ' "$work/strokes.tsv" || fail "strokes: the table does not say 50 strokes"
grep -q "a reciprocating record: 50 strokes at 0.0001 m/s" "$work/strokes.err" || fail "strokes: not said: $(cat "$work/strokes.err")"
/usr/bin/python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
s = d['strokes']
sys.exit(s['count'] != 50 or abs(s['speed'] - 1e-4) > 1e-6 or abs(d['points'][0]['omega'] / s['lowest_omega'] - 1) > 0.2)" "$work/strokes.json" ||
  fail "strokes: JSON $(grep -A4 '"strokes"' "$work/strokes.json")"

for case in "$sepiolite 20100:21290 2e-07" "$sepiolite 21350:22319 2e-06" "$basalt 11608:11674 3.02e-06" "$basalt 11675:11726 1e-05"; do
  set -- $case
  "$bin" analyze "$1" --window "$2" --no-plot --out "$work/real" 2> "$work/real.err" || fail "analyze $1 --window $2: $(cat "$work/real.err")"
  /usr/bin/python3 - "$work/real.json" "$3" <<'PY' || fail "analyze $1 --window $2: band or speed"
import json, math, sys
doc = json.load(open(sys.argv[1]))
T = doc["record"]["duration"]
lowest = doc["points"][0]["omega"]
speed = doc["measured_mean_speed"]["value"]
assert lowest <= 1.5 * 10 * 2 * math.pi / T, (lowest, T)
assert abs(speed / float(sys.argv[2]) - 1) < 0.05, speed
assert doc["estimator"]["name"] == "welch"
PY
done
"$bin" analyze "$basalt" --no-plot --out "$work/real" 2> "$work/real.err" || fail "basalt without options"
grep -q "rate changes inside the record" "$work/real.err" || fail "basalt: the rate change is not said"
# The part analysed is the longest in time, said so, and the part with the most samples named
# with the --window that picks it.
grep -q "longest part in time, 11607.7..11674.2 s.*the part 11674.21..11726.03 s holds the most samples (5183).*--window 11674.21:11726.03 picks it" "$work/real.err" || fail "basalt: the part analysed and the one with the most samples not said: $(cat "$work/real.err")"
"$bin" analyze "$basalt" --window 11674.21:11726.03 --no-plot --out "$work/most" 2> "$work/most.err" || fail "basalt: the --window the note gives is refused: $(cat "$work/most.err")"
# Resampled, the band stops where interpolation filters the coarsest input interval analysed:
# the basalt's longest steady segment was read every 0.1 s, so acos(0.85) / 0.1 s = 5.5 rad/s,
# and below it the spectrum is the unresampled one's within the error bars.
"$bin" analyze "$basalt" --resample median --no-plot --out "$work/rsm" 2> "$work/rsm.err" || fail "basalt --resample median: $(cat "$work/rsm.err")"
"$bin" analyze "$basalt" --window 11608:11674 --no-plot --out "$work/real" 2> /dev/null || fail "basalt --window 11608:11674"
/usr/bin/python3 - "$work/rsm.json" "$work/real.json" <<'PY' || fail "basalt --resample median: band beyond the 0.1 s samples' interpolation cut: $(cat "$work/rsm.err")"
import json, math, sys
import numpy as np
resampled, raw = (json.load(open(name)) for name in sys.argv[1:])
cut = math.acos(0.85) / 0.1
assert abs(resampled["record"]["dt"] - 0.01) < 1e-9, resampled["record"]
assert resampled["usable_band"]["omega_high"] <= cut, resampled["usable_band"]
assert "0.1 s" in resampled["usable_band"]["top_set_by"], resampled["usable_band"]
assert any("input interval 0.1 s" in note for note in resampled["notes"]), resampled["notes"]
omega = np.log([p["omega"] for p in raw["points"]])
for p in resampled["points"]:
    assert p["omega"] <= cut, p
    c, se = (math.exp(np.interp(math.log(p["omega"]), omega, np.log([q[k] for q in raw["points"]]))) for k in ("C_x", "stderr"))
    assert abs(p["C_x"] - c) < 2 * math.hypot(p["stderr"], se), (p["omega"], p["C_x"], c)
PY
# What set the top of the band, one thing named: the bin below Nyquist, or the omega_max asked for.
grep -q "^# usable_band = .*top set by the bin below Nyquist$" "$work/real.tsv" || fail "basalt: top of the band: $(grep usable_band "$work/real.tsv")"
"$bin" analyze "$basalt" --window 11608:11674 --omega-max 10 --no-plot --out "$work/top" 2> /dev/null || fail "basalt --omega-max 10"
grep -q "^# usable_band = .*top set by the omega_max asked for$" "$work/top.tsv" || fail "basalt --omega-max 10: top of the band: $(grep usable_band "$work/top.tsv")"
# A power law with the floor, jointly: parameters with errors, or a failure said so (exit 3).
"$bin" analyze "$basalt" --window 11608:11674 --fit power-law --no-plot --out "$work/pl" 2> "$work/pl.err" || fail "power-law fit on the basalt record: $(cat "$work/pl.err")"
/usr/bin/python3 -c "
import json; f = json.load(open('$work/pl.json'))['power_law_fit']
assert f['ok'] and f['slope_error'] > 0 and f['floor_error'] > 0 and f['amplitude_error'] > 0, f
assert 'compare-case' in f['undetermined']" || fail "power-law fit: parameters without errors"
"$bin" analyze "$sepiolite" --window 21350:22319 --fit power-law --no-plot --out "$work/pl" 2> "$work/pl.err"
status=$?
if [ $status -eq 3 ]; then
  grep -q "power-law fit FAILED" "$work/pl.err" || fail "power-law exit 3 without FAILED"
  grep -q '^  "ok": false' "$work/pl.json" || fail "power-law exit 3 with ok not false"
else
  [ $status -eq 0 ] || fail "power-law fit on the sepiolite record: status $status"
fi
# A model fit on the machine's terms that cannot describe the slip: exit 3, ok false, FAILED.
"$bin" analyze "$basalt" --window 11608:11674 --contact-area 25cm2 --machine-stiffness 0.001MPa/um --compare-case reference --fit alpha,a --no-plot --out "$work/mf" 2> "$work/mf.err"
[ $? -eq 3 ] && grep -q "model fit FAILED" "$work/mf.err" && grep -q '^# model_fit_ok = false' "$work/mf.tsv" && grep -q '"drive": "spring"' "$work/mf.json" || fail "failed model fit: not exit 3 with FAILED, ok false and the spring drive"
# An alpha fit whose alpha lies where the block can stall (no theory beyond first order to
# refit with): the work is written as a failed fit, exit 3, not refused as bad input.
"$bin" analyze "$basalt" --window 11608:11674 --compare-case reference --fit alpha --no-plot --out "$work/fa" 2> "$work/fa.err"
status=$?
[ $status -eq 3 ] && grep -q "alpha fit FAILED" "$work/fa.err" && grep -q "^# alpha_fit_ok = false.*no theory beyond it holds" "$work/fa.tsv" || fail "alpha fit into the stall: status $status, not a failed fit: $(cat "$work/fa.err")"
/usr/bin/python3 -c "
import json; f = json.load(open('$work/fa.json'))['alpha_fit']
assert not f['ok'] and f['theory_order'] == 1 and 'no theory beyond it holds' in f['failure'], f" || fail "alpha fit into the stall: JSON"
grep -q "^# columns: .*theory \[m^2 s\] the model's first-order theory" "$work/fa.tsv" \
  || fail "alpha fit into the stall: the theory column is not the first order it was fitted with"
expect_refused window-across-rates "sampling rate changes inside --window" analyze "$basalt" --window 11600:11700 $out
expect_refused window-outside "record runs from" analyze "$basalt" --window 0:100 $out
expect_refused window-syntax "T0:T1" analyze "$basalt" --window 100 $out
expect_refused friction-column "not a displacement" analyze "$basalt" --column Friction $out
# The normal stress is mu's normal load: not a displacement, nor a friction force.
expect_refused normal-stress-column "names a normal load, not a displacement" analyze "$basalt" --column Normal_stress $out
grep -q "give it as --force-column" "$work/stderr" && fail "--column Normal_stress: advised as --force-column"
expect_refused normal-stress-force "^slidespec: error: .*--force-column Normal_stress: the header names a normal load" analyze "$basalt" --force-column Normal_stress --contact-area 25cm2 $out
# A column named by its header without the unit in brackets: Displ for Displ(microns).
"$bin" analyze "$basalt" --window 11608:11674 --column Displ --no-plot --out "$work/col" 2> "$work/col.err" || fail "--column Displ for Displ(microns): $(cat "$work/col.err")"
grep -q "^# observable = displacement.*of column Displ(microns)$" "$work/col.tsv" || fail "--column Displ: $(grep observable "$work/col.tsv")"
expect_refused dt-with-time "has a time column" analyze "$basalt" --dt 0.1 $out
expect_refused resample-word "median" analyze "$basalt" --resample mean $out
# An 11 s gap in a record every second: the refusal suggests what analyze accepts (the
# stretch before the gap, or interpolation), never a tolerance beyond its limit.
/usr/bin/python3 -c "
print('t,x')
for k in range(3000): print(f'{k + (11 if k >= 1500 else 0)},{1e-6 * k}')" > "$work/gap.csv"
expect_refused gap-advice "give --window 0:1499 to analyze the longest stretch without a gap" analyze "$work/gap.csv" $out
grep -q "time-tolerance" "$work/stderr" && fail "gap: a --time-tolerance suggested: $(cat "$work/stderr")"
"$bin" analyze "$work/gap.csv" --window 0:1499 --quiet --no-plot --out "$work/gap" || fail "gap: the suggested --window is refused"
expect_refused tolerance-too-wide "^slidespec: error: --time-tolerance: must lie between 0 and 0.5" analyze "$work/gap.csv" --time-tolerance 10.01 $out
# A band no spectrum has is refused before the record is read, naming the option.
expect_refused omega-max-negative "^slidespec: error: --omega-max: -1 is not a frequency > 0" analyze "$basalt" --omega-max -1 $out
expect_refused omega-min-negative "^slidespec: error: --omega-min: -2 is not a frequency > 0" analyze "$basalt" --omega-min -2 $out
expect_refused omega-min-above-max "^slidespec: error: --omega-min 5 must be below --omega-max 3" analyze "$basalt" --omega-min 5 --omega-max 3 $out
expect_refused omega-min-is-max "must be below --omega-max" analyze "$basalt" --omega-min 3 --omega-max 3 $out
# A model fit over the default band, the usable one, when there is none says so.
expect_refused model-fit-no-band "^slidespec: error: --fit alpha,a: no usable band (the sensor floor exceeds 10%" analyze "$basalt" --window 11608:11674 --resolution 100 --compare-case reference --fit alpha,a $out
# A plausible resolution whose floor lies below the spectrum at the lowest point, but above a
# tenth of it: the rule is said, not a unit blamed; the basalt readings are finer than 0.6 um.
"$bin" analyze "$basalt" --resolution 0.6 --quiet --no-plot --out "$work/floor6" 2> "$work/floor6.err"
grep -q "no usable band: at the lowest point, where the band starts, the spectrum does not clear the sensor floor by the factor the usable band needs (the floor at most 10% of C_x; it is 15.9% there)" "$work/floor6.err" || fail "0.6 um: the usable band's rule not said: $(cat "$work/floor6.err")"
grep -q "wrong unit\|not white" "$work/floor6.err" && fail "0.6 um: a wrong unit or a non-white quantization blamed: $(cat "$work/floor6.err")"
grep -q "steps are not whole multiples of the --resolution given" "$work/floor6.err" || fail "0.6 um: the finer readings not said: $(cat "$work/floor6.err")"
expect_refused omega-min-too-low "reaches down to" analyze "$basalt" --window 11608:11674 --omega-min 0.01 $out

# The friction channel as a force (mu x normal stress x area) and the slip x - F/K, on both
# records: the observable said in the table, the JSON and the spectrum's column.
"$bin" analyze "$basalt" --window 11608:11674 --observable force --contact-area 25cm2 --out "$work/force" \
  2> "$work/force.err" || fail "basalt force channel: $(cat "$work/force.err")"
grep -q "^# observable = force  # C_F \[N^2 s\] of force Friction (mu) x Normal_stress(MPa) x contact area 0.0025 m^2" \
  "$work/force.tsv" || fail "force: observable line"
grep -q "^# omega	C_F	stderr" "$work/force.tsv" || fail "force: the spectrum column is not C_F"
[ -s "$work/force.png" ] || fail "force: no figure"
"$bin" analyze "$sepiolite" --window 21350:22319 --machine-stiffness 0.01MPa/um --contact-area 25cm2 --no-plot \
  --out "$work/slip" 2> "$work/slip.err" || fail "sepiolite slip: $(cat "$work/slip.err")"
/usr/bin/python3 -c "
import json; d = json.load(open('$work/slip.json'))
assert d['observable']['name'] == 'slip' and d['observable']['machine_stiffness'] == 2.5e7, d['observable']
assert 'C_x' in d['points'][0] and abs(d['measured_mean_speed']['value'] / 2e-6 - 1) < 0.05" || fail "slip: JSON"
expect_refused area-unused "applies to a force channel" analyze "$basalt" --contact-area 25cm2 $out
expect_refused mu-needs-area "give --contact-area" analyze "$basalt" --observable force $out
expect_refused stiffness-needs-area "needs --contact-area" analyze "$basalt" --machine-stiffness 0.01MPa/um $out
expect_refused stiffness-with-force "gives the slip" analyze "$basalt" --observable force --machine-stiffness 1e9 $out
expect_refused force-units-typo "did you mean 'kN'" analyze "$basalt" --observable force --force-units kNN $out
expect_refused observable-typo "did you mean 'slip'" analyze "$basalt" --observable slp $out
expect_refused force-compare "drive = spring" analyze "$basalt" --observable force --contact-area 25cm2 --compare-case reference $out
expect_refused force-resolution "displacement sensor" analyze "$basalt" --window 11608:11674 --observable force --contact-area 25cm2 --resolution 0.1um $out
printf 't,Displ(km)\n0,1\n1,2\n2,3\n' > "$work/km.csv"
expect_refused unknown-length-unit "not a length unit analyze knows (m, cm, mm" analyze "$work/km.csv" $out

# Headers as labs write them, read with no column option: a biaxial rig's (Penn State-style:
# Time(sec), LP_disp(micron), stresses in MPa, mu, effns_mpa) and an instrument's export with a
# preamble and a units row (CETR/Bruker UMT: forces in gram-force, positions in mm, time in sec).
/usr/bin/python3 -c "
import random
random.seed(5)
print('Time(sec)\tLP_disp(micron)\tShr_stress(MPa)\tNor_disp(micron)\tNor_stress(MPa)\tmu\teffns_mpa')
for k in range(3000):
    print(f'{20000 + 0.1 * k:.1f}\t{0.5 * k + random.gauss(0, 0.2):.3f}\t{12 + random.gauss(0, 0.01):.4f}\t300\t20\t0.6\t19.5')" > "$work/rig.txt"
"$bin" analyze "$work/rig.txt" --no-plot --out "$work/rig" 2> "$work/rig.err" || fail "biaxial rig's headers: $(cat "$work/rig.err")"
grep -q "^# observable = displacement  # C_x \[m^2 s\] of column LP_disp(micron)$" "$work/rig.tsv" || fail "rig: $(grep observable "$work/rig.tsv")"
grep -q "^# units = um  # of the displacement column, from header" "$work/rig.tsv" || fail "rig: $(grep units "$work/rig.tsv")"
grep -q "v = 5e-06 " "$work/rig.err" || fail "rig: the speed of 0.5 um per 0.1 s: $(cat "$work/rig.err")"
/usr/bin/python3 -c "
print('Created by CETR UMT ver.1.136.257 12 May 2022 12:21:50')
print('Run # 1')
print('Velocity     = 240')
print()
print('Fx,Fz,Z,X,V1,T,Ff,COF')
print('g,g,mm,mm,mm/sec,sec,g,')
print()
for k in range(2000):
    f = 100 + (k * 7919 % 13) / 13
    print(f'{f:.4f},-200,-0.69,{0.01 * k + 1e-4 * (k * 104729 % 17):.5f},1,{0.01 * k:.2f},{f:.4f},{f / 200:.5f}')" > "$work/umt.csv"
"$bin" analyze "$work/umt.csv" --no-plot --out "$work/umt" 2> "$work/umt.err" || fail "instrument export: $(cat "$work/umt.err")"
grep -q "^# observable = displacement  # C_x \[m^2 s\] of column X (mm)$" "$work/umt.tsv" || fail "umt: $(grep observable "$work/umt.tsv")"
grep -q "note: lines 1-3 above the header (line 5) are the file's preamble, not read" "$work/umt.err" || fail "umt: preamble not said: $(cat "$work/umt.err")"
grep -q "v = 0.001 " "$work/umt.err" || fail "umt: the speed of 0.01 mm per 0.01 s: $(cat "$work/umt.err")"
"$bin" analyze "$work/umt.csv" --observable force --no-plot --out "$work/umtf" 2> "$work/umtf.err" || fail "instrument export, force: $(cat "$work/umtf.err")"
grep -q "^# observable = force  # C_F \[N^2 s\] of force Fx (g)$" "$work/umtf.tsv" || fail "umt force: $(grep observable "$work/umtf.tsv")"
# A time unit analyze does not know is refused, as a length unit is: never read as seconds.
printf 't (days),x (um)\n0,1\n1,2\n2,3\n' > "$work/days.csv"
expect_refused unknown-time-unit "column t (days): 'days' is not a time unit analyze knows (s (sec), ms" analyze "$work/days.csv" $out
printf 'T (days),x (um)\n0,1\n1,2\n2,3\n' > "$work/days.csv"
expect_refused unknown-time-unit-named "time column T (days): 'days' is not a time unit" analyze "$work/days.csv" --time-column T $out
# Unit options that contradict the header: refused naming both, before any work.
expect_refused units-contradict "--units mm contradicts the header of column LP_disp(micron), which gives um" analyze "$work/rig.txt" --units mm $out
expect_refused force-units-stress "--force-units kN contradicts the header of column Shr_stress(MPa), which gives MPa" analyze "$work/rig.txt" --observable force --force-units kN --contact-area 25cm2 $out
expect_refused force-units-mu "--force-units MPa contradicts the header of column mu, which names a friction coefficient" analyze "$work/rig.txt" --force-column mu --force-units MPa --contact-area 25cm2 $out
expect_refused force-units-friction "--force-units MPa contradicts the header of column Friction, which names a friction coefficient" analyze "$basalt" --observable force --force-units MPa --contact-area 25cm2 $out
printf 't (s),x (um),Friction [uN]\n0,1,70\n1,2,71\n2,3,72\n' > "$work/micro.csv"
expect_refused force-units-micro "--force-units N contradicts the header of column Friction \[uN\], which gives uN" analyze "$work/micro.csv" --observable force --force-units N $out
# A power law stuck at the edge of its slope's search (a record whose lowest point towers
# over a white rest): FAILED, ok false, exit 3, as a model fit there.
/usr/bin/python3 -c "
import math, random
random.seed(1)
print('t,x (um)')
for k in range(400): print(f'{0.1 * k:.1f},{0.05 * k + 2 * math.sin(2 * math.pi * 3 * k / 400) + random.gauss(0, 0.05):.5f}')" > "$work/cliff.csv"
"$bin" analyze "$work/cliff.csv" --fit power-law --no-plot --out "$work/cliff" 2> "$work/cliff.err"
status=$?
[ $status -eq 3 ] || fail "power law at the edge of its search: exit $status, expected 3"
grep -q "power-law fit FAILED: the slope -10 ran to the edge of its search range" "$work/cliff.err" || fail "power law at the edge: $(cat "$work/cliff.err")"
/usr/bin/python3 -c "
import json; f = json.load(open('$work/cliff.json'))['power_law_fit']
assert not f['ok'] and f['slope_at_search_edge'] and 'edge of its search range' in f['failure'], f" || fail "power law at the edge: JSON"

[ $failures -eq 0 ] && echo "cli_analyze: all checks passed"
exit $((failures > 0))
