#!/usr/bin/env bash
# VLF against an independent renderer, Blender's Cycles (bench/blender_reference.py): for
# each scene
#   1. vlf_export_scene writes the scene as VLF loads it (faces, materials, lights, cameras)
#   2. J Blender processes (Cycles renders on one core here) render it with seeds 1..J at
#      SPP samples each, WxH, the default camera; their mean is NAME-blender.exr
#      (bench/exr_compare.py mean)
#   3. propagate with PROPAGATE_ARGS (default --quality preview)
#   4. texture mode (16 x 16 rays per pixel, the reference's pixel footprint) and VLF's own
#      path tracer (PT_SPP samples) against NAME-blender.exr: relative RMSE away from
#      emitters and the mean ratio (walkthrough --reference); and the 8 x 8-block error map
#      of the texture image (exr_compare.py map --block 8: low frequencies, not noise), and
#      the ratio tables per 16 x 16 block of the texture image and of Cycles' two seeds
# Needs Blender (scripts/install-deps.sh --bench installs Debian's). Usage:
#   bench/blender_compare.sh [-b BUILD] [-o OUTDIR (out/blender)] [-s SPP (4096)] [-j J (2)]
#                            [-z WxH (128x128)] [-t PT_SPP (4096)] [-p PROPAGATE_ARGS]
#                            [-c CYCLES_ARGS] SCENE...
# CYCLES_ARGS go to blender_reference.py: "--shadow-caustics on" (Cycles' manifold next-event
# estimation through glass for point lights) or "--point-radius R" (point lights as spheres
# of radius R that paths through glass can hit).
set -euo pipefail
build=build
out=out/blender
spp=4096
jobs=2
size=128x128
pt_spp=4096
args="--quality preview"
cycles_args=""
while getopts "b:o:s:j:z:t:p:c:" opt; do
  case $opt in
    b) build=$OPTARG ;;
    o) out=$OPTARG ;;
    s) spp=$OPTARG ;;
    j) jobs=$OPTARG ;;
    z) size=$OPTARG ;;
    t) pt_spp=$OPTARG ;;
    p) args=$OPTARG ;;
    c) cycles_args=$OPTARG ;;
    *) sed -n '2,/^set -euo/p' "$0" | sed '$d' >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
cd "$(dirname "$0")/.."
[ $# -gt 0 ] || { echo "blender_compare.sh: no scene given" >&2; exit 2; }
command -v blender > /dev/null ||
  { echo "blender_compare.sh: no blender (scripts/install-deps.sh --bench)" >&2; exit 2; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for scene in "$@"; do
  name=$(basename "$scene" .json)
  echo "== $name"
  "$build/bench/vlf_export_scene" "$scene" "$out/$name-export.json"
  start=$(date +%s.%N)
  parts=()
  for seed in $(seq 1 "$jobs"); do
    # shellcheck disable=SC2086
    blender -b --factory-startup --python bench/blender_reference.py -- \
      "$out/$name-export.json" "$work/$name-blender-$seed.exr" --size "$size" --spp "$spp" \
      --seed "$seed" $cycles_args > "$work/$name-blender-$seed.log" 2>&1 &
    parts+=("$work/$name-blender-$seed.exr:$spp")
  done
  wait
  for seed in $(seq 1 "$jobs"); do
    [ -s "$work/$name-blender-$seed.exr" ] ||
      { tail -5 "$work/$name-blender-$seed.log" >&2; exit 1; }
  done
  python3 bench/exr_compare.py mean "$out/$name-blender.exr" "${parts[@]}"
  if [ "$jobs" -ge 2 ]; then
    echo "cycles, seed 1 / seed 2 per 16 x 16 block (the reference's noise is about half this spread):"
    python3 bench/exr_compare.py ratios "$work/$name-blender-1.exr" "$work/$name-blender-2.exr" --block 16
  fi
  echo "cycles: $size, $jobs x $spp spp in $(echo "$(date +%s.%N) - $start" | bc) s"
  # shellcheck disable=SC2086
  "$build/propagate/propagate" "$scene" $args -q -o "$work/$name.vlf" --report "$out/$name-report.json"
  "$build/walkthrough/walkthrough" "$work/$name.vlf" --mode texture --size "$size" \
    --pixel-samples 16 --reference "$out/$name-blender.exr" -o "$out/$name-texture.exr" 2>&1 |
    grep -E "against|mean ratio" | sed 's/^/texture: /'
  "$build/walkthrough/walkthrough" "$work/$name.vlf" --mode pathtrace --spp "$pt_spp" \
    --size "$size" --reference "$out/$name-blender.exr" -o "$out/$name-pathtrace.exr" 2>&1 |
    grep -E "against|mean ratio" | sed 's/^/vlf path tracer: /'
  python3 bench/exr_compare.py map "$out/$name-texture.exr" "$out/$name-blender.exr" \
    "$out/$name-texture-map.png" --block 8 | sed 's/^/texture, 8x8 blocks: /'
  echo "texture / cycles per 16 x 16 block:"
  python3 bench/exr_compare.py ratios "$out/$name-texture.exr" "$out/$name-blender.exr" --block 16
done
