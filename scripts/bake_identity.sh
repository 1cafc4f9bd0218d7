#!/usr/bin/env bash
# Fingerprints of what the engine produces, for "no behaviour change" checks across a
# refactor: bakes every scene in scenes/ (small field, two option sets) and renders each
# bake in every lookup mode plus a few path-traced samples, then prints one SHA-256 per
# output file (the bake's lightmaps, light field and scene; every image). The manifest is
# left out: it holds the run's timings.
#   scripts/bake_identity.sh [build-dir] > before.txt   ... refactor ...
#   scripts/bake_identity.sh [build-dir] > after.txt && diff before.txt after.txt
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
options=("-l 33 -N 32 -m 8 -c 3"
         "-l 129 -N 32 -m 8 -c 3 --perturbations 1 --filter-sigma 0.7 --supersample 2 --scheme equal-area --store-all-rays")
for scene in scenes/*.json scenes/complexity/complexity-224.json; do
  name=$(basename "$scene" .json)
  for k in "${!options[@]}"; do
    out="$work/$name-$k.vlf"
    # shellcheck disable=SC2086
    "$build/propagate/propagate" "$scene" ${options[$k]} -t 2 -q -o "$out" > /dev/null
    for f in lightmaps.exr lightfield.exr scene.json; do
      [ -f "$out/$f" ] && echo "$(sha256sum < "$out/$f" | cut -c1-16)  $name-$k/$f"
    done
    for mode in texture raytrace rays pathtrace; do
      "$build/walkthrough/walkthrough" "$out" --mode "$mode" --size 48x32 --spp 4 \
        --pixel-samples 2 -o "$work/img.exr" > /dev/null
      echo "$(sha256sum < "$work/img.exr" | cut -c1-16)  $name-$k/$mode.exr"
    done
  done
done
