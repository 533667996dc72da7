#!/usr/bin/env bash
# Builds the whole project with AddressSanitizer + UndefinedBehaviorSanitizer (leak checks
# included) and runs the test suite under them. Any sanitizer report fails a test.
# Left out, to keep CI within its time (they run in the README's test command): the benchmark
# programs and their smoke tests, MRPT's own programs and mpirun (label mrpt_programs), and
# our programs run end to end on valid data (label end_to_end; their bad-input cases stay).
# Usage: scripts/sanitize.sh [build dir, default build-asan]
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build-asan}
scripts/setup.sh
# -O1 -g1 (line tables only), as ASan's docs suggest: a heavy file compiles in a third of the
# time it takes at -O2 -g, and reports still name files and lines. The test programs
# themselves at -Og: they compile as fast as at -O0 (12 s instead of 35 s for the heaviest)
# and their brute-force references run 10 times faster than at -O0.
# UBSan's null and alignment checks left out: with ASan they doubled gcc's compile times
# (ASan still stops at a null dereference; scripts/fuzz.sh keeps both on the parsers).
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DNDTOM_SANITIZE=ON -DNDTOM_WITH_MRPT=ON -DNDTOM_BUILD_APPS=ON -DNDTOM_BUILD_TESTS=ON \
  -DNDTOM_BUILD_BENCHMARKS=OFF -DNDTOM_TEST_COMPILE_OPTIONS=-Og -DNDTOM_UBSAN_SKIP=null,alignment >/dev/null
cmake --build "$dir" -j2
# Suppressions only for reports from MRPT's code, each explained in its file.
supp=$PWD/tests/sanitizers
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export LSAN_OPTIONS=suppressions=$supp/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp
ctest --test-dir "$dir" -j2 --output-on-failure -LE 'mrpt_programs|end_to_end'
