#!/usr/bin/env bash
# Builds Release in build-bench, then registers the held-out shared lidar scans against a map
# of the others with NDT-OM (P2D, D2D; 1 and 2 threads), MRPT's ICP and, when the build has
# PCL (scripts/setup.sh --with-pcl), PCL's NDT and GICP (apps/ndtom-regbench). Writes
# doc/registration/results.csv, doc/registration/trials.csv, doc/registration/summary.md and
# doc/registration/success_rate.png.
# Usage: scripts/regbench.sh [more ndtom-regbench options, e.g. --trials 8 or --systems ndtom-p2d]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
require_balm_data
build_bench ndtom-regbench
mkdir -p doc/registration
build-bench/apps/ndtom-regbench/ndtom-regbench --dataset "$data" --threads 1,2 \
  --csv doc/registration/results.csv --trials-csv doc/registration/trials.csv \
  --plot doc/registration/success_rate.png "$@" \
  | tee doc/registration/summary.md
