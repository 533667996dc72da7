#!/usr/bin/env bash
# Installs the Debian packages this project needs, and only those that are missing.
# Idempotent and silent when everything is present.
# Usage: scripts/setup.sh [--with-fuzz] [--with-pcl] [--with-octomap-tools]
#   --with-fuzz  clang and its runtime, for the libFuzzer targets (scripts/fuzz.sh)
#   --with-pcl   PCL 1.13 (libpcl-dev), only for the PCL peers of ndtom-regbench; no library,
#                test or CI step needs it
#   --with-octomap-tools  OctoMap's programs (graph2tree), for scripts/bench-map-e2e.sh
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libopencv-dev
  libmrpt-dev mrpt-apps mrpt-common
  liboctomap-dev
  openmpi-bin libopenmpi-dev  # ndtom-map-mpi, the distributed build
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  xvfb xauth
  zlib1g-dev  # the tests read ndtom-map's gzip scene back
  libdeflate-dev  # ndtom-map compresses its scene itself
  libgl1-mesa-dri  # Mesa's software OpenGL: MRPT's viewers under Xvfb in the tests (no GPU needed)
)
for option in "$@"; do
  case "$option" in
    --with-fuzz) packages+=(clang libclang-rt-14-dev) ;;
    --with-pcl) packages+=(libpcl-dev) ;;
    --with-octomap-tools) packages+=(octomap-tools) ;;
    *) echo "setup: unknown option '$option' (use --with-fuzz, --with-pcl, --with-octomap-tools)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "installed" ]] || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "setup: installing ${missing[*]}"
as_root=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  as_root=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
