#!/usr/bin/env bash
# What users meet first: usage and "did you mean", theory at given omegas,
# tables numpy reads as they are, JSON parameters that --params reads back, shortest
# numbers, run labels, sweep grids and their combined table, figures by extension, and
# an installed copy that plots.
source "$(dirname "$0")/common.sh"
python=/usr/bin/python3
out="--out $work/out"

# Usage and suggestions.
"$bin" > "$work/usage" 2>&1; status=$?
[ $status -eq 0 ] && grep -q "Usage:" "$work/usage" && grep -q "theory" "$work/usage" || fail "bare slidespec: no usage (status $status)"
expect_refused mistyped-command "did you mean 'theory'" theroy
expect_refused mistyped-option "did you mean '--omega-min'" run --omega-mni 3 $out
expect_refused mistyped-analyze-option "did you mean '--units'" analyze x.csv --unit um $out
expect_refused mistyped-case "did you mean 'reference'" theory --case refrence $out
expect_refused mistyped-key "did you mean 'alpha'" theory --set alhpa=1 $out
expect_refused mistyped-figure "did you mean 'fig6'" paper fgi6 --out-dir "$work"
"$bin" run --help | grep -q -- "--threads.*0: all cores" || fail "--threads 0 is not documented in run --help"

# theory at given omegas: a list and a file.
"$bin" theory --omega 1,10,548.2 > "$work/list.tsv" || fail "theory --omega"
[ "$(grep -vc '^#' "$work/list.tsv")" -eq 3 ] || fail "theory --omega: not 3 rows"
grep -q "^548.2	" "$work/list.tsv" || fail "theory --omega: omega 548.2 not in the first column"
printf '# omegas\n1\n10 100\n' > "$work/omegas.txt"
"$bin" theory --omega-file "$work/omegas.txt" > "$work/file.tsv" || fail "theory --omega-file"
[ "$(grep -vc '^#' "$work/file.tsv")" -eq 3 ] || fail "theory --omega-file: not 3 rows"
expect_refused omega-not-a-number "'x' is not a positive omega" theory --omega 1,x $out
expect_refused omega-negative "'-1' is not a positive omega" theory --omega=-1 $out
printf '1\nten\n' > "$work/bad_omegas.txt"
expect_refused omega-file-line "line 2" theory --omega-file "$work/bad_omegas.txt" $out

# A short run with keys set: its label, numbers, TSV and JSON.
"$bin" run --set N=5 --set alpha=0.5 --omega-min 1 --omega-max 100 --precision 0.2 --quiet --no-plot \
  --out "$work/small" || fail "small run"
grep -q "^# case = reference$" "$work/small.tsv" || fail "run: case line"
grep -q "^# label = reference + N=5, alpha=0.5$" "$work/small.tsv" || fail "run: label 'reference + N=5, alpha=0.5'"
grep -q '"label": "reference + N=5, alpha=0.5"' "$work/small.json" || fail "run JSON: label"
grep -q "^# m = 1e-05$" "$work/small.tsv" || fail "numbers are not in shortest form: $(grep '^# m =' "$work/small.tsv")"
grep -q "0000000000" "$work/small.tsv" "$work/small.json" && fail "a number printed with rounding noise"
grep -q "^# omega	C_x	stderr	theory" "$work/small.tsv" || fail "run: the column line does not start with '#'"
$python - "$work" <<'PY' || fail "numpy/pandas/--params checks (above)"
import json, sys, numpy as np
work = sys.argv[1]
for name in ("small.tsv", "list.tsv"):
    table = np.loadtxt(f"{work}/{name}")  # no options: '#' lines are comments
    assert table.ndim == 2 and table.shape[0] >= 3, (name, table.shape)
names = [l for l in open(f"{work}/small.tsv") if l.startswith("#")][-1][1:].split()
assert names[:4] == ["omega", "C_x", "stderr", "theory"], names
doc = json.load(open(f"{work}/small.json"))
p = doc["parameters"]
assert p["N"] == 5 and isinstance(p["N"], int) and p["alpha"] == 0.5 and p["m"] == 1e-05, p
assert all(isinstance(v, (int, float)) for k, v in p.items() if k not in ("chain", "renewal")), p
try:
    import pandas as pd
    frame = pd.read_csv(f"{work}/small.tsv", sep="\t", comment="#", names=names)
    assert list(frame.columns[:2]) == ["omega", "C_x"] and len(frame) == len(np.loadtxt(f"{work}/small.tsv"))
