#!/usr/bin/env bash
# Mutation check of the core: applies each one-line bug of tests/mutations/core.txt to a
# scratch copy of the sources, one at a time, builds the core's tests and runs them. A bug
# the tests do not catch "survives". Exit status 1 if any survives or a mutation no longer
# applies (its text is gone from the source: update the list).
# Usage: scripts/mutation-check.sh [list file (tests/mutations/core.txt)] [build jobs (2)]
set -euo pipefail
cd "$(dirname "$0")/.."
list=$(realpath "${1:-tests/mutations/core.txt}")
jobs=${2:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A copy of the tracked sources: the working tree and its build stay untouched.
git ls-files -z | xargs -0 cp --parents -t "$work"
cd "$work"
# ccache, where installed, turns each restored file's rebuild into a cache hit.
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DNDTOM_WITH_MRPT=OFF \
  -DNDTOM_BUILD_APPS=OFF "${launcher[@]}" >/dev/null
cmake --build build -j"$jobs" >/dev/null
ctest --test-dir build -j"$jobs" >/dev/null || { echo "mutation-check: the unmutated tests fail" >&2; exit 1; }

killed=0 survived=0 stale=0 n=0
while IFS= read -r line; do
  [[ -z "$line" || "$line" == \#* ]] && continue
  n=$((n + 1))
  # Exactly four fields: a "|" in the code (as in "||") would cut the entry elsewhere.
  bars=${line//[^|]/}
  if [[ ${#bars} -ne 3 ]]; then
    echo "[$n] STALE     not 4 fields separated by '|' (no '|' may occur in the code): $line"
    stale=$((stale + 1))
    continue
  fi
  IFS='|' read -r file old new why <<<"$line"
  cp "$file" "$file.orig"
  if ! python3 - "$file" "$old" "$new" <<'PY'
import sys
path, old, new = sys.argv[1:4]
text = open(path).read()
if text.count(old) != 1:
    sys.exit(1)
open(path, "w").write(text.replace(old, new))
PY
  then
    echo "[$n] STALE     $file: text not found once: $old"
    stale=$((stale + 1))
    continue
  fi
  if ! cmake --build build -j"$jobs" >/dev/null 2>&1; then
    verdict="killed (does not build)"
    killed=$((killed + 1))
  elif ctest --test-dir build -j"$jobs" --stop-on-failure >/dev/null 2>&1; then
    verdict="SURVIVED"
    survived=$((survived + 1))
  else
    verdict="killed"
    killed=$((killed + 1))
  fi
  echo "[$n] $verdict  $file: $why"
  mv "$file.orig" "$file"
  # Newer than the mutant's objects: ninja compares times, and the restored copy is older.
  touch "$file"
done < "$list"
cmake --build build -j"$jobs" >/dev/null
ctest --test-dir build -j"$jobs" >/dev/null || { echo "mutation-check: a mutant outlived its restore" >&2; exit 1; }
echo "mutation-check: $n mutations, $killed killed, $survived survived, $stale stale"
[[ $survived -eq 0 && $stale -eq 0 ]]
