#!/usr/bin/env bash
# An adversarial user's sweep over every command, option class, input file and signal.
# Each attack either must be refused (exit 2, one line, nothing touched: "refuse") or
# must work ("work": exit 0, its outputs there), or is a signal scenario. It counts
# crashes (a signal or "failed:"), hangs (over 30 s), inputs lost (an input's bytes
# changed), finished work lost (a run that finished or was interrupted and cannot be
# brought back bitwise) and nonsense accepted (a refusal expected, exit 0 seen).
# Usage: SLIDESPEC=build/slidespec [PYTHONPATH=build/python] tools/adversarial_sweep.sh [PART]
# PART: refusals (files, numbers, options, figures, JSON, units), results (stalls, theory,
# streams, memory, failed writes, Python: 88 attacks, 1 min), signals (interrupts, resumes,
# continued sweeps, locks: about 1.5 min), or all (the default: about 10 min on 2 busy cores;
# it prints its counts). Not part of ctest.
# PYTHONPATH may be relative: it is made absolute, as the attacks run in a scratch directory.
set -u
part=${1:-all}
case "$part" in all | refusals | results | signals) ;; *) echo "unknown part '$part'" >&2; exit 2 ;; esac
in_part() { [ "$part" = all ] || [ "$part" = "$1" ]; }
bin=$(realpath "${SLIDESPEC:?set SLIDESPEC to the slidespec executable}")
if [ -n "${PYTHONPATH:-}" ]; then
  absolute=""
  IFS=: read -ra entries <<< "$PYTHONPATH"
  for entry in "${entries[@]}"; do absolute+="$(realpath -m "$entry"):"; done
  export PYTHONPATH=${absolute%:}
fi
work=$(mktemp -d)
logs=$(mktemp -d)
trap 'rm -rf "$work" "$logs"' EXIT
cd "$work" || exit 1

attacks=0 crashes=0 hangs=0 inputs_lost=0 work_lost=0 nonsense=0 other=0
report() { echo "  $1: $2"; }

# Inputs lying around.
echo '{"alpha": 0.5}' > p.json
"$bin" synth --duration 5 --sample-interval 0.01 --out rec > /dev/null 2>&1
"$bin" theory --out table > /dev/null 2>&1
band="--omega-min 100 --omega-max 1000"
"$bin" run $band --realizations-range 0:8 --save-state part.state --out part --no-plot --quiet
"$bin" run $band --realizations-range 8:8 --save-state part8.state --out part8 --no-plot --quiet
mkdir adir
cp p.json fig.pdf; cp p.json fig.svg; cp rec.csv an.svg; cp part.state pt.svg; cp table.tsv tab.svg
cp p.json 'sw_alpha=0.6.json'; cp p.json 'sw_alpha=0.6.state'; cp p.json syn.csv
mkdir d6; cp rec.csv d6/fig6.tsv
ln -s p.json link.json; ln p.json hard.tsv
printf '{"alpha": 0.5, "alpha": 0.7}' > dup.json
printf '{"alpha": 0.5} trailing' > trail.json
printf '{"alpha": 0.5' > cut.json
printf '[1, 2]' > list.json
printf '{"alpha": true}' > bool.json
printf '{"alpha": 1e999}' > inf.json
head -c 2000000 /dev/zero | tr '\0' ' ' > big.json
printf 'garbage' > junk.state
head -c 1876 /dev/urandom > random.state
"$bin" analyze rec.csv --out an --no-plot --quiet 2> /dev/null
printf '1\n10\n' > om.tsv
printf '1\n-1\n' > om_bad.tsv
printf '# nothing\n' > om_empty.tsv
# A fifo (the results part makes one) is left out: reading it would wait for a writer.
snapshot() { find . -path ./scratch -prune -o ! -type p -print0 | sort -z | xargs -0 sha256sum 2> /dev/null; }

classify() {  # KIND NAME STATUS STDERR-FILE BEFORE
  local kind=$1 name=$2 status=$3 err=$4 before=$5
  attacks=$((attacks + 1))
  if [ "$status" -eq 124 ]; then hangs=$((hangs + 1)); report HANG "$name"; return; fi
  if [ "$status" -ge 128 ] || grep -q "failed:\|Sanitizer\|terminate called\|Traceback" "$err"; then
    crashes=$((crashes + 1)); report CRASH "$name: $status $(head -c 200 "$err")"; return
  fi
  if [ "$kind" = refuse ]; then
    if [ "$status" -eq 0 ]; then nonsense=$((nonsense + 1)); report NONSENSE "$name"; return; fi
    if [ "$before" != "$(snapshot)" ]; then inputs_lost=$((inputs_lost + 1)); report CHANGED "$name"; return; fi
    if [ "$status" -ne 2 ] || [ "$(wc -l < "$err")" -ne 1 ]; then
      other=$((other + 1)); report UNCLEAR "$name: $status $(head -c 200 "$err")"
    fi
  else
    if [ "$status" -ne 0 ]; then other=$((other + 1)); report FAILED "$name: $status $(head -c 200 "$err")"; fi
    if [ "$before" != "$(snapshot | grep -v ' ./scratch')" ] && [ "$kind" = work-keep ]; then
      inputs_lost=$((inputs_lost + 1)); report CHANGED "$name"
    fi
  fi
}

attack() {  # KIND NAME ARGS...
  local kind=$1 name=$2; shift 2
  mkdir -p scratch
  local before
  before=$(snapshot)
  (cd scratch && timeout 30 "$bin" "$@" > "$logs/stdout" 2> "$logs/stderr" < /dev/null)
  classify "$kind" "$name" $? "$logs/stderr" "$before"
  rm -rf scratch
}

# From scratch/, the inputs are one level up.
P=../p.json
R=../rec.csv
T=../table.tsv
S=../part

if in_part refusals; then
# 1. Every numeric option of every command, with every class of bad number.
for value in '' nan -nan inf -inf -1 0 1e999 -1e999 abc 1e-320 0x10 ' 5' '5 ' 1,5 1.5.5 '+' '-' 99999999999999999999999; do
  for opt in --omega-min --omega-max --precision --work-budget; do
    # A huge work budget means "no limit": a choice, not an attack.
    [ $opt = --work-budget ] && [ "$value" = 99999999999999999999999 ] && continue
    for cmd in run sweep paper; do
      extra=""
      [ $cmd = sweep ] && extra="alpha=0.5"
      [ $cmd = paper ] && extra="fig2"
      case "$value" in 1e-320 | ' 5' | '5 ') continue ;; esac
      attack refuse "$cmd $opt '$value'" $cmd $extra $opt "$value" --no-plot
    done
  done
  for opt in --points --realizations --seed --threads; do
    # A seed or thread count of 0 means something (seed 0; all cores).
    [ "$value" = 0 ] && { [ $opt = --seed ] || [ $opt = --threads ]; } && continue
    attack refuse "run $opt '$value'" run $opt "$value" --no-plot
  done
  # Padded spellings are numbers: not attacks for the commands below.
  case "$value" in ' 5' | '5 ') continue ;; esac
  attack refuse "theory --omega-min '$value'" theory --omega-min "$value"
  attack refuse "synth --duration '$value'" synth --duration "$value"
  # A huge sampling interval is representable: analyze's band then lies at tiny omegas.
  [ "$value" != 99999999999999999999999 ] && attack refuse "analyze --dt '$value'" analyze $R --dt "$value" --no-plot
done 2> /dev/null

# 2. Every parameter with out-of-range values, through --set, a file and a sweep.
for key in N M m k0 k1 eta0 eta1 v a alpha F_drive F_kin levels; do
  for value in -1 nan inf 1e308 word ''; do
    attack refuse "--set $key=$value" theory --set "$key=$value"
  done
  echo "{\"$key\": \"nope\"}" > "bad_$key.json"
  attack refuse "--params $key word" run --params "../bad_$key.json" --no-plot
  attack refuse "sweep $key bad" sweep "$key=1,nope" --no-plot
done

