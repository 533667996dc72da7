#!/usr/bin/env bash
# Runs every libFuzzer target for a bounded time over its committed seed corpus, under
# AddressSanitizer + UndefinedBehaviorSanitizer (leaks included). Any crash, leak, sanitizer
# report or timeout fails the script; the crashing input is left in build-fuzz/artifacts/ —
# copy it to tests/fuzz/regressions/<target>/ so the test suite replays it from then on.
# Usage: scripts/fuzz.sh [seconds per target, default 45]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-45}
scripts/setup.sh --with-fuzz
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DNDTOM_FUZZ=ON -DNDTOM_BUILD_TESTS=OFF -DNDTOM_BUILD_APPS=OFF -DNDTOM_WITH_MRPT=ON >/dev/null
targets=(fuzz_map_loader fuzz_map_decoder fuzz_pcd_reader fuzz_scan_insertion fuzz_tiled_map
  fuzz_mrpt_deserialization)
cmake --build build-fuzz -j2 --target "${targets[@]}"
rm -rf build-fuzz/artifacts && mkdir -p build-fuzz/artifacts
# As scripts/sanitize.sh: alignment reports are recoverable (for MRPT's headers) but halt.
supp=$PWD/tests/sanitizers
export LSAN_OPTIONS=suppressions=$supp/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp
status=0
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t
  mkdir -p "$work"
  echo "== $t: ${seconds}s"
  if ! build-fuzz/tests/fuzz/$t "$work" "tests/fuzz/corpus/$t" -max_total_time="$seconds" \
      -timeout=20 -rss_limit_mb=2048 -artifact_prefix="build-fuzz/artifacts/$t-" \
      -print_final_stats=1 2>build-fuzz/$t.log; then
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" build-fuzz/$t.log || true
  if ls build-fuzz/artifacts/$t-* >/dev/null 2>&1; then
    echo "FAIL $t: $(ls build-fuzz/artifacts/$t-*)"
    grep -m5 -E "ERROR|SUMMARY|runtime error" build-fuzz/$t.log || true
    status=1
  else
    echo "ok   $t"
  fi
done
exit $status
