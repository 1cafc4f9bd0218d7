#!/usr/bin/env bash
# The real-model scenes (scenes/bunny.json, scenes/spot.json by default) against the path
# tracer: for each scene
#   1. propagate with PROPAGATE_ARGS (default -l 513 -N 64 -m 8 -c 4; report kept as
#      NAME-report.json)
#   2. walkthrough texture mode, 512x512, default camera -> NAME-texture.png and .exr
#   3. walkthrough pathtrace, 512x512, SPP samples (default 256, about 1-2 min on 2 cores)
#      -> NAME-pathtrace.exr, and .png by bench/exr_to_png.py (the same tone map)
#   4. texture mode again with 16x16 rays per pixel (the reference's pixel footprint,
#      docs/rendering.md) --reference NAME-pathtrace.exr: prints the relative RMSE over the
#      whole image and away from emitters, and the mean ratio away from emitters
# The path tracer's own noise at 256 spp is part of the RMSE; the mean ratio is the robust
# figure. Usage: bench/model_gallery.sh [-b BUILD] [-o OUTDIR (out/model-gallery)]
#                                       [-s SPP] [-p PROPAGATE_ARGS] [SCENE.json ...]
set -euo pipefail
build=build
out=out/model-gallery
spp=256
args="-l 513 -N 64 -m 8 -c 4"
while getopts "b:o:s:p:" opt; do
  case $opt in
    b) build=$OPTARG ;;
    o) out=$OPTARG ;;
    s) spp=$OPTARG ;;
    p) args=$OPTARG ;;
    *) sed -n '2,/^set -euo/p' "$0" | sed '$d' >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
cd "$(dirname "$0")/.."
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/bunny.json scenes/spot.json)
propagate=("$build/propagate/propagate")
walk=(nice -n 19 "$build/walkthrough/walkthrough")
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  echo "== $name: propagate $args"
  # shellcheck disable=SC2086  # the arguments are words
  nice -n 19 "${propagate[@]}" "$scene" $args -q -o "$work/$name.vlf" \
    --report "$out/$name-report.json" | { grep -E '^(  faces|propagated)' || true; }
  for ext in png exr; do
    "${walk[@]}" "$work/$name.vlf" --mode texture --size 512x512 -o "$out/$name-texture.$ext" | tail -n 1
  done
  "${walk[@]}" "$work/$name.vlf" --mode pathtrace --spp "$spp" --size 512x512 \
    -o "$out/$name-pathtrace.exr" | tail -n 1
  bench/exr_to_png.py "$out/$name-pathtrace.exr" "$out/$name-pathtrace.png"
  echo "-- $name: texture (16x16 rays per pixel) against the ${spp}-spp path tracer"
  "${walk[@]}" "$work/$name.vlf" --mode texture --size 512x512 --pixel-samples 16 \
    --reference "$out/$name-pathtrace.exr" -o "$work/$name-texture-k16.exr" \
    | { grep -v '^walkthrough: loaded' || true; }
  rm -rf "$work/$name.vlf"
done
echo "images in $out/"
