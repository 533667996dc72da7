#!/usr/bin/env bash
# Downloads the public data the evaluation and the benchmarks read, and converts it to the
# layout they expect (see ../shared/datasets/README.md in a checkout that has it):
#   DEST/balm-realworld/  fullN.pcd (x y z intensity), poses.txt (KITTI), times.txt
#                         from hku-mars/BALM datas/benchmark_realworld (GPL-2.0), first 60 scans
#   DEST/tum-fr2-pioneer-slam2/  depth/ rgb/ associations.txt: the 10 frames of TUM RGB-D
#                         fr2/pioneer_slam2 (CC BY 4.0) listed in share/data/.../associations.txt
# then checks every file against scripts/data-checksums.sha256.
#
# Usage: scripts/fetch-data.sh [--dest DIR] [--scans N] [--balm-raw DIR] [--tum-archive FILE]
#                              [--no-verify]
#   --dest DIR          where to write (default: ../shared/datasets beside the repository,
#                       where the programs look by default)
#   --scans N           BALM scans to fetch (default 60, the evaluation's)
#   --balm-raw DIR      no download: convert a local copy of datas/benchmark_realworld
#   --tum-archive FILE  no download: the TUM sequence's .tgz, already downloaded
#   --skip-tum          only the lidar scans
#   --skip-balm         only the TUM frames
#   --no-verify         skip the checksums (e.g. for other scan counts or a test fixture)
# Needs curl, tar, python3, sha256sum. The TUM archive is large (the whole sequence, ~1 GB):
# only 10 frames are kept.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
dest="$repo/../shared/datasets"
scans=60 balm_raw="" tum_archive="" skip_tum=0 skip_balm=0 verify=1
die() { echo "fetch-data.sh: $*" >&2; exit 1; }
while (($#)); do
  case "$1" in
    --dest) dest="${2:?--dest needs a folder}"; shift 2 ;;
    --scans) scans="${2:?--scans needs a count}"; shift 2 ;;
    --balm-raw) balm_raw="${2:?--balm-raw needs a folder}"; shift 2 ;;
    --tum-archive) tum_archive="${2:?--tum-archive needs a file}"; shift 2 ;;
    --skip-tum) skip_tum=1; shift ;;
    --skip-balm) skip_balm=1; shift ;;
    --no-verify) verify=0; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option $1 (see --help)" ;;
  esac
done
[[ "$scans" =~ ^[1-9][0-9]*$ ]] || die "--scans: expected a positive count, got '$scans'"
mkdir -p "$dest" || die "cannot create $dest"
[[ -w "$dest" ]] || die "$dest is not writable (choose another with --dest)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

BALM_URL=https://raw.githubusercontent.com/hku-mars/BALM/master/datas/benchmark_realworld
TUM_URL=https://cvg.cit.tum.de/rgbd/dataset/freiburg2/rgbd_dataset_freiburg2_pioneer_slam2.tgz

fetch() {  # URL FILE: fails on HTTP errors and on a Git LFS pointer instead of the data
  curl -fsSL --retry 3 -o "$2" "$1" || die "download failed: $1"
  if head -c 40 "$2" | grep -q '^version https://git-lfs'; then die "$1 is a Git LFS pointer"; fi
}

# --- BALM lidar scans ---------------------------------------------------------------------
if ((!skip_balm)); then
  if [[ -z "$balm_raw" ]]; then
    balm_raw="$work/balm-raw"
    mkdir -p "$balm_raw"
    echo "fetch-data.sh: downloading alidarPose.csv and $scans BALM scans" >&2
    fetch "$BALM_URL/alidarPose.csv" "$balm_raw/alidarPose.csv"
    for ((i = 0; i < scans; ++i)); do fetch "$BALM_URL/full$i.pcd" "$balm_raw/full$i.pcd"; done
  fi
  [[ -d "$balm_raw" ]] || die "--balm-raw $balm_raw: not a folder"
  python3 "$repo/scripts/balm_convert.py" "$balm_raw" "$dest/balm-realworld" "$scans"
  cat >"$dest/balm-realworld/README.md" <<'TXT'
BALM 2.0 real-world benchmark (Liu & Zhang, T-RO 2023), hku-mars/BALM datas/benchmark_realworld
(GPL-2.0), converted by scripts/fetch-data.sh: fullN.pcd keep x y z intensity (sensor frame),
poses.txt is alidarPose.csv as KITTI lines (sensor -> world, lidar-inertial odometry),
times.txt its time stamps.
TXT
fi

# --- TUM RGB-D frames ---------------------------------------------------------------------
if ((!skip_tum)); then
  list="$repo/share/data/tum-fr2-pioneer-slam2/associations.txt"
  if [[ -z "$tum_archive" ]]; then
    tum_archive="$work/pioneer_slam2.tgz"
    echo "fetch-data.sh: downloading the TUM sequence (large)" >&2
    fetch "$TUM_URL" "$tum_archive"
  fi
  [[ -f "$tum_archive" ]] || die "--tum-archive $tum_archive: no such file"
  members=()
  while read -r rgb depth _; do
    [[ -z "$rgb" || "$rgb" == \#* ]] && continue
    members+=("rgbd_dataset_freiburg2_pioneer_slam2/$rgb" "rgbd_dataset_freiburg2_pioneer_slam2/$depth")
  done <"$list"
  tar -xzf "$tum_archive" -C "$work" "${members[@]}" || die "$tum_archive: frames missing"
  out="$dest/tum-fr2-pioneer-slam2"
  mkdir -p "$out/depth" "$out/rgb"
  cp "$work/rgbd_dataset_freiburg2_pioneer_slam2/depth/"*.png "$out/depth/"
  cp "$work/rgbd_dataset_freiburg2_pioneer_slam2/rgb/"*.png "$out/rgb/"
  # The poses: TUM's ground truth for these frames, as the repository ships them.
  cp "$list" "$repo/share/data/tum-fr2-pioneer-slam2/README.md" "$out/"
fi

# --- checks -------------------------------------------------------------------------------
if ((verify)); then
  sums="$work/expected.sha256"
  grep -v '^#' "$repo/scripts/data-checksums.sha256" | while read -r sum path; do
    case "$path" in
      balm-realworld/full*.pcd)
        n="${path#balm-realworld/full}"
        ((!skip_balm && ${n%.pcd} < scans)) || continue ;;
      balm-*) ((!skip_balm)) || continue ;;
      tum-*) ((!skip_tum)) || continue ;;
    esac
    echo "$sum  $path"
  done >"$sums"
  (cd "$dest" && sha256sum --quiet -c "$sums") ||
    die "checksums differ from scripts/data-checksums.sha256 (upstream changed, or a partial download)"
  echo "fetch-data.sh: $(wc -l <"$sums") files verified in $dest" >&2
fi
echo "fetch-data.sh: done: $dest" >&2