except ImportError:
    pass
PY
# The output JSON, or its parameters block, is accepted by --params and gives the same model.
"$bin" theory --params "$work/small.json" --omega 1,100 | grep -v '^# \(label\|slidespec\)' > "$work/from_json.tsv" || fail "--params run.json"
"$bin" theory --set N=5 --set alpha=0.5 --omega 1,100 | grep -v '^# \(label\|slidespec\)' > "$work/from_set.tsv"
diff -q "$work/from_json.tsv" "$work/from_set.tsv" > /dev/null || fail "--params of the output JSON gives another model"
$python -c "import json,sys; json.dump(json.load(open(sys.argv[1]))['parameters'], open(sys.argv[2], 'w'))" "$work/small.json" "$work/block.json"
"$bin" theory --params "$work/block.json" --omega 1,100 | grep -v '^# \(label\|slidespec\)' | diff -q - "$work/from_set.tsv" > /dev/null \
  || fail "--params of the parameters block gives another model"

# sweep: a grid of a linear range and a log range, the combined table beside the runs.
"$bin" sweep alpha=0.5:1:0.5 N=10..40 log 2 --omega-min 1 --omega-max 100 --precision 0.3 --quiet \
  --out "$work/sw" --format svg || fail "sweep grid"
for name in "alpha=0.5_N=10" "alpha=0.5_N=40" "alpha=1_N=10" "alpha=1_N=40"; do
  [ -s "$work/sw_$name.tsv" ] && [ -s "$work/sw_$name.json" ] || fail "sweep: no sw_$name.tsv/.json"
done
head -c 5 "$work/sw.svg" | grep -q "<?xml" || fail "sweep --format svg: no SVG overlay"
$python - "$work" <<'PY' || fail "sweep combined table (above)"
import json, sys, numpy as np
work = sys.argv[1]
table = np.loadtxt(f"{work}/sw.tsv")
runs = json.load(open(f"{work}/sw.json"))["runs"]
assert len(runs) == 4, len(runs)
assert [r["values"] for r in runs] == [{"alpha": a, "N": n} for a in (0.5, 1) for n in (10, 40)], runs
assert table.shape[0] == sum(len(r["points"]) for r in runs), table.shape
assert sorted(set(table[:, 0])) == [0, 1, 2, 3] and sorted(set(table[:, 2])) == [10, 40]
assert runs[0]["label"] == "reference + N=10, alpha=0.5", runs[0]["label"]
PY
expect_refused sweep-range-without-count "log 5" sweep N=10..100 $out
expect_refused sweep-bad-step "STEP" sweep alpha=1:0.1:0.1 $out
expect_refused sweep-key-twice "twice" sweep alpha=1,2 alpha=3 $out
expect_refused sweep-point-named "sweep run alpha=-1: parameter alpha" sweep alpha=1,-1 $out
expect_refused model-key-as-option "alpha is a model parameter, set it with --set alpha=VALUE" run --alpha 2 $out
# Swept across drives, the spring's stiffness goes to the spring's runs only.
"$bin" sweep drive=force,spring --set k_drive=1e4 --omega-min 10 --omega-max 100 --realizations 8 --quiet --no-plot \
  --out "$work/drives" || fail "sweep across drives with --set k_drive"
grep -q "^# k_drive = 10000" "$work/drives_drive=spring.tsv" || fail "sweep across drives: the spring run has no k_drive"
grep -q "^# k_drive" "$work/drives_drive=force.tsv" && fail "sweep across drives: the force run has a k_drive"
# The combined table holds each run's own point columns, to the character: the spring's
# force columns in every row, nan in the force-driven run's; the JSON each run's points.
$python - "$work" <<'PY' || fail "sweep across drives: the combined table is not the runs' own (above)"
import json, sys
work = sys.argv[1]
def rows(path):
    lines = open(path).read().splitlines()
    header = [l for l in lines if l.startswith("# ") and "\t" in l][-1][2:].split("\t")
    return header, [l.split("\t") for l in lines if not l.startswith("#")]
