#!/usr/bin/env bash
# A run whose outputs do not fit on the disk changes none of the files of its set: the
# older run's table, JSON and picture stay as they were, together, and no temporary remains.
# The finished run is not lost: its state stays, and the command slidespec prints writes
# its outputs once there is room.
# Needs a small tmpfs (root, and mount allowed); otherwise skipped with a message.
source "$(dirname "$0")/common.sh"

disk="$work/small"
mkdir "$disk"
if ! mount -t tmpfs -o size=320k tmpfs "$disk" 2> /dev/null; then
  echo "full_disk: skipped: cannot mount a small tmpfs here (needs root and mount permission)"
  exit 0
fi
trap 'umount "$disk"; rm -rf "$work"' EXIT

# A run whose state alone cannot fit is refused before any work (its realizations' own
# periodogram means alone take 8000 x 12 doubles, 770 kB, on a 320 kB disk).
"$bin" run --omega-min 100 --omega-max 1000 --realizations 8000 --out "$disk/big" --quiet 2> "$work/err"
status=$?
[ $status -eq 2 ] || fail "a state that cannot fit exited $status, expected 2"
grep -q "state needs at least .* MB free" "$work/err" || fail "no message naming the space: $(cat "$work/err")"
[ -z "$(ls "$disk")" ] || fail "a refused run left files: $(ls "$disk")"

band="--omega-min 100 --omega-max 1000 --precision 0.2"
"$bin" run $band --seed 4 --out "$disk/out" --quiet || fail "the first run failed"
for ext in tsv json png; do [ -s "$disk/out.$ext" ] || fail "the first run wrote no .$ext"; done
before=$(cd "$disk" && sha256sum out.tsv out.json out.png)
# Fill the disk but for room for the run's state and a little: not for the output set.
"$bin" run $band --seed 5 --out "$work/sized" --quiet --no-plot --save-state "$work/sized.state" || fail "sizing run"
room=$(( ($(du -b "$work/sized.state" | cut -f1) / 4096 + 2) * 4096 ))
head -c $(( 320 * 1024 - $(du -s -B1 "$disk" | cut -f1) - room )) /dev/zero > "$disk/filler" 2> /dev/null
"$bin" run $band --seed 5 --out "$disk/out" --quiet 2> "$work/err"
status=$?
[ $status -ne 0 ] || fail "a run on a full disk reported success"
[ $status -ne 2 ] || fail "a full disk is not bad input (exit 2): $(cat "$work/err")"
[ "$before" = "$(cd "$disk" && sha256sum out.tsv out.json out.png)" ] || fail "the older run's set was changed"
leftover=$(ls "$disk" | grep -v -e '^out\.\(tsv\|json\|png\|state\)$' -e '^filler$')
[ -z "$leftover" ] || fail "temporaries left on the full disk: $leftover"
finish=$(sed -n 's/.*write its outputs with: slidespec //p' "$work/err")
[ -s "$disk/out.state" ] || fail "the finished run's state is not on the disk: $(cat "$work/err")"
[ -n "$finish" ] || fail "no command to finish the job: $(cat "$work/err")"
rm "$disk/filler"
"$bin" $finish --quiet || fail "'$finish' failed once there was room"
cmp -s "$disk/out.tsv" "$work/sized.tsv" || fail "the finished run's table differs from an undisturbed run's"
[ -e "$disk/out.state" ] && fail "the state stayed after its outputs were written"
# A run to a precision runs at least a first round of realizations in every sub-band:
# refused before any work where even their state cannot fit (six sub-bands of 64
# realizations, about 30 kB, with 8 kB free).
head -c $(( 320 * 1024 - $(du -s -B1 "$disk" | cut -f1) - 8192 )) /dev/zero > "$disk/filler" 2> /dev/null
"$bin" run --omega-min 0.1 --omega-max 1e5 --precision 0.1 --out "$disk/wide" --quiet 2> "$work/err"
status=$?
[ $status -eq 2 ] || fail "a precision run whose first round cannot fit exited $status, expected 2"
grep -q "state needs at least .* MB free" "$work/err" || fail "no message naming the space: $(cat "$work/err")"
ls "$disk" | grep -q '^wide' && fail "a refused precision run left files: $(ls "$disk")"
rm "$disk/filler"
[ $failures -eq 0 ] && echo "full_disk: a full disk changed no file of the set and lost no run ($(head -c 120 "$work/err"))"
exit $((failures > 0))
