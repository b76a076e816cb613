#!/bin/bash
# Each vector path's object file may define global symbols only in its own namespaces
# (or xsimd's, instantiated for its own architecture). An inline function shared with
# other files (a std:: helper, say) would be a weak symbol compiled with that path's
# flags, and the linker could hand it to code running on a CPU without them.
# Arguments: the object files of slidespec_core.
status=0
checked=0
for object in "$@"; do
  case "$object" in */stepper/path_*.cpp.o | */estimator/path_*.cpp.o) ;; *) continue ;; esac
  path=${object##*/path_}
  path=${path%.cpp.o}
  [ "$path" = scalar ] && continue  # baseline flags: shared code from it is harmless
  checked=$((checked + 1))
  foreign=$(nm -C --defined-only "$object" | awk '$2 ~ /^[TWVDRBu]$/ { $1 = ""; $2 = ""; print }' |
            grep -v -e "$path" -e "__gxx_personality_v0")
  if [ -n "$foreign" ]; then
    echo "$object defines symbols outside the $path path:"
    echo "$foreign"
    status=1
  fi
done
if [ "$checked" -eq 0 ]; then
  echo "no vector path objects among the arguments"
  exit 1
fi
[ $status -eq 0 ] && echo "$checked vector path objects: only their own symbols"
exit $status
