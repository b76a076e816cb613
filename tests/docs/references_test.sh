#!/usr/bin/env bash
# Every citation "model.md §N" in code, docs, tools and tests names a section that
# docs/model.md has, and nothing cites a file outside the repository (MODEL.md).
set -u
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root" || exit 1
failures=0
sources=(README.md docs bench src include tools tests)
if grep -rIn --exclude=references_test.sh -e 'MODEL\.md' -e '/work/shared' "${sources[@]}"; then
  echo "FAIL: the lines above cite a file outside the repository"; failures=$((failures + 1))
fi
sections=$(grep -E '^##+ [0-9]+(\.[0-9]+)*\.? ' docs/model.md | awk '{print $2}' | sed 's/\.$//')
[ "$(echo "$sections" | grep -cE '^[1-6]$')" -eq 6 ] || { echo "FAIL: docs/model.md lacks sections 1-6"; failures=$((failures + 1)); }
while IFS= read -r cited; do
  echo "$sections" | grep -qxF "$cited" || { echo "FAIL: §$cited cited but docs/model.md has no such section"; failures=$((failures + 1)); }
done < <(grep -rIhoE --exclude=references_test.sh 'model\.md[)]? §[0-9]+(\.[0-9]+)?' "${sources[@]}" | sed -E 's/.*§//' | sort -u)
# Prose that says "section N" of the model without the file is ambiguous.
if grep -rIn --exclude=references_test.sh -E '\(section [0-9]' "${sources[@]}"; then
  echo "FAIL: the lines above cite a section without its file"; failures=$((failures + 1))
fi
[ $failures -eq 0 ] && echo "all model.md citations resolve"
exit $((failures > 0))
