#!/usr/bin/env bash
# Reproduces doc/localization.md's figures on the shared lidar scans (and the TUM frames that
# ship with the project): builds Release in build-bench, maps scans 0-29, then
#   tracking: ndtom-localize on scans 30-59 (a folder without poses) from 0.5 m and 5 deg off
#             scan 30's reference pose, one thread;
#   global:   every scan 30-59 searched for in the whole map without a start pose, one thread;
#   outside:  a VLP-16 scan of another place (MRPT's sample) searched for in the campus map;
#   TUM:      the even TUM frames tracked in a map of the odd ones.
# Writes doc/localization/{tracking.csv,global.csv,summary.md,tracking_top.png}.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
require_balm_data
build_bench ndtom-map ndtom-localize
bin=build-bench/apps
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=doc/localization
mkdir -p "$out"

# The map: scans 0-29 with their poses, rays up to 30 m.
"$bin/ndtom-map/ndtom-map" "$data" --max-scans 30 --max-range 30 --no-pictures -q -o "$work/map"

# Scans 30-59 without poses (times.txt kept), their reference poses apart.
mkdir -p "$work/scans"
for i in $(seq 30 59); do ln -s "$(realpath "$data/full$i.pcd")" "$work/scans/full$i.pcd"; done
sed -n 31,60p "$data/times.txt" > "$work/scans/times.txt"
sed -n 31,60p "$data/poses.txt" > "$work/reference.txt"

# Start: scan 30's pose moved 0.5 m (at 30 deg from x) and turned 5 deg about z.
initial=$(sed -n 31p "$data/poses.txt" | awk '{
  pi = atan2(0, -1); a = 5 * pi / 180; c = cos(a); s = sin(a)
  r11 = c*$1 - s*$5; r12 = c*$2 - s*$6; r13 = c*$3 - s*$7
  r21 = s*$1 + c*$5; r22 = s*$2 + c*$6; r23 = s*$3 + c*$7
  r31 = $9; r32 = $10; r33 = $11
  x = $4 + 0.5*cos(pi/6); y = $8 + 0.5*sin(pi/6); z = $12
  w = sqrt(1 + r11 + r22 + r33) / 2
  printf "%.9f %.9f %.9f %.9f %.9f %.9f %.9f", x, y, z, (r32-r23)/(4*w), (r13-r31)/(4*w), (r21-r12)/(4*w), w }')

echo "== tracking (scans 30-59, one thread)"
"$bin/ndtom-localize/ndtom-localize" "$work/map.ndtom" "$work/scans" -o "$work/track" --threads 1 \
  --initial "$initial" --reference "$work/reference.txt" | tee "$work/track.txt"
cp "$work/track.top.png" "$out/tracking_top.png"
cp "$work/track.scans.csv" "$out/tracking.csv"

echo "== global (every scan 30-59 searched for in the whole map, one thread)"
"$bin/ndtom-localize/ndtom-localize" "$work/map.ndtom" "$work/scans" -o "$work/global" --threads 1 \
  --global-every-scan --reference "$work/reference.txt" | tee "$work/global.txt"
cp "$work/global.scans.csv" "$out/global.csv"

echo "== outside the map (MRPT's VLP-16 sample scan, another place, in the campus map)"
"$bin/ndtom-localize/ndtom-localize" "$work/map.ndtom" /usr/share/mrpt/datasets/test_velodyne_VLP16.rawlog \
  -o "$work/outside" --threads 1 --no-pictures | tee "$work/outside.txt"
grep -o '"failure": "[^"]*"' "$work/outside.summary.json" >> "$work/outside.txt"

echo "== TUM RGB-D: even frames in a map of the odd ones (levels 0.8-0.2 m)"
tum=share/data/tum-fr2-pioneer-slam2
for part in odd even; do
  mkdir -p "$work/tum-$part"
  ln -s "$(realpath "$tum/depth")" "$work/tum-$part/depth"
  head -2 "$tum/associations.txt" > "$work/tum-$part/associations.txt"
done
awk 'NR > 2 && (NR - 3) % 2 == 1' "$tum/associations.txt" >> "$work/tum-odd/associations.txt"
awk 'NR > 2 && (NR - 3) % 2 == 0' "$tum/associations.txt" >> "$work/tum-even/associations.txt"
"$bin/ndtom-map/ndtom-map" "$work/tum-odd" --no-pictures -q -o "$work/tum-map"
tum_initial=$(sed -n 3p "$work/tum-even/associations.txt" | awk '{printf "%.6f %.6f %s %s %s %s %s", $3 + 0.3, $4 - 0.3, $5, $6, $7, $8, $9}')
"$bin/ndtom-localize/ndtom-localize" "$work/tum-map.ndtom" "$work/tum-even" -o "$work/tum" --threads 1 \
  --levels 4,2,1 --initial "$tum_initial" --no-pictures | tee "$work/tum.txt"

{
  echo "# Localization figures ($(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD))"
  echo
  echo "Map: shared lidar scans 0-29, 0.2 m, rays to 30 m. Scans 30-59 never in it."
  echo
  echo "## Tracking, from 0.5 m and 5 deg off scan 30 (one thread)"; echo; sed 's/^/    /' "$work/track.txt"; echo
  echo "## Global localization of every scan 30-59 (one thread)"; echo; sed 's/^/    /' "$work/global.txt"; echo
  echo "## MRPT's VLP-16 sample scan (another place) in the campus map"; echo; sed 's/^/    /' "$work/outside.txt"; echo
  echo "## TUM RGB-D: even frames in a map of the odd ones"; echo; sed 's/^/    /' "$work/tum.txt"
} > "$out/summary.md"
echo "localization.sh: wrote $out/summary.md, $out/tracking.csv, $out/global.csv, $out/tracking_top.png"
