#!/usr/bin/env bash
# The distributed build (ndtom-map-mpi) against ndtom-map on the same scans, in one script:
# (1) wall time of 1 and 2 processes (one thread each), each process reading the scans or
# process 0 broadcasting them, alternating runs; (2) ndtom-rank-model: each process's CPU
# time for 1-64 processes, measured one process at a time (balance and compute efficiency
# beyond this machine's cores). Writes doc/benchmarks/mpi-wall.csv and mpi-ranks.csv.
# Usage: scripts/bench-mpi.sh [RUNS (3)] [RANK_TILES (4)] [RESOLUTION (0.2)] [MAX_RANGE (30)]
# BUILD=dir to use an existing Release build instead of build-bench.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3} tiles=${2:-4} resolution=${3:-0.2} max_range=${4:-30}
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
echo "run,program,processes,scan_input,scan_loop_s,total_s" >>"$wall"
seconds() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(max(r['loop_s'] for r in d['per_rank']), d['total_s'])" "$1"; }
for run in $(seq "$runs"); do
  start=$(date +%s.%N)
  "$bin/ndtom-map/ndtom-map" "$data" -o "$work/serial" "${options[@]}"
  end=$(date +%s.%N)
  insert=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['time']['stages_s']['insert'] + d['time']['stages_s']['read'])" "$work/serial.summary.json" 2>/dev/null || echo nan)
  echo "$run,ndtom-map,1,each,$insert,$(python3 -c "print($end - $start)")" >>"$wall"
  for input in each broadcast; do
    for np in 1 2; do
      [[ $np == 1 && $input == broadcast ]] && continue
      mpirun --oversubscribe -np "$np" "$bin/ndtom-map-mpi/ndtom-map-mpi" "$data" -o "$work/np$np" \
        "${options[@]}" --scan-input "$input" --rank-tiles "$tiles"
      cmp -s "$work/serial.ndtom" "$work/np$np.ndtom" || { echo "bench-mpi: np $np map differs" >&2; exit 1; }
      read -r loop total < <(seconds "$work/np$np.mpi.json")
      echo "$run,ndtom-map-mpi,$np,$input,$loop,$total" >>"$wall"
    done
  done
done
column -s, -t <"$wall"

"$bin/ndtom-map-mpi/ndtom-rank-model" "$data" -o "$work/model" --resolution "$resolution" \
  --max-range "$max_range" --rank-tiles "$tiles" --ranks 1,2,4,8,16,32,64 --quiet | tee "$work/model.txt"
{ echo "# commit $commit; rank tiles $tiles; CPU seconds of each process's insertions"
  cat "$work/model.rank-model.csv"; } >doc/benchmarks/mpi-ranks.csv
