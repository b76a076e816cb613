#!/usr/bin/env bash
# End-to-end checks of the command line: exit codes, one-line errors, files untouched.
set -u
bin=${SLIDESPEC:?set SLIDESPEC to the slidespec executable}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_refused NAME WORD ARGS...: exit 2, one line on stderr naming WORD, no output file.
expect_refused() {
  local name=$1 word=$2; shift 2
  echo "sentinel" > "$work/out.tsv"
  "$bin" "$@" > "$work/stdout" 2> "$work/stderr"
  local status=$?
  [ $status -eq 2 ] || fail "$name: exit status $status, expected 2"
  [ "$(wc -l < "$work/stderr")" -eq 1 ] || fail "$name: stderr is not one line: $(cat "$work/stderr")"
  grep -q -- "$word" "$work/stderr" || fail "$name: stderr does not name '$word': $(cat "$work/stderr")"
  [ "$(cat "$work/out.tsv")" = "sentinel" ] || fail "$name: output file was touched"
}

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

# A good run writes the table atomically and leaves no temporary file behind.
"$bin" theory --out "$work/ref" > /dev/null 2>&1 || fail "theory --out failed"
[ -f "$work/ref.tsv" ] || fail "theory --out wrote no PREFIX.tsv"
grep -q "^omega	C_x	C_eq1$" "$work/ref.tsv" || fail "theory table has no header line"
[ "$(grep -vc '^#' "$work/ref.tsv")" -eq 50 ] || fail "theory table does not have 49 rows"
ls "$work" | grep -q tmp && fail "a temporary file was left behind"
"$bin" cases | grep -q "^concrete-fit" || fail "cases does not list concrete-fit"

# The parameter file route gives the same as --set.
echo '{"alpha": 0.4, "chain": "ring"}' > "$work/p.json"
"$bin" theory --params "$work/p.json" > "$work/a.tsv" && "$bin" theory --set alpha=0.4 --set chain=ring > "$work/b.tsv" \
  && cmp -s "$work/a.tsv" "$work/b.tsv" || fail "--params differs from --set"

echo "$((20 - failures)) passed, $failures failed" >/dev/null
[ $failures -eq 0 ] && echo "cli: all checks passed"
exit $((failures > 0))
