#!/usr/bin/env bash
# The scale figures of doc/scale.md (issue #22), on procedural city drives (ndtom-worldgen),
# each measured twice in this one script (the machine is shared: ranges, and ratios of runs
# made side by side):
#  (a) ndtom-map out of core (--resident-budget a tenth of the map) against in memory on a
#      KM_A km drive: insertion time per scan, their ratio, peak RSS against the budget, and
#      the two tiled files compared byte for byte;
#  (b) ndtom-localize --region-radius through a KM_B km drive (other noise, scans between the
#      map's) in a tiled map of the same streets: resident map bytes and RSS per km. Both
#      drives keep MARGIN_B rings of blocks between them and the city's edge, so that every
#      km sees city all round (on the edge streets a third of the region is empty ground).
# Writes doc/benchmarks/scale.csv and .md (CSV=FILE.csv: FILE.csv and FILE.md); big
# temporaries are removed.
# Usage: scripts/bench-scale.sh [BUILD_DIR (build, a Release build)]
# Settings (environment): KM_A=1 KM_B=3 STEP_B=2 DRIVE_STEP=6 RES=0.4 TILES=8 RADIUS=50
# LOC_RANGE=40 MARGIN_B=1 MAP_KM_B=KM_B (km of b's map drive: longer maps past the drive's end)
# MAP_BUDGET_B=4000 (MB, ndtom-map --memory-budget for b's map)
# MAP_RESIDENT_B= (MB: build b's map out of core, ndtom-map --resident-budget, so that the map
# never is whole in memory, neither built nor localized in) PARTS=ab (a, b or both) RUNS=2
# (for a) RUNS_B=1 (for b: its map bytes are the same every run). About 20 minutes on 2 busy
# cores, most of it localizing (0.6-1.5 s a scan).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
km_a=${KM_A:-1} km_b=${KM_B:-3} step_b=${STEP_B:-2} drive_step=${DRIVE_STEP:-6} res=${RES:-0.4} tiles=${TILES:-8}
radius=${RADIUS:-50} loc_range=${LOC_RANGE:-40} margin_b=${MARGIN_B:-1}
map_km_b=${MAP_KM_B:-$km_b} map_budget_b=${MAP_BUDGET_B:-4000} map_resident_b=${MAP_RESIDENT_B:-} runs=${RUNS:-2} runs_b=${RUNS_B:-1}
parts=${PARTS:-ab}
grep -q 'CMAKE_BUILD_TYPE:STRING=Release' "$build/CMakeCache.txt" ||
  { echo "bench-scale: $build is not a Release build" >&2; exit 1; }
