#!/usr/bin/env bash
# Propagates every scene of scenes/ at the settings below and renders its first camera in
# raytrace mode into docs/gallery/<scene>.png, so a reader sees what the engine does.
# Usage: bench/render_gallery.sh [-b BUILD]
set -euo pipefail
build=build
[ "${1:-}" = "-b" ] && build=$2
settings=(--directions 513 --resolution 64 --tile 8 --cycles 6 --perturbations 3 --filter-sigma 0.7)
mkdir -p docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for scene in cornell cornell-mirrors closed-box office ring caustic complexity/complexity-530; do
  name=$(basename "$scene")
  "$build/propagate/propagate" "scenes/$scene.json" "${settings[@]}" -q -o "$work/$name.vlf" > /dev/null
  "$build/walkthrough/walkthrough" "$work/$name.vlf" --mode raytrace --size 512x512 \
      -o "docs/gallery/$name.png" | tail -n 1
done
echo "settings: ${settings[*]}"