# 3. Outputs over inputs, every command and format; links; devices; empty and odd names.
attack refuse "run pdf over params" run --params ../fig.pdf --out ../fig --format pdf
attack refuse "run svg over params" run --params ../fig.svg --out ../fig --format svg
attack refuse "sweep sub-run over params" sweep alpha=0.5:0.6:0.1 --params '../sw_alpha=0.6.json' --out ../sw
attack refuse "sweep state over params" sweep alpha=0.6 --params '../sw_alpha=0.6.state' --out ../sw
attack refuse "merge svg over part" merge ../pt.svg --out ../pt --format svg
attack refuse "analyze svg over record" analyze ../an.svg --out ../an --format svg
attack refuse "synth over params" synth --params ../syn.csv --out ../syn
attack refuse "paper fig6 over record" paper fig6 --record ../d6/fig6.tsv --out-dir ../d6
attack refuse "plot over table" plot ../tab.svg -o ../tab.svg
attack refuse "symlink over params" run --params ../p.json --out ../link --no-plot
attack refuse "hard link over params" theory --params ../p.json --out ../hard
attack refuse "theory over omega file" theory --omega-file ../om.tsv --out ../om
attack refuse "save-state over params" run --params $P --save-state $P --no-plot
attack refuse "resume over stale" run $band --out ../part
for cmd in "run" "theory" "sweep alpha=1" "merge ../part.state" "analyze $R" "synth"; do
  for out in '' ../adir ../nowhere/x $'a\nb' $'a\tb' "$(printf 'n%.0s' $(seq 300))" $'odd\xff' ../adir/; do
    flags=--no-plot
    case "$cmd" in theory | synth) flags="" ;; esac
    # shellcheck disable=SC2086
    attack refuse "$cmd --out '$out'" $cmd --out "$out" $flags
  done
done
for input in /dev/zero /dev/null ../adir ../none ''; do
  attack refuse "run --params $input" run --params "$input" --no-plot
  attack refuse "merge $input" merge "$input"
  attack refuse "analyze $input" analyze "$input" --no-plot
  attack refuse "theory --omega-file $input" theory --omega-file "$input"
  attack refuse "plot $input" plot "$input" -o x.png
done
for f in dup trail cut list bool inf big; do attack refuse "params $f.json" run --params "../$f.json" --no-plot; done
for f in junk random; do
  attack refuse "merge $f.state" merge "../$f.state"
  cp "$f.state" "r_$f.state"
  attack refuse "resume $f.state" run --resume "../r_$f"
done
attack refuse "omega file bad" theory --omega-file ../om_bad.tsv
attack refuse "omega file empty" theory --omega-file ../om_empty.tsv

# 4. Conflicting, ignored or meaningless options.
attack refuse "realizations with precision" run --realizations 8 --precision 0.1 --no-plot
attack refuse "range with precision" run --realizations-range 0:8 --precision 0.1 --no-plot
attack refuse "duration with precision" run --duration 5 --precision 0.1 --no-plot
attack refuse "duration zero" run --duration 0 --no-plot
attack refuse "empty resume" run --resume ''
attack refuse "empty save-state" run --save-state '' --no-plot
attack refuse "empty omega" theory --omega ''
attack refuse "omega and file" theory --omega 1 --omega-file ../om.tsv
attack refuse "record with fig2" paper fig2 --record $R
attack refuse "unknown figure" paper fig9
attack refuse "unknown case" run --case slow --no-plot
attack refuse "unknown simd" run --simd neon --no-plot
attack refuse "unknown format" run --format bmp --no-plot
attack refuse "bad size" run --size 0x0
attack refuse "bad size word" run --size big
attack refuse "bad dpi" run --dpi 0
attack refuse "huge dpi" run --dpi 1e9
attack refuse "unknown units" analyze $R --units km --no-plot
# cm and inch are known units, but $R's header gives um: a unit option that contradicts it
# is refused, naming both.
attack refuse "units cm over a header in um" analyze $R --units cm --no-plot
attack refuse "units inch over a header in um" analyze $R --units inch --no-plot
attack refuse "resolution unit" analyze $R --resolution 1furlong --no-plot
attack refuse "theory order 3" theory --order 3
attack refuse "resume other seed" run --resume $S --seed 9 --no-plot
attack refuse "checkpoint zero" run --checkpoint-every 0 --no-plot
attack refuse "unknown command" wobble
attack refuse "unknown option" run --bogus
attack refuse "misspelled option" run --omega-mni 1
attack refuse "plot no tables" plot -o x.png
attack refuse "plot bad extension" plot $T -o x.bmp
attack refuse "sweep no values" sweep alpha
attack refuse "sweep empty list" sweep alpha=
attack refuse "sweep bad range" sweep alpha=1:0:0.1
attack refuse "sweep zero step" sweep alpha=0:1:0
attack refuse "sweep unknown key" sweep speed=1,2
attack refuse "merge overlap" merge ../part.state ../part.state --out x
attack refuse "range unaligned" run --realizations-range 3:8 --save-state x.state --no-plot
attack refuse "range without state" run --realizations-range 0:8 --no-plot
attack refuse "merge without realizations 0" merge ../part8.state --out x
attack refuse "theory above the doubles" theory --omega 1,1e45
attack refuse "synth unknown unit" synth --resolution 5furlong
attack refuse "synth negative noise" synth --sensor-noise -1um
attack refuse "tree too big" run --case hierarchical --set N_2=100000 --no-plot
# Bands and parameters beyond what the estimator or the exact theory resolve, level lists,
# two outputs on one file, analyze's JSON as parameters (the second outsider sweep).
attack refuse "band of too few renewals" run --omega-min 1e8 --omega-max 1e9 --precision 0.1 --no-plot
attack refuse "band far above the doubles' reach" run --omega-min 1e10 --omega-max 1e11 --precision 0.1 --no-plot
attack refuse "fixed count passing 9 renewals" run --omega-min 1e6 --omega-max 1e7 --realizations 64 --no-plot
attack refuse "band 60 octaves below the step" run --omega-min 1e-30 --omega-max 1e-29 --no-plot
for stiff in k1=1e19 k1=1e30 eta0=8e21 eta0=8e25 k0=1e-8 v=1e90; do
  attack refuse "theory beyond its contrast $stiff" theory --set $stiff --omega 1
  attack refuse "run beyond its contrast $stiff" run --set $stiff --omega-min 1 --omega-max 100 --no-plot
done
for touching in '' 1, 1,1; do
  attack refuse "touching='$touching'" theory --case hierarchical --set "touching=$touching" --omega 1
done
attack refuse "synth noise beyond the slide" synth --sensor-noise 1e300 --duration 10 --out syn2
attack refuse "save-state onto the run's table" run --realizations-range 0:8 --save-state x.tsv --out x --no-plot
attack refuse "analyze's JSON as parameters" run --params ../an.json --no-plot
attack refuse "resume onto another run's state" run --resume ../part --out ../part8 --no-plot

# 5. Things that must work (and leave the inputs alone).
attack work-keep "theory" theory --out t
attack work-keep "theory list" theory --omega 1,2,3
attack work-keep "theory order 2" theory --order 2 --omega-min 1 --omega-max 100
attack work-keep "run" run $band --realizations 8 --out r --no-plot --quiet
attack work-keep "run pdf" run $band --realizations 8 --out r --format pdf --quiet
attack work-keep "run params" run $band --realizations 8 --params $P --out r --no-plot --quiet
attack work-keep "sweep" sweep alpha=0.3,0.6 $band --realizations 8 --no-plot --quiet
attack work-keep "merge" merge ../part.state --out m --no-plot --quiet
attack work-keep "synth" synth --duration 5 --sample-interval 0.01
attack work-keep "analyze" analyze $R --no-plot --quiet
attack work-keep "plot" plot $T -o x.svg
attack work-keep "cases" cases


# 8. Every command's every output over an input it reads; figure options, titles, JSON,
# units and ignored options refused before any work (a default-band run takes minutes, so
# a late refusal shows as a hang).
# (run: .tsv .json .state and the figure; sweep's sub-runs .tsv .json .state; merge and
# analyze: .tsv .json and the figure; synth: .csv; theory: .tsv.)
for ext in tsv json png pdf svg state csv; do
  fig=--no-plot
  case $ext in png | pdf | svg) fig="--format $ext" ;; esac
  cp p.json "o_run.$ext"; cp p.json "o_sw_alpha=0.4.$ext"; cp p.json "o_syn.$ext"; cp p.json "o_th.$ext"
  cp part.state "o_mg.$ext"; cp rec.csv "o_an.$ext"; cp om.tsv "o_om.$ext"
  # shellcheck disable=SC2086
  case $ext in
    csv) attack refuse "synth .$ext over its params" synth --params "../o_syn.$ext" --out ../o_syn ;;
    *)
      attack refuse "run .$ext over its params" run --params "../o_run.$ext" --out ../o_run $fig
      [ $ext = state ] || {
        attack refuse "merge .$ext over its part" merge "../o_mg.$ext" --out ../o_mg $fig
        attack refuse "analyze .$ext over its record" analyze "../o_an.$ext" --out ../o_an $fig
      }
      case $ext in tsv | json | state)
        attack refuse "sweep sub-run .$ext over its params" sweep alpha=0.4 --params "../o_sw_alpha=0.4.$ext" --out ../o_sw
      esac
      [ $ext = tsv ] && {
        attack refuse "theory .$ext over its params" theory --params "../o_th.$ext" --out ../o_th
        attack refuse "theory .$ext over its omega file" theory --omega-file "../o_om.$ext" --out ../o_om
      }
      ;;
  esac
