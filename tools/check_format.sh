#!/usr/bin/env bash
# The C++ sources this branch changes (against `git merge-base HEAD BASE`, BASE = $1 or
# main), or every tracked one when there is no such base or it is HEAD itself, must read as
# clang-format writes them with the repository's .clang-format. Exit 1 naming each file
# that does not; skipped, saying so, where clang-format is not installed.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format > /dev/null; then
  echo "check_format: clang-format is not installed (apt-get install clang-format); skipped"
  exit 0
fi
base=$(git merge-base HEAD "${1:-main}" 2> /dev/null || true)
if [ -n "$base" ] && [ "$base" != "$(git rev-parse HEAD)" ]; then
  mapfile -t files < <(git diff --name-only --diff-filter=d "$base" -- '*.cpp' '*.hpp' '*.inc')
else
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.inc')
fi
unformatted=0
for file in "${files[@]}"; do
  if ! clang-format --dry-run -Werror "$file" > /dev/null 2>&1; then
    echo "check_format: $file differs from clang-format's layout (clang-format -i $file)"
    unformatted=$((unformatted + 1))
  fi
done
echo "check_format: ${#files[@]} files checked, $unformatted to format"
[ "$unformatted" -eq 0 ]
