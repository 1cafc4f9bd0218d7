#!/usr/bin/env bash
# Installs every Debian 12 package VLF needs to build, test and benchmark.
# Idempotent: a second run installs nothing new. Must run as root (or through sudo).
# --bench adds Blender (Debian's 3.4, Cycles on the CPU), the independent renderer that
# bench/blender_compare.sh compares VLF with; `make` and `make test` do not need it.
set -euo pipefail

packages=(
  build-essential cmake make pkg-config git clang-format
  libglm-dev libopenexr-dev libimath-dev libtbb-dev libopenmesh-dev libassimp-dev libssl-dev
  libembree-dev libcli11-dev nlohmann-json3-dev libfmt-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libglfw3-dev libgl-dev libopengl-dev
  xvfb libgl1-mesa-dri xauth
  openexr gnuplot-nox python3 python3-jsonschema linux-perf heaptrack
  libopenmpi-dev openmpi-bin
)
for arg in "$@"; do
  case $arg in
    --bench) packages+=(blender) ;;
    *) echo "install-deps: unknown option '$arg' (known: --bench)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