done
for ext in tsv json png pdf svg; do
  fig=--no-plot
  case $ext in png | pdf | svg) fig="--format $ext" ;; esac
  cp p.json "o_sw.$ext"
  # shellcheck disable=SC2086
  attack refuse "sweep combined .$ext over its params" sweep alpha=0.4 --params "../o_sw.$ext" --out ../o_sw $fig
done
mkdir -p pd
for f in fig6.tsv fig6.json fig6.png fig6.pdf fig6.svg; do
  cp rec.csv "pd/$f"
  fmt=png
  case $f in *.pdf) fmt=pdf ;; *.svg) fmt=svg ;; esac
  attack refuse "paper fig6 $f over its record" paper fig6 --record "../pd/$f" --out-dir ../pd --format $fmt
done
for f in fig2_reference.tsv fig2_fast.json fig2_short-renewal.state; do
  cp p.json "pd/$f"
  attack refuse "paper fig2 over an existing $f as --record" paper fig2 --record "../pd/$f" --out-dir ../pd
done
for fmt in png pdf svg; do
  cp table.tsv "pl.$fmt"
  attack refuse "plot .$fmt over its table" plot "../pl.$fmt" -o "../pl.$fmt"
  attack refuse "plot .$fmt over its table, absolute" plot "$work/pl.$fmt" -o "../pl.$fmt"
done

# Figure options that cannot be drawn, for every command that draws.
for bad in "--size 0x5" "--size 7x0" "--size 7x" "--size x5" "--size 7x5x3" "--size -7x5" "--size nanxnan" \
  "--size infx5" "--size 1e9x5" "--size 7X5" "--size 7,5" "--dpi 0" "--dpi -1" "--dpi nan" "--dpi inf" \
  "--dpi 1e-300" "--dpi 1e6" "--dpi many" "--format PNG" "--format jpg" "--format 'png '" "--format ''"; do
  # shellcheck disable=SC2086
  eval "set -- $bad"
  attack refuse "run $bad" run "$@"
  attack refuse "sweep $bad" sweep alpha=0.3,0.6 "$@"
  attack refuse "merge $bad" merge ../part.state --out m "$@"
  attack refuse "analyze $bad" analyze $R --out a "$@"
  attack refuse "paper fig2 $bad" paper fig2 "$@"
  case "$bad" in --format*) continue ;; esac
  attack refuse "plot $bad" plot $T -o x.png "$@"
done
# Titles matplotlib cannot typeset, and names that become titles.
for title in '$\frac{1}{$' '$x^$' '$a_b_c$' '$\nosuchcommand$' '$\sqrt[$' '$}$' '${$'; do
  attack refuse "plot title $title" plot $T -o x.png --title "$title"
done
cp rec.csv 'r$\frac{1$.csv'
# A file name is drawn as written, '$' and all: the figure must be drawn.
attack work-keep "analyze a record whose name is broken mathtext" analyze '../r$\frac{1$.csv' --out a --quiet
cp table.tsv 'q$x^$.tsv'
attack work-keep "plot a table whose name is broken mathtext" plot '../q$x^$.tsv' -o q.png

# Figure options given where no figure is drawn: they would be ignored.
for opt in "--format pdf" "--size 3x3" "--dpi 300"; do
  # shellcheck disable=SC2086
  attack refuse "run --no-plot $opt" run --no-plot $opt
  # shellcheck disable=SC2086
  attack refuse "analyze --no-plot $opt" analyze $R --out a --no-plot $opt
done

# Options that conflict, repeat or would be ignored.
attack refuse "theory --omega with --omega-min" theory --omega 1,2 --omega-min 5
attack refuse "theory --omega with --points" theory --omega 1,2 --points 3
attack refuse "theory --omega-file with --omega-max" theory --omega-file ../om.tsv --omega-max 5
attack refuse "paper fig6 --precision" paper fig6 --precision 0.1
attack refuse "paper fig6 --seed" paper fig6 --seed 3
attack refuse "paper fig6 --omega-min" paper fig6 --omega-min 1
attack refuse "paper fig6 --work-budget" paper fig6 --work-budget 1e9
attack refuse "sweep key also --set" sweep alpha=0.3,0.6 --set alpha=0.5 --no-plot
attack refuse "sweep key twice" sweep alpha=0.3 alpha=0.6 --no-plot
attack refuse "seed twice" run --seed 1 --seed 2 --no-plot
attack refuse "out twice" theory --out a --out b
attack refuse "set key twice" theory --set alpha=0.3 --set alpha=0.6
attack refuse "analyze --fit-band without --fit" analyze $R --out a --no-plot --fit-band 1 10
attack refuse "analyze --set without --compare-case" analyze $R --out a --no-plot --set alpha=1
attack refuse "analyze --normal-force without a friction column" analyze $R --out a --no-plot --normal-force 10
attack refuse "analyze --machine-stiffness without slip" analyze $R --out a --no-plot --machine-stiffness 1e6
attack refuse "analyze --dt beside a time column" analyze $R --out a --no-plot --dt 0.01
attack refuse "resume with another case" run --resume $S --case fast --no-plot
attack refuse "resume with another band" run --resume $S --omega-min 1 --no-plot

# Units: unknown spellings are refused, never read as metres.
for u in km M Mm furlong 'um ' '' µ pm; do
  attack refuse "analyze --units '$u'" analyze $R --out a --no-plot --units "$u"
  attack refuse "synth --units '$u'" synth --units "$u" --out s
done
for header in 't,x [km]' 't,x (furlong)' 't [ms],x' 't,x [mum]'; do
  printf '%s\n0,1\n0.001,2\n0.002,3\n' "$header" > hu.csv
  attack refuse "record header '$header'" analyze ../hu.csv --out a --no-plot
done

# Parameter files: JSON a strict reader refuses, and values of the wrong type.
printf '{"alpha": NaN}' > j_nan.json
printf '{"alpha": Infinity}' > j_infinity.json
printf '{"alpha": 0.5} // note' > j_comment.json
printf '{"alpha": 0.5,}' > j_comma.json
printf "{'alpha': 0.5}" > j_quote.json
printf '' > j_empty.json
printf '{"alpha": {"value": 0.5}}' > j_nested.json
printf '{"alpha": [0.5]}' > j_array.json
printf '{"alpha": null}' > j_null.json
printf '{"N": 2.5}' > j_fraction.json
printf '{"alpha": 1e-320}' > j_subnormal.json
printf '{"alpha": 0.5}{"alpha": 0.6}' > j_two.json
printf '{"alpha": 0.5, "\\u0061lpha": 0.6}' > j_escaped_twice.json
printf '{"alpha\\u0000": 0.5}' > j_nul_key.json
python3 -c "print('[' * 100000 + ']' * 100000)" > j_deep.json
python3 -c "print('{\"a\":' * 50000 + '1' + '}' * 50000)" > j_deep_objects.json
for f in j_*.json; do
  attack refuse "params $f" run --params "../$f" --no-plot
  attack refuse "synth params $f" synth --params "../$f" --out s
done
# A byte-order mark may be ignored (RFC 8259 8.1), and a number in a string reads as the
# command line reads its words: both are the parameter meant.
printf '\xef\xbb\xbf{"alpha": 0.5}' > ok_bom.json
printf '{"alpha": "0.5"}' > ok_string.json
for f in ok_bom.json ok_string.json; do attack work-keep "params $f" theory --params "../$f" --omega 1; done
fi

if in_part results; then
# 7. Results that must say what they are, streams, memory, and Python.
# A run some of whose realizations stall is not a spectrum: exit 3, never 0.
not_claimed() {  # NAME ARGS...: must end with exit 3 (or a refusal), never 0
  local name=$1; shift
  attacks=$((attacks + 1))
  (mkdir -p scratch && cd scratch && timeout 60 "$bin" "$@" > /dev/null 2> "$logs/stderr")
  local status=$?
  rm -rf scratch
  if [ $status -eq 124 ]; then hangs=$((hangs + 1)); report HANG "$name";
  elif [ $status -ge 128 ]; then crashes=$((crashes + 1)); report CRASH "$name: $status";
  elif [ $status -eq 0 ]; then nonsense=$((nonsense + 1)); report NONSENSE "$name exited 0";
  fi
}
stall="--set N=7 --set F_kin=6 --set k1=0 --no-plot --quiet"
for F in 8 8.1 8.2 8.3; do
  not_claimed "partial stall F_drive=$F" run $stall --set F_drive=$F --omega-min 1 --omega-max 10 --realizations 32
