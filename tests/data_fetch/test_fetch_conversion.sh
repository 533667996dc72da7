#!/usr/bin/env bash
# scripts/fetch-data.sh's conversion step without network: the BALM scans in tests/data (and,
# when present, the first scans of the shared copy) are turned back into the upstream layout
# (make_balm_raw.py), converted with fetch-data.sh --balm-raw, and must come out as they were:
# poses.txt and times.txt byte for byte, every PCD's points byte for byte (the shared copy's
# files entirely, header included). Also: bad input fails with a message, not a traceback.
# Usage: test_fetch_conversion.sh REPO_DIR SHARED_DATASETS_DIR
set -euo pipefail
repo="$1" shared="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

payload() {  # the bytes after the header of a binary PCD, and its POINTS line
  python3 - "$1" <<'PY'
import sys
d = open(sys.argv[1], "rb").read()
at = d.index(b"DATA binary\n") + 12
pts = [l for l in d[:at].split(b"\n") if l.startswith(b"POINTS")]
sys.stdout.buffer.write(pts[0] + b"\n" + d[at:])
PY
}

check() {  # SOURCE_DIR SCANS WHOLE_FILES
  local src="$1" n="$2" whole="$3" raw="$work/raw-$RANDOM" out="$work/out-$RANDOM"
  python3 "$repo/tests/data_fetch/make_balm_raw.py" "$src" "$raw" "$n"
  "$repo/scripts/fetch-data.sh" --balm-raw "$raw" --dest "$out" --scans "$n" --skip-tum \
    --no-verify 2>"$work/log" || { cat "$work/log"; fail "fetch-data.sh on $raw"; }
  head -n "$n" "$src/poses.txt" | cmp - "$out/balm-realworld/poses.txt" || fail "poses.txt of $src"
  head -n "$n" "$src/times.txt" | cmp - "$out/balm-realworld/times.txt" || fail "times.txt of $src"
  for ((i = 0; i < n; ++i)); do
    if ((whole)); then
      cmp "$src/full$i.pcd" "$out/balm-realworld/full$i.pcd" || fail "full$i.pcd of $src"
    else
      cmp <(payload "$src/full$i.pcd") <(payload "$out/balm-realworld/full$i.pcd") ||
        fail "points of full$i.pcd of $src"
    fi
  done
  echo "ok: $n scans of $src"
}

check "$repo/tests/data/balm-realworld" 10 0
if [[ -f "$shared/balm-realworld/poses.txt" ]]; then
  check "$shared/balm-realworld" 4 1
  # All 60 scans, checked against scripts/data-checksums.sha256 as a download would be.
  python3 "$repo/tests/data_fetch/make_balm_raw.py" "$shared/balm-realworld" "$work/raw60" 60
  "$repo/scripts/fetch-data.sh" --balm-raw "$work/raw60" --dest "$work/out60" --skip-tum ||
    fail "60 shared scans do not convert to their checksums"
  echo "ok: 60 shared scans match scripts/data-checksums.sha256"
else
  echo "skipped: no shared lidar copy at $shared"
fi
if [[ -f "$shared/tum-fr2-pioneer-slam2/associations.txt" ]]; then
  # The TUM archive's layout, with the shared frames (plus one the script must leave out).
  seq_dir="$work/tum/rgbd_dataset_freiburg2_pioneer_slam2"
  mkdir -p "$seq_dir"
  cp -r "$shared/tum-fr2-pioneer-slam2/depth" "$shared/tum-fr2-pioneer-slam2/rgb" "$seq_dir/"
  cp "$seq_dir/depth/$(ls "$seq_dir/depth" | head -n1)" "$seq_dir/depth/1311877999.000000.png"
  tar -czf "$work/tum.tgz" -C "$work/tum" rgbd_dataset_freiburg2_pioneer_slam2
  "$repo/scripts/fetch-data.sh" --tum-archive "$work/tum.tgz" --dest "$work/outtum" --skip-balm ||
    fail "TUM frames from an archive do not match their checksums"
  [[ ! -e "$work/outtum/tum-fr2-pioneer-slam2/depth/1311877999.000000.png" ]] ||
    fail "a frame outside associations.txt was copied"
  echo "ok: TUM frames from an archive match scripts/data-checksums.sha256"
else
  echo "skipped: no shared TUM copy at $shared"
fi

# Bad input: a truncated scan and a pose file with a number missing.
raw="$work/bad"
python3 "$repo/tests/data_fetch/make_balm_raw.py" "$repo/tests/data/balm-realworld" "$raw" 4
head -c 2000 "$raw/full3.pcd" >"$raw/t" && mv "$raw/t" "$raw/full3.pcd"
if "$repo/scripts/fetch-data.sh" --balm-raw "$raw" --dest "$work/bad-out" --scans 4 --skip-tum \
  --no-verify 2>"$work/err"; then fail "a truncated PCD was accepted"; fi
grep -q "full3.pcd" "$work/err" || fail "no file name in: $(cat "$work/err")"
! grep -q Traceback "$work/err" || fail "traceback: $(cat "$work/err")"
sed -i '1s/^[^,]*,//' "$raw/alidarPose.csv"
if "$repo/scripts/fetch-data.sh" --balm-raw "$raw" --dest "$work/bad-out" --scans 4 --skip-tum \
  --no-verify 2>"$work/err"; then fail "a short alidarPose.csv was accepted"; fi
grep -q "alidarPose.csv" "$work/err" || fail "no file name in: $(cat "$work/err")"
echo "ok: bad input refused"