header, combined = rows(f"{work}/drives.tsv")
assert header[:2] == ["run", "drive"], header
for run, drive in enumerate(["force", "spring"]):
    own_header, own = rows(f"{work}/drives_drive={drive}.tsv")
    mine = [r[2:] for r in combined if r[0] == str(run)]
    assert len(mine) == len(own) > 0, (drive, len(mine), len(own))
    width = len(own_header)
    assert header[2:2 + width] == own_header, (drive, header, own_header)
    assert [r[:width] for r in mine] == own, drive
    assert all(v == "nan" for r in mine for v in r[width:]), drive
assert header[-3:] == ["C_F_spring", "C_F_spring_stderr", "C_F_spring_theory"], header
whole = json.load(open(f"{work}/drives.json"))["runs"]
for run, drive in enumerate(["force", "spring"]):
    assert whole[run]["points"] == json.load(open(f"{work}/drives_drive={drive}.json"))["points"], drive
PY

# Figures: the format by the extension, refused before any work when unknown.
"$bin" plot "$work/small.tsv" -o "$work/fig.pdf" --size 5x4 && head -c 5 "$work/fig.pdf" | grep -q "%PDF-" || fail "plot -o .pdf: not a PDF"
"$bin" plot "$work/small.tsv" -o "$work/fig.png" --dpi 80 && head -c 4 "$work/fig.png" | grep -q "PNG" || fail "plot -o .png: not a PNG"
expect_refused plot-jpg "unknown figure format" plot "$work/small.tsv" -o "$work/out.jpg"
expect_refused run-format "--format" run --format jpg $out
expect_refused run-size "--size" run --size big $out
expect_refused run-png-beyond-cairo "32767 pixels" run --size 20x10 --dpi 2400 $out
# run and merge draw their own figure: a PDF and an SVG of the page asked for.
"$bin" run --omega-min 1 --omega-max 100 --realizations-range 0:8 --save-state "$work/part.state" --no-plot \
  --quiet --out "$work/part" || fail "a part of a run"
"$bin" merge "$work/part.state" --out "$work/merged" --format svg --size 5x4 --quiet \
  && grep -q 'width="360pt" height="288pt"' "$work/merged.svg" && tail -c 10 "$work/merged.svg" | grep -q "</svg>" \
  || fail "merge --format svg --size 5x4: not a whole 5x4 in SVG"
expect_refused plot-long-title "--title" plot "$work/small.tsv" -o "$work/out.png" --title "$(printf 'x%.0s' $(seq 200))"

# cmake --install into a temporary prefix: the installed executable plots with the
# installed tool (a stub put in its place proves which one runs).
if [ -n "${SLIDESPEC_BUILD_DIR:-}" ]; then
  prefix="$work/prefix"
  cmake --install "$SLIDESPEC_BUILD_DIR" --prefix "$prefix" > "$work/install.log" 2>&1 || fail "cmake --install: $(cat "$work/install.log")"
  [ -x "$prefix/bin/slidespec" ] && [ -f "$prefix/share/slidespec/plot_spectra.py" ] &&
    [ -f "$prefix/share/slidespec/plot_server.py" ] || fail "install: files missing"
  "$prefix/bin/slidespec" plot "$work/small.tsv" -o "$work/installed.png" && [ -s "$work/installed.png" ] || fail "installed slidespec cannot plot"
  cat > "$prefix/share/slidespec/plot_spectra.py" << 'EOF'
def main(argv):
    open(next(a for a in argv if a.startswith("--out="))[len("--out="):], "w").write("stub")
    return 0
EOF
  "$prefix/bin/slidespec" plot "$work/small.tsv" -o "$work/stub.png"
  [ "$(cat "$work/stub.png" 2>/dev/null)" = "stub" ] || fail "installed slidespec does not use the installed plotting tool"
fi

[ $failures -eq 0 ] && echo "cli_outputs: all checks passed"
exit $((failures > 0))