done
not_claimed "short stall-capable" run $stall --set F_drive=8 --set a=3e-4 --omega-min 1000 --omega-max 10000 --precision 0.3
# A block that stalls and creeps back at 14 v (F_drive - F_kin = 0.01 N): its precision out of
# reach, the sub-band's cap (its renewals counted) ends it in seconds, exit 3.
not_claimed "creeping stall F_drive=5.01" run --set F_drive=5.01 --omega-min 10 --omega-max 100 --no-plot --quiet
for omega in 1e-300 1e-200 1e-100 5e-324 2.8e-80; do
  attack refuse "theory --omega $omega" theory --omega "$omega,1"
done
attack refuse "theory --omega-min 1e-100" theory --omega-min 1e-100 --omega-max 1e-95
for omega in 1e-79 1e-40 1e-20 1e-14 1e-13; do attack work-keep "theory --omega $omega" theory --omega "$omega"; done
printf 't,x\n0,1\n0.001,1e158\n0.002,3\n' > huge.csv
attack refuse "analyze huge values" analyze ../huge.csv --no-plot
awk 'BEGIN { print "t,x (um)"; srand(5); for (k = 0; k < 20000; ++k) printf "%g,%.6f\n", k * 0.001, rand() - 0.5 }' > still.csv
not_claimed "a record at rest" analyze ../still.csv --no-plot --quiet
for stream in "cat /dev/zero" "cat /dev/urandom" "head -c 100000000 /dev/zero" "yes 1"; do
  attacks=$((attacks + 1))
  timeout 60 bash -c "$stream 2> /dev/null | '$bin' analyze - --out s --no-plot" > /dev/null 2> "$logs/stderr"
  status=$?
  if [ $status -eq 124 ]; then hangs=$((hangs + 1)); report HANG "analyze from $stream";
  elif [ $status -ge 128 ]; then crashes=$((crashes + 1)); report CRASH "analyze from $stream: $status";
  elif [ $status -eq 0 ]; then nonsense=$((nonsense + 1)); report NONSENSE "analyze from $stream exited 0";
  fi
  rm -f s.*
done
mkfifo fifo
for sig in INT TERM; do
  attacks=$((attacks + 1))
  ( timeout 60 cat /dev/zero > fifo 2> /dev/null & )
  timeout 60 "$bin" analyze fifo --out s --no-plot > /dev/null 2>&1
  status=$?
  [ $status -eq 124 ] && { hangs=$((hangs + 1)); report HANG "analyze from a fifo"; }
  [ $status -eq 0 ] && { nonsense=$((nonsense + 1)); report NONSENSE "analyze from a fifo exited 0"; }
done
# Memory running out is a failure (1) with a message, never a crash or bad input.
if (ulimit -v 400000; "$bin" cases > /dev/null 2>&1); then
  for d in 5e4 9e4; do
    attacks=$((attacks + 1))
    (ulimit -v 400000; timeout 60 "$bin" synth --duration $d --out oom > /dev/null 2> "$logs/stderr")
    status=$?
    if [ $status -ge 128 ] || [ $status -eq 124 ] || ! grep -q "out of memory" "$logs/stderr"; then
      crashes=$((crashes + 1)); report CRASH "synth out of memory: $status $(head -c 200 "$logs/stderr")"
    fi
    rm -f oom.*
  done
fi
# Python: the same refusals as ValueError, memory as MemoryError, Ctrl-C heard.
python_refused() {  # CALL: must raise ValueError or TypeError
  local call=$1
  attacks=$((attacks + 1))
  /usr/bin/python3 -c "import slidespec as ss
try:
    $call
except (ValueError, TypeError):
    raise SystemExit(2)
raise SystemExit(0)" > /dev/null 2> "$logs/stderr"
  local status=$?
  [ $status -eq 0 ] && { nonsense=$((nonsense + 1)); report NONSENSE "python $call accepted"; }
  [ $status -ne 0 ] && [ $status -ne 2 ] && { crashes=$((crashes + 1)); report CRASH "python $call: $(tail -c 200 "$logs/stderr")"; }
}
if [ -n "${PYTHONPATH:-}" ]; then
  for call in 'ss.theory("reference", 1e-300)' 'ss.theory("reference", float("nan"))' 'ss.eq1("reference", 1e-100)' \
      'ss.theory("reference", -1.0)' 'ss.run("reference", seed=1.5)' 'ss.run("reference", precision=0)' \
      'ss.synth(duration=1e12)' 'ss.analyze([0, 1, 2], [0, 1e158, 2])' 'ss.Parameters(alpha="x")'; do
    python_refused "$call"
  done
fi


# 9. A spring-driven block that stalls in part (a soft spring reloads slowly): its mean
# speed near v/2 is no spectrum either.
for k in 1e-2 0.3 0.4 0.5 0.6; do
  not_claimed "spring partial stall k_drive=$k" run $stall --set F_drive=8 --set drive=spring --set k_drive=$k \
    --omega-min 1 --omega-max 10 --realizations 32
