#!/usr/bin/env bash
# Builds Release in build-bench, then replays the shared lidar scans and the synthetic 64-ring
# sequence into NDT-OM, OctoMap and COccupancyGridMap3D (apps/ndtom-bench). Writes
# doc/benchmarks/results.csv, doc/benchmarks/summary.md and doc/benchmarks/time_per_scan_*.png.
# Usage: scripts/bench.sh [more ndtom-bench options, e.g. --repeats 3 or --resolutions 0.2]
set -euo pipefail
cd "$(dirname "$0")/.."
data="${NDTOM_SHARED_DATASETS:-../shared/datasets}/balm-realworld"
[[ -d "$data" ]] || { echo "bench.sh: no lidar data at $data (set NDTOM_SHARED_DATASETS)" >&2; exit 1; }

cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build-bench -j2 --target ndtom-bench
mkdir -p doc/benchmarks
build-bench/apps/ndtom-bench/ndtom-bench --dataset "$data" --dataset synthetic \
  --csv doc/benchmarks/results.csv --plot doc/benchmarks/time_per_scan "$@" \
  | tee doc/benchmarks/summary.md
