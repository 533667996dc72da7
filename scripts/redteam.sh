#!/usr/bin/env bash
# The red team of issue #17 (doc/robustness.md): builds ndtom-map and the red team's programs,
# runs every hostile case (one child process each, time and address space limited, peak
# memory measured) and prints the table. Takes 10-20 minutes on 2 cores.
#   --base COMMIT   run the same cases against COMMIT's ndtom-map and loaders instead (its
#                   source is extracted and built in build-redteam-base, with this probe)
# Other options go to ndtom-redteam, e.g. --only "2 " (a category), --sample 5, --csv FILE.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build -G Ninja >/dev/null
cmake --build build -j2 --target ndtom-map ndtom-redteam redteam_probe
mapper=build/apps/ndtom-map/ndtom-map
probe=build/tests/redteam/redteam_probe
if [[ "${1:-}" == "--base" ]]; then
  commit=$2
  shift 2
  base=build-redteam-base
  rm -rf "$base/src" && mkdir -p "$base/src/redteam_probe"
  git archive "$commit" | tar -x -C "$base/src"
  cp tests/redteam/redteam_probe.cpp "$base/src/redteam_probe/"
  cat >"$base/src/redteam_probe/CMakeLists.txt" <<'CMAKE'
add_executable(redteam_probe redteam_probe.cpp)
target_link_libraries(redteam_probe PRIVATE mrpt_ndtom ndtom_io ndtom ndtom_apps)
CMAKE
  echo 'add_subdirectory(redteam_probe)' >>"$base/src/CMakeLists.txt"
  cmake -S "$base/src" -B "$base/build" -G Ninja -DNDTOM_BUILD_TESTS=OFF >/dev/null
  cmake --build "$base/build" -j2 --target ndtom-map redteam_probe
  mapper=$base/build/apps/ndtom-map/ndtom-map
  probe=$base/build/redteam_probe/redteam_probe
fi
build/tests/redteam/ndtom-redteam --mapper "$mapper" --probe "$probe" "$@"
