# Sourced by the benchmark scripts (run from the project root).

# The shared lidar scans (balm-realworld under $NDTOM_SHARED_DATASETS, default
# ../shared/datasets) in $data; exits naming the calling script when they are missing.
require_balm_data() {
  data="${NDTOM_SHARED_DATASETS:-../shared/datasets}/balm-realworld"
  [[ -d "$data" ]] || { echo "$(basename "$0"): no lidar data at $data (set NDTOM_SHARED_DATASETS)" >&2; exit 1; }
}

# Builds the given targets in build-bench, a Release build.
build_bench() {
  cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build-bench -j2 --target "$@"
}