cmake --build "$build" -j2 --target ndtom-map ndtom-worldgen ndtom-localize >/dev/null
bin="$build/apps"
work=$(mktemp -d "${TMPDIR:-/tmp}/ndtom-bench-scale.XXXXXX")
trap 'rm -rf "$work"' EXIT
need_gb=$(awk -v k="$map_km_b" 'BEGIN{printf "%d", 2 + k + 0.999}')  # ~0.3 GB of PCD a km at 1 m steps, the maps
avail_gb=$(df -BG --output=avail "$work" | tail -1 | tr -dc 0-9)
(( avail_gb >= need_gb )) || { echo "bench-scale: $avail_gb GB free in $work, need $need_gb" >&2; exit 1; }
mkdir -p doc/benchmarks
csv=${CSV:-doc/benchmarks/scale.csv}
echo "part,run,what,value" > "$csv"
row() { echo "$1,$2,$3,$4" >> "$csv"; }
log() { echo "bench-scale: $*" >&2; }
# A number from a summary JSON: json FILE key.key...
json() { python3 -c 'import json,sys
v=json.load(open(sys.argv[1]))
for k in sys.argv[2:]: v=v[k]
print(v)' "$@"; }
# The ground (z = 0) lies on a cell boundary, where grazing rays clear the cells holding its
# points: every pose is raised by half a cell, as real ground is off the grid.
raise() { awk -v dz="$(awk -v r="$res" 'BEGIN{print r / 2}')" '{ $12 = sprintf("%.17g", $12 + dz); print }' \
            "$1/poses.txt" > "$1/poses.raised" && mv "$1/poses.raised" "$1/poses.txt"; }

# --- (a) out of core against in memory ---------------------------------------------------
if [[ $parts == *a* ]]; then
log "(a) a $km_a km drive"
"$bin/ndtom-worldgen/ndtom-worldgen" "$work/city_a" --km "$km_a" --threads 2 -q
raise "$work/city_a"
map=("$bin/ndtom-map/ndtom-map" "$work/city_a" --resolution "$res" --tiles "$tiles" -q)
budget_mb=""
for run in $(seq 1 "$runs"); do
  log "(a) run $run: in memory"
  "${map[@]}" --no-pictures -o "$work/mem"
  if [[ -z "$budget_mb" ]]; then
    budget_mb=$(python3 -c "import sys; print(f'{int(sys.argv[1]) / 10 / 1e6:.3f}')" \
                "$(json "$work/mem.summary.json" map map_bytes)")
  fi
  log "(a) run $run: out of core, $budget_mb MB resident"
  "${map[@]}" --resident-budget "$budget_mb" -o "$work/ooc"
  cmp "$work/mem.ndtomtiles" "$work/ooc.ndtomtiles" && identical=1 || identical=0
  for mode in mem ooc; do
    s="$work/$mode.summary.json"
    scans=$(json "$s" scans_inserted)
    row a "$run" "${mode}_insert_ms_per_scan" "$(python3 -c "print(1e3 * $(json "$s" time stages_s insert) / $scans)")"
    row a "$run" "${mode}_insert_ms_median" "$(json "$s" time insert_ms_median)"
    row a "$run" "${mode}_peak_rss_after_mapping_mb" "$(python3 -c "print($(json "$s" memory peak_rss_after_mapping_bytes) / 1e6)")"
    row a "$run" "${mode}_map_mb" "$(python3 -c "print($(json "$s" map map_bytes) / 1e6)")"
  done
  o=$work/ooc.summary.json
  row a "$run" scans "$(json "$o" scans_inserted)"
  row a "$run" budget_mb "$budget_mb"
  row a "$run" ooc_peak_resident_mb "$(python3 -c "print($(json "$o" memory out_of_core peak_resident_bytes) / 1e6)")"
  row a "$run" ooc_spills "$(json "$o" memory out_of_core spills)"
  row a "$run" ooc_loads "$(json "$o" memory out_of_core loads)"
  row a "$run" ooc_spilled_mb "$(python3 -c "print($(json "$o" memory out_of_core spilled_bytes) / 1e6)")"
  row a "$run" tiled_files_identical "$identical"
  rm -f "$work"/mem.* "$work"/ooc.*
done
rm -rf "$work/city_a"
fi

# --- (b) localization memory per km ------------------------------------------------------
if [[ $parts == *b* ]]; then
log "(b) the drive to localize: $km_b km, a scan every $drive_step m, its own noise"
drive_said=$("$bin/ndtom-worldgen/ndtom-worldgen" "$work/drive" --km "$km_b" --step "$drive_step" \
  --noise-seed 2 --margin "$margin_b" --threads 2)
raise "$work/drive"
# The map's drive goes through the same city: with its blocks and seed, a longer route starts
# with the shorter one (crossings are chosen greedily), so MAP_KM_B > KM_B maps past the end.
blocks=$(sed -n 's/.* city of \([0-9]*\)x[0-9]* blocks.*/\1/p' <<<"$drive_said")
[[ -n $blocks ]] || { echo "bench-scale: no city size in: $drive_said" >&2; exit 1; }
log "(b) a $map_km_b km drive for the map through its $blocks x $blocks blocks (a scan every $step_b m)"
"$bin/ndtom-worldgen/ndtom-worldgen" "$work/city_b" --km "$map_km_b" --blocks "$blocks" \
  --step "$step_b" --margin "$margin_b" --threads 2 -q
raise "$work/city_b"
# The default budget (512 MB) stops a map of over ~4 km.
out_of_core=()
[[ -n $map_resident_b ]] && out_of_core=(--resident-budget "$map_resident_b")
log "(b) building its map${map_resident_b:+ out of core, $map_resident_b MB resident}"
"$bin/ndtom-map/ndtom-map" "$work/city_b" --resolution "$res" --tiles "$tiles" --no-pictures -q \
  --memory-budget "$map_budget_b" "${out_of_core[@]}" -o "$work/city"
rm -rf "$work/city_b"
rm -f "$work"/city.3Dscene "$work"/city.ndtommap
initial=$(head -1 "$work/drive/poses.txt" | python3 -c '
import sys, math
m = [float(x) for x in sys.stdin.read().split()]
r = [[m[0], m[1], m[2]], [m[4], m[5], m[6]], [m[8], m[9], m[10]]]
w = math.sqrt(max(0.0, 1 + r[0][0] + r[1][1] + r[2][2])) / 2
x = math.copysign(math.sqrt(max(0.0, 1 + r[0][0] - r[1][1] - r[2][2])) / 2, r[2][1] - r[1][2])
y = math.copysign(math.sqrt(max(0.0, 1 - r[0][0] + r[1][1] - r[2][2])) / 2, r[0][2] - r[2][0])
z = math.copysign(math.sqrt(max(0.0, 1 - r[0][0] - r[1][1] + r[2][2])) / 2, r[1][0] - r[0][1])
print(m[3], m[7], m[11], x, y, z, w)')
for run in $(seq 1 "$runs_b"); do
  log "(b) run $run: ndtom-localize --region-radius $radius"
  "$bin/ndtom-localize/ndtom-localize" "$work/city.ndtomtiles" "$work/drive" --initial "$initial" \
    --region-radius "$radius" --max-range "$loc_range" --threads 2 --no-pictures -q -o "$work/loc"
  python3 - "$work/loc.scans.csv" "$work/loc.summary.json" "$run" "$drive_step" >> "$csv" <<'EOF'
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
summary = json.load(open(sys.argv[2]))
run, step = sys.argv[3], float(sys.argv[4])
# Kilometres along the route (scan i is i * step metres in). A km is whole when the drive
# reaches its last step (5 km at 6 m ends at 4,998 m); a shorter last one is left out.
per_km = {}
for r in rows:
    per_km.setdefault(int(int(r["index"]) * step // 1000), []).append(r)
driven = (len(rows) - 1) * step
full = [k for k in sorted(per_km) if (k + 1) * 1000 < driven + step - 1e-6]
print(f"b,{run},scans,{len(rows)}")
print(f"b,{run},lost,{sum(r['outcome'] == 'lost' for r in rows)}")
errors = sorted(float(r["error_m"]) for r in rows if r["error_m"])
print(f"b,{run},median_error_m,{errors[len(errors) // 2] if errors else float('nan')}")
for k in full:
    for col in ("map_bytes", "rss_bytes"):
        v = [float(r[col]) / 1e6 for r in per_km[k]]
        print(f"b,{run},km{k + 1}_{col[:-6]}_mb_mean,{sum(v) / len(v):.2f}")
        print(f"b,{run},km{k + 1}_{col[:-6]}_mb_max,{max(v):.2f}")
for col in ("map_bytes", "rss_bytes"):
    a = [float(r[col]) for r in per_km[full[0]]]
    b = [float(r[col]) for r in per_km[full[-1]]]
    print(f"b,{run},{col[:-6]}_last_km_vs_first_percent,{100 * (sum(b) / len(b) / (sum(a) / len(a)) - 1):.1f}")
print(f"b,{run},tiles_in_file,{summary['region']['tiles_in_file']}")
print(f"b,{run},max_resident_tiles,{summary['region']['max_resident_tiles']}")
EOF
  rm -f "$work"/loc.*
done
row b 0 whole_map_mb "$(python3 -c "print($(json "$work/city.summary.json" map map_bytes) / 1e6)")"
row b 0 map_scans "$(json "$work/city.summary.json" scans_inserted)"
row b 0 map_km "$map_km_b"
row b 0 margin_blocks "$margin_b"
row b 0 map_peak_rss_mb "$(python3 -c "print($(json "$work/city.summary.json" memory peak_rss_after_mapping_bytes) / 1e6)")"
if [[ -n $map_resident_b ]]; then
  row b 0 map_resident_budget_mb "$map_resident_b"
  row b 0 map_peak_resident_mb "$(python3 -c "print($(json "$work/city.summary.json" memory out_of_core peak_resident_bytes) / 1e6)")"
fi
fi

# --- Summary -------------------------------------------------------------------------------
python3 - "$csv" "$km_a" "$km_b" "$res" "$tiles" "$radius" "$loc_range" "$margin_b" <<'EOF' | tee "${csv%.csv}.md"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
km_a, km_b, res, tiles, radius, loc_range, margin_b = sys.argv[2:]
def vals(part, what):
    return [float(r["value"]) for r in rows if r["part"] == part and r["what"] == what]
def rng(part, what, fmt="{:.1f}"):
    v = vals(part, what)
    if not v:
        return "-"
    return fmt.format(min(v)) if min(v) == max(v) else fmt.format(min(v)) + "-" + fmt.format(max(v))
ratio = [o / m for o, m in zip(vals("a", "ooc_insert_ms_per_scan"), vals("a", "mem_insert_ms_per_scan"))]
if ratio:
  print(f"## Out of core against in memory: {km_a} km, {res} m cells, tiles of {tiles} blocks\n")
  print("| | in memory | out of core |\n|---|---|---|")
  print(f"| insertion per scan (mean) [ms] | {rng('a', 'mem_insert_ms_per_scan')} | {rng('a', 'ooc_insert_ms_per_scan')} |")
  print(f"| insertion per scan (median) [ms] | {rng('a', 'mem_insert_ms_median')} | {rng('a', 'ooc_insert_ms_median')} |")
  print(f"| peak RSS after mapping [MB] | {rng('a', 'mem_peak_rss_after_mapping_mb', '{:.0f}')} | {rng('a', 'ooc_peak_rss_after_mapping_mb', '{:.0f}')} |")
  print(f"| map [MB] | {rng('a', 'mem_map_mb', '{:.0f}')} | budget {rng('a', 'budget_mb')}, peak resident {rng('a', 'ooc_peak_resident_mb')} |")
  print(f"\nOut of core / in memory, time per scan, runs side by side: {min(ratio):.2f}-{max(ratio):.2f}. "
        f"Scans {rng('a', 'scans', '{:.0f}')}; tiles spilled {rng('a', 'ooc_spills', '{:.0f}')} "
        f"({rng('a', 'ooc_spilled_mb', '{:.0f}')} MB), read back {rng('a', 'ooc_loads', '{:.0f}')}; "
        f"tiled files identical: {'yes' if min(vals('a', 'tiled_files_identical')) == 1 else 'NO'}.\n")
print(f"## Localizing through {km_b} km, --region-radius {radius}, --max-range {loc_range}, "
      f"drives --margin {margin_b}\n")
built = (f"built out of core (--resident-budget {rng('b', 'map_resident_budget_mb', '{:.0f}')} MB: "
         f"peak resident {rng('b', 'map_peak_resident_mb', '{:.0f}')} MB, "
         if vals("b", "map_resident_budget_mb") else "built in memory (")
built += f"peak RSS {rng('b', 'map_peak_rss_mb', '{:.0f}')} MB)"
print(f"Whole map {rng('b', 'whole_map_mb', '{:.0f}')} MB ({rng('b', 'map_km', '{:g}')} km, "
      f"{rng('b', 'map_scans', '{:.0f}')} scans), {built}; "
      f"{rng('b', 'scans', '{:.0f}')} scans localized, {rng('b', 'lost', '{:.0f}')} lost, "
      f"median error {rng('b', 'median_error_m', '{:.3f}')} m; most tiles resident "
      f"{rng('b', 'max_resident_tiles', '{:.0f}')} of {rng('b', 'tiles_in_file', '{:.0f}')}.\n")
print("| km | resident map mean [MB] | resident map max [MB] | RSS mean [MB] | RSS max [MB] |\n|---|---|---|---|---|")
k = 1
while vals("b", f"km{k}_map_mb_mean"):
    print(f"| {k} | {rng('b', f'km{k}_map_mb_mean')} | {rng('b', f'km{k}_map_mb_max')} | "
          f"{rng('b', f'km{k}_rss_mb_mean', '{:.0f}')} | {rng('b', f'km{k}_rss_mb_max', '{:.0f}')} |")
    k += 1
print(f"\nLast km against the first (means): resident map {rng('b', 'map_last_km_vs_first_percent')} %, "
      f"RSS {rng('b', 'rss_last_km_vs_first_percent')} %.")
EOF