done
# Python: types and files as the command line checks them.
if [ -n "${PYTHONPATH:-}" ]; then
  for call in 'ss.run("reference", seed=True)' 'ss.run("reference", realizations=8.0)' 'ss.run("reference", omega_min=None)' \
      'ss.run("reference", threads=-1)' 'ss.run("reference", simd=3)' 'ss.synth(duration="5")' 'ss.synth(seed=-1)' \
      'ss.theory("reference", "1")' 'ss.theory("reference", 1, order=1.5)' 'ss.Parameters(N=2.5)' \
      'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0.01, points=2.5)' \
      'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt="0.01")' 'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0.01, units=1)' \
      'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0.01, omega_min="1")' 'ss.omegas(1, 10, points=2.5)'; do
    python_refused "$call"
  done
  # Files: what cannot be read is OSError (or ValueError for what is not a table), at once.
  for path in /dev/zero /dev/urandom "$work/adir" "$work/none.tsv" "$work/big.json" "$work/rec.csv"; do
    attacks=$((attacks + 1))
    (ulimit -v 2000000; timeout 30 /usr/bin/python3 -c "import sys, slidespec as ss
try:
    ss.read(sys.argv[1])
except (OSError, ValueError):
    raise SystemExit(2)
raise SystemExit(0)" "$path" > /dev/null 2> "$logs/stderr")
    status=$?
    if [ $status -eq 124 ]; then hangs=$((hangs + 1)); report HANG "python ss.read($path)";
    elif [ $status -eq 0 ]; then nonsense=$((nonsense + 1)); report NONSENSE "python ss.read($path) accepted";
    elif [ $status -ne 2 ]; then crashes=$((crashes + 1)); report CRASH "python ss.read($path): $(tail -c 200 "$logs/stderr")"; fi
  done
fi
fi

if in_part signals; then
# 6. Signals: an interrupt at any moment leaves a run that resumes to the undisturbed result
# (HUP and QUIT, which it does not catch, end it where its last checkpoint resumes).
"$bin" run --omega-min 10 --omega-max 1000 --precision 0.1 --seed 5 --out whole --no-plot --quiet
for delay in 0.05 0.2 0.5 1 1.5 2; do
  for sig in INT TERM KILL HUP QUIT; do
    attacks=$((attacks + 1))
    rm -f cut.*
    "$bin" run --omega-min 10 --omega-max 1000 --precision 0.1 --seed 5 --out cut --no-plot --quiet \
      --checkpoint-every 0.1 2> /dev/null &
    pid=$!
    sleep $delay
    kill -s $sig $pid 2> /dev/null
    wait $pid 2> /dev/null
    status=$?
    if [ -e cut.state ]; then
      timeout 120 "$bin" run --resume cut --no-plot --quiet 2> /dev/null
      status=$?
    fi
    if [ $status -ne 0 ] && [ ! -e cut.tsv ]; then
      # Stopped before its first checkpoint (or before it caught signals): nothing had
      # been saved, and no finished work was lost.
      [ "$status" -ge 128 ] && continue
      work_lost=$((work_lost + 1))
      report LOST "$sig after $delay s: status $status"
    elif ! cmp -s cut.tsv whole.tsv; then
      work_lost=$((work_lost + 1))
      report LOST "$sig after $delay s: resumed table differs"
    fi
  done
done
# A SIGKILL while the figure is drawn, then the resume. SLIDESPEC_FIGURE_STALL holds the
# run there (the state saved, no output written): it writes the pid to the file and waits.
for k in 1 2 3; do
  attacks=$((attacks + 1))
  rm -f cut.* plotting
  SLIDESPEC_FIGURE_STALL=$work/plotting "$bin" run --omega-min 10 --omega-max 1000 --precision 0.1 --seed 5 \
    --out cut --quiet &
  pid=$!
  for _ in $(seq 600); do [ -s plotting ] && break; sleep 0.05; done
  [ -s plotting ] || { other=$((other + 1)); report OTHER "SIGKILL while drawing ($k): the figure never started"; }
  kill -9 $pid; wait $pid 2> /dev/null
  "$bin" run --resume cut --no-plot --quiet 2> /dev/null
  cmp -s cut.tsv whole.tsv || { work_lost=$((work_lost + 1)); report LOST "SIGKILL while drawing ($k)"; }
done

# A fixed count and a part, interrupted and resumed: the fixed run forgets its state, the
# part keeps it for merge, and both give the undisturbed numbers.
"$bin" run --omega-min 10 --omega-max 1000 --realizations 256 --seed 5 --out wfix --no-plot --quiet
for kind in fixed part; do
  attacks=$((attacks + 1))
  rm -f cfix.*
  extra=(--realizations 256)
  [ $kind = part ] && extra=(--realizations-range 0:256 --save-state cfix.state)
  "$bin" run --omega-min 10 --omega-max 1000 "${extra[@]}" --seed 5 --out cfix --no-plot --quiet \
    --checkpoint-every 0.1 2> /dev/null &
  pid=$!
  sleep 0.5
  kill -INT $pid 2> /dev/null
  wait $pid 2> /dev/null
  [ -e cfix.state ] && "$bin" run --resume cfix --no-plot --quiet 2> /dev/null
  if ! cmp -s cfix.tsv wfix.tsv; then
    work_lost=$((work_lost + 1)); report LOST "$kind interrupted and resumed: the table differs"
  elif [ $kind = fixed ] && [ -e cfix.state ]; then
    other=$((other + 1)); report OTHER "a resumed fixed-count run kept its state"
  elif [ $kind = part ] && [ ! -e cfix.state ]; then
    work_lost=$((work_lost + 1)); report LOST "a resumed part lost the state merge reads"
  fi
done

# A SIGKILL in a sweep: what each run checkpointed resumes.
"$bin" sweep alpha=0.3,0.6 --omega-min 10 --omega-max 1000 --precision 0.1 --seed 5 --out wsw --no-plot --quiet
for delay in 0.3 0.8; do
  attacks=$((attacks + 1))
  rm -f csw*
  "$bin" sweep alpha=0.3,0.6 --omega-min 10 --omega-max 1000 --precision 0.1 --seed 5 --out csw --no-plot --quiet 2> /dev/null &
  pid=$!
  sleep $delay
  kill -9 $pid 2> /dev/null
  wait $pid 2> /dev/null
  for a in 0.3 0.6; do
    if [ -e "csw_alpha=$a.state" ]; then "$bin" run --resume "csw_alpha=$a" --no-plot --quiet 2> /dev/null; fi
    if [ -e "csw_alpha=$a.tsv" ] && ! cmp -s "csw_alpha=$a.tsv" "wsw_alpha=$a.tsv"; then
      work_lost=$((work_lost + 1)); report LOST "sweep SIGKILL after $delay s: alpha=$a resumed differs"
    fi
  done
done
fi

# 10. State files are outputs too, every failure is a failure, no limit or exit loses work.
if in_part refusals; then
  # A state already there is another run's: a part's --save-state never replaces it.
  attack refuse "second part onto a part's --save-state" run $band --realizations-range 8:8 --save-state ../part.state \
    --out p2 --no-plot
  attack refuse "resume with --save-state of another part" run --resume $S --save-state ../part8.state --no-plot
  attack refuse "resume with --work-budget" run --resume $S --work-budget 1 --no-plot
  attack refuse "sweep value twice (0.5, 0.50)" sweep alpha=0.5,0.50 $band --no-plot
  attack refuse "sweep value twice (0.5, 0.5)" sweep alpha=0.5,0.5 $band --no-plot
  attack refuse "analyze --segments --out" analyze $R --segments --out a
  attack refuse "analyze --segments --fit" analyze $R --segments --fit power-law
  printf 't (s),x (um),x (mm)\n0,1,0.001\n0.01,2,0.002\n0.02,3,0.003\n' > twox.csv
  attack refuse "two columns that could be x" analyze ../twox.csv --out a --no-plot
  # Messages naming the wrong thing (or exit 1 "out of memory" for bad input).
  for interval in 1e-300 1e-9 1e3; do
    attack refuse "analyze --resample $interval" analyze $R --resample $interval --out a --no-plot
  done
  attack refuse "theory alpha=0" theory --set alpha=0 --omega 1
  attack refuse "theory alpha=1e-310" theory --set alpha=1e-310 --omega 1
  # Refusals that must name their cause (the parameter, its value, the limit): else unclear.
  refuse_naming() {  # NAME WORDS ARGS...
    local name=$1 words=$2; shift 2
    attack refuse "$name" "$@"
    if ! grep -q -- "$words" "$logs/stderr"; then
      other=$((other + 1)); report UNCLEAR "$name: does not name '$words': $(head -c 200 "$logs/stderr")"
    fi
  }
  # A block coasting near the stall under a constant force: its renewals are work, refused
  # before any (a late refusal shows as a hang), naming F_drive.
  refuse_naming "F_drive=5.000001, default band" "parameter F_drive: 5.000001 N" run --set F_drive=5.000001 --no-plot
  refuse_naming "F_drive=5.000001 at 10..100, a budget" "parameter F_drive: 5.000001 N" \
    run --set F_drive=5.000001 --omega-min 10 --omega-max 100 --realizations 8 --work-budget 1e9 --no-plot
  refuse_naming "F_drive=5+1e-12, default band" "parameters F_drive, v: .* give F_drive at least" \
    run --set F_drive=5.000000000001 --no-plot
  refuse_naming "F_drive=5.000001 at 1..10" "parameter F_drive" run --set F_drive=5.000001 --omega-min 1 --omega-max 10 \
    --no-plot
  # A spring's omega_s sets the step: the messages name k_drive (and omega_s), not an omega option.
  for k in 1e16 1e40 1e90 1.5e15; do
    refuse_naming "spring k_drive=$k" "parameter k_drive: .* omega_s" run --set drive=spring --set k_drive=$k --no-plot
  done
  refuse_naming "spring near the stall" "parameter k_drive: 200 N/m puts omega_s" \
    run --set drive=spring --set k_drive=200 --set F_drive=5.000001 --no-plot
  refuse_naming "spring near the stall in a sweep" "omega_s" \
    sweep k_drive=200,1e3 --set drive=spring --set F_drive=5.000001 --no-plot
  # The outsider's last sweep: a coasting block at 100..1000 rad/s was planned at 5.6 m/s and
  # ran minutes; columns named alike; times no double holds; a NUL cutting a message short;
  # a sensor step swallowing the signal; a sweep range rounding to one value twice.
  refuse_naming "F_drive=5.000001 at 100..1000, 5%" "parameter F_drive: 5.000001 N" \
    run --set F_drive=5.000001 --omega-min 100 --omega-max 1000 --precision 0.05 --no-plot
  awk 'BEGIN { print "t,x"; for (k = 0; k < 400; ++k) print k "e300," k * 1e-6 }' > t1e300.csv
  refuse_naming "times x 1e300" "beyond 1e+30 s" analyze ../t1e300.csv --out a --no-plot
  awk 'BEGIN { print "t,t,x"; for (k = 0; k < 400; ++k) print k * 0.01 "," k * 0.01 "," k * 1e-6 }' > tt.csv
  refuse_naming "two time columns t,t,x" "2 columns 't'" analyze ../tt.csv --out a --no-plot
  awk 'BEGIN { print "t,x,x"; for (k = 0; k < 400; ++k) print k * 0.01 "," k * 1e-6 "," k * 2e-6 }' > xx.csv
  refuse_naming "x,x with --column x" "2 columns 'x'" analyze ../xx.csv --column x --out a --no-plot
  printf 't,x\n0,1\n0.01,"2\0003"\n0.02,4\n' > nul.csv
  refuse_naming "a NUL in a quoted field" "line 3: a control byte (0x00)" analyze ../nul.csv --out a --no-plot
  refuse_naming "synth --resolution 1e308" "resolution" synth --resolution 1e308 --out s
  refuse_naming "sweep N=10..12 log 5" "more than once" sweep "N=10..12 log 5" --no-plot
  # 11. Accepted without effect, or refused in words that name the wrong thing or are CLI11's.
  # A number a user types is decimal: hexadecimal, inf and nan are refused everywhere.
  refuse_naming "--set alpha=0x10" "parameter alpha: '0x10' is not a decimal number" theory --set alpha=0x10
  refuse_naming "--omega-min 0x10" "'0x10' is not a decimal number" run --omega-min 0x10 --no-plot
  refuse_naming "--order 0x1" "'0x1' is not a decimal number" theory --order 0x1
  refuse_naming "analyze --window 0x1:3" "--window" analyze $R --window 0x1:3 --out a --no-plot
  refuse_naming "analyze --resample 0x1p-7" "--resample" analyze $R --resample 0x1p-7 --out a --no-plot
  refuse_naming "--out without a value" "--out: no value after it" run --out
  refuse_naming "--seed twice" "--seed: given 2 times" run --seed 1 --seed 2 --no-plot
  refuse_naming "--fit-band 3 values" "--fit-band: takes 2 values, got 3" analyze $R --fit-band 1 2 3 --fit power-law
  refuse_naming "analyze without a record" "analyze: no file given" analyze
  refuse_naming "sweep without values" "sweep: no values given" sweep
  refuse_naming "merge without parts" "merge: no parts given" merge --out x
  refuse_naming "plot without tables" "plot: no tables given" plot -o x.png
  refuse_naming "an extra word" "theory: '2' was not expected" theory --omega-min 1 2
  refuse_naming "--omega-min abc" "--omega-min: 'abc' is not a number" run --omega-min abc --no-plot
  refuse_naming "--order 1.5" "--order: '1.5' is not a whole number" theory --order 1.5
  refuse_naming "theory --omeg" "did you mean '--omega'?" theory --omeg 5
  refuse_naming "a force column in um" "it holds a displacement, not a force" \
    analyze $R --observable force --force-column x --out a --no-plot
  awk 'BEGIN { print "t,x"; for (k = 0; k < 400; ++k) print k * 0.01 "," (k == 5 ? "1.0004e30" : k * 1e-6) }' > b30.csv
  refuse_naming "a value just beyond 1e30" "1.0004e+30 m is beyond 1e+30 m" analyze ../b30.csv --out a --no-plot
  refuse_naming "resume PREFIX.state with another case" "takes its case and parameters from its state" \
    run --resume ../part.state --case fast --no-plot
  printf '1,2,3\n4,5,6\n' > commas.tsv
  refuse_naming "plot a table of commas" "line 1: '1,2,3' is not a number" plot ../commas.tsv -o x.png
  refuse_naming "N=1e9" "parameter N: the tree would have" run --set N=1e9 --no-plot
  refuse_naming "a=1e90" "parameter a: 1e+90 m makes the renewal time" run --set a=1e90 --omega-min 1 --omega-max 100 --no-plot
  refuse_naming "v=1e90" "v at most 2.08333e+06 m/s" run --set v=1e90 --omega-min 1 --omega-max 100 --no-plot
  refuse_naming "synth --strokes 0" "--strokes: must be a whole number" synth --strokes 0 --stroke-length 1mm --out s
  printf '{"parameters": {"alpha": 0.5}, "alpha": 0.7}' > outer.json
  refuse_naming "a parameter beside the parameters block" "alpha is given outside" run --params ../outer.json --no-plot
  refuse_naming "--params -" "'-' (standard input) is not read here" run --params - --no-plot
  refuse_naming "--omega-file -" "'-' (standard input) is not read here" theory --omega-file -
  for mass in 0 -1 nan; do
    refuse_naming "analyze --slider-mass $mass" "--slider-mass" analyze $R --slider-mass $mass --out a --no-plot
  done
fi
if in_part results; then
  # A write the system refuses is a failure (1): standard output, a file-size limit, a figure.
  failed_write() {  # NAME ARGS-FOR-BASH: must exit 1, never 0 nor a signal
    local name=$1; shift
    attacks=$((attacks + 1))
    (mkdir -p scratch && cd scratch && timeout 60 bash -c "$1" > /dev/null 2> "$logs/stderr")
    local status=$?
    if [ $status -eq 124 ]; then hangs=$((hangs + 1)); report HANG "$name";
    elif [ $status -ge 128 ]; then crashes=$((crashes + 1)); report CRASH "$name: $status";
    elif [ $status -eq 0 ]; then nonsense=$((nonsense + 1)); report NONSENSE "$name exited 0";
    elif [ -n "$(ls scratch 2> /dev/null | grep 'tmp\|lock')" ]; then
      work_lost=$((work_lost + 1)); report LEFT "$name left $(ls scratch | tr '\n' ' ')"
    fi
    rm -rf scratch
  }
  failed_write "theory > /dev/full" "'$bin' theory --omega 1,2 > /dev/full"
  failed_write "cases > /dev/full" "'$bin' cases > /dev/full"
  failed_write "analyze --segments > /dev/full" "'$bin' analyze $R --segments > /dev/full"
  failed_write "analyze, its plotter broken" "SLIDESPEC_PYTHON=/bin/false '$bin' analyze $R --out a"
  failed_write "plot, its plotter broken" "SLIDESPEC_PYTHON=/bin/false '$bin' plot $T -o x.png"
  failed_write "plot, its interpreter missing" "SLIDESPEC_PYTHON=/nonexistent '$bin' plot $T -o x.png"
  failed_write "--help > /dev/full" "'$bin' --help > /dev/full"
  failed_write "run under ulimit -f 1" "ulimit -f 1; exec '$bin' run $band --precision 0.2 --out u --no-plot"
  failed_write "analyze under ulimit -f 1" "ulimit -f 1; exec '$bin' analyze $R --out u --no-plot"
  # Spectra of nothing: exit 3 (marked), never 0.
  awk 'BEGIN { print "t,x"; for (k = 0; k < 4000; ++k) print k * 0.01 ",0.002" }' > flat.csv
  awk 'BEGIN { print "t,x"; for (k = 0; k < 4000; ++k) print k * 0.01 ",0" }' > zero.csv
  not_claimed "analyze a constant record" analyze ../flat.csv --out a --no-plot
  not_claimed "analyze an all-zero record" analyze ../zero.csv --out a --no-plot
  not_claimed "analyze --dt 1e-170" analyze $R --dt 1e-170 --out a --no-plot
  # A window over a hold (10 um/s, held 40 s, 10 um/s) is the sensor at rest: exit 3.
  awk 'BEGIN { print "t (s),x (um)"; srand(5)
               for (k = 0; k < 12000; ++k) { t = k * 0.01; x = t < 40 ? 10 * t : t < 80 ? 400 : 400 + 10 * (t - 80)
                                              printf "%.2f,%.4f\n", t, x + 0.01 * (rand() - 0.5) } }' > held.csv
  not_claimed "analyze --window over a hold" analyze ../held.csv --window 50:70 --out a --no-plot
  # Python: arguments that would be ignored; the interpreter exiting while a daemon thread
  # runs ss.run ends cleanly (3 times).
  if [ -n "${PYTHONPATH:-}" ]; then
    for call in 'ss.run("reference", progress="yes")' \
        'ss.run(ss.Parameters("reference", drive="spring", k_drive=[1e4]))' \
        'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0.01, machine_stiffness=0)' \
        'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0)' 'ss.analyze("rec.csv", [0.0, 1.0, 2.0] * 100)' \
        'ss.analyze(None, [0.0, 1.0, 2.0] * 100, dt=0.01, fit_slope=(1,))' \
        'ss.analyze(None, [[0.0, 1.0, 2.0] * 100] * 2, dt=0.01)' \
        'ss.analyze([0.0, 0.01, 0.02] * 100, [0.0, 1.0, 2.0] * 100, fit_slope=(1, 2, 3))' \
        'ss.analyze([], [])' 'ss.analyze(None, [], dt=0.01)' 'ss.analyze(None, ["1", "2", "3"] * 100, dt=0.01)'; do
      python_refused "$call"
    done
    for k in 1 2 3; do
      attacks=$((attacks + 1))
      timeout 60 /usr/bin/python3 -c 'import threading, time, slidespec as ss
