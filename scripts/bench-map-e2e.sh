#!/usr/bin/env bash
# The whole ndtom-map process against OctoMap's graph2tree on the same scans, in the same
# script, alternating runs: wall time and peak memory of each, and their ratios. ndtom-map
# runs with its default outputs (map, MRPT map, scene, pictures, summary) and with
# --no-pictures; graph2tree writes its .bt and .ot. Needs octomap-tools (scripts/setup.sh
# --with-octomap-tools) and python3 (to convert the scans to OctoMap's scan graph, untimed).
# Writes doc/benchmarks/map-e2e.csv and prints a table.
# Usage: scripts/bench-map-e2e.sh [RUNS (3)] [RESOLUTION (0.2)] [MAX_RANGE (30)]
# BUILD=dir to use an existing Release build instead of build-bench.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3} resolution=${2:-0.2} max_range=${3:-30}
data="${NDTOM_SHARED_DATASETS:-../shared/datasets}/balm-realworld"
[[ -d "$data" ]] || { echo "bench-map-e2e: no lidar data at $data" >&2; exit 1; }
command -v graph2tree >/dev/null || { echo "bench-map-e2e: needs graph2tree (setup.sh --with-octomap-tools)" >&2; exit 1; }

build=${BUILD:-build-bench}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target ndtom-map >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scripts/pcd_to_octomap_log.py "$data" "$work/scans.log"
log2graph "$work/scans.log" "$work/scans.graph" >/dev/null 2>&1
rm "$work/scans.log"

# Wall seconds and peak RSS (MB) of a command, from GNU time.
measure() {
  /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>&1 || { echo "failed: $*" >&2; exit 1; }
  awk '{printf "%s %.0f", $1, $2 / 1024}' "$work/time"
}
mapper=$build/apps/ndtom-map/ndtom-map
csv=doc/benchmarks/map-e2e.csv
mkdir -p doc/benchmarks
echo "run,system,wall_s,peak_rss_mb,ratio_to_graph2tree" > "$csv"
for run in $(seq 1 "$runs"); do
  read -r g_s g_mb <<<"$(measure graph2tree -i "$work/scans.graph" -o "$work/octomap.bt" -res "$resolution" -m "$max_range")"
  read -r n_s n_mb <<<"$(measure "$mapper" "$data" -o "$work/ndtom" --resolution "$resolution" --max-range "$max_range" -q)"
  read -r p_s p_mb <<<"$(measure "$mapper" "$data" -o "$work/ndtom-np" --resolution "$resolution" --max-range "$max_range" -q --no-pictures)"
  for row in "graph2tree $g_s $g_mb" "ndtom-map $n_s $n_mb" "ndtom-map_no_pictures $p_s $p_mb"; do
    read -r system s mb <<<"$row"
    echo "$run,$system,$s,$mb,$(awk -v a="$s" -v b="$g_s" 'BEGIN{printf "%.3f", a / b}')" >> "$csv"
  done
done
python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["time"]["stages_s"]; print("last ndtom-map run, stages (s):", ", ".join(f"{k} {v:.2f}" for k, v in t.items()))' "$work/ndtom.summary.json"
tr , '\t' < "$csv"
