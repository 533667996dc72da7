#!/usr/bin/env bash
# Regenerates every CSV and figure of doc/evaluation.md from one command: the paper's Sec. IV
# (apps/ndtom-eval), the sensitivity runs under doc/evaluation/sensitivity, and Fig. 5
# (apps/ndtom-bench: NDT-OM in both ray modes and OctoMap, time per scan against resolution).
# Every CSV gets a first line "# commit <hash>[-dirty]": the commit the numbers come from
# ("-dirty": the sources differed from it; the outputs under doc/evaluation do not count).
# Takes about 10 minutes on a shared 2-core machine (build not included).
# Usage: scripts/evaluate.sh [--only-fig5] [--skip-fig5]
# Data: ../shared/datasets beside the repository (scripts/fetch-data.sh writes it there), or
# NDTOM_SHARED_DATASETS=DIR. Build folder: build-eval, or NDTOM_EVAL_BUILD=DIR (configured as
# Release).
set -euo pipefail
cd "$(dirname "$0")/.."
only_fig5=0 skip_fig5=0
for a in "$@"; do
  case "$a" in
    --only-fig5) only_fig5=1 ;;
    --skip-fig5) skip_fig5=1 ;;
    *) echo "evaluate.sh: unknown option $a" >&2; exit 2 ;;
  esac
done
data="${NDTOM_SHARED_DATASETS:-../shared/datasets}"
for d in balm-realworld tum-fr2-pioneer-slam2; do
  [[ -d "$data/$d" ]] || { echo "evaluate.sh: no $data/$d: run scripts/fetch-data.sh" >&2; exit 1; }
done

commit="$(git rev-parse --short HEAD)"
if [[ -n "$(git status --porcelain -- . ':(exclude)doc/evaluation' ':(exclude)doc/evaluation.md')" ]]; then
  commit="$commit-dirty"
fi
build="${NDTOM_EVAL_BUILD:-build-eval}"  # a Release build of its own unless told
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target ndtom-eval ndtom-bench
eval_exe="$build/apps/ndtom-eval/ndtom-eval"
bench_exe="$build/apps/ndtom-bench/ndtom-bench"
out=doc/evaluation
sens="$out/sensitivity"
data_args=(--tum "$data/tum-fr2-pioneer-slam2" --lidar "$data/balm-realworld")
run() { echo "evaluate.sh: $*" >&2; "$@"; }
started=$SECONDS
marker="$(mktemp)"  # the CSVs newer than this are this run's
trap 'rm -f "$marker"' EXIT

if ((!only_fig5)); then
  # The main run: every experiment with the defaults.
  run "$eval_exe" "${data_args[@]}" --out "$out"
  # Sensitivity: the covariance floor, the depth decimation, the clamp, the insertion rule.
  run "$eval_exe" "${data_args[@]}" --experiments consistency --min-eigenvalue 1e-4 \
    --out "$sens/floor-1e-4"
  run "$eval_exe" "${data_args[@]}" --experiments consistency --consistency-data tum \
    --tum-decimation 4 --out "$sens/tum-decimation-4"
  for clamp in "-2 10" "-2 50" "-10 10"; do
    read -r lo hi <<<"$clamp"
    run "$eval_exe" "${data_args[@]}" --experiments consistency,mapping --clamp-min "$lo" \
      --clamp-max "$hi" --out "$sens/clamp$lo,$hi"
  done
  run "$eval_exe" "${data_args[@]}" --experiments consistency,mapping,multires \
    --consistency-data lidar --min-travel 0.05 --out "$sens/min-travel-0.05"
fi

if ((!skip_fig5)); then
  # Fig. 5: no range cut (as the paper), one thread, one replay of the 60 scans per system and
  # resolution. Scan periods: our lidar's 500 ms (2 Hz) and the paper's 100 ms (HDL-32, 10 Hz).
  run "$bench_exe" --dataset "$data/balm-realworld" --resolutions 0.1,0.2,0.3,0.4,0.5,0.7,1.0 \
    --systems ndtom-point,ndtom-hitcell,octomap --threads 1 --max-range none --repeats 1 \
    --real-time 500,100 --csv "$out/fig5_time.csv" --plot "$out/fig5" --quiet \
    >"$out/fig5_summary.md"
fi

# Stamp every CSV this run wrote (newer than the start marker) with the commit.
find "$out" -name '*.csv' -newer "$marker" -print0 |
  while IFS= read -r -d '' f; do
    if head -n1 "$f" | grep -q '^# commit '; then sed -i '1d' "$f"; fi
    sed -i "1i # commit $commit" "$f"
  done
echo "evaluate.sh: done in $((SECONDS - started)) s, commit $commit" >&2
