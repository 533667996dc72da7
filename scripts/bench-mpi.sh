#!/usr/bin/env bash
# The distributed build (ndtom-map-mpi) against ndtom-map on the same scans, in one script:
# (1) wall time of 1 and 2 processes (one thread each), each process reading the scans or
# process 0 broadcasting them, the rays shared by tiles or whole (--ray-share), alternating
# runs; (2) ndtom-rank-model for either way of sharing the rays: each process's CPU time for
# 1-64 processes (balance and compute efficiency beyond this machine's cores; sharing the
# rays, the bytes each sends). Writes doc/benchmarks/mpi-wall.csv and mpi-ranks.csv.
# Usage: scripts/bench-mpi.sh [RUNS (3)] [RANK_TILES (each --ray-share's default: "")] [RESOLUTION (0.2)] [MAX_RANGE (30)]
# BUILD=dir to use an existing Release build instead of build-bench.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3} tiles=${2:-} resolution=${3:-0.2} max_range=${4:-30}
tile_option=()
[[ -n $tiles ]] && tile_option=(--rank-tiles "$tiles")
data="${NDTOM_SHARED_DATASETS:-../shared/datasets}/balm-realworld"
[[ -d "$data" ]] || { echo "bench-mpi: no lidar data at $data" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

build=${BUILD:-build-bench}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target ndtom-map ndtom-map-mpi ndtom-rank-model >/dev/null
bin=$build/apps
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
options=(--resolution "$resolution" --max-range "$max_range" --threads 1 --no-pictures --quiet)
commit=$(git rev-parse --short HEAD)$(git diff --quiet || echo -dirty)

wall=doc/benchmarks/mpi-wall.csv
echo "# commit $commit; $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg) at start" >"$wall"
echo "run,program,processes,scan_input,ray_share,scan_loop_s,total_s" >>"$wall"
seconds() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(max(r['loop_s'] for r in d['per_rank']), d['total_s'])" "$1"; }
for run in $(seq "$runs"); do
  start=$(date +%s.%N)
  "$bin/ndtom-map/ndtom-map" "$data" -o "$work/serial" "${options[@]}"
  end=$(date +%s.%N)
  insert=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['time']['stages_s']['insert'] + d['time']['stages_s']['read'])" "$work/serial.summary.json" 2>/dev/null || echo nan)
  echo "$run,ndtom-map,1,each,,$insert,$(python3 -c "print($end - $start)")" >>"$wall"
  for input in each broadcast; do
    for np in 1 2; do
      for share in tiles rays; do
        [[ $np == 1 && ( $input == broadcast || $share == rays ) ]] && continue
        mpirun --oversubscribe -np "$np" "$bin/ndtom-map-mpi/ndtom-map-mpi" "$data" -o "$work/np$np" \
          "${options[@]}" --scan-input "$input" "${tile_option[@]}" --ray-share "$share"
        cmp -s "$work/serial.ndtom" "$work/np$np.ndtom" || { echo "bench-mpi: np $np map differs" >&2; exit 1; }
        read -r loop total < <(seconds "$work/np$np.mpi.json")
        echo "$run,ndtom-map-mpi,$np,$input,$share,$loop,$total" >>"$wall"
      done
    done
  done
done
column -s, -t <"$wall"

ranks=doc/benchmarks/mpi-ranks.csv
echo "# commit $commit; rank tiles ${tiles:-default}; CPU seconds of each process's insertions" >"$ranks"
for share in tiles rays; do
  echo "ray share: $share"
  "$bin/ndtom-rank-model/ndtom-rank-model" "$data" -o "$work/model" --resolution "$resolution" \
    --max-range "$max_range" "${tile_option[@]}" --ray-share "$share" \
    --ranks 1,2,4,8,16,32,64 --quiet
  if [[ $share == tiles ]]; then
    sed 's/^/ray_share,/;2,$s/^ray_share,/tiles,/' "$work/model.rank-model.csv" >>"$ranks"
  else
    tail -n +2 "$work/model.rank-model.csv" | sed 's/^/rays,/' >>"$ranks"
  fi
done
