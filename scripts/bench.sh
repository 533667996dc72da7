#!/usr/bin/env bash
# Builds Release in build-bench, then replays the shared lidar scans and the synthetic 64-ring
# sequence into NDT-OM, OctoMap and COccupancyGridMap3D (apps/ndtom-bench). Writes
# doc/benchmarks/results.csv, doc/benchmarks/summary.md and doc/benchmarks/time_per_scan_*.png.
# Usage: scripts/bench.sh [more ndtom-bench options, e.g. --repeats 3 or --resolutions 0.2]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
require_balm_data
build_bench ndtom-bench
mkdir -p doc/benchmarks
build-bench/apps/ndtom-bench/ndtom-bench --dataset "$data" --dataset synthetic \
  --csv doc/benchmarks/results.csv --plot doc/benchmarks/time_per_scan "$@" \
  | tee doc/benchmarks/summary.md
