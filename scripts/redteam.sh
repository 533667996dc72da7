#!/usr/bin/env bash
# The red team of issues #17 and #38 (doc/robustness.md): builds ndtom-map, ndtom-localize,
# ndtom-worldgen, ndtom-rawlog-from-pcd, the plugin (and ndtom-map-mpi where MPI is found)
# and the red team's programs, runs every hostile case (one child process each, time and
# address space limited, peak memory measured) and prints the table. Takes 15-30 minutes on
# 2 cores; categories 8-10 (issue #38) alone about 10: --only "8 ", --only "9 ", --only "10 ".
#   --base COMMIT   run the same cases against COMMIT's programs and loaders instead (its
#                   source is extracted and built in build-redteam-base, with this probe);
#                   issue #38's programs where COMMIT has them
# Other options go to ndtom-redteam, e.g. --only "2 " (a category), --sample 5, --csv FILE.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build -G Ninja >/dev/null
cmake --build build -j2 --target ndtom-map ndtom-localize ndtom-worldgen ndtom-rawlog-from-pcd \
  mrpt_ndtom ndtom-redteam redteam_probe
# ndtom-map-mpi only where MPI was found (its cases are left out otherwise).
cmake --build build -j2 --target ndtom-map-mpi 2>/dev/null || true
build_dir=build
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
  for target in ndtom-localize ndtom-worldgen ndtom-rawlog-from-pcd mrpt_ndtom ndtom-map-mpi; do
    cmake --build "$base/build" -j2 --target "$target" 2>/dev/null || true
  done
  build_dir=$base/build
  probe=$base/build/redteam_probe/redteam_probe
fi
programs=(--mapper "$build_dir/apps/ndtom-map/ndtom-map" --probe "$probe")
for pair in localizer:ndtom-localize worldgen:ndtom-worldgen rawlog-from-pcd:ndtom-rawlog-from-pcd \
            mpi-mapper:ndtom-map-mpi; do
  path=$build_dir/apps/${pair#*:}/${pair#*:}
  [[ -x "$path" ]] && programs+=("--${pair%%:*}" "$path")
done
plugin=$build_dir/libs/mrpt_ndtom/libmrpt_ndtom.so
[[ -f "$plugin" ]] && programs+=(--plugin "$(realpath "$plugin")")
build/tests/redteam/ndtom-redteam "${programs[@]}" "$@"