threading.Thread(target=lambda: ss.run("reference", precision=0.005, threads=1), daemon=True).start()
time.sleep(0.5)' > /dev/null 2> "$logs/stderr"
      status=$?
      if [ $status -ne 0 ] || grep -q "terminate called" "$logs/stderr"; then
        crashes=$((crashes + 1)); report CRASH "python exit during a daemon run ($k): $status $(tail -c 200 "$logs/stderr")"
      fi
    done
  fi
fi
if in_part signals; then
  # stop_within PID SIG WHAT: signals PID and waits 3 s at most (past that a hang, then
  # SIGKILL); the tenths of a second waited in $waited, its exit status in $status.
  stop_within() {
    kill -s "$2" "$1" 2> /dev/null
    waited=0
    while kill -0 "$1" 2> /dev/null && [ $waited -lt 30 ]; do sleep 0.1; waited=$((waited + 1)); done
    if kill -0 "$1" 2> /dev/null; then
      hangs=$((hangs + 1)); report HANG "$3: still running 3 s later"
      kill -KILL "$1" 2> /dev/null
    fi
    wait "$1" 2> /dev/null
    status=$?
  }
  # A signal inside one long realization (a block coasting near the stall, its warm-up or
  # its steps) ends the run within about a second, saving its state: else a hang.
  # (At 100..1000 rad/s a second in, a fixed count: a precision there is refused.)
  for attack_case in "INT 0.3 10" "INT 2 10" "TERM 0.3 10" "TERM 2 10" "INT 1 100"; do
    read -r sig delay low <<< "$attack_case"
    attacks=$((attacks + 1))
    rm -f coast.*
    "$bin" run --set F_drive=5.000001 --omega-min $low --omega-max $((low * 10)) --realizations 8 --out coast \
      --no-plot --quiet 2> /dev/null &
    pid=$!
    sleep $delay
    stop_within $pid $sig "SIG$sig after $delay s inside a long realization at $low.."
    [ $status -ge 128 ] || { nonsense=$((nonsense + 1)); report NONSENSE "SIG$sig in a long realization: exit $status"; }
    [ -e coast.state ] || { work_lost=$((work_lost + 1)); report LOST "SIG$sig in a long realization: no state"; }
  done
  # An interrupt in a sweep's last run is an interrupt (130/143), as in an earlier run (at
  # 0.3%, so that the last run lasts seconds: at 1% the whole sweep takes half a second).
  for sig in INT TERM; do
    attacks=$((attacks + 1))
    rm -f lsw*
    "$bin" sweep alpha=1,0.9 --omega-min 0.1 --omega-max 1e4 --precision 0.003 --out lsw --no-plot 2> "$logs/stderr" &
    pid=$!
    for _ in $(seq 400); do grep -q "sweep 2/2" "$logs/stderr" && break; sleep 0.05; done
    sleep 0.3
    kill -s $sig $pid 2> /dev/null
    wait $pid 2> /dev/null
    status=$?
    [ $status -ge 128 ] || { nonsense=$((nonsense + 1)); report NONSENSE "sweep, $sig in its last run: exit $status"; }
  done
  # A run resumed into another prefix leaves no state behind at the one it came from.
  attacks=$((attacks + 1))
  rm -f from.* into.*
  "$bin" run --omega-min 10 --omega-max 1000 --precision 0.1 --seed 5 --out from --no-plot --quiet \
    --checkpoint-every 0.05 2> /dev/null &
  pid=$!
  sleep 0.5
  kill -INT $pid 2> /dev/null
  wait $pid 2> /dev/null
  if [ -e from.state ]; then
    "$bin" run --resume from --out into --no-plot --quiet 2> /dev/null
    if ! cmp -s <(grep -v '^#' into.tsv) <(grep -v '^#' whole.tsv); then
      work_lost=$((work_lost + 1)); report LOST "resumed into another prefix: the table differs"
    elif [ -e from.state ]; then
      other=$((other + 1)); report LEFT "resumed into another prefix: from.state stayed"
    fi
  fi
  # A signal ends analyze (reading a record that does not end) and synth without their lock.
  mkfifo feed
  for sig in INT TERM HUP QUIT; do
    attacks=$((attacks + 1))
    "$bin" analyze - --out sig --no-plot --quiet < feed 2> /dev/null &
    pid=$!
    exec 7> feed
    printf 't,x\n0,0\n' >&7
    sleep 0.5
    kill -s $sig $pid 2> /dev/null
    wait $pid 2> /dev/null
    exec 7>&-
    [ -e sig.lock ] && { other=$((other + 1)); report LEFT "analyze ended by SIG$sig left its lock"; }
    rm -f sig.*
    attacks=$((attacks + 1))
    "$bin" synth --duration 1e5 --sample-interval 0.01 --out syn 2> /dev/null &
    pid=$!
    sleep 0.5
    kill -s $sig $pid 2> /dev/null
    wait $pid 2> /dev/null
    [ -e syn.lock ] && { other=$((other + 1)); report LEFT "synth ended by SIG$sig left its lock"; }
    rm -f syn.*
  done
  rm -f feed core core.*
  # With the most contacts a run steps (2^20) a signal is heard within about a second, its
  # state saved (the result rebuilt the million-block tree five times after it: 2-2.7 s).
  for sig in INT TERM; do
    attacks=$((attacks + 1))
    rm -f wide.*
    "$bin" run --set N=1048576 --omega-min 1 --omega-max 10 --precision 0.2 --work-budget 1e15 --out wide \
      --no-plot --quiet 2> /dev/null &
    pid=$!
    sleep 2
    stop_within $pid $sig "SIG$sig with 2^20 contacts"
    if [ $waited -gt 12 ] && [ $waited -lt 30 ]; then
      other=$((other + 1)); report SLOW "SIG$sig with 2^20 contacts: heard only after $waited tenths of a second"
    fi
    [ -e wide.state ] || { work_lost=$((work_lost + 1)); report LOST "SIG$sig with 2^20 contacts: no state"; }
  done
  rm -f wide.*
  # A signal while the plotter reads the theory lines leaves no scratch directory.
  mkdir -p scratch/tmp
  printf '#!/bin/sh\nexec sleep 60\n' > slow_plotter
  chmod +x slow_plotter
  for sig in INT TERM HUP QUIT; do
    attacks=$((attacks + 1))
    TMPDIR=$work/scratch/tmp SLIDESPEC_PYTHON=$work/slow_plotter "$bin" analyze rec.csv --out sfig --quiet \
      2> /dev/null &
    pid=$!
    for _ in $(seq 100); do ls scratch/tmp/slidespec-plot-* > /dev/null 2>&1 && break; sleep 0.05; done
    sleep 0.2
    kill -s $sig $pid 2> /dev/null
    wait $pid 2> /dev/null
    if ls -d scratch/tmp/slidespec-plot-* > /dev/null 2>&1; then
      other=$((other + 1)); report LEFT "analyze ended by SIG$sig in its figure left its scratch directory"
    fi
    rm -rf scratch/tmp/* sfig.* core core.*
  done
  # Python: Ctrl-C ends ss.analyze of 3e7 samples within a second, and ss.analyze_many
  # keeps the records finished.
  if [ -n "${PYTHONPATH:-}" ]; then
    attacks=$((attacks + 1))
    timeout 120 /usr/bin/python3 -c '
import os, signal, threading, time, numpy as np, slidespec as ss
x = 1e-9 * np.arange(30_000_000) + np.cumsum(np.random.default_rng(1).normal(0, 1e-9, 30_000_000))
sent = []
threading.Timer(0.5, lambda: (sent.append(time.monotonic()), os.kill(os.getpid(), signal.SIGINT))).start()
try:
    ss.analyze(None, x, dt=1e-3)
    print("finished")
except KeyboardInterrupt:
    print("interrupted after %.2f s" % (time.monotonic() - sent[0]))' > "$logs/stdout" 2> "$logs/stderr"
    case $(cat "$logs/stdout") in
      "interrupted after 0."* | "interrupted after 1."*) ;;
      *) other=$((other + 1)); report SLOW "ss.analyze of 3e7 samples, Ctrl-C: $(cat "$logs/stdout") $(tail -c 200 "$logs/stderr")" ;;
    esac
    attacks=$((attacks + 1))
    # Records of 2e5 samples, some 50 ms each: 240 of them outlast the interrupt at 1 s.
    "$bin" synth --duration 2000 --sample-interval 0.01 --out many1 > /dev/null 2>&1
    for k in 2 3 4 5 6; do cp many1.csv "many$k.csv"; done
    timeout 120 /usr/bin/python3 -c '
import os, signal, threading, time, slidespec as ss
paths = ["many%d.csv" % k for k in range(1, 7)] * 40
threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    ss.analyze_many(paths)
    print("finished")
except ss.AnalysesInterrupted as cut:
    print("kept", len(cut.results), len(cut.table))
except KeyboardInterrupt:
    print("lost")' > "$logs/stdout" 2> "$logs/stderr"
    case $(cat "$logs/stdout") in
      kept*) ;;
      *) work_lost=$((work_lost + 1)); report LOST "ss.analyze_many, Ctrl-C: $(cat "$logs/stdout") $(tail -c 200 "$logs/stderr")" ;;
    esac
    rm -f many*.csv
  fi
  # Two parts at once onto one --save-state: one is refused, the other's state stays whole.
  attacks=$((attacks + 1))
  rm -f same.state
  "$bin" run --omega-min 10 --omega-max 1000 --realizations-range 0:64 --save-state same.state --out sa \
    --no-plot --quiet 2> /dev/null &
  pid=$!
  sleep 0.2
  "$bin" run --omega-min 10 --omega-max 1000 --realizations-range 64:64 --save-state same.state --out sb \
    --no-plot --quiet 2> /dev/null
  second=$?
  wait $pid
  first=$?
  if [ $first -eq 0 ] && [ $second -eq 0 ]; then
    work_lost=$((work_lost + 1)); report LOST "two parts onto one --save-state both exited 0"
  fi
  # An interrupted sweep continues with --resume: whatever the signal and wherever it lands
  # (a run, between runs, the continuation itself), the continued sweep's combined table and
  # JSON are the uninterrupted one's, bit for bit, and nothing of it is left behind.
  sweep_args="alpha=0.3,0.6,0.9 --omega-min 10 --omega-max 1000 --precision 0.01 --seed 5 --no-plot"
  mkdir -p swwhole && (cd swwhole && "$bin" sweep $sweep_args --out s --quiet)
  continued_as_whole() {  # NAME: continues the sweep in swcut and compares it with swwhole
    (cd swcut && timeout 120 "$bin" sweep $sweep_args --out s --quiet --resume 2> "$logs/stderr")
    local status=$?
    if [ $status -ne 0 ]; then
      work_lost=$((work_lost + 1)); report LOST "$1: the continuation exited $status: $(head -c 200 "$logs/stderr")"
    elif ! cmp -s swcut/s.tsv swwhole/s.tsv || ! cmp -s swcut/s.json swwhole/s.json; then
      work_lost=$((work_lost + 1)); report LOST "$1: the continued sweep differs from the uninterrupted one"
    elif [ -n "$(ls swcut | grep '\.state$\|\.sweep$\|\.lock$\|tmp')" ]; then
      other=$((other + 1)); report LEFT "$1: the continued sweep left $(ls swcut | tr '\n' ' ')"
    fi
  }
  for delay in 0.1 0.4 0.8 1.2 1.6; do
    for sig in INT TERM KILL; do
      attacks=$((attacks + 1))
      rm -rf swcut && mkdir swcut
      (cd swcut && exec "$bin" sweep $sweep_args --out s --quiet 2> /dev/null) &
      pid=$!
      sleep $delay
      kill -s $sig $pid 2> /dev/null
      wait $pid 2> /dev/null
      status=$?
      if [ -e swcut/s.sweep ]; then
        [ $sig != KILL ] && [ $status -lt 128 ] && { nonsense=$((nonsense + 1)); report NONSENSE "sweep cut by $sig: exit $status"; }
        continued_as_whole "sweep cut by $sig after $delay s"
      elif [ $status -eq 0 ] && ! cmp -s swcut/s.tsv swwhole/s.tsv; then  # finished before the signal
        work_lost=$((work_lost + 1)); report LOST "sweep finished before $sig: differs"
      fi
    done
  done
  # Cut between two runs (held there by SLIDESPEC_SWEEP_STALL): SIG in DIR, and whether it took.
  cut_between() {  # SIG DIR [--resume]
    local sig=$1 dir=$2
    rm -f "$dir/stalled"
    (cd "$dir" && SLIDESPEC_SWEEP_STALL=$work/$dir/stalled exec "$bin" sweep $sweep_args --out s --quiet ${3:-} \
      2> /dev/null) &
    local pid=$!
    for _ in $(seq 600); do [ -s "$dir/stalled" ] && break; sleep 0.05; done
    kill -s "$sig" $pid 2> /dev/null
    wait $pid 2> /dev/null
    rm -f "$dir/stalled"
    [ -e "$dir/s.sweep" ]
  }
  for sig in INT KILL; do
    attacks=$((attacks + 1))
    rm -rf swcut && mkdir swcut
    cut_between $sig swcut && continued_as_whole "sweep cut by $sig between runs"
  done
  # A continuation cut in its turn (between its runs), then continued again.
  attacks=$((attacks + 1))
  rm -rf swcut && mkdir swcut
  if cut_between INT swcut && cut_between TERM swcut --resume; then
    continued_as_whole "a continuation cut again"
  else
    other=$((other + 1)); report OTHER "a continuation cut again: a cut between runs did not take"
  fi
  # Continuing another sweep than the one cut, or nothing, is refused and touches nothing.
  rm -rf swref && mkdir swref
  cut_between INT swref
  if [ -e swref/s.sweep ]; then
    refused_naming() {  # NAME WORDS ARGS...: refused, and the message names WORDS
      local name=$1 words=$2; shift 2
      attack refuse "$name" "$@"
      grep -q -- "$words" "$logs/stderr" || { other=$((other + 1)); report UNCLEAR "$name: $(head -c 200 "$logs/stderr")"; }
    }
    refused_naming "sweep --resume, other values" "the grid: alpha=0.3,0.6,0.9 there, alpha=0.3,0.6,1 here" \
      sweep alpha=0.3,0.6,1 ${sweep_args#* } --out ../swref/s --resume
    refused_naming "sweep --resume, a value less" "the grid" sweep alpha=0.3,0.6 ${sweep_args#* } --out ../swref/s --resume
    refused_naming "sweep --resume, another seed" "--seed: 5 there, 6 here" \
      sweep ${sweep_args% --seed*} --seed 6 --no-plot --out ../swref/s --resume
    refused_naming "sweep --resume, another precision" "--precision: 0.01 there, 0.02 here" \
      sweep alpha=0.3,0.6,0.9 --omega-min 10 --omega-max 1000 --precision 0.02 --seed 5 --no-plot --out ../swref/s --resume
    refused_naming "sweep --resume, another case" "--case: reference there, weak-noise here" \
      sweep $sweep_args --case weak-noise --out ../swref/s --resume
    refused_naming "sweep --resume, another --set" "parameter N: 30 there, 12 here" \
      sweep $sweep_args --set N=12 --out ../swref/s --resume
    refused_naming "sweep --resume, another band" "--omega-min: 10 there, 20 here" \
      sweep alpha=0.3,0.6,0.9 --omega-min 20 --omega-max 1000 --precision 0.01 --seed 5 --no-plot --out ../swref/s --resume
    refused_naming "a fresh sweep over a cut one" "s.sweep holds a sweep not yet written whole" \
      sweep $sweep_args --out ../swref/s
    refused_naming "sweep --resume, nothing to continue" "nothing to continue" sweep $sweep_args --out ../swwhole/s --resume
    refused_naming "sweep --resume, nothing ever run" "nothing to continue" sweep $sweep_args --out nothing --resume
    if [ -e "swref/s_alpha=0.3.json" ]; then
      (cd swref && "$bin" run --set alpha=0.3 --omega-min 10 --omega-max 1000 --precision 0.01 --seed 6 \
        --out other --no-plot --quiet && cp other.json "s_alpha=0.3.json" && cp other.tsv "s_alpha=0.3.tsv")
      refused_naming "sweep --resume, a run's outputs of another seed" "run alpha=0.3: .* is of another run" \
        sweep $sweep_args --out ../swref/s --resume
    fi
  else
    other=$((other + 1)); report OTHER "sweep --resume refusals: the sweep to refuse was not cut"
  fi
  rm -rf swcut swref swwhole
fi

echo "adversarial sweep: $attacks attacks: crashes $crashes, hangs $hangs, inputs lost $inputs_lost," \
  "finished work lost $work_lost, nonsense accepted $nonsense; other (unclear message or failed work) $other"
