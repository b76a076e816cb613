#!/usr/bin/env bash
# mpirun with 1, 2 and 3 ranks gives bitwise the table of a single process, for a fixed
# realization count and for a precision-driven run (whose rounds every rank must plan alike).
source "$(dirname "$0")/common.sh"
mpiexec=${MPIEXEC:-mpirun}
# OpenMPI refuses root unless told; CI containers run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Ranks on a two-core machine: more ranks than cores is allowed here, and nothing is bound.
launch() { "$mpiexec" --oversubscribe --bind-to none -np "$@"; }

for request in "--realizations 40" "--precision 0.05"; do
  name=$(echo "$request" | tr -d ' -')
  args="--omega-min 10 --omega-max 1000 --seed 11 --no-plot --quiet $request"
  "$bin" run $args --out "$work/single_$name" || fail "$request: single process failed"
  for ranks in 1 2 3; do
    launch $ranks "$bin" run $args --threads 1 --out "$work/ranks${ranks}_$name" \
      || fail "$request: mpirun -np $ranks failed"
    cmp -s "$work/single_$name.tsv" "$work/ranks${ranks}_$name.tsv" \
      || fail "$request: $ranks ranks differ from one process"
  done
done

# Bad input: one line (from rank 0 only), exit 2, no file.
launch 2 "$bin" run --set N=0 --out "$work/bad" 2> "$work/bad.err"
status=$?
[ $status -ne 0 ] || fail "bad input under mpirun exited 0"
[ "$(grep -c 'parameter N' "$work/bad.err")" -eq 1 ] || fail "bad input not reported once: $(cat "$work/bad.err")"
[ -e "$work/bad.tsv" ] && fail "bad input wrote a file"

[ $failures -eq 0 ] && echo "mpi: all checks passed"
exit $((failures > 0))
